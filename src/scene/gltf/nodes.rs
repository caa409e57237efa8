//! The node hierarchy: each node's local transform, the depth-first walk
//! that composes them into world matrices (disjoint trees, as glTF
//! requires), and the geometry the nodes instance, counted before any of
//! it is built.

use glam::{DMat4, DQuat};

use super::accessors::f32x3;
use super::document::GltfFile;
use super::locations::node_name;
use crate::scene::error::SceneError;
use crate::scene::footprint::GeometrySize;

fn local_matrix(label: &str, node: &gltf::Node) -> Result<DMat4, SceneError> {
    let m = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let cols: Vec<f64> = matrix.iter().flatten().map(|&x| f64::from(x)).collect();
            let mut arr = [0.0; 16];
            arr.copy_from_slice(&cols);
            DMat4::from_cols_array(&arr)
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let q = DQuat::from_xyzw(
                f64::from(rotation[0]),
                f64::from(rotation[1]),
                f64::from(rotation[2]),
                f64::from(rotation[3]),
            );
            // Renormalise in f64 so f32-rounded unit quaternions stay exact.
            let q = if q.length() > 0.0 {
                q.normalize()
            } else {
                DQuat::IDENTITY
            };
            DMat4::from_scale_rotation_translation(f32x3(scale), q, f32x3(translation))
        }
    };
    if !m.is_finite() {
        return Err(SceneError::mesh(
            label,
            format!("{} has a non-finite transform", node_name(node)),
        ));
    }
    Ok(m)
}

/// Calls `visit` on every node reachable from the scene's roots with its
/// world matrix, in depth-first order. Nothing is kept per node: a file
/// instancing a mesh millions of times has millions of nodes.
pub(super) fn walk_nodes<'a>(
    file: &'a GltfFile,
    mut visit: impl FnMut(gltf::Node<'a>, &DMat4) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    let roots: Vec<gltf::Node> = match file
        .doc
        .default_scene()
        .or_else(|| file.doc.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; file.doc.nodes().len()];
            for n in file.doc.nodes() {
                for c in n.children() {
                    if let Some(flag) = is_child.get_mut(c.index()) {
                        *flag = true;
                    }
                }
            }
            file.doc
                .nodes()
                .filter(|n| !is_child.get(n.index()).copied().unwrap_or(false))
                .collect()
        }
    };
    let mut visited = vec![false; file.doc.nodes().len()];
    let mut stack: Vec<(gltf::Node, DMat4)> = Vec::new();
    for root in roots {
        stack.push((root, DMat4::IDENTITY));
        while let Some((node, parent)) = stack.pop() {
            match visited.get_mut(node.index()) {
                Some(seen) if !*seen => *seen = true,
                _ => {
                    return Err(SceneError::mesh(
                        &file.label,
                        format!(
                            "{} appears more than once in the node hierarchy (a cycle or several parents); expected disjoint trees as glTF requires",
                            node_name(&node)
                        ),
                    ))
                }
            }
            let world = parent * local_matrix(&file.label, &node)?;
            let children: Vec<gltf::Node> = node.children().collect();
            for child in children.into_iter().rev() {
                stack.push((child, world));
            }
            visit(node, &world)?;
        }
    }
    Ok(())
}

/// The geometry the file's nodes instance, counted from accessor sizes
/// alone: what loading it would build.
pub(super) fn instanced_size(file: &GltfFile) -> Result<GeometrySize, SceneError> {
    let mut size = GeometrySize::default();
    walk_nodes(file, |node, _| {
        for prim in node.mesh().iter().flat_map(|m| m.primitives()) {
            let Some(positions) = prim.get(&gltf::Semantic::Positions) else {
                continue;
            };
            let vertices = positions.count() as u64;
            let corners = prim.indices().map_or(vertices, |i| i.count() as u64);
            size.add(1, vertices, corners / 3);
            // Counted whenever the file has them: coordinates are read only
            // for a texture or pattern, which is not known here, so this may
            // count more.
            let attributed = prim.attributes().any(|(s, _)| {
                matches!(s, gltf::Semantic::Colors(0) | gltf::Semantic::TexCoords(_))
            });
            if attributed {
                size.add_attributed(vertices, corners / 3);
            }
        }
        Ok(())
    })?;
    Ok(size)
}

#[cfg(test)]
mod tests {
    use glam::{DMat4, DVec3};

    use crate::scene::gltf::test_support::{fixture, meshes, only_mesh};

    #[test]
    fn hierarchy_composes_node_transforms() {
        let l = meshes(&fixture("hierarchy.gltf"), DMat4::IDENTITY).unwrap();
        let m = only_mesh(&l);
        let expected = [
            DVec3::new(1.0, 4.0, 3.0),
            DVec3::new(-1.0, 2.0, 3.0),
            DVec3::new(1.0, 2.0, 5.0),
        ];
        for (p, e) in m.positions.iter().zip(expected) {
            assert!((*p - e).length() < 1e-9, "{p} != {e}");
        }
        // Computed normals of a single triangle are its face normal.
        let face = (expected[1] - expected[0])
            .cross(expected[2] - expected[0])
            .normalize();
        for n in &m.normals {
            assert!((*n - face).length() < 1e-9);
        }
        // A post transform (the TOML mesh object's T * R * S) applies after.
        let post = DMat4::from_translation(DVec3::new(0.0, 0.0, -3.0));
        let l = meshes(&fixture("hierarchy.gltf"), post).unwrap();
        assert!((only_mesh(&l).positions[2] - DVec3::new(1.0, 2.0, 2.0)).length() < 1e-9);
    }
}
