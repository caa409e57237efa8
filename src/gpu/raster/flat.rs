//! The vertex layout flat shading draws: one vertex of its own per
//! triangle, so the formula runs once per face.
//!
//! A flat varying takes the value of the triangle's first (provoking)
//! vertex. Give every triangle a provoking vertex that provokes no other
//! triangle, and the vertex stage can compute the face's colour there:
//! vertex `f` (for `f` below the face count) belongs to face `f` and carries
//! nothing but a position; the vertex shader finds the face's record by its
//! index. The other two corners of a triangle reuse any vertex at the same
//! position, so an indexed draw runs about one vertex invocation per face,
//! where three vertices of its own per face would cost three. A vertex that
//! provokes no face (rare: the greedy choice below covers almost every
//! shared vertex) is appended after the faces' and carries a copy of a
//! neighbouring face's record, whose colour nothing uses.

use crate::gpu::raster::layout::GpuFace;
use crate::gpu::raster::scene::RasterGeometry;

pub struct FlatMesh {
    /// Camera-relative positions; vertex `f` below the face count is face
    /// `f`'s own.
    pub positions: Vec<[f32; 3]>,
    /// Three per triangle, in the order of `RasterGeometry::indices` (so a
    /// draw's `first_index` holds), each triangle rotated (winding kept)
    /// so its own vertex comes first.
    pub indices: Vec<u32>,
    /// One record per vertex: the faces' records, then copies for the
    /// appended vertices.
    pub faces: Vec<GpuFace>,
    /// Like `faces`, the faces' colours (`RasterGeometry::face_colors`),
    /// a second vertex stream; empty when the scene has no vertex colours.
    pub colors: Vec<[f32; 3]>,
}

const UNCOVERED: u32 = u32::MAX;

impl FlatMesh {
    pub fn new(geometry: &RasterGeometry) -> Self {
        let face_count = geometry.faces.len();
        let mut positions = Vec::with_capacity(face_count + face_count / 8);
        let mut faces = geometry.faces.clone();
        let mut colors = geometry.face_colors.clone();
        // For each shared vertex, the flat vertex at its position (the one
        // of the face it provokes), or UNCOVERED.
        let mut flat_vertex = vec![UNCOVERED; geometry.vertices.len()];
        // Each face's shared corners, rotated so its provoking one is first.
        let mut rotated_faces: Vec<[u32; 3]> = Vec::with_capacity(face_count);
        for tri in geometry.indices.chunks_exact(3) {
            let corners = [tri[0], tri[1], tri[2]];
            // Greedy: provoke from a corner no earlier face took, so that
            // corner needs no vertex of its own later.
            let first = (0..3)
                .find(|&k| flat_vertex[corners[k] as usize] == UNCOVERED)
                .unwrap_or(0);
            let rotated = [0, 1, 2].map(|k| corners[(first + k) % 3]);
            let own = rotated[0] as usize;
            if flat_vertex[own] == UNCOVERED {
                flat_vertex[own] = positions.len() as u32;
            }
            positions.push(geometry.vertices[own].position);
            rotated_faces.push(rotated);
        }
        let mut indices = Vec::with_capacity(face_count * 3);
        for (face, corners) in rotated_faces.iter().enumerate() {
            indices.push(face as u32);
            for &corner in &corners[1..] {
                let corner = corner as usize;
                if flat_vertex[corner] == UNCOVERED {
                    flat_vertex[corner] = positions.len() as u32;
                    positions.push(geometry.vertices[corner].position);
                    faces.push(faces[face]);
                    if !colors.is_empty() {
                        colors.push(colors[face]);
                    }
                }
                indices.push(flat_vertex[corner]);
            }
        }
        FlatMesh {
            positions,
            indices,
            faces,
            colors,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::View;
    use crate::gpu::raster::scene::build_geometry;
    use crate::scene::default_scene;

    /// The default scene: spheres, a box and a plane, several draws.
    fn geometry() -> RasterGeometry {
        let scene = default_scene();
        let view = View::new(&scene, 64, 64);
        build_geometry(&scene, &view, true)
    }

    #[test]
    fn every_triangle_keeps_its_corners_and_winding_and_provokes_its_own_record() {
        let g = geometry();
        let flat = FlatMesh::new(&g);
        assert_eq!(flat.indices.len(), g.indices.len());
        assert_eq!(flat.faces.len(), flat.positions.len());
        let mut face = 0;
        for (tri, flat_tri) in g.indices.chunks_exact(3).zip(flat.indices.chunks_exact(3)) {
            assert_eq!(
                flat_tri[0], face as u32,
                "face {face} provoked by another vertex"
            );
            let corner = |i: u32| g.vertices[i as usize].position;
            let expected = [corner(tri[0]), corner(tri[1]), corner(tri[2])];
            let got = [0, 1, 2].map(|k| flat.positions[flat_tri[k] as usize]);
            // Same triangle, same winding: `got` is a rotation of `expected`.
            let rotation = (0..3).find(|&r| (0..3).all(|k| got[k] == expected[(r + k) % 3]));
            assert!(
                rotation.is_some(),
                "face {face}: {got:?} is not {expected:?}"
            );
            assert_eq!(flat.faces[face].center, g.faces[face].center);
            assert_eq!(flat.faces[face].normal, g.faces[face].normal);
            face += 1;
        }
        assert_eq!(face, g.faces.len());
    }

    #[test]
    fn closed_meshes_need_few_vertices_beyond_one_per_face() {
        let g = geometry();
        let flat = FlatMesh::new(&g);
        let extra = flat.positions.len() - g.faces.len();
        // The greedy choice covers most shared vertices; three vertices of
        // its own per face would need twice the face count more.
        assert!(
            extra * 10 <= g.vertices.len(),
            "{extra} extra vertices for {} shared ones",
            g.vertices.len()
        );
    }
}
