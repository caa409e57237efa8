//! What the importer's unit tests share: fixtures, loading a file as a TOML
//! `mesh` object does, and writing or patching small glTF files.

use std::path::{Path, PathBuf};

use glam::DMat4;

use super::contents::Loading;
use super::import::load_meshes;
use crate::scene::error::SceneError;
use crate::scene::footprint::LoadLimits;
use crate::scene::image_file::TextureStore;
use crate::scene::model::{Material, Object, Shape, TriangleMesh};

pub(super) fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

pub(super) struct Loaded {
    pub(super) objects: Vec<Object>,
    pub(super) materials: Vec<Material>,
    pub(super) warnings: Vec<String>,
}

pub(super) fn meshes(path: &Path, post: DMat4) -> Result<Loaded, SceneError> {
    let mut materials = Vec::new();
    let mut warnings = Vec::new();
    let objects = load_meshes(
        path,
        post,
        None,
        &mut materials,
        &mut warnings,
        &mut Loading {
            limits: &LoadLimits::default(),
            textures: &mut TextureStore::default(),
        },
    )?;
    Ok(Loaded {
        objects,
        materials,
        warnings,
    })
}

pub(super) fn only_mesh(l: &Loaded) -> &TriangleMesh {
    assert_eq!(l.objects.len(), 1);
    match &l.objects[0].shape {
        Shape::Mesh(m) => m,
        other => panic!("{other:?}"),
    }
}

pub(super) fn err_of(path: &Path) -> String {
    match meshes(path, DMat4::IDENTITY) {
        Ok(_) => panic!("{} should not load", path.display()),
        Err(e) => e.to_string(),
    }
}

/// Geometric normals agree with the vertex normals, which are unit.
pub(super) fn assert_winding_matches_normals(m: &TriangleMesh) {
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        let g = (b - a).cross(c - a);
        for &i in t {
            let n = m.normals[i as usize];
            assert!((n.length() - 1.0).abs() < 1e-12);
            assert!(g.dot(n) > 0.0, "triangle {t:?} disagrees with normal {n}");
        }
    }
}

/// Writes a glTF with an external .bin: f32 positions, optional f32
/// normals, optional u32 indices. `patch` edits the JSON afterwards.
pub(super) fn write_gltf(
    dir: &Path,
    name: &str,
    positions: &[[f32; 3]],
    normals: Option<&[[f32; 3]]>,
    indices: Option<&[u32]>,
    patch: impl FnOnce(&mut serde_json::Value),
) -> PathBuf {
    use serde_json::json;
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut attributes = serde_json::Map::new();
    let mut add_vec3 = |bin: &mut Vec<u8>, data: &[[f32; 3]]| {
        let offset = bin.len();
        for v in data {
            for c in v {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len() * 12}));
        accessors.push(json!({"bufferView": views.len() - 1, "componentType": 5126,
                              "count": data.len(), "type": "VEC3",
                              "min": [-1e9, -1e9, -1e9], "max": [1e9, 1e9, 1e9]}));
        accessors.len() - 1
    };
    attributes.insert("POSITION".into(), json!(add_vec3(&mut bin, positions)));
    if let Some(n) = normals {
        attributes.insert("NORMAL".into(), json!(add_vec3(&mut bin, n)));
    }
    let mut prim = json!({"attributes": attributes});
    if let Some(idx) = indices {
        let offset = bin.len();
        for i in idx {
            bin.extend_from_slice(&i.to_le_bytes());
        }
        views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": idx.len() * 4}));
        accessors.push(json!({"bufferView": views.len() - 1, "componentType": 5125,
                              "count": idx.len(), "type": "SCALAR"}));
        prim["indices"] = json!(accessors.len() - 1);
    }
    let bin_name = format!("{name}.bin");
    std::fs::write(dir.join(&bin_name), &bin).unwrap();
    let mut doc = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "m", "primitives": [prim]}],
        "buffers": [{"uri": bin_name, "byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors,
    });
    patch(&mut doc);
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    path
}

/// The fixture `name` (tests/data) with `patch` applied, loaded from a
/// scratch folder: what it gives, or its error's message.
pub(super) fn load_patched_fixture(
    name: &str,
    patch: impl FnOnce(&mut serde_json::Value),
) -> Result<Loaded, String> {
    load_patched(&fixture(name), patch)
}

/// The glTF JSON at `path` with `patch` applied, written to a folder
/// of its own (its buffers and images must be data URIs), and what
/// loading it says.
pub(super) fn load_patched(
    path: &std::path::Path,
    patch: impl FnOnce(&mut serde_json::Value),
) -> Result<Loaded, String> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    patch(&mut doc);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("patched.gltf");
    std::fs::write(&path, doc.to_string()).unwrap();
    meshes(&path, DMat4::IDENTITY).map_err(|e| e.to_string())
}
