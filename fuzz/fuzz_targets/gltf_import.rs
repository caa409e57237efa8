//! The glTF/GLB importer on arbitrary bytes: an error or a scene, never a
//! panic. External buffers and images resolve in an empty folder; the
//! memory limit keeps an input that instances a mesh a million times, or
//! an image whose header claims 60000 x 60000 pixels, from taking the
//! run's memory.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shadelab::scene::gltf::scene_from_slice;
use shadelab::scene::{LoadLimits, Pattern, Shape};
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
        // valid material indices, unit normals, vertex colours and texture
        // coordinates per vertex, textures with a whole mip chain.
        assert!(scene.camera.position.is_finite());
        for material in &scene.materials {
            if let Some(Pattern::Image(img)) = &material.pattern {
                let levels = &img.texture.levels;
                assert!(!levels.is_empty());
                assert!(levels[0].width >= 1 && levels[0].height >= 1);
                for (i, level) in levels.iter().enumerate() {
                    assert_eq!(
                        level.texels.len() as u64,
                        u64::from(level.width) * u64::from(level.height)
                    );
                    assert!(level
                        .texels
                        .iter()
                        .flatten()
                        .all(|t| t.is_finite() && *t >= 0.0));
                    if let Some(next) = levels.get(i + 1) {
                        assert!(level.width > 1 || level.height > 1);
                        assert_eq!(next.width, (level.width / 2).max(1));
                        assert_eq!(next.height, (level.height / 2).max(1));
                    } else {
                        assert!(level.width == 1 && level.height == 1);
                    }
                }
                assert!(img.transform.0.iter().all(|x| x.is_finite()));
            }
        }
        for object in &scene.objects {
            assert!(object.material < scene.materials.len());
            if let Shape::Mesh(m) = &object.shape {
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
                assert!(m
                    .colors
                    .iter()
                    .all(|c| c.is_finite() && c.min_element() >= 0.0));
                // Texture coordinates: none, or one per vertex, finite; a
                // mesh whose material has an image has them.
                assert!(m.uvs.is_empty() || m.uvs.len() == m.positions.len());
                assert!(m.uvs.iter().all(|uv| uv.is_finite()));
                if let Some(Pattern::Image(_)) = &scene.materials[object.material].pattern {
                    assert!(!m.uvs.is_empty());
                }
            }
        }
    }
});
