//! What the unit tests of the intersections share: rays and a unit sphere.

use glam::DVec3;

use super::hit::Ray;
use crate::rt_scene::RtSphere;

/// A ray from `origin` along `dir` (normalized).
pub(super) fn ray(origin: DVec3, dir: DVec3) -> Ray {
    Ray {
        origin,
        dir: dir.normalize(),
    }
}

pub(super) fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-12
}

pub(super) fn unit_sphere(center: DVec3, object: u32) -> RtSphere {
    RtSphere {
        center,
        radius: 1.0,
        material: 0,
        object,
    }
}
