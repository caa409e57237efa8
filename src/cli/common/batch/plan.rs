//! A batch planned before any rendering: each scene loaded with the
//! overrides applied (or why not), each case's file name from `--name`, its
//! backend and its memory estimate.

use std::path::{Path, PathBuf};

use shadelab::backend_choice::{self, Backend, Choice};
use shadelab::memory::MemoryLimit;
use shadelab::output::ImageFormat;
use shadelab::scene::Scene;
use shadelab::shading::Shading;

use super::args::RenderArgs;
use super::scene::{apply_overrides, load_scene};
use crate::cli::common::failure::Failure;

/// One scene of the batch: loaded with the overrides applied, or why not.
pub(super) struct PlannedScene {
    pub(super) path: Option<PathBuf>,
    /// The `{scene}` of the file names: the file's stem, made unique.
    pub(super) name: String,
    pub(super) scene: Result<Scene, Failure>,
}

/// One image to make: which scene, which mode, where, on which backend.
pub(super) struct PlannedCase {
    /// Its place in the whole batch (of every shard).
    pub(super) order: usize,
    pub(super) scene: usize,
    pub(super) shading: Shading,
    /// Its file's name, from `--name`.
    pub(super) file_name: String,
    /// The backend, or why the case cannot run (over the memory limit).
    pub(super) backend: Result<Backend, Failure>,
    pub(super) choice: Option<Choice>,
    /// The memory estimate (0 where the case cannot run).
    pub(super) estimate: u64,
}

/// The file name `pattern` gives for a scene and a mode.
pub fn file_name(pattern: &str, scene: &str, shading: Shading) -> String {
    pattern
        .replace("{scene}", scene)
        .replace("{mode}", &shading.to_string())
}

/// Refuses a `--name` pattern that would give two cases one file, names a
/// placeholder other than `{scene}` and `{mode}`, or is not a .png/.exr
/// file name in the folder itself.
pub(super) fn check_pattern(
    pattern: &str,
    scenes: usize,
    modes: usize,
    first: (&str, Shading),
) -> Result<(), Failure> {
    let bad = |why: &str| Err(Failure::usage(format!("--name {pattern:?} {why}")));
    let stripped = pattern.replace("{scene}", "").replace("{mode}", "");
    if stripped.contains(['{', '}']) {
        return bad("has a placeholder other than {scene} and {mode}");
    }
    if pattern.contains(['/', '\\']) {
        return bad("must be a file name, not a path (the folder is --out-dir)");
    }
    if scenes > 1 && !pattern.contains("{scene}") {
        return bad("needs {scene}: there is more than one scene");
    }
    if modes > 1 && !pattern.contains("{mode}") {
        return bad("needs {mode}: there is more than one mode");
    }
    let example = file_name(pattern, first.0, first.1);
    if ImageFormat::from_path(Path::new(&example)).is_err() {
        return bad(&format!(
            "would write {example}: expected a file name ending in .png (8-bit sRGB) or .exr (linear float)"
        ));
    }
    Ok(())
}

pub(super) fn plan_scenes(
    args: &RenderArgs,
    modes: &[Shading],
    memory: &MemoryLimit,
) -> Vec<PlannedScene> {
    let paths: Vec<Option<PathBuf>> = if args.scenes.is_empty() {
        vec![None]
    } else {
        args.scenes.iter().cloned().map(Some).collect()
    };
    let mut planned: Vec<PlannedScene> = Vec::new();
    for (k, path) in paths.into_iter().enumerate() {
        let loaded = load_scene(path.as_deref(), memory).and_then(|(mut scene, stem)| {
            apply_overrides(&mut scene, args, modes, false)?;
            Ok((scene, stem))
        });
        let (scene, mut name) = match loaded {
            Ok((scene, stem)) => (Ok(scene), stem),
            Err(failure) => {
                let stem = path.as_ref().and_then(|p| p.file_stem()).map_or_else(
                    || "default".to_string(),
                    |s| s.to_string_lossy().into_owned(),
                );
                (Err(failure), stem)
            }
        };
        if let Some(given) = args.scene_names.as_ref().and_then(|names| names.get(k)) {
            name = given.clone();
        } else if planned.iter().any(|p| p.name == name) {
            name = format!("{name}-{}", planned.len() + 1);
        }
        planned.push(PlannedScene { path, name, scene });
    }
    planned
}

/// The backend each case renders on: `--backend`, or for `auto` the
/// choice made for that scene and mode; the memory estimate held to the
/// limit.
pub(super) fn plan_case(
    args: &RenderArgs,
    scene: &PlannedScene,
    shading: Shading,
    memory: &MemoryLimit,
) -> (Result<(Backend, u64), Failure>, Option<Choice>) {
    let loaded = match &scene.scene {
        Ok(loaded) => loaded,
        Err(failure) => return (Err(failure.clone()), None),
    };
    let choice = (args.backend == "auto").then(|| backend_choice::choose(loaded, shading));
    let backend = match (&choice, args.backend.as_str()) {
        (Some(choice), _) => choice.backend,
        (None, "cpu") => Backend::Cpu,
        (None, _) => Backend::Gpu,
    };
    let (gpu_modes, cpu_modes): (&[Shading], &[Shading]) = match backend {
        Backend::Gpu => (&[shading], &[]),
        Backend::Cpu => (&[], &[shading]),
    };
    let estimate = memory.check(&scene.name, loaded, gpu_modes, cpu_modes);
    (
        estimate.map(|e| (backend, e)).map_err(Failure::from),
        choice,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_that_would_overwrite_or_misname_are_refused() {
        let first = ("room", Shading::Phong);
        assert!(check_pattern("{scene}-{mode}.png", 3, 4, first).is_ok());
        assert!(check_pattern("{mode}.exr", 1, 4, first).is_ok());
        assert!(check_pattern("{scene}.png", 3, 1, first).is_ok());
        let message = |p: &str, s, m| check_pattern(p, s, m, first).err().map(|f| f.message);
        assert!(message("{scene}.png", 1, 2).is_some_and(|m| m.contains("needs {mode}")));
        assert!(message("{mode}.png", 2, 1).is_some_and(|m| m.contains("needs {scene}")));
        assert!(message("{scene}-{shading}.png", 1, 1).is_some_and(|m| m.contains("placeholder")));
        assert!(message("a/{scene}.png", 1, 1).is_some_and(|m| m.contains("not a path")));
        // The file it would write, named: the scene's, not a placeholder's.
        let jpg = message("{scene}-{mode}.jpg", 1, 1).unwrap_or_default();
        assert!(jpg.contains("would write room-phong.jpg"), "{jpg}");
        assert_eq!(
            file_name("{scene}_{mode}.exr", "room", Shading::Gouraud),
            "room_gouraud.exr"
        );
    }
}
