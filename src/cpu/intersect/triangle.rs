//! Mesh triangles: the watertight test and the interpolated normal.

use glam::DVec3;

use super::hit::Ray;
use crate::rt_scene::RtTriangle;

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

#[inline]
pub(super) fn triangle_in(
    frame: &RayFrame,
    ray: &Ray,
    tri: &RtTriangle,
) -> Option<(f64, f64, f64)> {
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
pub(super) struct RayFrame {
    axes: [usize; 3],
    shear: DVec3,
}

impl RayFrame {
    #[inline]
    pub(super) fn new(d: DVec3) -> Self {
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
    #[inline]
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
#[inline]
pub fn triangle_normal(tri: &RtTriangle, u: f64, v: f64) -> DVec3 {
    let [n0, n1, n2] = tri.normals;
    ((1.0 - u - v) * n0 + u * n1 + v * n2).normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::super::test_support::ray;
    use super::*;

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
}
