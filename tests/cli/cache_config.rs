//! One shader cache shared by two code generator configurations (issue 30):
//! Phong renders at 128-bit vectors (`LP_NATIVE_VECTOR_WIDTH=128`, as on a
//! CPU without AVX) after `check` filled the cache at the default width
//! aborted or crashed 2 to 16 times in 20 with lavapipe's code of the other
//! width handed to them (Mesa's key misses the vector width). shadelab
//! keeps one Mesa cache folder per configuration, inside the folder the
//! user chose too; with one folder for both, the same run crashes again.

use std::path::Path;
use std::process::Command;

fn shadelab(dir: &Path, cache: &Path, width: Option<&str>, args: &[&str]) -> std::process::Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_shadelab"));
    command
        .args(args)
        .current_dir(dir)
        .env("SHADELAB_CACHE_DIR", dir.join("cache"))
        .env("MESA_SHADER_CACHE_DIR", cache)
        .env_remove("MESA_SHADER_CACHE_DISABLE")
        .env_remove("LP_NATIVE_VECTOR_WIDTH");
    if let Some(w) = width {
        command.env("LP_NATIVE_VECTOR_WIDTH", w);
    }
    command.output().unwrap()
}

#[test]
fn one_cache_folder_at_two_vector_widths_crashes_no_render() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("shared-mesa-cache");
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    let mut scenes: Vec<String> = std::fs::read_dir(&assets)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| p.display().to_string())
        .collect();
    scenes.sort();
    let mut fill = vec!["check", "--shading", "phong", "--images", "none"];
    fill.extend(scenes.iter().map(String::as_str));
    let filled = shadelab(dir.path(), &cache, None, &fill);
    assert_eq!(
        filled.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&filled.stderr)
    );
    for k in 0..20 {
        let scene = &scenes[k % scenes.len()];
        let out = shadelab(
            dir.path(),
            &cache,
            Some("128"),
            &["render", scene, "--shading", "phong", "-o", "x.png"],
        );
        assert_eq!(
            out.status.code(),
            Some(0),
            "render {k} of {scene} at 128 bits: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let folders = std::fs::read_dir(&cache).unwrap().count();
    assert_eq!(folders, 2, "one Mesa cache folder per configuration");
}
