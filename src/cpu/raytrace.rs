//! The CPU twin of the compute-shader ray tracer: backward (Whitted) ray
//! tracing in `f64`, following `docs/raytracing.md` step for step (sample
//! grid, explicit ray stack and its order, weights, cut-off, offsets,
//! counting), so that the two images can be compared pixel by pixel.
//!
//! Geometry is `cpu::intersect`, the formula `cpu::lighting`; this file owns
//! the ray tree, the per-pixel path signature and the parallel loop. It
//! shares nothing with the shaders but the scene (`rt_scene`) and the camera.

use glam::DVec3;
use rayon::prelude::*;

use super::intersect::{Accel, Hit, Ray};
use super::lighting::{shade_visible, Surface};
use super::surface::hit_tint;
use crate::camera::View;
use crate::linear_image::LinearImage;
use crate::rt_scene::{sample_grid, Primitive, RayStats, RtScene};
use crate::scene::Scene;
use crate::work_counter::WorkCounter;

/// The ray-traced image and, per pixel, what its rays saw.
pub struct RayTraced {
    pub image: LinearImage,
    pub stats: RayStats,
    /// `scene.objects` index hit by the pixel's first sample (`None`:
    /// background).
    pub primary_object_ids: Vec<Option<u32>>,
    /// Per pixel, the hash of everything discrete along its ray trees
    /// (`PathSignature`): neighbours with the same signature see the same
    /// surfaces and shadows.
    pub path_signatures: Vec<u64>,
    /// Wall time of the tracing alone, after the scene and its BVH are
    /// built (what the GPU's dispatch time compares with).
    pub trace_ms: f64,
}

/// What one ray is in the tree.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum RayKind {
    Primary = 0,
    Reflected = 1,
    Refracted = 2,
}

/// FNV-1a 64 over the discrete events of a pixel's ray trees, in the order
/// they happen (`docs/raytracing.md`, "Path signature"):
///
/// - every traced ray: its kind (1 byte: 0 primary, 1 reflected,
///   2 refracted), its depth (u32), the object hit (u32, `u32::MAX` on a
///   miss) and the part of it (u32: a box's face `2 axis + (0 for -, 1 for
///   +)`, else 0; `u32::MAX` on a miss); integers little-endian;
/// - after a hit's ray record, for every light the shading asks about
///   (`lighting::facing`, light not at the point), in light order: the byte 3, the
///   light index (u32) and 1 if it is visible (always, with shadows off) or
///   2 if its shadow ray is blocked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PathSignature(pub u64);

impl Default for PathSignature {
    fn default() -> Self {
        PathSignature(0xcbf2_9ce4_8422_2325)
    }
}

impl PathSignature {
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    fn ray(&mut self, kind: RayKind, depth: u32, hit: Option<&Hit>) {
        let (object, part) = match hit {
            None => (u32::MAX, u32::MAX),
            Some(h) => (
                h.object,
                match h.primitive {
                    Primitive::Box { face, .. } => face,
                    _ => 0,
                },
            ),
        };
        self.bytes(&[kind as u8]);
        self.bytes(&depth.to_le_bytes());
        self.bytes(&object.to_le_bytes());
        self.bytes(&part.to_le_bytes());
    }

    /// The pattern cell a hit lies in: a pattern's colour changes between
    /// cells as a surface's does at its edge.
    fn cell(&mut self, cell: i64) {
        self.bytes(&[4]);
        self.bytes(&cell.to_le_bytes());
    }

    fn light(&mut self, index: usize, visible: bool) {
        self.bytes(&[3]);
        self.bytes(&(index as u32).to_le_bytes());
        self.bytes(&[if visible { 1 } else { 2 }]);
    }
}

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

/// `eps = 1e-4 * max(|p|_max, |o|_max)`: the offset of a secondary ray's
/// origin from `p`, found by a ray from `o`. The hit's rounding grows with
/// both (`p = o + t d`, and each test subtracts `o`), and with nothing
/// else: a scene a millionth of a unit across gets offsets a millionth as
/// large (`assets/hard/mesh-scale-1e-6.toml`).
pub fn offset_epsilon(p: DVec3, o: DVec3) -> f64 {
    1e-4 * p.abs().max_element().max(o.abs().max_element())
}

/// The normal the local model lights a hit with: the side the ray arrives
/// on. Seen from behind its geometric normal (`Ng·d > 0`: the inside of a
/// sphere or a box, the underside of a plane, the back of a triangle) a
/// surface is lit as its back, with the shading normal negated
/// (`docs/lighting-model.md`, "Which side is lit"). Reflection and
/// refraction keep the outward normal, which says whether a ray enters.
pub fn facing_normal(normal: DVec3, geometric_normal: DVec3, d: DVec3) -> DVec3 {
    if geometric_normal.dot(d) > 0.0 {
        -normal
    } else {
        normal
    }
}

/// The origin of a secondary ray leaving `p` (found by a ray from `o`) in
/// direction `dir`: pushed by `eps` along the geometric normal to the side
/// `dir` goes (`Ng·dir = 0` counts as the front side).
pub fn offset_origin(p: DVec3, o: DVec3, geometric_normal: DVec3, dir: DVec3) -> DVec3 {
    let s = if geometric_normal.dot(dir) < 0.0 {
        -1.0
    } else {
        1.0
    };
    p + s * offset_epsilon(p, o) * geometric_normal
}

/// One pixel's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelTrace {
    /// The mean of the sample values.
    pub color: DVec3,
    /// The object the first sample's primary ray hit.
    pub object: Option<u32>,
    pub signature: u64,
}

/// A ray waiting on the stack.
#[derive(Debug, Clone, Copy)]
struct Pending {
    ray: Ray,
    weight: f64,
    depth: u32,
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
        let mut signature = PathSignature::default();
        let mut sum = DVec3::ZERO;
        let mut object = None;
        for (i, &(sx, sy)) in self.offsets.iter().enumerate() {
            let ray = self.primary_ray(f64::from(x) + sx, f64::from(y) + sy);
            stats.primary += 1;
            let (value, hit) = self.trace(ray, stats, &mut signature);
            if i == 0 {
                object = hit;
            }
            sum += value;
        }
        PixelTrace {
            color: sum / self.offsets.len() as f64,
            object,
            signature: signature.0,
        }
    }

    /// The value of the ray tree rooted at `ray` (weight 1, depth 0), and
    /// the object the root ray hit. Counts every ray but the root.
    pub fn trace(
        &self,
        ray: Ray,
        stats: &mut RayStats,
        signature: &mut PathSignature,
    ) -> (DVec3, Option<u32>) {
        let scene = self.accel.scene;
        let settings = scene.render;
        let mut stack = Vec::with_capacity(settings.depth as usize + 1);
        stack.push(Pending {
            ray,
            weight: 1.0,
            depth: 0,
            kind: RayKind::Primary,
            cone_width: 0.0,
            cone_spread: self.pixel_spread,
        });
        let mut sum = DVec3::ZERO;
        let mut root_object = None;
        while let Some(pending) = stack.pop() {
            stats.max_depth_reached = stats.max_depth_reached.max(pending.depth);
            let Ray { origin, dir: d } = pending.ray;
            let hit = self.accel.nearest(&pending.ray);
            signature.ray(pending.kind, pending.depth, hit.as_ref());
            let Some(hit) = hit else {
                sum += pending.weight * scene.background;
                continue;
            };
            if pending.kind == RayKind::Primary {
                root_object = Some(hit.object);
            }
            let p = origin + hit.t * d;
            let (n, ng) = (hit.normal, hit.geometric_normal);
            let material = &scene.materials[hit.material as usize];
            let cone_width = pending.cone_width + pending.cone_spread * hit.t;
            let (tint, cell) = hit_tint(scene, &hit, p, d, cone_width);
            if let Some(cell) = cell {
                signature.cell(cell);
            }
            let surface = Surface { material, tint };
            let local = shade_visible(
                &scene.lighting,
                &scene.lights,
                surface,
                // Camera-relative: the eye is the origin.
                (p, DVec3::ZERO),
                facing_normal(n, ng, d),
                -d,
                |j, light| {
                    let visible = !settings.shadows || {
                        stats.shadow += 1;
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
                    };
                    signature.light(j, visible);
                    visible
                },
            );
            sum += pending.weight * local;
            // No children at the depth limit, nor from a zero normal: there
            // is no direction to reflect or refract about.
            if pending.depth >= settings.depth || n == DVec3::ZERO {
                continue;
            }
            // The children: reflected, then refracted (so the refracted one
            // is traced first).
            let (kr, kt) = (material.kr, material.kt);
            let mut reflected_weight = (kr > 0.0).then_some(pending.weight * kr);
            let mut refracted = None;
            if kt > 0.0 {
                let (normal, eta) = if n.dot(d) < 0.0 {
                    (n, 1.0 / material.ior)
                } else {
                    (-n, material.ior)
                };
                let cos_i = -normal.dot(d);
                // sin²(i) from the direction's part along the surface, not as
                // 1 - cos²(i), which near normal incidence is a rounding
                // error that an index of 1e3 multiplies by 1e6
                // (assets/hard/glass-ior-1e3.toml).
                let along = d + cos_i * normal;
                let k = 1.0 - eta * eta * along.length_squared();
                if k < 0.0 {
                    reflected_weight = Some(pending.weight * (kr + kt));
                } else {
                    let dir = (eta * along - k.sqrt() * normal).normalize();
                    refracted = Some((dir, pending.weight * kt));
                }
            }
            let children = [
                reflected_weight.map(|w| (d - 2.0 * d.dot(n) * n, w, RayKind::Reflected)),
                refracted.map(|(dir, w)| (dir, w, RayKind::Refracted)),
            ];
            for (dir, weight, kind) in children.into_iter().flatten() {
                if weight < settings.cutoff {
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
                    kind,
                    cone_width,
                    cone_spread: pending.cone_spread + curvature,
                });
            }
        }
        (sum, root_object)
    }
}

fn add_stats(a: RayStats, b: RayStats) -> RayStats {
    RayStats {
        primary: a.primary + b.primary,
        shadow: a.shadow + b.shadow,
        reflected: a.reflected + b.reflected,
        refracted: a.refracted + b.refracted,
        pruned: a.pruned + b.pruned,
        max_depth_reached: a.max_depth_reached.max(b.max_depth_reached),
    }
}

/// Ray traces `scene` at its image size with its `[render]` settings.
pub fn render(scene: &Scene) -> RayTraced {
    render_counted(scene, &WorkCounter::default())
}

/// [`render`], counting its rows into `counter` as they finish.
pub fn render_counted(scene: &Scene, counter: &WorkCounter) -> RayTraced {
    let (width, height) = (scene.image.width, scene.image.height);
    let rt = RtScene::new(scene);
    let tracer = Tracer::new(&rt, View::new(scene, width, height));
    let started = std::time::Instant::now();
    counter.begin("rows", u64::from(height));
    let rows: Vec<(Vec<PixelTrace>, RayStats)> = (0..height)
        .into_par_iter()
        .map(|y| {
            let mut stats = RayStats::default();
            let row = (0..width).map(|x| tracer.pixel(x, y, &mut stats)).collect();
            counter.add(1);
            (row, stats)
        })
        .collect();
    let trace_ms = started.elapsed().as_secs_f64() * 1e3;
    let count = width as usize * height as usize;
    let mut out = RayTraced {
        image: LinearImage {
            width,
            height,
            pixels: Vec::with_capacity(count),
        },
        stats: RayStats::default(),
        primary_object_ids: Vec::with_capacity(count),
        path_signatures: Vec::with_capacity(count),
        trace_ms,
    };
    for (row, stats) in rows {
        out.stats = add_stats(out.stats, stats);
        for px in row {
            out.image.pixels.push(px.color.as_vec3().to_array());
            out.primary_object_ids.push(px.object);
            out.path_signatures.push(px.signature);
        }
    }
    out
}
