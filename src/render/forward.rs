//! Forward ray tracing: photons from the lights splatted into a film, on
//! the GPU and with the f64 twin that traces the same photons.

use std::sync::Arc;
use std::time::Instant;

use super::integrator::{Integrator, Work};
use super::rendered::{Coverage, FilmRender, Rendered, Timings};
use crate::error::Error;
use crate::film_sums::scaled_image;
use crate::gpu::{raytrace, GpuContext};
use crate::scene::Traversal;

/// The forward tracer's compute shader.
pub(super) struct GpuForward<'d> {
    pub context: &'d Arc<GpuContext>,
}

impl Integrator for GpuForward<'_> {
    fn render(&self, work: &Work) -> Result<Rendered, Error> {
        let part = work.part;
        let out = raytrace::forward::render(self.context, work.scene, part, work.counter)?;
        let image = scaled_image(&out.film, out.stats.emitted, part.count());
        let mut rendered = Rendered::new(image, Timings::gpu(&out.timings));
        rendered.traversal = Some(Traversal::Bvh);
        rendered.film = Some(FilmRender {
            film: out.film,
            traced: out.stats.emitted,
            photons: Some(out.stats),
            estimated_rmse: out.estimate,
        });
        Ok(rendered)
    }
}

/// The f64 twin. The GPU traces its photons one by one, but a photon that
/// f32 rounding sends another way moves a splat to any pixel at all:
/// every pixel is marked as an edge one, and `check` bounds the share
/// that differ and the images' means (`check::FORWARD_*`).
pub(super) struct CpuForward;

impl Integrator for CpuForward {
    fn render(&self, work: &Work) -> Result<Rendered, Error> {
        let part = work.part;
        let started = Instant::now();
        let out = crate::cpu::forward::render(work.scene, part, work.counter).expect(
            "the plan lets only scenes with light through (refusals::forward_without_light)",
        );
        let pixels = out.film.width as usize * out.film.height as usize;
        let image = scaled_image(&out.film, out.stats.emitted, part.count());
        let mut rendered = Rendered::new(image, Timings::cpu(started));
        rendered.film = Some(FilmRender {
            film: out.film,
            traced: out.stats.emitted,
            photons: Some(out.stats),
            estimated_rmse: None,
        });
        rendered.coverage = Some(Coverage {
            object_ids: vec![None; pixels],
            surface_ids: vec![None; pixels],
            near_edge: vec![true; pixels],
        });
        Ok(rendered)
    }
}
