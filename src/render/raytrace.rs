//! Backward ray tracing, Whitted's and with diffuse bounces: the compute
//! shader (or ray queries) on the GPU, and the f64 twin.

use std::sync::Arc;
use std::time::Instant;

use super::coverage::signature_edges;
use super::integrator::{Integrator, Work};
use super::rendered::{Coverage, FilmRender, Rendered, Timings};
use crate::error::Error;
use crate::gpu::{raytrace, GpuContext};

/// The ray tracer on the GPU.
pub(super) struct GpuRayTrace<'d> {
    pub context: &'d Arc<GpuContext>,
}

impl Integrator for GpuRayTrace<'_> {
    fn render(&self, work: &Work) -> Result<Rendered, Error> {
        let options = raytrace::TraceOptions {
            count_rays: work.count_rays,
            every_feature: work.every_feature,
            ..raytrace::TraceOptions::default()
        };
        let out = raytrace::render(self.context, work.scene, options, work.part, work.counter)?;
        let mut rendered = Rendered::new(out.image, Timings::gpu(&out.timings));
        rendered.ray_stats = out.stats;
        rendered.traversal = Some(out.traversal);
        rendered.film = out.sums.map(|sums| FilmRender {
            film: sums.film,
            traced: u64::from(sums.traced),
            photons: None,
            estimated_rmse: sums.estimate,
        });
        Ok(rendered)
    }
}

/// The f64 twin. A pixel is near an edge when its 3x3 neighbourhood
/// (within the image) holds more than one path signature: there a
/// reflected, refracted or shadow edge, or a silhouette, passes close by,
/// and another tracer's rounding may put it on the other side.
pub(super) struct CpuRayTrace;

impl Integrator for CpuRayTrace {
    fn render(&self, work: &Work) -> Result<Rendered, Error> {
        let (scene, part) = (work.scene, work.part);
        let started = Instant::now();
        let out = crate::cpu::raytrace::render(scene, part, work.counter);
        let timings = Timings {
            trace_ms: Some(out.trace_ms),
            ..Timings::cpu(started)
        };
        let mut rendered = Rendered::new(out.image, timings);
        rendered.ray_stats = Some(out.stats);
        rendered.film = out.film.map(|film| FilmRender {
            film,
            traced: u64::from(part.count()),
            photons: None,
            estimated_rmse: None,
        });
        let (width, height) = (scene.image.width as usize, scene.image.height as usize);
        rendered.coverage = Some(Coverage {
            object_ids: out.primary_object_ids.clone(),
            surface_ids: out.primary_object_ids,
            near_edge: signature_edges(width, height, &out.path_signatures),
        });
        Ok(rendered)
    }
}
