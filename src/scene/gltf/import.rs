//! The importer's entry points: a glTF file's meshes for a TOML `mesh`
//! object, or a glTF file (on disk or in memory) as a whole scene.

use std::path::Path;

use glam::DMat4;

use super::cameras_and_lights::{
    bounds, framing_camera, light_at_camera, node_camera, point_lights,
};
use super::contents::{contents, Contents, Loading};
use super::document::{open, parse, GltfFile};
use crate::scene::error::SceneError;
use crate::scene::footprint::LoadLimits;
use crate::scene::image_file::TextureStore;
use crate::scene::model::{ImageSettings, Lighting, Material, Object, RenderSettings, Scene};

/// Loads every mesh of the glTF file at `path` for a TOML `mesh` object:
/// world transform `post * node_world`, materials either `material_override`
/// or the file's own (added to `materials`). Returns the objects.
pub(crate) fn load_meshes(
    path: &Path,
    post: DMat4,
    material_override: Option<usize>,
    materials: &mut Vec<Material>,
    warnings: &mut Vec<String>,
    loading: &mut Loading,
) -> Result<Vec<Object>, SceneError> {
    let file = open(path)?;
    Ok(contents(&file, post, material_override, materials, warnings, loading)?.objects)
}

/// Loads a glTF file as a whole scene (rules in the crate docs of `scene`):
/// its meshes, the first perspective camera of the node tree (else a camera
/// framing the bounding box), and its point lights.
pub(crate) fn load_scene(path: &Path, limits: &LoadLimits) -> Result<Scene, SceneError> {
    scene_of(&open(path)?, limits)
}

/// A glTF or GLB held in memory as a whole scene, as
/// [`scene::load_within`](crate::scene::load_within) reads a file; `label`
/// names it in messages, external buffers are read from `base`.
pub fn scene_from_slice(
    bytes: &[u8],
    label: &str,
    base: &Path,
    limits: &LoadLimits,
) -> Result<Scene, SceneError> {
    let file = parse(bytes, label.to_string(), "scene".to_string(), base)?;
    scene_of(&file, limits)
}

/// The file as a whole scene: its contents, then the camera and lights
/// from its nodes (or framing and lighting it), with the default image,
/// lighting and render settings.
fn scene_of(file: &GltfFile, limits: &LoadLimits) -> Result<Scene, SceneError> {
    let mut materials = Vec::new();
    let mut warnings = Vec::new();
    let mut textures = TextureStore::default();
    let Contents { objects, nodes } = contents(
        file,
        DMat4::IDENTITY,
        None,
        &mut materials,
        &mut warnings,
        &mut Loading {
            limits,
            textures: &mut textures,
        },
    )?;
    let (lo, hi) = bounds(&objects);
    let camera = node_camera(file, &nodes, &mut warnings).unwrap_or_else(|| framing_camera(lo, hi));
    let mut lights = point_lights(file, &nodes, &mut warnings)?;
    if lights.is_empty() {
        let center = (lo + hi) * 0.5;
        lights.push(light_at_camera(file, &camera, center, &mut warnings));
    }
    Ok(Scene {
        camera,
        image: ImageSettings::default(),
        lighting: Lighting::default(),
        lights,
        materials,
        objects,
        render: RenderSettings::default(),
        lighting_hook: None,
        warnings,
    })
}
