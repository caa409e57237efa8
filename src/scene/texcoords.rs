//! Texture coordinates `(u, v)` of the analytic shapes, the one
//! parameterisation of each that the ray tracers evaluate at a hit and the
//! tessellation gives its vertices (docs/lighting-model.md, "Surface
//! colour"). `shaders/include/rt_surface.glsl` has the same formulas in f32.

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
/// `(axis_u, axis_v)` (`plane_axes`: right and up as its image reads): the
/// square covers `[0, 1]` once, `u` rightward and `v` down the image, so
/// `(0, 0)` is the top left corner seen from the side the normal points to.
pub fn plane_uv(offset: DVec3, axis_u: DVec3, axis_v: DVec3, size: f64) -> DVec2 {
    DVec2::new(
        offset.dot(axis_u) / size + 0.5,
        0.5 - offset.dot(axis_v) / size,
    )
}

/// A box face's two axes in the order `u`, `v` with `u x v` the face's
/// outward normal, and the box's half extents along them. `face` is
/// `2 * axis + (1 for the + side, 0 for -)`, as the CPU tracer numbers
/// faces; the tessellation gives each face the same axes.
///
/// `u` is the face's edge (one of the box's two other axes, either way)
/// nearest the right of an image on a plane with the face's normal
/// (`plane_axes`), so an unrotated box's faces read as planes do and a
/// turned box's images turn with it by whole quarter turns at most; `v`
/// is `n x u`, the image's up. Ties (a face turned by exactly 45 degrees
/// about its normal) go to the box axis after the face's, then to its +
/// direction.
pub fn box_face_axes(rotation: &DMat3, half: DVec3, face: u32) -> ((DVec3, f64), (DVec3, f64)) {
    let axes = [rotation.x_axis, rotation.y_axis, rotation.z_axis];
    let h = [half.x, half.y, half.z];
    let (a, sign) = ((face / 2) as usize, if face % 2 == 1 { 1.0 } else { -1.0 });
    let n = axes[a] * sign;
    let (right, _) = super::model::plane_axes(n.normalize());
    let (b, c) = ((a + 1) % 3, (a + 2) % 3);
    let mut best = (b, 1.0, f64::NEG_INFINITY);
    for k in [b, c] {
        for s in [1.0, -1.0] {
            let along = (axes[k] * s).dot(right);
            if along > best.2 {
                best = (k, s, along);
            }
        }
    }
    let (ku, su, _) = best;
    let u = axes[ku] * su;
    let kv = if ku == b { c } else { b };
    let sv = n.cross(u).dot(axes[kv]).signum();
    ((u, h[ku]), (axes[kv] * sv, h[kv]))
}

/// A box face at `offset` from the box's centre: `[0, 1]` across the face
/// along each of its axes (`box_face_axes`), `v` down the image as on a
/// plane.
pub fn box_uv(offset: DVec3, rotation: &DMat3, half: DVec3, face: u32) -> DVec2 {
    let ((u, hu), (v, hv)) = box_face_axes(rotation, half, face);
    DVec2::new(
        offset.dot(u) / (2.0 * hu) + 0.5,
        0.5 - offset.dot(v) / (2.0 * hv),
    )
}

/// Which box axis, and which way, each face's texture axes run
/// (`box_face_axes`), packed for the GPU tracer: face `f`'s `u` in bits
/// `3 f .. 3 f + 3` of the first word, its `v` in the second, each as the
/// axis index (0..3) plus 4 when it runs along the axis's minus direction.
pub fn box_face_codes(rotation: &DMat3) -> [u32; 2] {
    let axes = [rotation.x_axis, rotation.y_axis, rotation.z_axis];
    let code = |d: DVec3| -> u32 {
        let k = (0..3)
            .max_by(|&i, &j| d.dot(axes[i]).abs().total_cmp(&d.dot(axes[j]).abs()))
            .unwrap_or(0);
        k as u32 + if d.dot(axes[k]) < 0.0 { 4 } else { 0 }
    };
    let mut words = [0u32; 2];
    for face in 0..6u32 {
        let ((u, _), (v, _)) = box_face_axes(rotation, DVec3::ONE, face);
        words[0] |= code(u) << (3 * face);
        words[1] |= code(v) << (3 * face);
    }
    words
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
    fn a_plane_covers_zero_to_one_from_its_top_left_corner() {
        // A wall facing +Z seen from the front: right +X, up +Y, so the
        // corner at (-1, +1) is the image's top left.
        let (u, v) = crate::scene::plane_axes(DVec3::Z);
        assert_eq!((u, v), (DVec3::X, DVec3::Y));
        assert_eq!(plane_uv(DVec3::new(-1.0, 1.0, 0.0), u, v, 2.0), DVec2::ZERO);
        assert_eq!(plane_uv(DVec3::new(1.0, -1.0, 0.0), u, v, 2.0), DVec2::ONE);
    }

    /// Each face of an unrotated box reads as a viewer outside it sees it,
    /// the sides upright, the top and bottom with `u` along +X: the corner
    /// that viewer sees at the top left, worked out by hand for each face.
    #[test]
    fn every_face_of_a_box_has_its_image_top_left_where_its_viewer_sees_it() {
        let half = DVec3::new(1.0, 2.0, 3.0);
        // (face, top left corner's direction from the centre, u axis, v axis)
        let faces = [
            (5, DVec3::new(-1.0, 1.0, 1.0), DVec3::X, DVec3::Y), // +Z, seen from the front
            (4, DVec3::new(1.0, 1.0, -1.0), DVec3::NEG_X, DVec3::Y), // -Z, from behind
            (1, DVec3::new(1.0, 1.0, 1.0), DVec3::NEG_Z, DVec3::Y), // +X, from the right
            (0, DVec3::new(-1.0, 1.0, -1.0), DVec3::Z, DVec3::Y), // -X, from the left
            (3, DVec3::new(-1.0, 1.0, -1.0), DVec3::X, DVec3::NEG_Z), // +Y, top toward -Z
            (2, DVec3::new(-1.0, -1.0, 1.0), DVec3::X, DVec3::Z), // -Y, top toward +Z
        ];
        for (face, corner, want_u, want_v) in faces {
            let ((u, _), (v, _)) = box_face_axes(&DMat3::IDENTITY, half, face);
            assert_eq!((u, v), (want_u, want_v), "face {face}");
            let n = u.cross(v);
            let axis = [DVec3::X, DVec3::Y, DVec3::Z][(face / 2) as usize];
            assert_eq!(n, axis * if face % 2 == 1 { 1.0 } else { -1.0 });
            let top_left = box_uv(corner * half, &DMat3::IDENTITY, half, face);
            assert_eq!(top_left, DVec2::ZERO, "face {face}");
            let bottom_right = box_uv(
                (2.0 * n.abs() - 1.0) * corner * half,
                &DMat3::IDENTITY,
                half,
                face,
            );
            assert_eq!(bottom_right, DVec2::ONE, "face {face}");
        }
    }

    /// A box turned a quarter turn about Y shows its images as an unturned
    /// box does: the face now toward +Z is upright too.
    #[test]
    fn a_box_turned_about_the_vertical_keeps_its_sides_upright() {
        let rotation = DMat3::from_rotation_y(std::f64::consts::FRAC_PI_2);
        // Local +X now faces world -Z, so local -X (face 0) faces +Z.
        let ((u, _), (v, _)) = box_face_axes(&rotation, DVec3::ONE, 0);
        assert!(
            (u - DVec3::X).length() < 1e-12 && (v - DVec3::Y).length() < 1e-12,
            "{u} {v}"
        );
    }

    #[test]
    fn the_gpu_codes_name_each_faces_axes() {
        let codes = box_face_codes(&DMat3::IDENTITY);
        let decode = |word: u32, face: u32| {
            let c = (word >> (3 * face)) & 7;
            [DVec3::X, DVec3::Y, DVec3::Z][(c & 3) as usize] * if c & 4 != 0 { -1.0 } else { 1.0 }
        };
        for face in 0..6 {
            let ((u, _), (v, _)) = box_face_axes(&DMat3::IDENTITY, DVec3::ONE, face);
            assert_eq!((decode(codes[0], face), decode(codes[1], face)), (u, v));
        }
    }
}
