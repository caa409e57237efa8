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
//! by photon, so a render is the same at any thread count.

mod film;
mod photon;

pub use film::Film;
pub use photon::{trace_photon, PhotonStats};

use rayon::prelude::*;

use crate::camera::View;
use crate::cpu::intersect::Accel;
use crate::linear_image::LinearImage;
use crate::rt_scene::RtScene;
use crate::scene::Scene;

/// Photons traced by one task into a film of its own. Fixed, so that the
/// films are summed in the same order whatever the thread count.
const PHOTONS_PER_TASK: u32 = 1 << 14;

/// A forward render: the image and what its photons did.
pub struct ForwardImage {
    pub image: LinearImage,
    pub stats: PhotonStats,
}

/// Traces `photons` photons through `scene` at its image size, split over
/// its lights by power. `None` where the scene has no light with power.
pub fn render(scene: &Scene, photons: u32) -> Option<ForwardImage> {
    let rt = RtScene::new(scene);
    let view = View::new(scene, scene.image.width, scene.image.height);
    let accel = Accel::new(&rt);
    let lights = photon::LightChoice::new(&rt)?;
    let tasks = photons.div_ceil(PHOTONS_PER_TASK);
    let films: Vec<(Film, PhotonStats)> = (0..tasks)
        .into_par_iter()
        .map(|task| {
            let mut film = Film::new(&view);
            let mut stats = PhotonStats::default();
            let first = task * PHOTONS_PER_TASK;
            for i in first..(first + PHOTONS_PER_TASK).min(photons) {
                trace_photon(&accel, &lights, i, photons, &mut film, &mut stats);
            }
            (film, stats)
        })
        .collect();
    let mut total = Film::new(&view);
    let mut stats = PhotonStats::default();
    for (film, s) in films {
        total.add(&film);
        stats.add(&s);
    }
    Some(ForwardImage {
        image: total.image(),
        stats,
    })
}
