//! Spheres: the plain test, and the anchored one for a sphere too large
//! for it (`crate::huge_sphere`).

use super::hit::Ray;
use crate::rt_scene::{RtHugeSphere, RtSphere};

/// `sign(x)` with `sign(0) = 1`, as the spec writes it.
#[inline]
pub(super) fn sign(x: f64) -> f64 {
    if x < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// Ray Tracing Gems ch. 7, the stable form: the smaller positive root.
#[inline]
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
#[inline]
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
#[inline]
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

#[cfg(test)]
mod tests {
    use super::super::test_support::{close, ray, unit_sphere};
    use super::*;
    use glam::DVec3;

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
}
