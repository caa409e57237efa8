//! One photon's path from a light: where it goes, what it carries, and
//! its splat toward the eye at every surface that is not a mirror or
//! glass (docs/lighting-model.md, "Forward: photons from the lights").

use glam::DVec3;

use super::film::Film;
use crate::cpu::intersect::{Accel, Hit, Ray};
use crate::cpu::raytrace::{
    children, cosine_direction, facing_normal, offset_epsilon, offset_origin,
};
use crate::cpu::surface::hit_tint;
use crate::film_sums::PhotonStats;
use crate::random_streams::Sampler;
use crate::rt_scene::{LightShares, RtScene};
use crate::scene::Material;

/// The scene's lights, picked in proportion to their power
/// (`LightShares`, the GPU's split too).
pub struct LightChoice<'a> {
    pub(crate) scene: &'a RtScene,
    shares: LightShares,
}

impl<'a> LightChoice<'a> {
    /// `None` for a scene with no light that has power.
    pub fn new(scene: &'a RtScene) -> Option<Self> {
        Some(LightChoice {
            scene,
            shares: LightShares::of(scene)?,
        })
    }
}

/// A photon on its way: its ray, the flux it carries, and what the path
/// has met so far.
pub(crate) struct Flight {
    pub ray: Ray,
    /// Without the falloff until the path's first surface that is not a
    /// mirror or glass has been left by a diffuse bounce; with it after.
    flux: DVec3,
    /// The path's length from the light so far, while the falloff waits.
    travelled: f64,
    falloff_applied: bool,
    /// Diffuse surfaces met so far.
    diffuse_vertices: u32,
}

impl Flight {
    /// Counts a surface the photon met: a diffuse one (`albedo`, its `kd C`,
    /// not zero) counts toward the diffuse bounces it may take.
    pub(crate) fn met(&mut self, albedo: DVec3) {
        if albedo != DVec3::ZERO {
            self.diffuse_vertices += 1;
        }
    }

    /// Whether the photon may leave its last surface by a diffuse bounce:
    /// no more diffuse surfaces met than the scene's bounces.
    pub(crate) fn may_bounce(&self, scene: &RtScene) -> bool {
        self.diffuse_vertices <= scene.render.bounces
    }

    /// Photon `i` of `total` leaving a light chosen by power in a uniform
    /// direction, with flux `4 pi Il / (total p)`.
    pub(crate) fn emit(lights: &LightChoice, i: u32, total: u32) -> Self {
        let scene = lights.scene;
        let mut numbers = Sampler::start_photon(i).at_level(0);
        let u0 = numbers.get_1d();
        let [u1, u2] = numbers.get_2d();
        let (j, chance) = lights.shares.pick(u0);
        let light = &scene.lights[j];
        let z = 1.0 - 2.0 * u1;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * std::f64::consts::PI * u2;
        Flight {
            ray: Ray {
                origin: light.position,
                dir: DVec3::new(r * phi.cos(), r * phi.sin(), z),
            },
            flux: 4.0 * std::f64::consts::PI * light.intensity / (f64::from(total) * chance),
            travelled: 0.0,
            falloff_applied: false,
            diffuse_vertices: 0,
        }
    }

    /// The flux arriving at a hit at distance `t` along the ray: with the
    /// falloff of the path's length from the light, `d^2 F(d)`, until a
    /// diffuse bounce has applied it.
    pub(crate) fn arriving(&self, scene: &RtScene, t: f64) -> DVec3 {
        if self.falloff_applied {
            return self.flux;
        }
        let d = self.travelled + t;
        let lighting = &scene.lighting;
        self.flux * d * d * lighting.falloff.attenuate(DVec3::ONE, d, lighting.k)
    }
}

/// Traces photon `i` of `total`: emitted from a light chosen by power in
/// a uniform direction with flux `4 pi Il / (total p)`, splatted at every
/// surface it meets that is not a mirror or glass, and sent on by one
/// event chosen at random in proportion to the surface's `mean(kd C)`,
/// `kr` and `kt` (or absorbed).
pub fn trace_photon(
    accel: &Accel,
    lights: &LightChoice,
    i: u32,
    total: u32,
    film: &mut Film,
    stats: &mut PhotonStats,
) {
    let scene = lights.scene;
    let mut flight = Flight::emit(lights, i, total);
    stats.emitted += 1;
    let mut seen = false;
    for level in 0..=scene.render.depth {
        let Some(hit) = accel.nearest(&flight.ray) else {
            break;
        };
        stats.hits += 1;
        let p = flight.ray.origin + hit.t * flight.ray.dir;
        let material = &scene.materials[hit.material as usize];
        let (tint, _) = hit_tint(scene, &hit, p, flight.ray.dir, 0.0);
        let albedo = material.kd * material.color * tint;
        let arriving = flight.arriving(scene, hit.t);
        let first_surface = flight.diffuse_vertices == 0;
        let shows = albedo != DVec3::ZERO || (first_surface && material.ks > 0.0);
        if shows && hit.normal != DVec3::ZERO {
            let vertex = Vertex {
                hit: &hit,
                p,
                material,
                albedo,
                first_surface,
            };
            seen |= splat(accel, film, &flight.ray, &vertex, arriving, stats);
        }
        flight.met(albedo);
        if level == scene.render.depth || hit.normal == DVec3::ZERO {
            break;
        }
        let numbers = Sampler::start_photon(i).at_level(level + 1).all();
        let surface = (&hit, p, material, albedo);
        let diffuse_allowed = flight.may_bounce(scene);
        if !go_on(&mut flight, surface, arriving, numbers, diffuse_allowed) {
            break;
        }
    }
    stats.seen += u64::from(seen);
}

/// Where a photon met a surface that shows it to the eye.
struct Vertex<'a> {
    hit: &'a Hit,
    p: DVec3,
    material: &'a Material,
    albedo: DVec3,
    /// No diffuse surface before this one on the path: the Phong lobe
    /// counts here.
    first_surface: bool,
}

/// Splats what the eye sees of a photon of flux `arriving` along `ray` at
/// `vertex`: `flux f cos_x / (r^2 cos_c^3 A)` in `pi`-times-radiance units,
/// `f = kd C (N.L / Ng.L) (+ ks S / Ng.L on the first surface)`, where the
/// shadow ray to the eye is clear and the eye sees the side the photon
/// lit. Whether it landed.
fn splat(
    accel: &Accel,
    film: &mut Film,
    ray: &Ray,
    vertex: &Vertex,
    arriving: DVec3,
    stats: &mut PhotonStats,
) -> bool {
    let (hit, p) = (vertex.hit, vertex.p);
    let ng = hit.geometric_normal;
    let distance = p.length();
    let v = -p / distance;
    let l = -ray.dir;
    if ng.dot(v) * ng.dot(l) <= 0.0 {
        return false;
    }
    let n = facing_normal(hit.normal, ng, ray.dir);
    let n_dot_l = n.dot(l);
    if n_dot_l <= 0.0 {
        return false;
    }
    let Some((pixel, cos_c)) = film.pixel_of(p) else {
        return false;
    };
    let o = offset_origin(p, ray.origin, ng, v);
    let to_eye = -o;
    let reach = to_eye.length() - offset_epsilon(DVec3::ZERO, o);
    let shadow = Ray {
        origin: o,
        dir: to_eye / to_eye.length(),
    };
    if accel.any(&shadow, reach) {
        return false;
    }
    let ng_dot_l = ng.dot(l).abs();
    let mut f = vertex.albedo * (n_dot_l / ng_dot_l);
    let m = vertex.material;
    if vertex.first_surface && m.ks > 0.0 {
        let reflected = 2.0 * n_dot_l * n - l;
        let s = if m.p == 0.0 {
            1.0
        } else {
            reflected.dot(v).max(0.0).powf(m.p)
        };
        f += DVec3::splat(m.ks * s / ng_dot_l);
    }
    let cos_x = ng.dot(v).abs();
    let value = arriving * f * cos_x / (distance * distance * cos_c.powi(3) * film.pixel_area());
    film.add_to(pixel, value);
    stats.splats += 1;
    true
}

/// Sends the photon on from its hit by one event picked with `u0` in
/// proportion to `mean(kd C)` (while diffuse bounces are left), `kr` and
/// `kt` (total internal reflection giving `kt` to the reflection), scaled
/// down together where they add to more than 1 (no diffuse event unless
/// `diffuse_allowed`); whether it goes on (not absorbed, nor sent below
/// the surface).
pub(crate) fn go_on(
    flight: &mut Flight,
    (hit, p, material, albedo): (&Hit, DVec3, &Material, DVec3),
    arriving: DVec3,
    [u0, u1, u2, _]: [f64; 4],
    diffuse_allowed: bool,
) -> bool {
    let d = flight.ray.dir;
    let [reflected, refracted] = children(d, hit.normal, material, DVec3::ONE);
    let p_diffuse = if diffuse_allowed && albedo != DVec3::ZERO {
        (albedo.x + albedo.y + albedo.z) / 3.0
    } else {
        0.0
    };
    let p_reflect = reflected.map_or(0.0, |(_, w, _)| w.x);
    let p_refract = refracted.map_or(0.0, |(_, w, _)| w.x);
    let scale = (p_diffuse + p_reflect + p_refract).max(1.0);
    let pick = u0 * scale;
    let ng = hit.geometric_normal;
    let (dir, weight, diffuse) = if pick < p_diffuse {
        let dir = cosine_direction(facing_normal(hit.normal, ng, d), u1, u2);
        (dir, albedo * scale / p_diffuse, true)
    } else if pick < p_diffuse + p_reflect {
        let (dir, _, _) = reflected.expect("a reflection was picked");
        (dir, DVec3::splat(scale), false)
    } else if pick < p_diffuse + p_reflect + p_refract {
        let (dir, _, _) = refracted.expect("a refraction was picked");
        (dir, DVec3::splat(scale), false)
    } else {
        return false;
    };
    if diffuse {
        // Back out on the side the photon came from, or nothing.
        if ng.dot(dir) * ng.dot(d) >= 0.0 {
            return false;
        }
        flight.flux = arriving * weight;
        flight.falloff_applied = true;
    } else {
        flight.flux *= weight;
        if !flight.falloff_applied {
            flight.travelled += (p - flight.ray.origin).length();
        }
    }
    flight.ray = Ray {
        origin: offset_origin(p, flight.ray.origin, ng, dir),
        dir,
    };
    true
}
