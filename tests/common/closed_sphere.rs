//! The secondary-illumination oracle that tests/gpu/path_trace.rs and
//! tests/cpu/forward.rs share: a point light at the centre of a closed
//! sphere of radius `R` whose inside is diffuse of albedo `a` (falloff
//! 1/d^2). Every point of the inside gets the same direct light, `E = Il /
//! R^2` at normal incidence, so it shows `a E`; each bounce sees another
//! inside point, showing the same, so one more bounce adds `a` times the
//! last term: with `n` bounces a pixel is `a E (1 + a + ... + a^n)` exactly,
//! whatever directions the random numbers pick. The eye sits at the light,
//! where the Phong lobe of every direct hit is at its peak (R·V = 1): `ks E`
//! more, once, and never again after a bounce.

use glam::DVec3;
use shadelab::scene::{Falloff, Object, Scene, Shape};

pub const RADIUS: f64 = 2.0;
pub const INTENSITY: f64 = 3.0;
pub const ALBEDO: f64 = 0.6;
pub const KS: f64 = 0.25;
/// The material's `ka`, and the scene's ambient intensity: what the
/// Whitted tracer (no bounces) adds, `KA * AMBIENT`.
pub const KA: f64 = 0.5;
pub const AMBIENT: f64 = 0.2;

/// The sphere at 32 x 24 pixels, traced with `bounces` bounces, depth 8.
pub fn closed_sphere(bounces: u32) -> Scene {
    let mut s = super::scene(32, 24, 60.0);
    s.camera.position = DVec3::ZERO;
    s.camera.look_at = DVec3::new(0.3, 0.1, -1.0);
    s.lights[0].position = DVec3::ZERO;
    s.lights[0].intensity = DVec3::splat(INTENSITY);
    s.lighting.falloff = Falloff::InverseSquare;
    // An ambient term that secondary illumination must drop.
    s.lighting.ambient = DVec3::splat(AMBIENT);
    s.materials[0] = super::material(DVec3::ONE, KA, ALBEDO, KS, 20.0);
    s.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::ZERO,
            radius: RADIUS,
            segments: 32,
        },
        material: 0,
    });
    s.render.bounces = bounces;
    s.render.depth = 8;
    s
}

/// Every pixel's value (its expectation, where Russian roulette runs):
/// `a E (1 + a + ... + a^n) + ks E`.
pub fn expected(bounces: u32) -> f64 {
    let e = INTENSITY / (RADIUS * RADIUS);
    let series: f64 = (0..=bounces).map(|k| ALBEDO.powi(k as i32)).sum();
    ALBEDO * e * series + KS * e
}
