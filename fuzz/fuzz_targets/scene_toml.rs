//! The TOML scene loader on arbitrary text: an error or a scene, never a
//! panic. Mesh paths resolve in an empty folder, so no file is read.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shadelab::scene::{from_toml_str, tessellate, tessellate_textured, GeometrySize};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(scene) = from_toml_str(text, Path::new("/nonexistent-fuzz-dir"), "fuzz.toml") {
        // What a loaded scene promises: every object tessellates to finite
        // geometry (kept small so one input cannot take the whole run).
        if GeometrySize::of_scene(&scene, true).triangles < 200_000 {
            for object in &scene.objects {
                let mesh = tessellate(&object.shape);
                assert!(mesh.positions.iter().all(|p| p.is_finite()));
                // A patterned surface: texture coordinates per vertex, finite.
                if scene.materials[object.material].pattern.is_some() {
                    let mesh = tessellate_textured(&object.shape);
                    assert_eq!(mesh.uvs.len(), mesh.positions.len());
                    assert!(mesh.uvs.iter().all(|uv| uv.is_finite()));
                }
            }
        }
    }
});
