//! The ray tree of one pixel's samples: an explicit stack of pending rays
//! in `docs/raytracing.md`'s order, each hit shaded with its shadow rays
//! and its reflected and refracted children pushed, weights and cones
//! carried along; with `render.bounces`, a diffuse bounce too
//! (docs/lighting-model.md, "Secondary illumination").

use glam::DVec3;

use super::bounce::{cosine_direction, roulette, ROULETTE_AFTER};
use super::path_signature::{PathSignature, RayKind};
use super::pixel_samples::pixel_sample;
use super::secondary_rays::{children, facing_normal, offset_epsilon, offset_origin};
use crate::camera::View;
use crate::cpu::intersect::{Accel, Hit, Ray};
use crate::cpu::lighting::{shade_visible, Surface};
use crate::cpu::surface::hit_tint;
use crate::random_streams::{Draw, Sampler};
use crate::rt_scene::{sample_grid, Primitive, RayStats, RtScene};
use crate::scene::{Material, PointLight};

/// The sub-pixel sample positions `(sx, sy)` for `n` samples: the cell
/// centres of a `kx x ky` grid, `kx = ceil(sqrt(n))`, `ky = ceil(n / kx)`,
/// row by row, the first `n` of them.
pub fn sample_offsets(n: u32) -> Vec<(f64, f64)> {
    let (kx, ky) = sample_grid(n);
    (0..n.max(1))
        .map(|i| {
            (
                (f64::from(i % kx) + 0.5) / f64::from(kx),
                (f64::from(i / kx) + 0.5) / f64::from(ky),
            )
        })
        .collect()
}

/// One pixel's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelTrace {
    /// The sum of the sample values over the samples the pixel has: their
    /// mean when all are traced.
    pub color: DVec3,
    /// With bounces, the same sum in the films' fixed point, a term per
    /// sample (`film_sums::to_fixed`), as the GPU sums it (0 without).
    pub sums: [u64; 3],
    /// The object the first sample's primary ray hit.
    pub object: Option<u32>,
    pub signature: u64,
}

/// A ray waiting on the stack.
#[derive(Debug, Clone, Copy)]
struct Pending {
    ray: Ray,
    /// RGB: a diffuse bounce multiplies it by a colour.
    weight: DVec3,
    depth: u32,
    /// Diffuse bounces on the path so far.
    bounces: u32,
    kind: RayKind,
    /// The ray's cone (texture level of detail): its width at the origin
    /// and how fast it widens per unit of distance.
    cone_width: f64,
    cone_spread: f64,
}

/// Traces rays through one scene.
pub struct Tracer<'a> {
    accel: Accel<'a>,
    view: View,
    offsets: Vec<(f64, f64)>,
    /// A primary ray's cone spread (`level_of_detail::pixel_spread`).
    pixel_spread: f64,
    /// The scene's materials without their Phong lobe, as a path sees them
    /// after a diffuse bounce (empty without bounces).
    diffuse_materials: Vec<Material>,
}

impl<'a> Tracer<'a> {
    /// `view` places the primary rays; its eye is the origin of `scene`'s
    /// camera-relative coordinates.
    pub fn new(scene: &'a RtScene, view: View) -> Self {
        Tracer {
            accel: Accel::new(scene),
            pixel_spread: crate::level_of_detail::pixel_spread(&view),
            view,
            offsets: sample_offsets(scene.render.samples),
            diffuse_materials: if scene.render.bounces > 0 {
                let diffuse = |m: &Material| Material {
                    ks: 0.0,
                    ..m.clone()
                };
                scene.materials.iter().map(diffuse).collect()
            } else {
                Vec::new()
            },
        }
    }

    /// The primary ray through image point `(x, y)` in pixels.
    pub fn primary_ray(&self, x: f64, y: f64) -> Ray {
        Ray {
            origin: DVec3::ZERO,
            dir: self.view.ray_direction(x, y),
        }
    }

    /// Pixel `(x, y)`: every sample traced, their mean, and the signature.
    pub fn pixel(&self, x: u32, y: u32, stats: &mut RayStats) -> PixelTrace {
        self.pixel_part(x, y, 0..self.offsets.len() as u32, stats)
    }

    /// Pixel `(x, y)`'s samples `samples` (of those it has: a shard's
    /// range), their values summed over all it has, and the signature.
    pub fn pixel_part(
        &self,
        x: u32,
        y: u32,
        samples: std::ops::Range<u32>,
        stats: &mut RayStats,
    ) -> PixelTrace {
        let mut signature = PathSignature::default();
        let mut sum = DVec3::ZERO;
        let mut sums = [0u64; 3];
        let mut object = None;
        let pixel = y.wrapping_mul(self.view.width).wrapping_add(x);
        let per_sample = 1.0 / self.offsets.len() as f64;
        let with_bounces = !self.diffuse_materials.is_empty();
        let first = samples.start;
        for i in samples {
            // Paths take the progressive sequence, so that any prefix of
            // the samples is an honest image; Whitted keeps its grid.
            let (sx, sy) = if with_bounces {
                pixel_sample(pixel, i)
            } else {
                self.offsets[i as usize]
            };
            let ray = self.primary_ray(f64::from(x) + sx, f64::from(y) + sy);
            stats.primary += 1;
            let (value, hit) = self.trace(ray, (pixel, i), stats, &mut signature);
            if i == first {
                object = hit;
            }
            // Only paths with bounces sum into a film; a Whitted pixel
            // keeps its f64 mean alone.
            if with_bounces {
                let term = value * per_sample;
                for (sum, v) in sums.iter_mut().zip(term.to_array()) {
                    *sum = sum.wrapping_add(crate::film_sums::to_fixed(v));
                }
            }
            sum += value;
        }
        PixelTrace {
            color: sum / self.offsets.len() as f64,
            sums,
            object,
            signature: signature.0,
        }
    }

    /// The value of the ray tree rooted at `ray` (weight 1, depth 0), and
    /// the object the root ray hit. Counts every ray but the root. `key`
    /// (the pixel's index `y * width + x`, the sample's) starts the
    /// sampler its diffuse bounces draw from.
    pub fn trace(
        &self,
        ray: Ray,
        key: (u32, u32),
        stats: &mut RayStats,
        signature: &mut PathSignature,
    ) -> (DVec3, Option<u32>) {
        let scene = self.accel.scene;
        let settings = scene.render;
        let sampler = Sampler::start_pixel_sample(key.0, key.1);
        let mut stack = Vec::with_capacity(settings.depth as usize + 1);
        stack.push(Pending {
            ray,
            weight: DVec3::ONE,
            depth: 0,
            bounces: 0,
            kind: RayKind::Primary,
            cone_width: 0.0,
            cone_spread: self.pixel_spread,
        });
        let mut sum = DVec3::ZERO;
        let mut root_object = None;
        while let Some(pending) = stack.pop() {
            stats.max_depth_reached = stats.max_depth_reached.max(pending.depth);
            let hit = self.accel.nearest(&pending.ray);
            signature.ray(pending.kind, pending.depth, hit.as_ref());
            let Some(hit) = hit else {
                // The background lights nothing: only eye rays see it.
                if pending.bounces == 0 {
                    sum += pending.weight * scene.background;
                }
                continue;
            };
            if pending.kind == RayKind::Primary {
                root_object = Some(hit.object);
            }
            let p = pending.ray.origin + hit.t * pending.ray.dir;
            let cone_width = pending.cone_width + pending.cone_spread * hit.t;
            let (local, albedo) = self.shade_hit(&pending, &hit, (p, cone_width), stats, signature);
            sum += pending.weight * local;
            // No children at the depth limit, nor from a zero normal: there
            // is no direction to reflect or refract about.
            if pending.depth >= settings.depth || hit.normal == DVec3::ZERO {
                continue;
            }
            // Pushed first, so traced after the mirror and glass children.
            if pending.bounces < settings.bounces && albedo != DVec3::ZERO {
                let geometry = (p, hit.normal, hit.geometric_normal);
                let numbers = sampler.at_level(pending.depth);
                if let Some(child) =
                    self.bounce(&pending, geometry, (albedo, cone_width), numbers, stats)
                {
                    stack.push(child);
                }
            }
            self.push_children(&pending, &hit, (p, cone_width), stats, &mut stack);
        }
        (sum, root_object)
    }

    /// The local model at `hit` (point `p`, reached by a cone
    /// `cone_width` wide) of `pending`'s ray, asking a shadow ray of each
    /// light it needs whether the light is visible (with shadows on); and
    /// the surface's diffuse albedo `kd C`. After a diffuse bounce the
    /// Phong lobe counts no more (docs/lighting-model.md, "Secondary
    /// illumination").
    fn shade_hit(
        &self,
        pending: &Pending,
        hit: &Hit,
        (p, cone_width): (DVec3, f64),
        stats: &mut RayStats,
        signature: &mut PathSignature,
    ) -> (DVec3, DVec3) {
        let scene = self.accel.scene;
        let Ray { origin, dir: d } = pending.ray;
        let materials = if pending.bounces > 0 {
            &self.diffuse_materials
        } else {
            &scene.materials
        };
        let material = &materials[hit.material as usize];
        let (tint, cell) = hit_tint(scene, hit, p, d, cone_width);
        if let Some(cell) = cell {
            signature.cell(cell);
        }
        let surface = Surface { material, tint };
        let albedo = material.kd * surface.color();
        let local = shade_visible(
            &scene.lighting,
            &scene.lights,
            surface,
            // Camera-relative: the eye is the origin.
            (p, DVec3::ZERO),
            facing_normal(hit.normal, hit.geometric_normal, d),
            -d,
            |j, light| {
                let visible = !scene.render.shadows || {
                    stats.shadow += 1;
                    self.light_visible(p, origin, hit.geometric_normal, light)
                };
                signature.light(j, visible);
                visible
            },
        );
        (local, albedo)
    }

    /// The diffuse bounce of `pending`'s hit at `p` (normals `n`, `ng`;
    /// albedo `albedo`; a cone `cone_width` wide), drawn with `numbers`
    /// (its direction's two, then its roulette's):
    /// `None` where Russian roulette ends the path or the direction leaves
    /// below the surface's geometric side.
    fn bounce(
        &self,
        pending: &Pending,
        (p, n, ng): (DVec3, DVec3, DVec3),
        (albedo, cone_width): (DVec3, f64),
        mut numbers: Draw,
        stats: &mut RayStats,
    ) -> Option<Pending> {
        let [u0, u1] = numbers.get_2d();
        let u2 = numbers.get_1d();
        let mut weight = pending.weight * albedo;
        if pending.bounces >= ROULETTE_AFTER {
            let Some(kept) = roulette(weight, u2) else {
                stats.pruned += 1;
                return None;
            };
            weight = kept;
        }
        let d = pending.ray.dir;
        let dir = cosine_direction(facing_normal(n, ng, d), u0, u1);
        // Back out on the side the ray came from, or nothing: an
        // interpolated normal may tilt the hemisphere through the surface.
        if ng.dot(dir) * ng.dot(d) >= 0.0 {
            return None;
        }
        stats.reflected += 1;
        Some(Pending {
            ray: Ray {
                origin: offset_origin(p, pending.ray.origin, ng, dir),
                dir,
            },
            weight,
            depth: pending.depth + 1,
            bounces: pending.bounces + 1,
            kind: RayKind::Diffuse,
            // As a refracted ray's: as wide as the parent's at the hit.
            cone_width,
            cone_spread: pending.cone_spread,
        })
    }

    /// Whether nothing blocks the shadow ray from `p` (found by a ray from
    /// `origin`, geometric normal `ng`) to `light`.
    fn light_visible(&self, p: DVec3, origin: DVec3, ng: DVec3, light: &PointLight) -> bool {
        let o = offset_origin(p, origin, ng, light.position - p);
        let to_light = light.position - o;
        let distance = to_light.length();
        let shadow = Ray {
            origin: o,
            dir: to_light / distance,
        };
        // Stop short of the light by the offset epsilon at
        // the light, as the ray starts off the surface: a
        // light on a surface would otherwise be hidden by
        // that surface at random (assets/hard/grazing-light.toml).
        let reach = distance - offset_epsilon(light.position, o);
        !self.accel.any(&shadow, reach)
    }

    /// The reflected and refracted children of `pending`'s `hit` at `p`,
    /// pushed with their weights, depths and cones (the refracted one last,
    /// so traced first); those under the cut-off counted as pruned.
    fn push_children(
        &self,
        pending: &Pending,
        hit: &Hit,
        (p, cone_width): (DVec3, f64),
        stats: &mut RayStats,
        stack: &mut Vec<Pending>,
    ) {
        let scene = self.accel.scene;
        let Ray { origin, dir: d } = pending.ray;
        let (n, ng) = (hit.normal, hit.geometric_normal);
        let material = &scene.materials[hit.material as usize];
        for (dir, weight, kind) in children(d, n, material, pending.weight)
            .into_iter()
            .flatten()
        {
            if weight.max_element() < scene.render.cutoff {
                stats.pruned += 1;
                continue;
            }
            match kind {
                RayKind::Refracted => stats.refracted += 1,
                _ => stats.reflected += 1,
            }
            // A mirror sphere of radius r spreads a cone by 2 w / r
            // more (its curvature); planes, boxes and triangles are
            // flat, and refraction keeps the spread.
            let curvature = match (kind, hit.primitive) {
                (RayKind::Reflected, Primitive::Sphere(_) | Primitive::HugeSphere(_)) => {
                    2.0 * cone_width / scene.sphere_radius(hit.primitive)
                }
                _ => 0.0,
            };
            stack.push(Pending {
                ray: Ray {
                    origin: offset_origin(p, origin, ng, dir),
                    dir,
                },
                weight,
                depth: pending.depth + 1,
                bounces: pending.bounces,
                kind,
                cone_width,
                cone_spread: pending.cone_spread + curvature,
            });
        }
    }
}
