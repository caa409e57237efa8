//! Scene loading: files in, a validated [`Scene`] out.
//!
//! This module owns everything between a file on disk and the plain data in
//! [`model`]: the TOML scene format of `docs/interface.md`
//! ([`toml`]), glTF 2.0 files as meshes or as whole scenes
//! ([`gltf`]), image files as textures within the memory limit
//! ([`image_file`]), the values both use for what a file leaves out
//! ([`defaults`]), the built-in default scene (`default.toml`), and the
//! tessellation of the primitive shapes for the raster modes
//! ([`mod@tessellate`]). It never renders and never prints: non-fatal findings
//! go to [`Scene::warnings`], fatal ones are a [`SceneError`] whose message
//! is one sentence naming the file, the line or key, and what was expected.
//! No input makes it panic.
//!
//! # Scene files
//!
//! - `.toml`: the format of `docs/interface.md`; keys, defaults and
//!   constraints are listed in [`toml`].
//! - `.gltf` / `.glb` as a whole scene: every mesh primitive of the default
//!   scene (geometry and material rules in [`gltf`]); the camera is
//!   the first perspective camera met in a depth-first walk of the node tree
//!   (at its node's world position, looking down its local -Z with local +Y
//!   up, `yfov` converted to degrees); without one, the camera looks at the
//!   centre of the bounding box from +Z at the distance where the bounding
//!   sphere fits a 40 degree field of view. `KHR_lights_punctual` point
//!   lights become [`PointLight`]s at their node's world position with
//!   `intensity = color * intensity` (`range` is ignored); spot and
//!   directional lights are skipped with a warning. Without any point light,
//!   one is placed at the camera with intensity `d` (the distance from the
//!   camera to the bounding-box centre, so `Il / (d + k)` is about 1 there),
//!   with a warning. Image, lighting and render settings are the
//!   [`defaults`]: 640x480, ambient 0.2, k 1, perspective interpolation,
//!   attenuation on.

use std::path::Path;

pub mod defaults;
mod edit;
pub mod error;
pub mod footprint;
pub mod gltf;
pub mod image_file;
mod lighting_hook;
pub mod model;
pub mod tessellate;
pub mod texcoords;
pub mod texture;
pub mod toml;

pub use error::SceneError;
pub use footprint::{GeometrySize, LoadLimits};
pub use model::*;
pub use tessellate::{tessellate, tessellate_textured};

/// The built-in default scene (TOML), shown when no scene is given.
pub const DEFAULT_SCENE_TOML: &str = include_str!("default.toml");

/// Loads a scene file: `.toml` as a TOML scene, `.gltf`/`.glb` as a glTF
/// scene (meshes, first perspective camera, point lights). Any other
/// extension is an error.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    load_within(path, &LoadLimits::default())
}

/// As [`load`], refusing a glTF file whose instanced geometry would take
/// more than `limits` allows, before building it.
pub fn load_within(path: &Path, limits: &LoadLimits) -> Result<Scene, SceneError> {
    load_keeping_text(path, limits).map(|(scene, _)| scene)
}

/// As [`load_within`], with a TOML file's text as it was read (None for
/// glTF): for a caller that wants the file's table too without reading
/// the file twice (the Python package's `Scene.load`).
pub fn load_keeping_text(
    path: &Path,
    limits: &LoadLimits,
) -> Result<(Scene, Option<String>), SceneError> {
    let label = path.display().to_string();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "toml" => {
            let text = std::fs::read_to_string(path).map_err(|e| SceneError::Read {
                file: label.clone(),
                reason: e.to_string(),
            })?;
            let base = match path.parent() {
                Some(p) if !p.as_os_str().is_empty() => p,
                _ => Path::new("."),
            };
            let scene = self::toml::parse_within(&text, base, &label, limits)?;
            Ok((scene, Some(text)))
        }
        "gltf" | "glb" => Ok((gltf::load_scene(path, limits)?, None)),
        _ => Err(SceneError::UnsupportedFile { file: label }),
    }
}

/// Parses a TOML scene from `text`. Mesh paths are resolved against
/// `base_dir`; `label` (normally the file name) is used in messages.
pub fn from_toml_str(text: &str, base_dir: &Path, label: &str) -> Result<Scene, SceneError> {
    self::toml::parse(text, base_dir, label)
}

/// The built-in default scene ([`DEFAULT_SCENE_TOML`]).
pub fn default_scene() -> Scene {
    // The text is compiled in and a unit test parses it, so failure here is
    // a build defect, not bad input.
    from_toml_str(DEFAULT_SCENE_TOML, Path::new("."), "default.toml")
        .expect("the embedded default scene parses (see the unit test)")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn manifest(rel: &str) -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(rel)
    }

    #[test]
    fn default_scene_parses_and_shows_every_mode() {
        let scene = from_toml_str(DEFAULT_SCENE_TOML, Path::new("."), "default.toml")
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        let d = default_scene();
        assert!(d.warnings.is_empty());
        assert_eq!((d.image.width, d.image.height), (640, 480));
        assert_eq!(d.lights.len(), 2);
        assert_ne!(d.lights[0].intensity, d.lights[1].intensity);
        assert!(
            d.camera.position.y > d.camera.look_at.y,
            "camera looks down"
        );
        let mat = |o: &Object| &d.materials[o.material];
        let spheres: Vec<_> = d
            .objects
            .iter()
            .filter_map(|o| match o.shape {
                Shape::Sphere { segments, .. } => Some((segments, mat(o))),
                _ => None,
            })
            .collect();
        assert!(spheres
            .iter()
            .any(|(s, m)| *s >= 48 && m.p >= 80.0 && m.ks > 0.0));
        assert!(spheres.iter().any(|(s, m)| *s == 8 && m.ks == 0.0));
        assert!(spheres.iter().any(|(_, m)| m.kr >= 0.5 && m.p >= 300.0));
        assert!(spheres.iter().any(|(_, m)| m.kt >= 0.8 && m.ior == 1.5));
        assert!(d
            .objects
            .iter()
            .any(|o| matches!(o.shape, Shape::Box { .. })));
        assert!(d
            .objects
            .iter()
            .any(|o| matches!(o.shape, Shape::Plane { segments, .. } if segments >= 4)));
    }

    #[test]
    fn load_dispatches_on_the_extension() {
        let e = load(Path::new("scene.obj")).unwrap_err().to_string();
        assert!(e.contains("scene.obj") && e.contains("unsupported"), "{e}");
        let e = load(Path::new("/nonexistent/dir/scene.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/nonexistent/dir/scene.toml") && e.contains("cannot read"),
            "{e}"
        );
        let e = load(Path::new("/nonexistent/dir/x.glb"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.glb") && e.contains("cannot read"), "{e}");
    }

    #[test]
    fn example_assets_load() {
        let s = load(&manifest("assets/spheres.toml")).unwrap_or_else(|e| panic!("{e}"));
        assert!(s.objects.len() >= 4);
        let s = load(&manifest("assets/teapot-free-mesh.toml")).unwrap_or_else(|e| panic!("{e}"));
        assert!(s
            .objects
            .iter()
            .any(|o| matches!(&o.shape, Shape::Mesh(m) if m.triangles.len() == 12)));
        for o in &s.objects {
            let m = tessellate(&o.shape);
            assert!(!m.triangles.is_empty());
            assert!(o.material < s.materials.len());
        }
    }
}
