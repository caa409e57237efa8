//! Caustic photons (docs/lighting-model.md, "Caustics"): photons from the
//! lights, exactly as the forward tracer emits them, that reach a diffuse
//! surface through at least one mirror or glass event (paths `L S+ D`).
//! They are kept where they land, with the flux they arrive with, and go
//! no further: light that leaves a diffuse surface is the backward
//! tracer's, which also finds light that reaches a diffuse surface
//! straight from a light, so no path is counted twice.

use glam::DVec3;
use rayon::prelude::*;

use crate::cpu::forward::{go_on, Flight, LightChoice};
use crate::cpu::intersect::Accel;
use crate::cpu::raytrace::facing_normal;
use crate::cpu::surface::hit_tint;
use crate::random_streams::Sampler;
use crate::rt_scene::RtScene;

/// Photons traced by one task: tasks run in parallel, and their photons
/// are put together in photon order, so the list is the same at any
/// thread count.
const PHOTONS_PER_TASK: u32 = 1 << 14;

/// Where a caustic photon landed (camera-relative, as the ray tracer's
/// scene is), the side it lit, and what it carries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CausticPhoton {
    pub position: DVec3,
    /// The shading normal on the side the photon arrived from.
    pub normal: DVec3,
    /// The flux it arrives with, falloff included (`d^2 F(d)`, `d` its
    /// path's length from the light through the mirrors and glass), in
    /// the units the forward tracer's photons carry.
    pub flux: DVec3,
    /// The photon's number, `0..total`.
    pub photon: u32,
}

/// Traces photons `range` of `total` through `scene` and keeps the
/// caustic ones, in photon order; traces none where no material has `kr`
/// or `kt`. `None` for a scene with no light that has power.
pub fn caustic_photons(
    scene: &RtScene,
    range: std::ops::Range<u32>,
    total: u32,
) -> Option<Vec<CausticPhoton>> {
    let lights = LightChoice::new(scene)?;
    // No mirror or glass, no caustic: no photon is traced.
    if !scene.materials.iter().any(|m| m.kr > 0.0 || m.kt > 0.0) {
        return Some(Vec::new());
    }
    Some(trace_caustic_photons(
        &Accel::new(scene),
        &lights,
        range,
        total,
    ))
}

/// Traces photons `range` of `total` through `accel`'s scene from
/// `lights`, and keeps the caustic ones, in photon order: the same list
/// at any thread count.
pub(crate) fn trace_caustic_photons(
    accel: &Accel,
    lights: &LightChoice,
    range: std::ops::Range<u32>,
    total: u32,
) -> Vec<CausticPhoton> {
    let tasks = range
        .end
        .saturating_sub(range.start)
        .div_ceil(PHOTONS_PER_TASK);
    let parts: Vec<Vec<CausticPhoton>> = (0..tasks)
        .into_par_iter()
        .map(|task| {
            let first = range.start + task * PHOTONS_PER_TASK;
            let end = first.saturating_add(PHOTONS_PER_TASK).min(range.end);
            let mut kept = Vec::new();
            for i in first..end {
                trace_caustic_photon(accel, lights, (i, total), &mut kept);
            }
            kept
        })
        .collect();
    parts.concat()
}

/// Traces photon `i` of `total`: from its first surface by a mirror or
/// glass event picked in proportion to `kr` and `kt` (absorbed with what
/// is left), then by any event as the forward tracer's photons go, diffuse
/// bounces included up to the scene's `bounces`; kept at every surface
/// with `kd C` not zero that it reaches after its first.
pub fn trace_caustic_photon(
    accel: &Accel,
    lights: &LightChoice,
    (i, total): (u32, u32),
    kept: &mut Vec<CausticPhoton>,
) {
    let scene = lights.scene;
    let mut flight = Flight::emit(lights, i, total);
    for level in 0..=scene.render.depth {
        let Some(hit) = accel.nearest(&flight.ray) else {
            return;
        };
        if hit.normal == DVec3::ZERO {
            return;
        }
        let p = flight.ray.origin + hit.t * flight.ray.dir;
        let material = &scene.materials[hit.material as usize];
        let (tint, _) = hit_tint(scene, &hit, p, flight.ray.dir, 0.0);
        let albedo = material.kd * material.color * tint;
        let arriving = flight.arriving(scene, hit.t);
        if level > 0 && albedo != DVec3::ZERO {
            kept.push(CausticPhoton {
                position: p,
                normal: facing_normal(hit.normal, hit.geometric_normal, flight.ray.dir),
                flux: arriving,
                photon: i,
            });
        }
        if level == scene.render.depth {
            return;
        }
        flight.met(albedo);
        let numbers = Sampler::start_photon(i).at_level(level + 1).all();
        // Light that leaves its first surface diffusely is the backward
        // tracer's (its shadow rays find that surface's light).
        let diffuse_allowed = level > 0 && flight.may_bounce(scene);
        if !go_on(
            &mut flight,
            (&hit, p, material, albedo),
            arriving,
            numbers,
            diffuse_allowed,
        ) {
            return;
        }
    }
}
