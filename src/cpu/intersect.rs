//! Ray intersection for the CPU ray tracer, in `f64`: exact spheres, finite
//! planes, oriented boxes and mesh triangles (through the BVH of
//! `rt_scene::RtScene`), following `docs/raytracing.md` ("Nearest hit")
//! formula for formula, so that the compute shader can do the same in `f32`.
//!
//! It owns only geometry: no shading, no ray tree (that is `raytrace.rs`).

use std::ops::ControlFlow;

use glam::{DVec2, DVec3};

use crate::rt_scene::{widened_box, RtBox, RtHugeSphere, RtPlane, RtScene, RtSphere, RtTriangle};

/// A ray `origin + t dir`, `dir` a unit vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: DVec3,
    pub dir: DVec3,
}

/// Which primitive a hit is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Primitive {
    Sphere(u32),
    /// An index into `RtScene::huge_spheres`.
    HugeSphere(u32),
    Plane(u32),
    /// The box's index, and the face: `2 * axis + (0 for -, 1 for +)`.
    Box {
        index: u32,
        face: u32,
    },
    Triangle(u32),
}

/// The nearest hit of a ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub t: f64,
    /// `scene.objects` index.
    pub object: u32,
    pub material: u32,
    pub primitive: Primitive,
    /// The shading normal: unit, not flipped toward the ray; zero where a
    /// mesh's vertex normals interpolate to nothing.
    pub normal: DVec3,
    /// The geometric normal, used only to offset secondary rays (the shading
    /// normal for spheres, planes and boxes).
    pub geometric_normal: DVec3,
    /// The hit's barycentrics `(u, v)` on a triangle (weights of its second
    /// and third corners), zero elsewhere: what its vertex colours and
    /// texture coordinates are interpolated with.
    pub barycentrics: DVec2,
}

/// `sign(x)` with `sign(0) = 1`, as the spec writes it.
fn sign(x: f64) -> f64 {
    if x < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// Ray Tracing Gems ch. 7, the stable form: the smaller positive root.
pub fn sphere(ray: &Ray, s: &RtSphere) -> Option<f64> {
    let f = ray.origin - s.center;
    let b = -f.dot(ray.dir);
    let l = f + b * ray.dir;
    let r2 = s.radius * s.radius;
    let disc = r2 - l.dot(l);
    if disc < 0.0 {
        return None;
    }
    let q = b + sign(b) * disc.sqrt();
    nearer_positive((f.dot(f) - r2) / q, q)
}

/// The anchored form (`crate::huge_sphere`), for a sphere large where the
/// rays are: with `g = o - anchor`, `cr = g·(g/r + 2n)` is `c / r` with
/// its `r²` terms cancelled in the algebra, `b = -(g·d)/r - n·d` is the
/// plain form's `b / r`, and the roots are `t0 = cr / q` and `t1 = q r`
/// for `q = b + sign(b) sqrt(b² - cr/r)`.
pub fn huge_sphere(ray: &Ray, s: &RtHugeSphere) -> Option<f64> {
    let (anchor, n, r) = (s.anchor.point, s.anchor.normal, s.sphere.radius);
    let inv_r = 1.0 / r;
    let g = ray.origin - anchor;
    let cr = g.dot(g * inv_r + 2.0 * n);
    let b = -g.dot(ray.dir) * inv_r - n.dot(ray.dir);
    let disc = b * b - cr * inv_r;
    if disc < 0.0 {
        return None;
    }
    let q = b + sign(b) * disc.sqrt();
    nearer_positive(cr / q, q * r)
}

/// The smaller positive of two roots. NaN (q = 0: a ray grazing from its
/// own tangent point) fails both.
fn nearer_positive(t0: f64, t1: f64) -> Option<f64> {
    let (lo, hi) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
    if lo > 0.0 {
        Some(lo)
    } else if hi > 0.0 {
        Some(hi)
    } else {
        None
    }
}

/// A finite square; the edges themselves count (`<= half_size`).
pub fn plane(ray: &Ray, pl: &RtPlane) -> Option<f64> {
    let denom = ray.dir.dot(pl.normal);
    if denom == 0.0 {
        return None;
    }
    let t = (pl.center - ray.origin).dot(pl.normal) / denom;
    if t <= 0.0 {
        return None;
    }
    let rel = ray.origin + t * ray.dir - pl.center;
    (rel.dot(pl.u).abs() <= pl.half_size && rel.dot(pl.v).abs() <= pl.half_size).then_some(t)
}

/// The slab test in box-local coordinates: `(t, world face normal, face)`.
/// The entering `t` if positive, else the exiting one (a ray from inside).
/// A slab parallel to the ray constrains nothing when the origin lies within
/// it (boundary included) and misses otherwise. On equal `t` the slab of
/// the lower axis gives the normal (X, then Y, then Z).
pub fn cuboid(ray: &Ray, b: &RtBox) -> Option<(f64, DVec3, u32)> {
    let rt = b.rotation.transpose();
    let o = rt * (ray.origin - b.center);
    let d = rt * ray.dir;
    let (mut t_enter, mut enter_axis) = (f64::NEG_INFINITY, usize::MAX);
    let (mut t_exit, mut exit_axis) = (f64::INFINITY, usize::MAX);
    for axis in 0..3 {
        let h = b.half_extents[axis];
        if d[axis] == 0.0 {
            if o[axis].abs() > h {
                return None;
            }
            continue;
        }
        let ta = (-h - o[axis]) / d[axis];
        let tb = (h - o[axis]) / d[axis];
        let (near, far) = if ta < tb { (ta, tb) } else { (tb, ta) };
        if near > t_enter {
            (t_enter, enter_axis) = (near, axis);
        }
        if far < t_exit {
            (t_exit, exit_axis) = (far, axis);
        }
    }
    if t_enter > t_exit || t_exit <= 0.0 {
        return None;
    }
    let (t, axis) = if t_enter > 0.0 {
        (t_enter, enter_axis)
    } else {
        (t_exit, exit_axis)
    };
    let side = sign(o[axis] + t * d[axis]);
    let mut local = DVec3::ZERO;
    local[axis] = side;
    let face = 2 * axis as u32 + u32::from(side > 0.0);
    Some((t, b.rotation * local, face))
}

/// The watertight ray/triangle test of Woop, Benthin and Wald (JCGT 2013),
/// with no culling: `(t, u, v)`, the barycentrics of the second and third
/// vertices. The twin of `hit_triangle` in raytrace.comp.glsl.
///
/// The vertices are moved into a frame where the ray runs along +z from the
/// origin; the three edge functions are then 2D cross products of vertex
/// coordinates that each vertex computes on its own. A shared edge gives its
/// two triangles the same two products in the other order, so their edge
/// functions are exact negatives and a ray cannot slip between them. An
/// edge function that rounds to exactly 0 counts as inside for both
/// triangles (the tie rule of docs/raytracing.md then picks one).
pub fn triangle(ray: &Ray, tri: &RtTriangle) -> Option<(f64, f64, f64)> {
    triangle_in(&RayFrame::new(ray.dir), ray, tri)
}

/// `triangle` with the ray's shear computed once for all its triangles.
fn triangle_in(frame: &RayFrame, ray: &Ray, tri: &RtTriangle) -> Option<(f64, f64, f64)> {
    let [a, b, c] = tri.positions.map(|p| frame.transform(p - ray.origin));
    let u = c.x * b.y - c.y * b.x;
    let v = a.x * c.y - a.y * c.x;
    let w = b.x * a.y - b.y * a.x;
    let inside = (u >= 0.0 && v >= 0.0 && w >= 0.0) || (u <= 0.0 && v <= 0.0 && w <= 0.0);
    let det = u + v + w;
    if !inside || det == 0.0 {
        return None;
    }
    let t = (u * a.z + v * b.z + w * c.z) / det;
    (t > 0.0).then_some((t, v / det, w / det))
}

/// The shear of the watertight test: `z` is the ray's largest component,
/// `x` and `y` the next two in cyclic order (swapped when `d.z < 0`, which
/// keeps the winding).
struct RayFrame {
    axes: [usize; 3],
    shear: DVec3,
}

impl RayFrame {
    fn new(d: DVec3) -> Self {
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        Self {
            axes: [kx, ky, kz],
            shear: DVec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]),
        }
    }

    /// A point relative to the ray origin, sheared so that the ray is +z:
    /// `(x - Sx z, y - Sy z, Sz z)`.
    fn transform(&self, p: DVec3) -> DVec3 {
        let [kx, ky, kz] = self.axes;
        DVec3::new(
            p[kx] - self.shear.x * p[kz],
            p[ky] - self.shear.y * p[kz],
            self.shear.z * p[kz],
        )
    }
}

/// The normal at barycentrics `(u, v)`: `normalize((1-u-v) n0 + u n1 + v n2)`,
/// or zero if that vanishes.
pub fn triangle_normal(tri: &RtTriangle, u: f64, v: f64) -> DVec3 {
    let [n0, n1, n2] = tri.normals;
    ((1.0 - u - v) * n0 + u * n1 + v * n2).normalize_or_zero()
}

/// A BVH node with its f32 bounds widened in f64, so that no f64 triangle
/// (whose f32 rounding the bounds were built from) pokes out of it.
#[derive(Debug, Clone, Copy)]
struct Node {
    min: DVec3,
    max: DVec3,
    prim_count: u32,
    first_index: u32,
}

/// Entry distance of a ray into an axis-aligned box, if it meets the box at
/// some `t` in `[0, t_max]`.
fn box_entry(ray: &Ray, min: DVec3, max: DVec3, t_max: f64) -> Option<f64> {
    let (mut lo, mut hi) = (0.0f64, t_max);
    for axis in 0..3 {
        let (o, d) = (ray.origin[axis], ray.dir[axis]);
        if d == 0.0 {
            if o < min[axis] || o > max[axis] {
                return None;
            }
            continue;
        }
        let ta = (min[axis] - o) / d;
        let tb = (max[axis] - o) / d;
        let (near, far) = if ta < tb { (ta, tb) } else { (tb, ta) };
        lo = lo.max(near);
        hi = hi.min(far);
        if lo > hi {
            return None;
        }
    }
    Some(lo)
}

/// A traversal stack: 64 entries inline, more on the heap only for a tree
/// deeper than that.
struct NodeStack {
    inline: [u32; 64],
    len: usize,
    spill: Vec<u32>,
}

impl NodeStack {
    fn new(root: u32) -> Self {
        let mut s = NodeStack {
            inline: [0; 64],
            len: 0,
            spill: Vec::new(),
        };
        s.push(root);
        s
    }

    fn push(&mut self, node: u32) {
        if self.len < self.inline.len() {
            self.inline[self.len] = node;
            self.len += 1;
        } else {
            self.spill.push(node);
        }
    }

    fn pop(&mut self) -> Option<u32> {
        if let Some(node) = self.spill.pop() {
            return Some(node);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.inline[self.len])
    }
}

/// The scene prepared for tracing: the BVH with widened `f64` boxes.
pub struct Accel<'a> {
    pub scene: &'a RtScene,
    nodes: Vec<Node>,
}

/// Whether `(t, object, primitive)` beats the current best: nearer, or at
/// exactly the same distance a lower object index, then (two triangles of
/// one mesh) a lower triangle index.
fn better(t: f64, object: u32, order: u32, best: Option<&Hit>) -> bool {
    match best {
        None => true,
        Some(b) => {
            t < b.t || (t == b.t && (object, order) < (b.object, primitive_order(b.primitive)))
        }
    }
}

/// Tie-break index within one object (only meshes have more than one
/// primitive per object).
fn primitive_order(p: Primitive) -> u32 {
    match p {
        Primitive::Triangle(i) => i,
        _ => 0,
    }
}

impl<'a> Accel<'a> {
    pub fn new(scene: &'a RtScene) -> Self {
        let nodes = if scene.triangles.is_empty() {
            Vec::new()
        } else {
            scene
                .bvh
                .nodes
                .iter()
                .map(|n| {
                    let aabb = n.aabb();
                    let (min, max) = widened_box(aabb.min.as_dvec3(), aabb.max.as_dvec3());
                    Node {
                        min,
                        max,
                        prim_count: n.prim_count,
                        first_index: n.first_index,
                    }
                })
                .collect()
        };
        Accel { scene, nodes }
    }

    /// The nearest hit with `t > 0`, ties to the lower object index.
    pub fn nearest(&self, ray: &Ray) -> Option<Hit> {
        let s = self.scene;
        let mut best: Option<Hit> = None;
        // Either kind of sphere, hit at `t`: the same normal and record.
        let sphere_hit = |t: f64, sp: &RtSphere, primitive| {
            let n = (ray.origin + t * ray.dir - sp.center) / sp.radius;
            Hit {
                t,
                object: sp.object,
                material: sp.material,
                primitive,
                normal: n,
                geometric_normal: n,
                barycentrics: DVec2::ZERO,
            }
        };
        for (i, sp) in s.spheres.iter().enumerate() {
            if let Some(t) = sphere(ray, sp) {
                if better(t, sp.object, 0, best.as_ref()) {
                    best = Some(sphere_hit(t, sp, Primitive::Sphere(i as u32)));
                }
            }
        }
        for (i, huge) in s.huge_spheres.iter().enumerate() {
            if let Some(t) = huge_sphere(ray, huge) {
                if better(t, huge.sphere.object, 0, best.as_ref()) {
                    best = Some(sphere_hit(t, &huge.sphere, Primitive::HugeSphere(i as u32)));
                }
            }
        }
        for (i, pl) in s.planes.iter().enumerate() {
            if let Some(t) = plane(ray, pl) {
                if better(t, pl.object, 0, best.as_ref()) {
                    best = Some(Hit {
                        t,
                        object: pl.object,
                        material: pl.material,
                        primitive: Primitive::Plane(i as u32),
                        normal: pl.normal,
                        geometric_normal: pl.normal,
                        barycentrics: DVec2::ZERO,
                    });
                }
            }
        }
        for (i, b) in s.boxes.iter().enumerate() {
            if let Some((t, n, face)) = cuboid(ray, b) {
                if better(t, b.object, 0, best.as_ref()) {
                    best = Some(Hit {
                        t,
                        object: b.object,
                        material: b.material,
                        primitive: Primitive::Box {
                            index: i as u32,
                            face,
                        },
                        normal: n,
                        geometric_normal: n,
                        barycentrics: DVec2::ZERO,
                    });
                }
            }
        }
        let frame = RayFrame::new(ray.dir);
        let t_max = best.map_or(f64::INFINITY, |b| b.t);
        self.walk(ray, t_max, |leaf, t_max| {
            for &k in leaf {
                let tri = &s.triangles[k as usize];
                let Some((t, u, v)) = triangle_in(&frame, ray, tri) else {
                    continue;
                };
                if better(t, tri.object, k, best.as_ref()) {
                    best = Some(Hit {
                        t,
                        object: tri.object,
                        material: tri.material,
                        primitive: Primitive::Triangle(k),
                        normal: triangle_normal(tri, u, v),
                        geometric_normal: tri.geometric_normal(),
                        barycentrics: DVec2::new(u, v),
                    });
                    *t_max = t;
                }
            }
            ControlFlow::Continue(())
        });
        best
    }

    /// Whether anything is hit at `0 < t < t_max` (a shadow ray).
    pub fn any(&self, ray: &Ray, t_max: f64) -> bool {
        let s = self.scene;
        let within = |t: f64| t < t_max;
        if s.spheres
            .iter()
            .any(|sp| sphere(ray, sp).is_some_and(within))
            || s.huge_spheres
                .iter()
                .any(|sp| huge_sphere(ray, sp).is_some_and(within))
            || s.planes.iter().any(|pl| plane(ray, pl).is_some_and(within))
            || s.boxes
                .iter()
                .any(|b| cuboid(ray, b).is_some_and(|(t, _, _)| within(t)))
        {
            return true;
        }
        let frame = RayFrame::new(ray.dir);
        let mut blocked = false;
        self.walk(ray, t_max, |leaf, _| {
            blocked = leaf.iter().any(|&k| {
                triangle_in(&frame, ray, &s.triangles[k as usize])
                    .is_some_and(|(t, _, _)| within(t))
            });
            if blocked {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        blocked
    }

    /// Walks the BVH depth-first, handing `leaf` the triangle indices of
    /// every leaf whose box the ray enters before `t_max`. `leaf` may lower
    /// `t_max` (a nearer hit) or break off the walk (any hit will do).
    fn walk(
        &self,
        ray: &Ray,
        mut t_max: f64,
        mut leaf: impl FnMut(&[u32], &mut f64) -> ControlFlow<()>,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = NodeStack::new(0);
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index as usize];
            if box_entry(ray, node.min, node.max, t_max).is_none() {
                continue;
            }
            if node.prim_count == 0 {
                stack.push(node.first_index);
                stack.push(node.first_index + 1);
                continue;
            }
            let first = node.first_index as usize;
            let indices =
                &self.scene.bvh.primitive_indices[first..first + node.prim_count as usize];
            if leaf(indices, &mut t_max).is_break() {
                return;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DMat3;

    fn ray(origin: DVec3, dir: DVec3) -> Ray {
        Ray {
            origin,
            dir: dir.normalize(),
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    fn unit_sphere(center: DVec3, object: u32) -> RtSphere {
        RtSphere {
            center,
            radius: 1.0,
            material: 0,
            object,
        }
    }

    fn floor(y: f64, half_size: f64, object: u32) -> RtPlane {
        let (u, v) = crate::scene::plane_axes(DVec3::Y);
        RtPlane {
            center: DVec3::new(0.0, y, 0.0),
            normal: DVec3::Y,
            u,
            v,
            half_size,
            material: 0,
            object,
        }
    }

    fn cube(center: DVec3, rotation: DMat3) -> RtBox {
        RtBox {
            center,
            half_extents: DVec3::new(1.0, 2.0, 3.0),
            rotation,
            material: 0,
            object: 0,
        }
    }

    #[test]
    fn sphere_from_outside_inside_and_missing() {
        let s = unit_sphere(DVec3::new(0.0, 0.0, -5.0), 0);
        // Straight at it: t = 5 - 1.
        assert_eq!(sphere(&ray(DVec3::ZERO, -DVec3::Z), &s), Some(4.0));
        // Off-centre by 0.6: chord half-length 0.8, t = 5 - 0.8.
        let t = sphere(&ray(DVec3::new(0.6, 0.0, 0.0), -DVec3::Z), &s).unwrap();
        assert!(close(t, 4.2), "{t}");
        // From the centre: t = r; from inside off-centre: the far root.
        assert_eq!(sphere(&ray(s.center, DVec3::X), &s), Some(1.0));
        let t = sphere(&ray(s.center + DVec3::new(0.0, 0.6, 0.0), DVec3::X), &s).unwrap();
        assert!(close(t, 0.8), "{t}");
        // Behind the ray, beside it, and pointing away.
        assert_eq!(sphere(&ray(DVec3::ZERO, DVec3::Z), &s), None);
        assert_eq!(sphere(&ray(DVec3::new(1.5, 0.0, 0.0), -DVec3::Z), &s), None);
        // Tangent: disc = 0 counts, t = 5.
        let t = sphere(&ray(DVec3::new(1.0, 0.0, 0.0), -DVec3::Z), &s).unwrap();
        assert!(close(t, 5.0), "{t}");
        // Far away and small: the stable form keeps the near root exact.
        let far = RtSphere {
            center: DVec3::new(0.0, 0.0, -1e7),
            radius: 1e-3,
            material: 0,
            object: 0,
        };
        let t = sphere(&ray(DVec3::ZERO, -DVec3::Z), &far).unwrap();
        assert_eq!(t, 1e7 - 1e-3);
    }

    #[test]
    fn plane_hits_within_its_square_and_on_its_edge() {
        let pl = floor(-1.0, 2.0, 0);
        let t = plane(&ray(DVec3::ZERO, DVec3::new(1.0, -1.0, 0.0)), &pl).unwrap();
        assert!(close(t, 2f64.sqrt()), "{t}");
        // From below: same plane, the normal stays +Y (the Hit's job).
        let t = plane(&ray(DVec3::new(0.5, -3.0, 0.5), DVec3::Y), &pl).unwrap();
        assert!(close(t, 2.0), "{t}");
        // Exactly on the edge (|x| = h) counts; just past it does not.
        assert_eq!(
            plane(&ray(DVec3::new(2.0, 0.0, 0.0), -DVec3::Y), &pl),
            Some(1.0)
        );
        let past = 2.0 + 1e-12;
        assert_eq!(
            plane(&ray(DVec3::new(past, 0.0, 0.0), -DVec3::Y), &pl),
            None
        );
        // Parallel (grazing within the plane) and pointing away: no hit.
        assert_eq!(plane(&ray(DVec3::new(0.0, -1.0, 0.0), DVec3::X), &pl), None);
        assert_eq!(plane(&ray(DVec3::ZERO, DVec3::Y), &pl), None);
    }

    #[test]
    fn box_slab_test_gives_the_face_normal() {
        let b = cube(DVec3::new(0.0, 0.0, -10.0), DMat3::IDENTITY);
        // Head on: the +Z face at z = -7.
        let (t, n, face) = cuboid(&ray(DVec3::ZERO, -DVec3::Z), &b).unwrap();
        assert_eq!((t, n, face), (7.0, DVec3::Z, 5));
        // From inside (the centre) toward +X: the exiting face x = +1.
        let (t, n, face) = cuboid(&ray(b.center, DVec3::X), &b).unwrap();
        assert_eq!((t, n, face), (1.0, DVec3::X, 1));
        // From inside toward -Y: y = -2.
        let (t, n, _) = cuboid(&ray(b.center, -DVec3::Y), &b).unwrap();
        assert_eq!((t, n), (2.0, -DVec3::Y));
        // Missing beside it, and parallel to a slab outside it.
        assert!(cuboid(&ray(DVec3::new(1.5, 0.0, 0.0), -DVec3::Z), &b).is_none());
        assert!(cuboid(&ray(DVec3::new(0.0, 2.5, 0.0), -DVec3::Z), &b).is_none());
        // Parallel, exactly in the face's plane: the face counts (boundary
        // included), and the hit is on the +Z face.
        let (t, n, _) = cuboid(&ray(DVec3::new(1.0, 0.0, 0.0), -DVec3::Z), &b).unwrap();
        assert_eq!((t, n), (7.0, DVec3::Z));
        // Behind the ray.
        assert!(cuboid(&ray(DVec3::ZERO, DVec3::Z), &b).is_none());
    }

    #[test]
    fn box_edge_ties_go_to_x_then_y() {
        // A cube of half-size 1: a diagonal ray through the edge x = y = 1
        // enters the X and Y slabs at the same t: the X face wins.
        let b = RtBox {
            half_extents: DVec3::ONE,
            ..cube(DVec3::ZERO, DMat3::IDENTITY)
        };
        let (t, n, _) = cuboid(
            &ray(DVec3::new(3.0, 3.0, 0.0), DVec3::new(-1.0, -1.0, 0.0)),
            &b,
        )
        .unwrap();
        assert!(close(t, 2.0 * 2f64.sqrt()), "{t}");
        assert_eq!(n, DVec3::X);
        // Through the edge y = z = -1: Y before Z.
        let (_, n, _) = cuboid(
            &ray(DVec3::new(0.0, -4.0, -4.0), DVec3::new(0.0, 1.0, 1.0)),
            &b,
        )
        .unwrap();
        assert_eq!(n, -DVec3::Y);
    }

    #[test]
    fn rotated_box_normal_is_rotated_back() {
        // Turned 90 degrees about Y: local +X is world -Z, so a ray coming
        // down -Z meets the local -X face (half-extent 1) at z = -10 + 1,
        // and its normal, rotated back, is world +Z.
        let r = DMat3::from_rotation_y(std::f64::consts::FRAC_PI_2);
        let b = cube(DVec3::new(0.0, 0.0, -10.0), r);
        let (t, n, face) = cuboid(&ray(DVec3::ZERO, -DVec3::Z), &b).unwrap();
        assert!(close(t, 9.0), "{t}");
        assert!((n - DVec3::Z).length() < 1e-12, "{n}");
        assert_eq!(face, 0, "local -X");
    }

    fn tri(positions: [DVec3; 3], normals: [DVec3; 3]) -> RtTriangle {
        RtTriangle {
            positions,
            normals,
            material: 0,
            object: 0,
        }
    }

    #[test]
    fn triangle_hits_both_sides_with_barycentric_normals() {
        let t = tri(
            [
                DVec3::new(0.0, 0.0, -2.0),
                DVec3::new(4.0, 0.0, -2.0),
                DVec3::new(0.0, 4.0, -2.0),
            ],
            [DVec3::Z, DVec3::X, DVec3::Y],
        );
        let (d, u, v) = triangle(&ray(DVec3::new(1.0, 2.0, 0.0), -DVec3::Z), &t).unwrap();
        assert_eq!((d, u, v), (2.0, 0.25, 0.5));
        let n = triangle_normal(&t, u, v);
        assert!((n - DVec3::new(0.25, 0.5, 0.25).normalize()).length() < 1e-15);
        assert_eq!(t.geometric_normal(), DVec3::Z);
        // From behind: no culling.
        let (d, _, _) = triangle(&ray(DVec3::new(1.0, 2.0, -5.0), DVec3::Z), &t).unwrap();
        assert_eq!(d, 3.0);
        // Outside (u + v > 1), parallel, and behind the origin.
        assert!(triangle(&ray(DVec3::new(3.0, 3.0, 0.0), -DVec3::Z), &t).is_none());
        assert!(triangle(&ray(DVec3::new(1.0, 1.0, -2.0), DVec3::X), &t).is_none());
        assert!(triangle(&ray(DVec3::new(1.0, 1.0, 0.0), DVec3::Z), &t).is_none());
        // On the hypotenuse (u + v = 1) counts.
        let (_, u, v) = triangle(&ray(DVec3::new(2.0, 2.0, 0.0), -DVec3::Z), &t).unwrap();
        assert_eq!(u + v, 1.0);
        // Opposite normals interpolating to zero: a zero normal, no NaN.
        let flip = tri(t.positions, [DVec3::Z, -DVec3::Z, DVec3::Z]);
        assert_eq!(triangle_normal(&flip, 0.5, 0.0), DVec3::ZERO);
    }

    fn empty_scene() -> RtScene {
        let mut scene = crate::scene::default_scene();
        scene.objects.clear();
        scene.camera.position = DVec3::ZERO;
        scene.camera.look_at = -DVec3::Z;
        RtScene::new(&scene)
    }

    #[test]
    fn ties_go_to_the_lower_object_index() {
        let mut rt = empty_scene();
        // Two coincident spheres: listed in reverse object order.
        rt.spheres = vec![
            unit_sphere(DVec3::new(0.0, 0.0, -5.0), 7),
            unit_sphere(DVec3::new(0.0, 0.0, -5.0), 3),
        ];
        // A plane through the sphere's front point at the same t, with a
        // higher object index; and one with a lower index.
        let (u, v) = crate::scene::plane_axes(DVec3::Z);
        let front = RtPlane {
            center: DVec3::new(0.0, 0.0, -4.0),
            normal: DVec3::Z,
            u,
            v,
            half_size: 10.0,
            material: 0,
            object: 9,
        };
        rt.planes = vec![front];
        let accel = Accel::new(&rt);
        let r = ray(DVec3::ZERO, -DVec3::Z);
        let hit = accel.nearest(&r).unwrap();
        assert_eq!((hit.t, hit.object), (4.0, 3));
        rt.planes[0].object = 1;
        let accel = Accel::new(&rt);
        let hit = accel.nearest(&r).unwrap();
        assert_eq!((hit.t, hit.object, hit.normal), (4.0, 1, DVec3::Z));
        // Any-hit is strict: a blocker exactly at t_max does not block.
        assert!(!accel.any(&r, 4.0));
        assert!(accel.any(&r, 4.0 + 1e-9));
    }

    #[test]
    fn bvh_traversal_equals_brute_force() {
        // A tessellated sphere and a tilted plane as meshes: every ray's
        // nearest hit through the BVH equals a loop over all triangles.
        let mut scene = crate::scene::default_scene();
        scene.camera.position = DVec3::new(0.3, 0.2, 6.0);
        for object in &mut scene.objects {
            object.shape = crate::scene::Shape::Mesh(crate::scene::tessellate(&object.shape));
        }
        let rt = RtScene::new(&scene);
        assert!(rt.triangles.len() > 1000);
        let accel = Accel::new(&rt);
        let mut hits = 0;
        for i in 0..2000 {
            let a = f64::from(i) * 0.618_033_988_749;
            let b = f64::from(i) * 0.414_213_562_373;
            let dir = DVec3::new((a.fract() - 0.5) * 1.2, (b.fract() - 0.7) * 1.0, -1.0);
            let r = ray(DVec3::ZERO, dir);
            let brute = rt
                .triangles
                .iter()
                .enumerate()
                .filter_map(|(k, t)| triangle(&r, t).map(|(t, _, _)| (t, k as u32)))
                .min_by(|x, y| x.partial_cmp(y).unwrap());
            let bvh = accel.nearest(&r).map(|h| match h.primitive {
                Primitive::Triangle(k) => (h.t, k),
                _ => unreachable!(),
            });
            assert_eq!(bvh, brute, "ray {i}");
            hits += usize::from(bvh.is_some());
            if let Some((t, _)) = brute {
                assert!(accel.any(&r, t * 1.000001));
                assert!(!accel.any(&r, t));
            }
        }
        assert!(hits > 500, "{hits} hits");
    }
}
