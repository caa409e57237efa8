//! Stochastic progressive photon mapping of the caustic photons, in f64
//! (docs/lighting-model.md, "Caustics"). Each pass, every pixel's eye path
//! (a point in the pixel, then through mirrors and glass by one event
//! picked in proportion to `kr` and `kt`) stops at its first surface with
//! `kd C` not zero: the pixel's visible point, with the path's weight
//! times `kd C`. The pass's caustic photons within the pixel's radius of
//! it, on the side it faces, add their flux times that weight; then the
//! radius shrinks by SPPM's rule, keeping `alpha` of the new photons:
//! `n' = n + alpha m`, `r' = r sqrt(n' / (n + m))`, and the flux so far
//! is scaled by `(r' / r)^2`. The image is the flux over
//! `passes pi r^2`: `kd C` times the irradiance the photons' density
//! gives, in the image's units.

use std::collections::HashMap;

use glam::DVec3;
use rayon::prelude::*;

use super::photons::{trace_caustic_photons, CausticPhoton};
use crate::camera::View;
use crate::cpu::forward::LightChoice;
use crate::cpu::intersect::{Accel, Ray};
use crate::cpu::raytrace::{children, facing_normal, offset_origin};
use crate::cpu::surface::hit_tint;
use crate::linear_image::LinearImage;
use crate::random_streams::Sampler;
use crate::rt_scene::RtScene;
use crate::scene::{CausticSettings, Scene};

/// A pixel's eye path where it stops on a diffuse surface.
#[derive(Debug, Clone, Copy)]
struct VisiblePoint {
    position: DVec3,
    normal: DVec3,
    /// The path's mirror and glass weights times the surface's `kd C`.
    weight: DVec3,
    /// The path's length from the eye.
    length: f64,
}

/// What a pixel has gathered so far.
#[derive(Debug, Clone, Copy)]
struct PixelState {
    /// 0 until its eye path first finds a diffuse surface.
    radius: f64,
    /// Photons kept by the radius rule (fractional).
    count: f64,
    /// Flux times weight, scaled with the radius.
    flux: DVec3,
}

/// The caustic image of `scene` at its image size, `settings.passes`
/// passes of `settings.photons_per_pass` photons. `None` for a scene with
/// no light that has power, or more photons than have numbers (2^32).
pub fn render_caustics(scene: &Scene, settings: &CausticSettings) -> Option<LinearImage> {
    let (width, height) = (scene.image.width, scene.image.height);
    settings.total_photons()?;
    let rt = RtScene::new(scene);
    let lights = LightChoice::new(&rt)?;
    // Built once for every pass, the photons' and the eye's.
    let accel = Accel::new(&rt);
    let view = View::new(scene, width, height);
    let per_pass = settings.photons_per_pass;
    let pixel_angle = 2.0 / (view.focal * f64::from(height));
    let fresh = PixelState {
        radius: 0.0,
        count: 0.0,
        flux: DVec3::ZERO,
    };
    let mut states = vec![fresh; width as usize * height as usize];
    for pass in 0..settings.passes {
        let first = pass * per_pass;
        let photons = trace_caustic_photons(&accel, &lights, first..first + per_pass, per_pass);
        let points: Vec<Option<VisiblePoint>> = (0..states.len() as u32)
            .into_par_iter()
            .map(|pixel| visible_point(&rt, &accel, &view, (pixel, pass)))
            .collect();
        for (state, point) in states.iter_mut().zip(&points) {
            if let (Some(point), true) = (point, state.radius == 0.0) {
                state.radius = settings.initial_radius * point.length * pixel_angle;
            }
        }
        let widest = states.iter().map(|s| s.radius).fold(0.0, f64::max);
        let grid = PhotonGrid::new(&photons, widest);
        states
            .par_iter_mut()
            .zip(points.par_iter())
            .for_each(|(state, point)| {
                let Some(point) = point else {
                    return;
                };
                let (found, flux) = grid.gather(point, state.radius);
                if found > 0 {
                    let count = state.count + settings.alpha * f64::from(found);
                    let shrink = count / (state.count + f64::from(found));
                    state.flux = (state.flux + flux) * shrink;
                    state.radius *= shrink.sqrt();
                    state.count = count;
                }
            });
    }
    let passes = f64::from(settings.passes.max(1));
    let pixels = states
        .iter()
        .map(|s| {
            if s.count == 0.0 {
                return [0.0; 3];
            }
            let area = std::f64::consts::PI * s.radius * s.radius * passes;
            (s.flux / area).as_vec3().to_array()
        })
        .collect();
    Some(LinearImage {
        width,
        height,
        pixels,
    })
}

/// The visible point of `pixel` (`y * width + x`) in `pass`: its eye ray
/// through a point of the pixel drawn at level 0 of its eye path's numbers
/// (`Sampler::start_eye_path`), then one event at each surface drawn at its level
/// (docs/lighting-model.md, "Caustics": stop on the surface's `kd C`, or go
/// on by `kr` or `kt`), to the surface it stops on. `None` where the path
/// leaves the scene, is absorbed, or runs past `depth`.
fn visible_point(
    rt: &RtScene,
    accel: &Accel,
    view: &View,
    (pixel, pass): (u32, u32),
) -> Option<VisiblePoint> {
    let eye = Sampler::start_eye_path(pixel, pass);
    let [u0, u1] = eye.at_level(0).get_2d();
    let (x, y) = (pixel % view.width, pixel / view.width);
    let mut ray = Ray {
        origin: DVec3::ZERO,
        dir: view.ray_direction(f64::from(x) + u0, f64::from(y) + u1),
    };
    let (mut weight, mut length) = (DVec3::ONE, 0.0);
    for level in 0..=rt.render.depth {
        let hit = accel.nearest(&ray)?;
        if hit.normal == DVec3::ZERO {
            return None;
        }
        let p = ray.origin + hit.t * ray.dir;
        length += hit.t;
        let material = &rt.materials[hit.material as usize];
        let (tint, _) = hit_tint(rt, &hit, p, ray.dir, 0.0);
        let albedo = material.kd * material.color * tint;
        let ng = hit.geometric_normal;
        let [reflected, refracted] = children(ray.dir, hit.normal, material, DVec3::ONE);
        let p_reflect = reflected.map_or(0.0, |(_, w, _)| w.x);
        let p_refract = refracted.map_or(0.0, |(_, w, _)| w.x);
        // Where the surface also reflects or transmits, half the paths
        // stop on it and half go on, each weighted up by two.
        let p_stop = match (albedo != DVec3::ZERO, p_reflect + p_refract > 0.0) {
            (false, _) => 0.0,
            (true, false) => 1.0,
            (true, true) => 0.5,
        };
        let u = eye.at_level(level + 1).get_1d();
        if u < p_stop {
            return Some(VisiblePoint {
                position: p,
                normal: facing_normal(hit.normal, ng, ray.dir),
                weight: weight * albedo / p_stop,
                length,
            });
        }
        let scale = (p_reflect + p_refract).max(1.0);
        let pick = (u - p_stop) / (1.0 - p_stop) * scale;
        let dir = if pick < p_reflect {
            reflected?.0
        } else if pick < p_reflect + p_refract {
            refracted?.0
        } else {
            return None;
        };
        weight *= scale / (1.0 - p_stop);
        ray = Ray {
            origin: offset_origin(p, ray.origin, ng, dir),
            dir,
        };
    }
    None
}

/// A pass's photons by cell of a grid as wide as the widest radius, so
/// that a pixel's photons are in the 27 cells around its visible point.
struct PhotonGrid<'a> {
    photons: &'a [CausticPhoton],
    cell: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
}

impl<'a> PhotonGrid<'a> {
    fn new(photons: &'a [CausticPhoton], cell: f64) -> Self {
        let cell = cell.max(f64::MIN_POSITIVE);
        let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (i, photon) in photons.iter().enumerate() {
            let key = Self::key(photon.position, cell);
            cells.entry(key).or_default().push(i as u32);
        }
        PhotonGrid {
            photons,
            cell,
            cells,
        }
    }

    fn key(p: DVec3, cell: f64) -> [i64; 3] {
        (p / cell).floor().as_i64vec3().to_array()
    }

    /// The photons within `radius` of `point` that lit the side it faces:
    /// how many, and their flux times its weight, added in cell order then
    /// photon order (the same sum at any thread count).
    fn gather(&self, point: &VisiblePoint, radius: f64) -> (u32, DVec3) {
        let centre = Self::key(point.position, self.cell);
        let (mut found, mut flux) = (0u32, DVec3::ZERO);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let key = [centre[0] + dx, centre[1] + dy, centre[2] + dz];
                    for &i in self.cells.get(&key).map_or(&[][..], Vec::as_slice) {
                        let photon = &self.photons[i as usize];
                        let near =
                            photon.position.distance_squared(point.position) < radius * radius;
                        if near && photon.normal.dot(point.normal) > 0.0 {
                            found += 1;
                            flux += photon.flux * point.weight;
                        }
                    }
                }
            }
        }
        (found, flux)
    }
}
