//! The primitive kinds of `RtScene`, camera-relative and in `f64`, each
//! with the scene object and material it came from; and `Primitive`, which
//! of them a hit is on (an index into the scene's list of that kind).

use glam::{DMat3, DVec3};

use crate::huge_sphere::SphereAnchor;

#[derive(Debug, Clone, Copy)]
pub struct RtSphere {
    pub center: DVec3,
    pub radius: f64,
    pub material: u32,
    pub object: u32,
}

/// A sphere the plain test cannot hold in `f32` (`huge_sphere`): tested
/// from its anchor, the point of its surface nearest the eye.
#[derive(Debug, Clone, Copy)]
pub struct RtHugeSphere {
    /// Its centre relative to the eye, its radius, material and object, as
    /// any sphere's: what its normal and texture coordinates come from.
    pub sphere: RtSphere,
    pub anchor: SphereAnchor,
}

/// A finite square: points `center + a u + b v` with `|a|, |b| <= half_size`.
#[derive(Debug, Clone, Copy)]
pub struct RtPlane {
    pub center: DVec3,
    pub normal: DVec3,
    pub u: DVec3,
    pub v: DVec3,
    pub half_size: f64,
    pub material: u32,
    pub object: u32,
}

/// An oriented box: `rotation` maps box-local axes to world axes.
#[derive(Debug, Clone, Copy)]
pub struct RtBox {
    pub center: DVec3,
    pub half_extents: DVec3,
    pub rotation: DMat3,
    pub material: u32,
    pub object: u32,
}

impl RtSphere {
    /// The smallest axis-aligned box around the sphere (min, max).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        (self.center - self.radius, self.center + self.radius)
    }
}

impl RtPlane {
    /// The smallest axis-aligned box around the square (min, max).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let reach = self.half_size * (self.u.abs() + self.v.abs());
        (self.center - reach, self.center + reach)
    }
}

impl RtBox {
    /// The smallest axis-aligned box around the oriented box (min, max).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let r = self.rotation;
        let reach = r.x_axis.abs() * self.half_extents.x
            + r.y_axis.abs() * self.half_extents.y
            + r.z_axis.abs() * self.half_extents.z;
        (self.center - reach, self.center + reach)
    }
}

#[derive(Debug, Clone, Copy)]
pub struct RtTriangle {
    pub positions: [DVec3; 3],
    /// Unit vertex normals, interpolated with the hit's barycentrics.
    pub normals: [DVec3; 3],
    pub material: u32,
    pub object: u32,
}

impl RtTriangle {
    /// `normalize((b - a) x (c - a))`, or zero for a degenerate triangle:
    /// what both tracers offset secondary rays along (the GPU receives it
    /// rounded to f32).
    pub fn geometric_normal(&self) -> DVec3 {
        let [a, b, c] = self.positions;
        (b - a).cross(c - a).normalize_or_zero()
    }
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
