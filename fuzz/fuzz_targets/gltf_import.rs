//! The glTF/GLB importer on arbitrary bytes: an error or a scene, never a
//! panic. External buffers resolve in an empty folder; the memory limit
//! keeps an input that instances a mesh a million times from taking the
//! run's memory.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shadelab::scene::gltf_import::scene_from_slice;
use shadelab::scene::LoadLimits;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let limits = LoadLimits {
        max_bytes: 64 << 20,
        source: "fuzz".into(),
    };
    if let Ok(scene) = scene_from_slice(
        data,
        "fuzz.gltf",
        Path::new("/nonexistent-fuzz-dir"),
        &limits,
    ) {
        // What a loaded scene promises (`scene::model`): finite numbers,
        // valid material indices, unit normals, vertex colours per vertex.
        assert!(scene.camera.position.is_finite());
        for object in &scene.objects {
            assert!(object.material < scene.materials.len());
            if let shadelab::scene::Shape::Mesh(m) = &object.shape {
                assert!(!m.triangles.is_empty());
                assert!(m.positions.iter().all(|p| p.is_finite()));
                assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-6));
                assert!(m
                    .triangles
                    .iter()
                    .flatten()
                    .all(|&i| (i as usize) < m.positions.len()));
                // Vertex colours: none, or one per vertex, finite and >= 0.
                assert!(m.colors.is_empty() || m.colors.len() == m.positions.len());
                assert!(m.colors.iter().all(|c| c.is_finite() && c.min_element() >= 0.0));
                // Texture coordinates are read only for a pattern, which a
                // glTF scene's own materials never have.
                assert!(m.uvs.is_empty());
            }
        }
    }
});
