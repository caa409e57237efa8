//! Oriented boxes: the slab test in the box's own axes.

use glam::DVec3;

use super::hit::Ray;
use super::sphere::sign;
use crate::rt_scene::RtBox;

/// The slab test in box-local coordinates: `(t, world face normal, face)`.
/// The entering `t` if positive, else the exiting one (a ray from inside).
/// A slab parallel to the ray constrains nothing when the origin lies within
/// it (boundary included) and misses otherwise. On equal `t` the slab of
/// the lower axis gives the normal (X, then Y, then Z).
#[inline]
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

#[cfg(test)]
mod tests {
    use super::super::test_support::{close, ray};
    use super::*;
    use glam::DMat3;

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
}
