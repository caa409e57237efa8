//! What a glTF file contributes to a scene: its size checked against the
//! limit, then every primitive of every node as an object with its
//! material (the file's own, mapped once per file, or one given to all of
//! it), and the nodes that carry a camera or a light.

use std::collections::HashMap;

use glam::DMat4;

use super::document::GltfFile;
use super::locations::material_label;
use super::materials::{default_material, file_material, push_material};
use super::meshes::primitive_mesh;
use super::nodes::{instanced_size, walk_nodes};
use super::textures::base_colour_set;
use super::vertex_attributes::UvUse;
use crate::scene::error::SceneError;
use crate::scene::footprint::LoadLimits;
use crate::scene::image_file::TextureStore;
use crate::scene::model::{Material, Object, Shape};

/// What a glTF file contributes to a scene.
pub(super) struct Contents<'a> {
    pub(super) objects: Vec<Object>,
    /// The nodes that carry a camera or a light, with their world matrices,
    /// in depth-first order.
    pub(super) nodes: Vec<(gltf::Node<'a>, DMat4)>,
}

/// How one glTF file is being loaded into a scene: the limit, and the
/// scene's textures so far.
pub(crate) struct Loading<'s> {
    pub limits: &'s LoadLimits,
    pub textures: &'s mut TextureStore,
}

/// The objects of `file` placed by `post * node_world`, each with
/// `material_override` or the file's own material (added to `materials`),
/// and the nodes that carry a camera or a light. Refused before anything
/// is built when its geometry would not fit `loading.limits`.
pub(super) fn contents<'a>(
    file: &'a GltfFile,
    post: DMat4,
    material_override: Option<usize>,
    materials: &mut Vec<Material>,
    warnings: &mut Vec<String>,
    loading: &mut Loading,
) -> Result<Contents<'a>, SceneError> {
    let size = instanced_size(file)?;
    loading.limits.check(&file.label, &size)?;
    let geometry = size.model_bytes();
    let mut per_file: HashMap<Option<usize>, usize> = HashMap::new();
    let mut objects = Vec::with_capacity(size.objects as usize);
    let mut nodes = Vec::new();
    walk_nodes(file, |node, world| {
        if node.camera().is_some() || node.light().is_some() {
            nodes.push((node.clone(), *world));
        }
        let Some(mesh) = node.mesh() else {
            return Ok(());
        };
        for prim in mesh.primitives() {
            let uv_use = uv_use(file, &prim, material_override, materials);
            let at = post * *world;
            let Some(tri) = primitive_mesh(file, &mesh, &prim, at, uv_use.as_ref(), warnings)?
            else {
                continue;
            };
            let material = match material_override {
                Some(i) => i,
                None => {
                    let mat = prim.material();
                    let table = &mut per_file;
                    file_material_index(file, &mat, table, materials, geometry, loading, warnings)?
                }
            };
            objects.push(Object {
                shape: Shape::Mesh(tri),
                material,
            });
        }
        Ok(())
    })?;
    if objects.is_empty() {
        return Err(SceneError::mesh(
            &file.label,
            "contains no triangle mesh in its scene; expected at least one mesh primitive with mode TRIANGLES",
        ));
    }
    Ok(Contents { objects, nodes })
}

/// Which texture coordinates a primitive's material reads, if any.
/// Texture coordinates are read only for a material that uses them: a
/// TOML material with a pattern or texture given to the whole file
/// (TEXCOORD_0), or the file's own material with a base colour texture
/// (its set).
fn uv_use(
    file: &GltfFile,
    prim: &gltf::Primitive,
    material_override: Option<usize>,
    materials: &[Material],
) -> Option<UvUse> {
    match material_override {
        Some(i) => materials[i].pattern.as_ref().map(|p| UvUse {
            set: 0,
            user: format!(
                "the {} of material `{}`",
                if p.image().is_some() {
                    "texture"
                } else {
                    "pattern"
                },
                materials[i].name
            ),
        }),
        None => {
            let mat = prim.material();
            base_colour_set(file, &mat).map(|set| UvUse {
                set,
                user: format!(
                    "the base colour texture of material `{}`",
                    material_label(&mat)
                ),
            })
        }
    }
}

/// The index in `materials` of the file's material `mat`, mapped (with its
/// texture, counted against the limit beside the file's `geometry` bytes,
/// and its warnings) the first time a primitive uses it. `per_file` holds
/// the index of each of the file's materials mapped so far (`None`: the
/// default material of primitives without one).
fn file_material_index(
    file: &GltfFile,
    mat: &gltf::Material,
    per_file: &mut HashMap<Option<usize>, usize>,
    materials: &mut Vec<Material>,
    geometry: u64,
    loading: &mut Loading,
    warnings: &mut Vec<String>,
) -> Result<usize, SceneError> {
    let key = mat.index();
    if let Some(&i) = per_file.get(&key) {
        return Ok(i);
    }
    let m = match key {
        Some(_) => file_material(
            file,
            mat,
            loading.textures,
            loading.limits,
            geometry,
            warnings,
        )?,
        None => default_material(format!("{}/default", file.stem)),
    };
    let i = push_material(materials, m);
    per_file.insert(key, i);
    Ok(i)
}
