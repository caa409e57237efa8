//! What identifies a `golden` case's reference: the scene's path relative
//! to a root (`--root`, or the folder every scene lies in), so that the
//! order of the scenes on the command line and two scenes of one file name
//! in two folders cannot swap or share references; and what made a
//! reference, read back from its PNG, to name the difference where a
//! render fails against one made with other settings; and the folder of a
//! driver's own references.

use std::path::{Component, Path, PathBuf};

use crate::Error;

/// Each scene's `{scene}` in reference names: its path relative to `root`
/// (or to the deepest folder holding every scene), without its extension,
/// folders joined by `/`. The built-in default scene (no scenes) is
/// `default`. A scene outside `--root` is refused.
pub fn scene_keys(scenes: &[PathBuf], root: Option<&Path>) -> Result<Vec<String>, Error> {
    if scenes.is_empty() {
        return Ok(vec!["default".to_string()]);
    }
    let paths: Vec<PathBuf> = scenes.iter().map(|p| absolute(p)).collect();
    let root = match root {
        Some(root) => absolute(root),
        None => common_folder(&paths),
    };
    let mut keys = Vec::with_capacity(scenes.len());
    for (given, path) in scenes.iter().zip(&paths) {
        let relative = path.strip_prefix(&root).map_err(|_| {
            Error::Usage(format!(
                "the scene {} is not under --root {}",
                given.display(),
                root.display()
            ))
        })?;
        let mut parts: Vec<String> = relative
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        if let Some(last) = parts.last_mut() {
            let stem = Path::new(last.as_str())
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned());
            *last = stem.unwrap_or_else(|| last.clone());
        }
        keys.push(parts.join("/"));
    }
    Ok(keys)
}

/// `path` made absolute and free of `.` and `..` (resolving links where
/// the file exists, so two spellings of one file are one key).
fn absolute(path: &Path) -> PathBuf {
    if let Ok(real) = std::fs::canonicalize(path) {
        return real;
    }
    let joined = std::env::current_dir()
        .map(|cwd| cwd.join(path))
        .unwrap_or_else(|_| path.to_path_buf());
    let mut clean = PathBuf::new();
    for c in joined.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                clean.pop();
            }
            other => clean.push(other),
        }
    }
    clean
}

/// The deepest folder that holds every path.
fn common_folder(paths: &[PathBuf]) -> PathBuf {
    let mut common: PathBuf = paths[0].parent().map(Path::to_path_buf).unwrap_or_default();
    for path in &paths[1..] {
        while !path.starts_with(&common) {
            if !common.pop() {
                break;
            }
        }
    }
    common
}

/// The folder name for a device's references: the device and driver
/// names, lower case, each run of characters other than a-z, 0-9 and `.`
/// made one `-` (`llvmpipe-llvm-15.0.6-256-bits-mesa-25.0.7-...`): the
/// vector width and the Mesa version, which change the image, are in it.
pub fn driver_key(device: &str, driver: &str) -> String {
    let mut key = String::new();
    for c in format!("{device} {driver}").to_lowercase().chars() {
        if c.is_ascii_alphanumeric() || c == '.' {
            key.push(c);
        } else if !key.ends_with('-') {
            key.push('-');
        }
    }
    key.trim_matches('-').to_string()
}

/// Two cases that would read and write one reference: the first pair, as
/// `(file, first scene, second scene)`.
pub fn first_clash(cases: &[(String, String)]) -> Option<(&str, &str, &str)> {
    for (i, (file, scene)) in cases.iter().enumerate() {
        if let Some((_, other)) = cases[..i].iter().find(|(f, _)| f == file) {
            return Some((file, other, scene));
        }
    }
    None
}

/// The settings that change a render's pixels, as `render` records them
/// in a PNG's `shadelab:settings` (the CLI's `effective_settings`),
/// plus the reference's key and the hook's source digest that `golden`
/// adds.
const PIXEL_SETTINGS: [&str; 15] = [
    "golden_scene",
    "shading",
    "width",
    "height",
    "msaa",
    "lighting",
    "traversal",
    "depth",
    "samples",
    "bounces",
    "photons",
    "caustics",
    "shadows",
    "cutoff",
    "backend",
];

/// The pixel-changing settings where `reference` (what made the stored
/// image) and `render` differ, each as `name: reference's -> render's`;
/// settings a reference does not record (made before they were) are not
/// compared. A lighting hook is compared by its source's digest where both
/// record one (the same file by another path is the same hook).
pub fn settings_differences(
    reference: &serde_json::Value,
    render: &serde_json::Value,
) -> Vec<String> {
    let shown = |v: &serde_json::Value| match v {
        serde_json::Value::Null => "none".to_string(),
        serde_json::Value::String(s) => s.clone(),
        other => other.to_string(),
    };
    let null = serde_json::Value::Null;
    let mut out = Vec::new();
    for name in PIXEL_SETTINGS {
        let Some(theirs) = reference.get(name) else {
            continue;
        };
        let ours = render.get(name).unwrap_or(&null);
        let differ = if name == "lighting" {
            let digest = |v: &serde_json::Value| v.get("lighting_fnv1a").cloned();
            match (digest(reference), digest(render)) {
                (Some(a), Some(b)) if !theirs.is_null() && !ours.is_null() => a != b,
                _ => theirs != ours,
            }
        } else {
            theirs != ours
        };
        if differ {
            let mut line = format!("{name} {} -> {}", shown(theirs), shown(ours));
            if name == "lighting" && theirs == ours {
                line.push_str(" (its source changed)");
            }
            out.push(line);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_paths_below_the_common_folder_whatever_the_order() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a/x.toml");
        let b = dir.path().join("b/x.toml");
        let keys = scene_keys(&[a.clone(), b.clone()], None).unwrap();
        assert_eq!(keys, ["a/x", "b/x"]);
        let keys = scene_keys(&[b.clone(), a.clone()], None).unwrap();
        assert_eq!(keys, ["b/x", "a/x"]);
        // One folder: the file's stem, as before keys had folders.
        assert_eq!(scene_keys(std::slice::from_ref(&a), None).unwrap(), ["x"]);
        // A root of the user's.
        assert_eq!(
            scene_keys(std::slice::from_ref(&a), Some(dir.path())).unwrap(),
            ["a/x"]
        );
        let outside = scene_keys(&[a], Some(&dir.path().join("b"))).unwrap_err();
        assert!(
            outside.to_string().contains("is not under --root"),
            "{}",
            outside
        );
        assert_eq!(scene_keys(&[], None).unwrap(), ["default"]);
        let dotted = dir.path().join("a/../b/./x.toml");
        assert_eq!(scene_keys(&[dotted, b], None).unwrap(), ["x", "x"]);
    }

    #[test]
    fn the_first_clash_names_both_scenes() {
        let cases = [
            ("a/x-phong.png".to_string(), "a/x.toml".to_string()),
            ("b/x-phong.png".to_string(), "b/x.toml".to_string()),
            ("a/x-phong.png".to_string(), "a/x.glb".to_string()),
        ];
        assert_eq!(
            first_clash(&cases),
            Some(("a/x-phong.png", "a/x.toml", "a/x.glb"))
        );
        assert_eq!(first_clash(&cases[..2]), None);
    }

    #[test]
    fn differences_name_each_pixel_setting_and_skip_the_unrecorded() {
        let reference =
            serde_json::json!({"shading": "phong", "msaa": "4", "width": 64, "device": "x"});
        let render = serde_json::json!({"shading": "phong", "msaa": "1", "width": 32, "depth": 5, "device": "y"});
        assert_eq!(
            settings_differences(&reference, &render),
            ["width 64 -> 32", "msaa 4 -> 1"]
        );
        let hooked = serde_json::json!({"lighting": "a/h.glsl", "lighting_fnv1a": "1"});
        let moved = serde_json::json!({"lighting": "b/h.glsl", "lighting_fnv1a": "1"});
        assert!(settings_differences(&hooked, &moved).is_empty());
        let none = serde_json::json!({"lighting": null});
        assert_eq!(
            settings_differences(&hooked, &none),
            ["lighting a/h.glsl -> none"]
        );
        let edited = serde_json::json!({"lighting": "a/h.glsl", "lighting_fnv1a": "2"});
        assert_eq!(
            settings_differences(&hooked, &edited),
            ["lighting a/h.glsl -> a/h.glsl (its source changed)"]
        );
    }

    #[test]
    fn the_driver_key_is_a_folder_name_holding_the_vector_width_and_the_version() {
        let key = driver_key(
            "llvmpipe (LLVM 15.0.6, 256 bits)",
            "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)",
        );
        assert_eq!(
            key,
            "llvmpipe-llvm-15.0.6-256-bits-mesa-25.0.7-2-bpo12-1-llvm-15.0.6"
        );
        assert_ne!(
            key,
            driver_key(
                "llvmpipe (LLVM 15.0.6, 128 bits)",
                "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"
            )
        );
        assert_eq!(driver_key("A/B", ".."), "a-b-..");
    }
}
