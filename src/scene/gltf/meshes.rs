//! A primitive as a triangle mesh in world space: its accessors checked,
//! positions placed by the node's world matrix, the winding kept
//! counter-clockwise, degenerate triangles dropped, and normals stored or
//! computed (the rules are the `gltf` module docs' "Geometry").

use glam::{DMat3, DMat4, DVec2, DVec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use super::accessors::{check_accessor, f32x3};
use super::document::GltfFile;
use super::locations::mesh_name;
use super::vertex_attributes::{texture_coordinates, vertex_colors, UvUse};
use crate::scene::error::SceneError;
use crate::scene::model::TriangleMesh;

/// One primitive's triangles in world space, or `None` when skipped.
pub(super) fn primitive_mesh(
    file: &GltfFile,
    mesh: &gltf::Mesh,
    prim: &gltf::Primitive,
    world: DMat4,
    uv_use: Option<&UvUse>,
    warnings: &mut Vec<String>,
) -> Result<Option<TriangleMesh>, SceneError> {
    let what = format!("{}, primitive {}", mesh_name(mesh), prim.index());
    let Some(placement) = placement(file, &what, prim, world, warnings) else {
        return Ok(None);
    };
    let pos_acc = checked_accessors(file, &what, prim)?;
    let reader = prim.reader(|b| file.buffers.get(b.index()).map(|d| &d[..]));
    let positions = world_positions(file, &what, &pos_acc, &reader, world)?;
    let n = positions.len();
    let stored_normals = stored_normals(file, &what, prim, &reader, &placement, n, warnings);
    let colors = match prim.get(&gltf::Semantic::Colors(0)) {
        Some(acc) => vertex_colors(file, &what, &acc, &reader, n, warnings)?,
        None => Vec::new(),
    };
    let uvs = match uv_use {
        Some(used) => texture_coordinates(file, &what, prim, &reader, used, n)?,
        None => Vec::new(),
    };
    let indices = vertex_indices(file, &what, &reader, n, warnings)?;
    let triangles = kept_triangles(file, &what, &indices, &positions, placement.flip, warnings)?;
    let attributes = VertexAttributes { colors, uvs };
    Ok(Some(build_mesh(
        positions,
        stored_normals,
        attributes,
        triangles,
    )))
}

/// How a primitive's world matrix acts on its normals and its winding.
struct Placement {
    /// The inverse transpose of the matrix's upper 3x3.
    normal_matrix: DMat3,
    /// The matrix mirrors (`det < 0`): triangles are wound the other way.
    flip: bool,
}

/// The primitive's [`Placement`] under `world`, or `None` (with a warning)
/// when it is skipped: a mode other than TRIANGLES, or a singular node
/// transform.
fn placement(
    file: &GltfFile,
    what: &str,
    prim: &gltf::Primitive,
    world: DMat4,
    warnings: &mut Vec<String>,
) -> Option<Placement> {
    if prim.mode() != Mode::Triangles {
        warnings.push(format!(
            "{}: {what} has mode {:?}; only TRIANGLES is drawn, so it was skipped",
            file.label,
            prim.mode()
        ));
        return None;
    }
    let m3 = DMat3::from_mat4(world);
    let det = m3.determinant();
    if det == 0.0 || !det.is_finite() {
        warnings.push(format!(
            "{}: {what} has a singular node transform (a zero scale), so it was skipped",
            file.label
        ));
        return None;
    }
    Some(Placement {
        normal_matrix: m3.inverse().transpose(),
        flip: det < 0.0,
    })
}

/// Checks the accessors of the primitive's POSITION, NORMAL and indices
/// (`check_accessor`), and returns POSITION's.
fn checked_accessors<'a>(
    file: &GltfFile,
    what: &str,
    prim: &gltf::Primitive<'a>,
) -> Result<gltf::Accessor<'a>, SceneError> {
    let pos_acc = prim.get(&gltf::Semantic::Positions).ok_or_else(|| {
        SceneError::mesh(&file.label, format!("{what} has no POSITION attribute"))
    })?;
    let pos_what = format!("{what} POSITION");
    check_accessor(
        file,
        &pos_what,
        &pos_acc,
        Dimensions::Vec3,
        &[DataType::F32],
    )?;
    if let Some(acc) = &prim.get(&gltf::Semantic::Normals) {
        check_accessor(
            file,
            &format!("{what} NORMAL"),
            acc,
            Dimensions::Vec3,
            &[DataType::F32],
        )?;
    }
    if let Some(acc) = prim.indices() {
        check_accessor(
            file,
            &format!("{what} indices"),
            &acc,
            Dimensions::Scalar,
            &[DataType::U8, DataType::U16, DataType::U32],
        )?;
    }
    Ok(pos_acc)
}

/// The primitive's positions placed by `world`; one that is not finite
/// there is an error naming the vertex.
fn world_positions<'a, 's, F>(
    file: &GltfFile,
    what: &str,
    pos_acc: &gltf::Accessor,
    reader: &gltf::mesh::Reader<'a, 's, F>,
    world: DMat4,
) -> Result<Vec<DVec3>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let pos_what = format!("{what} POSITION");
    let local: Vec<[f32; 3]> = reader
        .read_positions()
        .ok_or_else(|| SceneError::mesh(&file.label, format!("{pos_what} cannot be read")))?
        .collect();
    if local.len() != pos_acc.count() || local.len() > u32::MAX as usize {
        return Err(SceneError::mesh(
            &file.label,
            format!(
                "{pos_what} (accessor {}) could not be read completely",
                pos_acc.index()
            ),
        ));
    }
    let mut positions = Vec::with_capacity(local.len());
    for (i, p) in local.iter().enumerate() {
        let w = world.transform_point3(f32x3(*p));
        if !w.is_finite() {
            let why = if p.iter().all(|c| c.is_finite()) {
                "overflows to infinity under the node transform"
            } else {
                "is not a finite number"
            };
            return Err(SceneError::mesh(
                &file.label,
                format!(
                    "{pos_what} (accessor {}) vertex {i} {why}; expected finite coordinates",
                    pos_acc.index()
                ),
            ));
        }
        positions.push(w);
    }
    Ok(positions)
}

/// The primitive's stored normals in world space (zero where they cannot
/// be normalised), or `None` when it has none or not one per vertex (then
/// with a warning): `build_mesh` computes them.
fn stored_normals<'a, 's, F>(
    file: &GltfFile,
    what: &str,
    prim: &gltf::Primitive,
    reader: &gltf::mesh::Reader<'a, 's, F>,
    placement: &Placement,
    n: usize,
    warnings: &mut Vec<String>,
) -> Option<Vec<DVec3>>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let nrm_acc = prim.get(&gltf::Semantic::Normals);
    match (&nrm_acc, reader.read_normals()) {
        (Some(_), Some(it)) => {
            let v: Vec<DVec3> = it
                .map(|nv| (placement.normal_matrix * f32x3(nv)).normalize_or_zero())
                .collect();
            if v.len() == n {
                Some(v)
            } else {
                warnings.push(format!(
                    "{}: {what} has {} normals for {n} positions; normals were recomputed",
                    file.label,
                    v.len()
                ));
                None
            }
        }
        _ => None,
    }
}

/// The primitive's vertex indices (`0..n` without an index accessor), each
/// below the vertex count `n`; a count that is not a multiple of 3 leaves
/// the rest out, with a warning.
fn vertex_indices<'a, 's, F>(
    file: &GltfFile,
    what: &str,
    reader: &gltf::mesh::Reader<'a, 's, F>,
    n: usize,
    warnings: &mut Vec<String>,
) -> Result<Vec<u32>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let indices: Vec<u32> = match reader.read_indices() {
        Some(it) => it.into_u32().collect(),
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(SceneError::mesh(
            &file.label,
            format!(
                "{what} uses vertex index {bad} but POSITION has only {n} vertices; expected indices below {n}"
            ),
        ));
    }
    if indices.len() % 3 != 0 {
        warnings.push(format!(
            "{}: {what} has {} indices, not a multiple of 3; the last {} were ignored",
            file.label,
            indices.len(),
            indices.len() % 3
        ));
    }
    Ok(indices)
}

/// The triangles of `indices`, wound the other way when the placement
/// mirrors (`flip`), without the degenerate ones (counted in a warning);
/// none left is an error.
fn kept_triangles(
    file: &GltfFile,
    what: &str,
    indices: &[u32],
    positions: &[DVec3],
    flip: bool,
    warnings: &mut Vec<String>,
) -> Result<Vec<[u32; 3]>, SceneError> {
    let mut triangles = Vec::with_capacity(indices.len() / 3);
    let mut dropped = 0usize;
    for t in indices.chunks_exact(3) {
        let mut tri = [t[0], t[1], t[2]];
        if flip {
            tri.swap(1, 2);
        }
        if is_degenerate(positions, tri) {
            dropped += 1;
        } else {
            triangles.push(tri);
        }
    }
    if dropped > 0 {
        warnings.push(format!(
            "{}: {what}: dropped {dropped} degenerate triangle(s) (repeated vertex or zero area)",
            file.label
        ));
    }
    if triangles.is_empty() {
        return Err(SceneError::mesh(
            &file.label,
            format!("{what} has no non-degenerate triangle; expected at least one triangle with non-zero area"),
        ));
    }
    Ok(triangles)
}

/// The degenerate-triangle rule documented in the `gltf` module docs.
pub(crate) fn is_degenerate(positions: &[DVec3], t: [u32; 3]) -> bool {
    if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
        return true;
    }
    let (Some(a), Some(b), Some(c)) = (
        positions.get(t[0] as usize),
        positions.get(t[1] as usize),
        positions.get(t[2] as usize),
    ) else {
        return true;
    };
    let (e1, e2, e3) = (*b - *a, *c - *a, *c - *b);
    let longest = e1
        .length_squared()
        .max(e2.length_squared())
        .max(e3.length_squared());
    let twice_area = e1.cross(e2).length();
    let well_shaped = twice_area.is_finite() && twice_area > 1e-12 * longest;
    !well_shaped
}

/// Compacts the vertices to those the kept triangles use and fills in the
/// normals (rule in the `gltf` module docs). `triangles` must be in range.
/// What a vertex may carry besides its position and normal, each list
/// empty or one per vertex.
struct VertexAttributes {
    colors: Vec<DVec3>,
    uvs: Vec<DVec2>,
}

fn build_mesh(
    positions: Vec<DVec3>,
    stored: Option<Vec<DVec3>>,
    attributes: VertexAttributes,
    triangles: Vec<[u32; 3]>,
) -> TriangleMesh {
    // Keep the used vertices in their original order.
    let mut used = vec![false; positions.len()];
    for t in &triangles {
        for &i in t {
            used[i as usize] = true;
        }
    }
    let mut remap = vec![0u32; positions.len()];
    let mut out_pos = Vec::new();
    let mut out_stored = Vec::new();
    let mut out_colors = Vec::new();
    let mut out_uvs = Vec::new();
    for (i, p) in positions.iter().enumerate() {
        if used[i] {
            remap[i] = out_pos.len() as u32;
            out_pos.push(*p);
            out_stored.push(stored.as_ref().map_or(DVec3::ZERO, |s| s[i]));
            out_colors.extend(attributes.colors.get(i));
            out_uvs.extend(attributes.uvs.get(i));
        }
    }
    let tris: Vec<[u32; 3]> = triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .collect();
    let mut sum = vec![DVec3::ZERO; out_pos.len()];
    let mut first_face = vec![DVec3::ZERO; out_pos.len()];
    for t in &tris {
        let [a, b, c] = t.map(|i| out_pos[i as usize]);
        let face = (b - a).cross(c - a);
        for &i in t {
            sum[i as usize] += face;
            if first_face[i as usize] == DVec3::ZERO {
                first_face[i as usize] = face.normalize_or_zero();
            }
        }
    }
    let normals = out_stored
        .iter()
        .zip(sum.iter().zip(&first_face))
        .map(|(s, (area, first))| {
            if s.is_finite() && s.length_squared() > 0.0 {
                *s
            } else {
                let n = area.normalize_or_zero();
                if n == DVec3::ZERO {
                    *first
                } else {
                    n
                }
            }
        })
        .collect();
    TriangleMesh {
        positions: out_pos,
        normals,
        triangles: tris,
        colors: out_colors,
        uvs: out_uvs,
    }
}

#[cfg(test)]
mod tests {
    use glam::{DMat4, DVec3};

    use super::is_degenerate;
    use crate::scene::gltf::test_support::{
        assert_winding_matches_normals, err_of, fixture, meshes, only_mesh, write_gltf,
    };

    #[test]
    fn unindexed_primitive_uses_sequential_indices_and_default_material() {
        let l = meshes(&fixture("tri_unindexed.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert_eq!(m.triangles, vec![[0, 1, 2], [3, 4, 5]]);
        assert_eq!(m.positions.len(), 6);
        let mat = &l.materials[l.objects[0].material];
        assert_eq!(mat.name, "tri_unindexed/default");
        assert_eq!(
            (mat.color, mat.ka, mat.kd, mat.ks, mat.p),
            (DVec3::splat(0.8), 0.2, 0.8, 0.0, 32.0)
        );
    }

    #[test]
    fn missing_normals_are_area_weighted() {
        let l = meshes(&fixture("no_normals.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert_eq!(m.triangles.len(), 4);
        let expected = [DVec3::splat(-1.0).normalize(), DVec3::X, DVec3::Y, DVec3::Z];
        for (n, e) in m.normals.iter().zip(expected) {
            assert!((*n - e).length() < 1e-12, "{n} != {e}");
        }
    }

    #[test]
    fn mirrored_node_flips_the_winding() {
        let l = meshes(&fixture("mirrored.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert!(m.positions.contains(&DVec3::new(-1.0, 0.0, 0.0)));
        assert_eq!(m.normals, vec![DVec3::Z; 3]);
        assert_winding_matches_normals(m);
        assert_eq!(m.triangles, vec![[0, 2, 1]]);
    }

    #[test]
    fn degenerate_triangles_are_dropped_with_a_warning() {
        let l = meshes(&fixture("degenerate.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        assert_eq!(m.triangles.len(), 2);
        assert_eq!(
            m.positions.len(),
            4,
            "the unused midpoint vertex is removed"
        );
        assert_eq!(m.normals, vec![DVec3::Z; 4]);
        assert_eq!(l.warnings.len(), 1);
        assert!(
            l.warnings[0].contains("dropped 2 degenerate"),
            "{:?}",
            l.warnings
        );
        assert!(l.warnings[0].contains("degenerate.gltf"));
    }

    #[test]
    fn degenerate_rule_is_relative() {
        let tiny = [
            DVec3::ZERO,
            DVec3::new(1e-9, 0.0, 0.0),
            DVec3::new(0.0, 1e-9, 0.0),
        ];
        assert!(!is_degenerate(&tiny, [0, 1, 2]), "small but well-shaped");
        let sliver = [
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(2.0, 1e-14, 0.0),
        ];
        assert!(is_degenerate(&sliver, [0, 1, 2]));
        assert!(is_degenerate(&tiny, [0, 0, 2]));
    }

    #[test]
    fn bad_geometry_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let p = write_gltf(dir.path(), "oob", &tri, None, Some(&[0, 1, 7]), |_| {});
        let e = err_of(&p);
        assert!(
            e.contains("oob.gltf") && e.contains("index 7") && e.contains("3 vertices"),
            "{e}"
        );
        let p = write_gltf(
            dir.path(),
            "flat",
            &tri,
            None,
            Some(&[0, 1, 1, 2, 2, 2]),
            |_| {},
        );
        let e = err_of(&p);
        assert!(
            e.contains("flat.gltf") && e.contains("no non-degenerate triangle"),
            "{e}"
        );
        let p = write_gltf(dir.path(), "nobin", &tri, None, None, |d| {
            d["buffers"][0]["uri"] = "missing.bin".into();
        });
        let e = err_of(&p);
        assert!(
            e.contains("nobin.gltf") && e.contains("`missing.bin`, which does not exist"),
            "{e}"
        );
        let p = write_gltf(dir.path(), "vec2", &tri, None, None, |d| {
            d["accessors"][0]["type"] = "VEC2".into();
        });
        let e = err_of(&p);
        assert!(e.contains("vec2.gltf") && e.contains("POSITION"), "{e}");
        let p = write_gltf(dir.path(), "toolong", &tri, None, None, |d| {
            d["accessors"][0]["count"] = 1000.into();
        });
        let e = err_of(&p);
        assert!(e.contains("toolong.gltf"), "{e}");
        let p = write_gltf(dir.path(), "zeroscale", &tri, None, None, |d| {
            d["nodes"][0]["scale"] = serde_json::json!([1.0, 0.0, 1.0]);
        });
        let e = err_of(&p);
        assert!(
            e.contains("zeroscale.gltf") && e.contains("no triangle mesh"),
            "{e}"
        );
        let p = write_gltf(dir.path(), "badref", &tri, None, None, |d| {
            d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9.into();
        });
        let e = err_of(&p);
        assert!(e.contains("badref.gltf") && e.contains("accessor 9"), "{e}");
        let p = write_gltf(dir.path(), "cycle", &tri, None, None, |d| {
            d["nodes"] = serde_json::json!([{"mesh": 0, "children": [1]}, {"children": [0]}]);
        });
        let e = err_of(&p);
        assert!(
            e.contains("cycle.gltf") && e.contains("more than once"),
            "{e}"
        );
        let p = write_gltf(dir.path(), "dag", &tri, None, None, |d| {
            d["nodes"] = serde_json::json!([{"children": [1, 2]}, {"children": [2]}, {"mesh": 0}]);
        });
        let e = err_of(&p);
        assert!(e.contains("dag.gltf") && e.contains("node 2"), "{e}");
    }

    #[test]
    fn zero_or_nan_stored_normals_are_recomputed() {
        let dir = tempfile::tempdir().unwrap();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let normals = [[0.0, 0.0, 0.0], [f32::NAN, 0.0, 1.0], [0.0, 0.0, 2.0]];
        let p = write_gltf(dir.path(), "zn", &tri, Some(&normals), None, |_| {});
        let l = meshes(&p, DMat4::IDENTITY).unwrap();
        assert_eq!(only_mesh(&l).normals, vec![DVec3::Z; 3]);
    }
}
