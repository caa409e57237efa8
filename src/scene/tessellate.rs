//! Triangle meshes for the raster modes.
//!
//! Every shape becomes indexed triangles in world space, counter-clockwise
//! seen from outside (from the normal side for a plane), with one unit
//! normal per vertex. The ray tracer may intersect spheres, planes and boxes
//! exactly; this is only what the rasterisers draw.

use glam::{DVec2, DVec3};
use std::f64::consts::PI;

use super::model::{plane_axes, Shape, TriangleMesh};
use super::texcoords::box_face_axes;

/// Tessellates `shape`; a `Shape::Mesh` is returned as a clone.
///
/// - Sphere: a UV sphere with `segments` vertices around (at least 3) and
///   `max(segments / 2, 2)` bands from pole to pole. Each pole is a single
///   vertex joined to the first/last ring by one triangle per segment, so no
///   triangle is degenerate. Vertex normals are the exact sphere normals.
///   Vertices: `segments * (bands - 1) + 2`.
/// - Plane: a `segments x segments` grid over the square, edges along
///   `plane_axes(normal)`, all normals equal to the plane normal.
///   Vertices: `(segments + 1)^2`.
/// - Box: 6 faces of 4 vertices each with the face normal, 12 triangles.
pub fn tessellate(shape: &Shape) -> TriangleMesh {
    match shape {
        Shape::Sphere {
            center,
            radius,
            segments,
        } => sphere(*center, *radius, *segments),
        Shape::Plane {
            center,
            normal,
            size,
            segments,
        } => plane(*center, *normal, *size, *segments),
        Shape::Box {
            center,
            half_extents,
            rotation,
        } => cuboid(*center, *half_extents, rotation),
        Shape::Mesh(mesh) => mesh.clone(),
    }
}

/// As `tessellate`, with texture coordinates per vertex
/// (`scene::texcoords`), for a surface with a pattern. A sphere then has
/// its seam and poles cut open: the column of vertices on the seam (the
/// -Z side, where `u` wraps from 1 to 0) twice, once with `u = 1` and once
/// with `u = 0`, and each pole once per segment, at the middle of the
/// segment's `u`, so that no triangle interpolates across the wrap. A
/// plane's and a box's vertices are those of `tessellate`. A mesh keeps
/// the coordinates it was loaded with.
pub fn tessellate_textured(shape: &Shape) -> TriangleMesh {
    match shape {
        Shape::Sphere {
            center,
            radius,
            segments,
        } => textured_sphere(*center, *radius, *segments),
        Shape::Plane { normal, .. } => {
            let mut mesh = tessellate(shape);
            let (u, v) = plane_axes(*normal);
            let Shape::Plane { center, size, .. } = shape else {
                unreachable!()
            };
            mesh.uvs = mesh
                .positions
                .iter()
                .map(|p| super::texcoords::plane_uv(*p - *center, u, v, *size))
                .collect();
            mesh
        }
        Shape::Box { .. } => {
            let mut mesh = tessellate(shape);
            // Four corners per face, (-,-), (+,-), (+,+), (-,+) along the
            // face's axes (`cuboid`), `v` down the image (`box_uv`).
            let corners = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)];
            mesh.uvs = (0..6)
                .flat_map(|_| corners.map(|(u, v)| DVec2::new(u, v)))
                .collect();
            mesh
        }
        Shape::Mesh(mesh) => mesh.clone(),
    }
}

/// The vertex and triangle counts `tessellate(shape)` returns, computed
/// from the numbers alone, so the memory a scene needs can be estimated
/// before any of it is built.
pub fn counts(shape: &Shape) -> (u64, u64) {
    match shape {
        Shape::Sphere { segments, .. } => {
            let seg = u64::from((*segments).max(3));
            let bands = (seg / 2).max(2);
            (seg * (bands - 1) + 2, 2 * seg * (bands - 1))
        }
        Shape::Plane { segments, .. } => {
            let n = u64::from((*segments).max(1));
            ((n + 1) * (n + 1), 2 * n * n)
        }
        Shape::Box { .. } => (24, 12),
        Shape::Mesh(mesh) => (mesh.positions.len() as u64, mesh.triangles.len() as u64),
    }
}

fn sphere(center: DVec3, radius: f64, segments: u32) -> TriangleMesh {
    let seg = segments.max(3);
    let bands = (seg / 2).max(2);
    let dir = |theta: f64, phi: f64| {
        DVec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        )
    };
    let mut normals = vec![DVec3::Y];
    for i in 1..bands {
        let theta = PI * f64::from(i) / f64::from(bands);
        for j in 0..seg {
            let phi = 2.0 * PI * f64::from(j) / f64::from(seg);
            normals.push(dir(theta, phi));
        }
    }
    normals.push(DVec3::NEG_Y);
    let positions = normals.iter().map(|n| center + *n * radius).collect();

    let south = seg * (bands - 1) + 1;
    // ring r (0-based, r < bands - 1), segment j (wrapping)
    let at = |r: u32, j: u32| 1 + r * seg + j % seg;
    let triangles = sphere_triangles(seg, bands, |_| 0, at, |_| south);
    TriangleMesh::new(positions, normals, triangles)
}

/// A UV sphere's triangles, wound outward: a fan from the north pole's
/// vertex for segment `j` (`north(j)`), two per segment between rings `r`
/// and `r + 1` (`at(r, j)`), a fan to the south pole's (`south(j)`).
fn sphere_triangles(
    seg: u32,
    bands: u32,
    north: impl Fn(u32) -> u32,
    at: impl Fn(u32, u32) -> u32,
    south: impl Fn(u32) -> u32,
) -> Vec<[u32; 3]> {
    let mut triangles = Vec::with_capacity((2 * seg * (bands - 1)) as usize);
    for j in 0..seg {
        triangles.push([north(j), at(0, j + 1), at(0, j)]);
    }
    for r in 0..bands - 2 {
        for j in 0..seg {
            let (a, c) = (at(r, j), at(r, j + 1));
            let (b, d) = (at(r + 1, j), at(r + 1, j + 1));
            triangles.push([a, c, b]);
            triangles.push([c, d, b]);
        }
    }
    for j in 0..seg {
        triangles.push([at(bands - 2, j), at(bands - 2, j + 1), south(j)]);
    }
    triangles
}

/// `sphere`'s rings, each with a vertex more (the seam twice) and starting
/// on the seam, and a pole vertex per segment (see `tessellate_textured`).
fn textured_sphere(center: DVec3, radius: f64, segments: u32) -> TriangleMesh {
    let seg = segments.max(3);
    let bands = (seg / 2).max(2);
    // Longitude phi from the seam, where `sphere_uv`'s u is 0 (or 1): the
    // normal (sin t cos phi, cos t, sin t sin phi) has u = 0.75 - phi / 2pi.
    let seam = 1.5 * PI;
    let dir = |theta: f64, phi: f64| {
        DVec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        )
    };
    let column_u = |j: f64| 1.0 - j / f64::from(seg);
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for j in 0..seg {
        normals.push(DVec3::Y);
        uvs.push(DVec2::new(column_u(f64::from(j) + 0.5), 0.0));
    }
    for i in 1..bands {
        let theta = PI * f64::from(i) / f64::from(bands);
        for j in 0..=seg {
            let phi = seam + 2.0 * PI * f64::from(j) / f64::from(seg);
            normals.push(dir(theta, phi));
            uvs.push(DVec2::new(
                column_u(f64::from(j)),
                f64::from(i) / f64::from(bands),
            ));
        }
    }
    let south = normals.len() as u32;
    for j in 0..seg {
        normals.push(DVec3::NEG_Y);
        uvs.push(DVec2::new(column_u(f64::from(j) + 0.5), 1.0));
    }
    let positions = normals.iter().map(|n| center + *n * radius).collect();
    let at = |r: u32, j: u32| seg + r * (seg + 1) + j;
    let triangles = sphere_triangles(seg, bands, |j| j, at, |j| south + j);
    TriangleMesh {
        uvs,
        ..TriangleMesh::new(positions, normals, triangles)
    }
}

fn plane(center: DVec3, normal: DVec3, size: f64, segments: u32) -> TriangleMesh {
    let n = segments.max(1);
    let (u, v) = plane_axes(normal);
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            let s = f64::from(i) / f64::from(n) - 0.5;
            let t = f64::from(j) / f64::from(n) - 0.5;
            positions.push(center + u * (size * s) + v * (size * t));
        }
    }
    let normals = vec![normal; positions.len()];
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut triangles = Vec::with_capacity((2 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            // u x v = normal, so (i,j) -> (i+1,j) -> (i,j+1) is CCW.
            triangles.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
            triangles.push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    TriangleMesh::new(positions, normals, triangles)
}

fn cuboid(center: DVec3, half: DVec3, rotation: &glam::DMat3) -> TriangleMesh {
    let axes = [rotation.x_axis, rotation.y_axis, rotation.z_axis];
    let h = [half.x, half.y, half.z];
    let mut positions = Vec::with_capacity(24);
    let mut normals = Vec::with_capacity(24);
    let mut triangles = Vec::with_capacity(12);
    for a in 0..3 {
        for sign in [1.0, -1.0] {
            let n = axes[a] * sign;
            // (u, v) with u x v = n for a proper rotation: the face's
            // texture axes too.
            let face = 2 * a as u32 + u32::from(sign > 0.0);
            let ((u, hu), (v, hv)) = box_face_axes(rotation, half, face);
            let base = positions.len() as u32;
            for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                positions.push(center + n * h[a] + u * (hu * su) + v * (hv * sv));
                normals.push(n.normalize_or_zero());
            }
            triangles.push([base, base + 1, base + 2]);
            triangles.push([base, base + 2, base + 3]);
        }
    }
    TriangleMesh::new(positions, normals, triangles)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DMat3;

    #[test]
    fn counts_match_the_tessellation() {
        let mut shapes = Vec::new();
        for segments in [0, 3, 4, 5, 8, 33, 64] {
            shapes.push(Shape::Sphere {
                center: DVec3::ZERO,
                radius: 1.0,
                segments,
            });
            shapes.push(Shape::Plane {
                center: DVec3::ZERO,
                normal: DVec3::Y,
                size: 2.0,
                segments,
            });
        }
        shapes.push(Shape::Box {
            center: DVec3::ZERO,
            half_extents: DVec3::ONE,
            rotation: DMat3::IDENTITY,
        });
        let mesh = tessellate(&shapes[3]);
        shapes.push(Shape::Mesh(mesh));
        for shape in &shapes {
            let m = tessellate(shape);
            let expected = (m.positions.len() as u64, m.triangles.len() as u64);
            assert_eq!(counts(shape), expected, "{shape:?}");
        }
    }

    /// Every triangle's geometric normal agrees with its vertex normals and
    /// every normal is unit length.
    fn assert_consistent(mesh: &TriangleMesh) {
        assert_eq!(mesh.positions.len(), mesh.normals.len());
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let g = (b - a).cross(c - a);
            assert!(g.length() > 1e-12, "degenerate triangle {t:?}");
            for &i in t {
                let n = mesh.normals[i as usize];
                assert!((n.length() - 1.0).abs() < 1e-12);
                assert!(g.dot(n) > 0.0, "triangle {t:?} faces away from vertex {i}");
            }
        }
    }

    #[test]
    fn sphere_is_closed_ccw_and_on_the_sphere() {
        let center = DVec3::new(1.0, -2.0, 0.5);
        for segments in [3, 4, 8, 33, 64] {
            let mesh = tessellate(&Shape::Sphere {
                center,
                radius: 2.5,
                segments,
            });
            let bands = (segments / 2).max(2);
            assert_eq!(mesh.positions.len() as u32, segments * (bands - 1) + 2);
            assert_eq!(mesh.triangles.len() as u32, 2 * segments * (bands - 1));
            assert_consistent(&mesh);
            for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                assert!(((*p - center).length() - 2.5).abs() < 1e-12);
                assert!((((*p - center) / 2.5) - *n).length() < 1e-12);
            }
            // Closed surface: the signed volume equals the sphere's volume
            // approximation, positive when the winding is outward.
            let vol: f64 = mesh
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| mesh.positions[i as usize] - center);
                    a.dot(b.cross(c)) / 6.0
                })
                .sum();
            assert!(vol > 0.0);
        }
    }

    #[test]
    fn plane_grid_faces_its_normal() {
        for normal in [
            DVec3::Y,
            DVec3::NEG_Z,
            DVec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let mesh = tessellate(&Shape::Plane {
                center: DVec3::new(0.0, -1.0, 0.0),
                normal,
                size: 4.0,
                segments: 3,
            });
            assert_eq!(mesh.positions.len(), 16);
            assert_eq!(mesh.triangles.len(), 18);
            assert_consistent(&mesh);
            let area: f64 = mesh
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                    0.5 * (b - a).cross(c - a).length()
                })
                .sum();
            assert!((area - 16.0).abs() < 1e-9);
            assert!(mesh.normals.iter().all(|n| *n == normal));
        }
    }

    #[test]
    fn box_has_outward_faces() {
        let rotation = DMat3::from_rotation_z(0.3)
            * DMat3::from_rotation_y(-1.1)
            * DMat3::from_rotation_x(0.7);
        let center = DVec3::new(2.0, 0.0, -1.0);
        let mesh = tessellate(&Shape::Box {
            center,
            half_extents: DVec3::new(0.5, 1.0, 1.5),
            rotation,
        });
        assert_eq!(mesh.positions.len(), 24);
        assert_eq!(mesh.triangles.len(), 12);
        assert_consistent(&mesh);
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let centroid = (a + b + c) / 3.0;
            assert!((b - a).cross(c - a).dot(centroid - center) > 0.0);
        }
        let local = |p: DVec3| rotation.transpose() * (p - center);
        for p in &mesh.positions {
            let l = local(*p).abs();
            assert!((l - DVec3::new(0.5, 1.0, 1.5)).length() < 1e-12);
        }
    }

    #[test]
    fn mesh_is_cloned() {
        let m = TriangleMesh::new(
            vec![DVec3::ZERO, DVec3::X, DVec3::Y],
            vec![DVec3::Z; 3],
            vec![[0, 1, 2]],
        );
        assert_eq!(tessellate(&Shape::Mesh(m.clone())), m);
    }

    #[test]
    fn a_textured_sphere_carries_its_parameterisation_and_cuts_its_seam() {
        use crate::scene::texcoords::sphere_uv;
        let center = DVec3::new(1.0, 2.0, 3.0);
        let seg = 12;
        let m = tessellate_textured(&Shape::Sphere {
            center,
            radius: 2.0,
            segments: seg,
        });
        assert_eq!(m.uvs.len(), m.positions.len());
        for (n, uv) in m.normals.iter().zip(&m.uvs) {
            let want = sphere_uv(*n);
            assert!((uv.y - want.y).abs() < 1e-12, "{uv} at {n}");
            if n.y.abs() == 1.0 {
                continue; // a pole: u is the segment's
            }
            // On the seam either end of the range.
            let du = (uv.x - want.x).abs();
            assert!(du < 1e-12 || (du - 1.0).abs() < 1e-12, "{uv} at {n}");
        }
        for t in &m.triangles {
            let us = t.map(|i| m.uvs[i as usize].x);
            let span = us.iter().copied().fold(f64::MIN, f64::max)
                - us.iter().copied().fold(f64::MAX, f64::min);
            assert!(
                span <= 1.0 / f64::from(seg) + 1e-12,
                "{t:?} spans {span} in u"
            );
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            let outward = (b - a).cross(c - a).dot((a + b + c) / 3.0 - center);
            assert!(outward > 0.0, "{t:?} wound inward");
        }
    }

    #[test]
    fn textured_boxes_and_planes_take_the_same_coordinates_as_the_tracers() {
        use crate::scene::texcoords::{box_uv, plane_uv};
        let rotation = glam::DMat3::from_rotation_y(0.3) * glam::DMat3::from_rotation_x(0.2);
        let (center, half) = (DVec3::new(1.0, 0.0, -2.0), DVec3::new(0.5, 1.0, 1.5));
        let m = tessellate_textured(&Shape::Box {
            center,
            half_extents: half,
            rotation,
        });
        // Faces in the order `cuboid` makes them: + then - along x, y, z.
        let faces = [1, 0, 3, 2, 5, 4];
        for (k, (p, uv)) in m.positions.iter().zip(&m.uvs).enumerate() {
            let want = box_uv(*p - center, &rotation, half, faces[k / 4]);
            assert!(
                (*uv - want).length() < 1e-12,
                "vertex {k}: {uv} against {want}"
            );
        }
        let normal = DVec3::new(0.0, 1.0, 0.2).normalize();
        let m = tessellate_textured(&Shape::Plane {
            center,
            normal,
            size: 3.0,
            segments: 4,
        });
        let (u, v) = plane_axes(normal);
        assert_eq!(m.uvs[0], plane_uv(m.positions[0] - center, u, v, 3.0));
        // The first vertex is the bottom left corner, the last the top right.
        assert!((m.uvs[0] - DVec2::new(0.0, 1.0)).length() < 1e-12);
        assert!((m.uvs[24] - DVec2::new(1.0, 0.0)).length() < 1e-12);
    }
}
