//! Texture coordinates `(u, v)` of the analytic shapes, the one
//! parameterisation of each that the ray tracers evaluate at a hit and the
//! tessellation gives its vertices (docs/lighting-model.md, "Surface
//! colour"). `shaders/raytrace.comp.glsl` has the same formulas in f32.

use glam::{DMat3, DVec2, DVec3};
use std::f64::consts::PI;

/// A sphere at its unit normal `n`: longitude and colatitude,
/// `u = 0.5 + atan2(n.x, n.z) / 2 pi` (0.5 facing +Z, growing toward +X,
/// the seam on the -Z side) and `v = acos(n.y) / pi` (0 at the top).
pub fn sphere_uv(n: DVec3) -> DVec2 {
    DVec2::new(
        0.5 + n.x.atan2(n.z) / (2.0 * PI),
        n.y.clamp(-1.0, 1.0).acos() / PI,
    )
}

/// A plane of edge `size` at `offset` from its centre, along its axes
/// `(axis_u, axis_v)` (`plane_axes`): the square covers `[0, 1]` once.
pub fn plane_uv(offset: DVec3, axis_u: DVec3, axis_v: DVec3, size: f64) -> DVec2 {
    DVec2::new(
        offset.dot(axis_u) / size + 0.5,
        offset.dot(axis_v) / size + 0.5,
    )
}

/// A box face's two axes in the order `u`, `v` with `u x v` the face's
/// outward normal, and the box's half extents along them. `face` is
/// `2 * axis + (1 for the + side, 0 for -)`, as the CPU tracer numbers
/// faces; the tessellation gives each face the same axes.
pub fn box_face_axes(rotation: &DMat3, half: DVec3, face: u32) -> ((DVec3, f64), (DVec3, f64)) {
    let axes = [rotation.x_axis, rotation.y_axis, rotation.z_axis];
    let h = [half.x, half.y, half.z];
    let a = (face / 2) as usize;
    let (b, c) = ((a + 1) % 3, (a + 2) % 3);
    if face % 2 == 1 {
        ((axes[b], h[b]), (axes[c], h[c]))
    } else {
        ((axes[c], h[c]), (axes[b], h[b]))
    }
}

/// A box face at `offset` from the box's centre: `[0, 1]` across the face
/// along each of its axes (`box_face_axes`).
pub fn box_uv(offset: DVec3, rotation: &DMat3, half: DVec3, face: u32) -> DVec2 {
    let ((u, hu), (v, hv)) = box_face_axes(rotation, half, face);
    DVec2::new(
        offset.dot(u) / (2.0 * hu) + 0.5,
        offset.dot(v) / (2.0 * hv) + 0.5,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sphere_faces_plus_z_at_the_middle_and_grows_toward_plus_x() {
        let front = sphere_uv(DVec3::Z);
        assert!((front - DVec2::new(0.5, 0.5)).length() < 1e-15);
        assert!((sphere_uv(DVec3::X).x - 0.75).abs() < 1e-15);
        assert!((sphere_uv(DVec3::NEG_X).x - 0.25).abs() < 1e-15);
        assert_eq!(sphere_uv(DVec3::Y).y, 0.0);
        assert_eq!(sphere_uv(DVec3::NEG_Y).y, 1.0);
        // The seam behind: either side of -Z is near 0 or near 1.
        let left = sphere_uv(DVec3::new(-1e-9, 0.0, -1.0)).x;
        let right = sphere_uv(DVec3::new(1e-9, 0.0, -1.0)).x;
        assert!(left < 1e-9 && right > 1.0 - 1e-9, "{left} {right}");
    }

    #[test]
    fn a_plane_and_a_box_face_cover_zero_to_one() {
        let uv = plane_uv(DVec3::new(-1.0, 0.0, 1.0), DVec3::X, DVec3::Z, 2.0);
        assert_eq!(uv, DVec2::new(0.0, 1.0));
        let half = DVec3::new(1.0, 2.0, 3.0);
        // The +Y face (face 3): u along z (half 3), v along x (half 1).
        let uv = box_uv(DVec3::new(1.0, 2.0, -3.0), &DMat3::IDENTITY, half, 3);
        assert_eq!(uv, DVec2::new(0.0, 1.0));
        let ((u, _), (v, _)) = box_face_axes(&DMat3::IDENTITY, half, 3);
        assert_eq!(u.cross(v), DVec3::Y);
        let ((u, _), (v, _)) = box_face_axes(&DMat3::IDENTITY, half, 2);
        assert_eq!(u.cross(v), DVec3::NEG_Y);
    }
}
