//! `shadelab.Scene`: a scene loaded by the library's one loader from a
//! file, TOML text or a dict (the schema of the TOML files), kept with the
//! table it came from so that `to_dict` gives it back to be changed.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use shadelab::memory::MemoryLimit;
use shadelab::scene::{self, SceneError};

use crate::errors::{refusal, released, scene_error, to_py};
use crate::values::{to_table, toml_to_py};

/// A scene, validated: every rule of the TOML files holds (docs/interface.md).
#[pyclass(module = "shadelab", frozen)]
pub struct Scene {
    pub(crate) inner: Arc<scene::Scene>,
    /// The table it came from (a TOML file, text or dict): `to_dict`.
    source: Option<toml::Table>,
    /// The file it was loaded from.
    pub(crate) path: Option<PathBuf>,
    /// What images say made them (`settings["scene"]`): the file, or
    /// `<dict>` or `<toml text>`; `None` for the built-in default scene.
    pub(crate) origin: Option<PathBuf>,
    /// The name images and golden references take: the file's stem.
    pub(crate) name: String,
}

/// The folder a scene's relative file names are taken from.
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Relative file names in a scene's table made absolute against `base`,
/// so that a table taken from a file still names its meshes and textures
/// when given back from elsewhere.
fn absolute_files(table: &mut toml::Table, base: &Path) {
    let absolute = |value: &mut toml::Value| {
        if let Some(name) = value.as_str().filter(|n| Path::new(n).is_relative()) {
            let full = base.join(name);
            let full = std::fs::canonicalize(&full).unwrap_or(full);
            *value = toml::Value::String(full.display().to_string());
        }
    };
    if let Some(toml::Value::Array(objects)) = table.get_mut("objects") {
        for object in objects.iter_mut().filter_map(|o| o.as_table_mut()) {
            object.get_mut("file").map(absolute);
        }
    }
    if let Some(toml::Value::Table(materials)) = table.get_mut("materials") {
        for (_, material) in materials.iter_mut() {
            let Some(material) = material.as_table_mut() else {
                continue;
            };
            if let Some(toml::Value::Table(texture)) = material.get_mut("texture") {
                texture.get_mut("file").map(absolute);
            }
        }
    }
}

impl Scene {
    pub(crate) fn from_library(
        inner: scene::Scene,
        source: Option<toml::Table>,
        path: Option<PathBuf>,
        name: String,
    ) -> Self {
        Self {
            inner: Arc::new(inner),
            source,
            origin: path.clone(),
            path,
            name,
        }
    }

    /// A scene from what a Python call was given: a `Scene`, a path, or a
    /// dict; `None` for the built-in default scene.
    pub(crate) fn coerce(py: Python<'_>, given: Option<&Bound<'_, PyAny>>) -> PyResult<Py<Scene>> {
        match given {
            None => Py::new(py, Scene::default_scene()),
            Some(obj) => {
                if let Ok(scene) = obj.cast::<Scene>() {
                    return Ok(scene.clone().unbind());
                }
                if let Ok(dict) = obj.cast::<PyDict>() {
                    return Py::new(py, Scene::from_dict(py, dict, None)?);
                }
                let path: PathBuf = obj.extract().map_err(|_| {
                    refusal(
                        py,
                        "a scene is a shadelab.Scene, a path to a scene file or a dict",
                    )
                })?;
                Py::new(py, Scene::load(py, path)?)
            }
        }
    }
}

#[pymethods]
impl Scene {
    /// Loads a scene file: `.toml`, or `.gltf`/`.glb`. A glTF file whose
    /// geometry would be over the memory limit is refused before it is
    /// built (`SHADELAB_MAX_MEMORY`).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Scene> {
        let limits = MemoryLimit::resolve(None)
            .map_err(|e| to_py(py, e))?
            .load_limits();
        // The file read once: its text gives both the scene and the table.
        let (inner, text) = released(py, "loading a scene", || {
            scene::load_keeping_text(&path, &limits)
        })?
        .map_err(|e| scene_error(py, &e))?;
        let source = text
            .and_then(|text| text.parse::<toml::Table>().ok())
            .map(|mut table| {
                absolute_files(&mut table, &folder_of(&path));
                table
            });
        let name = path
            .file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
        Ok(Scene::from_library(inner, source, Some(path), name))
    }

    /// A scene from a dict of the TOML files' schema (`{"camera":
    /// {"position": [0, 1, 6], ...}, "objects": [...]}`); an error names
    /// the key path of the bad value (`objects[2].radius`). Mesh and
    /// texture files are taken from `base_dir` (default: the current
    /// folder).
    #[staticmethod]
    #[pyo3(signature = (d, base_dir=None))]
    fn from_dict(
        py: Python<'_>,
        d: &Bound<'_, PyDict>,
        base_dir: Option<PathBuf>,
    ) -> PyResult<Scene> {
        let table = to_table(d).map_err(|bad| {
            let error = SceneError::AtKey {
                key: bad.key(),
                message: bad.message().to_string(),
            };
            scene_error(py, &error)
        })?;
        let base = base_dir.unwrap_or_else(|| PathBuf::from("."));
        let inner = scene::toml::from_table(&table, &base).map_err(|e| scene_error(py, &e))?;
        Ok(Scene::from_library(
            inner,
            Some(table),
            None,
            "scene".into(),
        ))
    }

    /// A scene from TOML text, as a file holds it; errors name its lines.
    #[staticmethod]
    #[pyo3(signature = (text, base_dir=None))]
    fn from_toml(py: Python<'_>, text: &str, base_dir: Option<PathBuf>) -> PyResult<Scene> {
        let base = base_dir.unwrap_or_else(|| PathBuf::from("."));
        let inner = scene::from_toml_str(text, &base, "<text>").map_err(|e| scene_error(py, &e))?;
        Ok(Scene::from_library(
            inner,
            text.parse().ok(),
            None,
            "scene".into(),
        ))
    }

    /// The built-in default scene (what `shadelab render` renders with no
    /// scene file).
    #[staticmethod]
    #[pyo3(name = "default")]
    fn default_scene() -> Scene {
        Scene::from_library(
            scene::default_scene(),
            scene::DEFAULT_SCENE_TOML.parse().ok(),
            None,
            "default".into(),
        )
    }

    /// This scene with light `index` (0-based) moved to `position` and/or
    /// of `intensity` (a number or `[r, g, b]`): what an animation changes
    /// between frames, without the TOML written and read again that
    /// `from_dict` takes. The values are held to the file's rules; a bad
    /// one raises `SceneError` naming `lights[i].position`.
    #[pyo3(signature = (index, *, position=None, intensity=None))]
    fn with_light(
        &self,
        py: Python<'_>,
        index: usize,
        position: Option<[f64; 3]>,
        intensity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Scene> {
        let intensity = match intensity {
            None => None,
            Some(i) => Some(match i.extract::<f64>() {
                Ok(v) => [v; 3],
                Err(_) => i.extract::<[f64; 3]>().map_err(|_| {
                    let message = "expected a number or [r, g, b]".to_string();
                    let key = format!("lights[{index}].intensity");
                    scene_error(py, &SceneError::AtKey { key, message })
                })?,
            }),
        };
        let inner = self
            .inner
            .with_light(index, position, intensity)
            .map_err(|e| scene_error(py, &e))?;
        // The table `to_dict` gives keeps up with the change.
        let source = self.source.clone().map(|mut table| {
            let light = table
                .get_mut("lights")
                .and_then(|l| l.as_array_mut())
                .and_then(|l| l.get_mut(index))
                .and_then(|l| l.as_table_mut());
            if let Some(light) = light {
                let array = |v: [f64; 3]| toml::Value::Array(v.map(toml::Value::Float).to_vec());
                if let Some(p) = position {
                    light.insert("position".into(), array(p));
                }
                if let Some(i) = intensity {
                    light.insert("intensity".into(), array(i));
                }
            }
            table
        });
        Ok(Scene {
            inner: Arc::new(inner),
            source,
            path: self.path.clone(),
            origin: self.origin.clone(),
            name: self.name.clone(),
        })
    }

    /// The scene as a dict of the TOML files' schema, to change and give
    /// back to `Scene.from_dict` (file names made absolute). A glTF scene
    /// has no such form.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match &self.source {
            Some(table) => toml_to_py(py, &toml::Value::Table(table.clone())),
            None => Err(refusal(
                py,
                "a glTF scene has no dict form (only a TOML scene, text or dict has one)",
            )),
        }
    }

    /// The image's width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.inner.image.width
    }

    /// The image's height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.inner.image.height
    }

    /// The name images and golden references take (the file's stem).
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// The file it was loaded from, if any.
    #[getter]
    fn path(&self) -> Option<String> {
        self.path.as_ref().map(|p| p.display().to_string())
    }

    /// What the loader found and let pass (degenerate triangles dropped, ...).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}, {}x{}, {} objects, {} lights)",
            self.name,
            self.inner.image.width,
            self.inner.image.height,
            self.inner.objects.len(),
            self.inner.lights.len()
        )
    }
}
