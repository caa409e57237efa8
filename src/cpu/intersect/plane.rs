//! Finite planes: squares around a centre.

use super::hit::Ray;
use crate::rt_scene::RtPlane;

/// A finite square; the edges themselves count (`<= half_size`).
#[inline]
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

#[cfg(test)]
mod tests {
    use super::super::test_support::{close, ray};
    use super::*;
    use glam::DVec3;

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
}
