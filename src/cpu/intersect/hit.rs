//! A ray, the hit it finds, and which of two hits wins.

use glam::{DVec2, DVec3};

use crate::rt_scene::Primitive;

/// A ray `origin + t dir`, `dir` a unit vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: DVec3,
    pub dir: DVec3,
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

/// Whether `(t, object, primitive)` beats the current best: nearer, or at
/// exactly the same distance a lower object index, then (two triangles of
/// one mesh) a lower triangle index.
#[inline]
pub(super) fn better(t: f64, object: u32, order: u32, best: Option<&Hit>) -> bool {
    match best {
        None => true,
        Some(b) => {
            t < b.t || (t == b.t && (object, order) < (b.object, primitive_order(b.primitive)))
        }
    }
}

/// Tie-break index within one object (only meshes have more than one
/// primitive per object).
#[inline]
fn primitive_order(p: Primitive) -> u32 {
    match p {
        Primitive::Triangle(i) => i,
        _ => 0,
    }
}
