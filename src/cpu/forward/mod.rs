//! Forward ray tracing from the lights (the lecture's other half), in
//! `f64`: photons leave every light, bounce off diffuse surfaces, mirrors
//! and glass, and at every surface that is not a mirror or glass a shadow
//! ray to the eye adds what the eye sees of them to the pixel it lands in
//! (a light tracer; docs/lighting-model.md, "Forward: photons from the
//! lights"). It solves the transport the backward tracer with
//! `render.bounces` solves, so the two converge to one image.
//!
//! `photon.rs` follows one photon; `film.rs` is where its splats land.
//! The random numbers are the backward tracer's counter-based hash, keyed
//! by photon, and the film sums in fixed point as the GPU's does, so a
//! render is the same bits at any thread count.

mod film;
mod photon;

pub use crate::film_sums::PhotonStats;
pub use film::Film;
pub use photon::trace_photon;
pub use photon::LightChoice;
pub(crate) use photon::{go_on, Flight};

use rayon::prelude::*;

use crate::camera::View;
use crate::cpu::intersect::Accel;
use crate::film_sums::{FilmSums, RenderPart};
use crate::linear_image::LinearImage;
use crate::rt_scene::RtScene;
use crate::scene::Scene;
use crate::work_counter::WorkCounter;

/// Photons traced by one task: progress is counted a task at a time.
const PHOTONS_PER_TASK: u32 = 1 << 14;

/// A forward render: its film and what its photons did.
pub struct ForwardImage {
    pub film: FilmSums,
    pub stats: PhotonStats,
}

impl ForwardImage {
    pub fn image(&self) -> LinearImage {
        self.film.image()
    }
}

/// Traces `part`'s photons through `scene` at its image size, split over
/// its lights by power, counting them into `counter` as tasks finish
/// (under a time budget, the tasks that start before it). `None` where the
/// scene has no light with power.
/// Each thread splats into a film of its own; the films' integer sums add
/// up to the same bits in any order.
pub fn render(scene: &Scene, part: &RenderPart, counter: &WorkCounter) -> Option<ForwardImage> {
    let rt = RtScene::new(scene);
    let view = View::new(scene, scene.image.width, scene.image.height);
    let accel = Accel::new(&rt);
    let lights = photon::LightChoice::new(&rt)?;
    let range = part.range.clone();
    let tasks = (range.end.saturating_sub(range.start)).div_ceil(PHOTONS_PER_TASK);
    counter.begin("photons", u64::from(range.end.saturating_sub(range.start)));
    let fresh = || (Film::new(&view), PhotonStats::default());
    let (film, stats) = (0..tasks)
        .into_par_iter()
        .fold(fresh, |(mut film, mut stats), task| {
            // The first task runs whatever the budget (`may_start`).
            if !part.may_start(task == 0) {
                return (film, stats);
            }
            let first = range.start + task * PHOTONS_PER_TASK;
            let end = first.saturating_add(PHOTONS_PER_TASK).min(range.end);
            for i in first..end {
                trace_photon(&accel, &lights, i, part.total, &mut film, &mut stats);
            }
            counter.add(u64::from(end - first));
            (film, stats)
        })
        .reduce(fresh, |(mut a, mut sa), (b, sb)| {
            a.add(&b);
            sa.add(&sb);
            (a, sa)
        });
    Some(ForwardImage {
        film: film.into_sums(),
        stats,
    })
}
