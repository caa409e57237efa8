//! A render's keyword arguments as the library's `Overrides` and
//! `Budgets`: the same fields the CLI's flags fill, checked by the same
//! code (`shadelab::render::overrides`), so the same values are refused
//! with the same sentences.

use std::path::PathBuf;
use std::sync::Arc;

use pyo3::prelude::*;
use shadelab::render::overrides::{Budgets, Overrides};
use shadelab::scene::LightingHook;

use crate::errors::{refusal, scene_error};

/// `Device.render`'s settings, as given.
#[derive(Default)]
pub struct RenderOptions {
    pub width: Option<i64>,
    pub height: Option<i64>,
    pub msaa: Option<String>,
    pub samples: Option<i64>,
    pub depth: Option<i64>,
    pub bounces: Option<i64>,
    pub photons: Option<i64>,
    pub caustics: Option<i64>,
    pub caustic_passes: Option<i64>,
    pub lighting: Option<String>,
    pub traversal: Option<String>,
    pub watchdog: Option<f64>,
    pub shadows: Option<bool>,
    pub time: Option<f64>,
    pub error: Option<f64>,
}

/// `msaa=4` or `msaa="4,per-sample"`.
pub fn msaa_text(py: Python<'_>, msaa: Option<&Bound<'_, PyAny>>) -> PyResult<Option<String>> {
    let Some(msaa) = msaa else {
        return Ok(None);
    };
    if let Ok(n) = msaa.extract::<i64>() {
        return Ok(Some(n.to_string()));
    }
    msaa.extract::<String>()
        .map(Some)
        .map_err(|_| refusal(py, "msaa is a count of samples (4) or \"4,per-sample\""))
}

/// `lighting=`: GLSL source (text with a line break or a call in it) or
/// the path of a file holding it.
fn lighting_hook(py: Python<'_>, given: &str) -> PyResult<LightingHook> {
    let is_source = given.contains('\n') || given.contains('(');
    let hook = if is_source {
        LightingHook::from_source("<lighting source>", given)
    } else {
        LightingHook::load(&PathBuf::from(given))
    };
    hook.map_err(|e| scene_error(py, &e))
}

impl RenderOptions {
    /// The overrides these ask for, the hook's file read.
    pub fn overrides(&self, py: Python<'_>) -> PyResult<Overrides> {
        let lighting = match &self.lighting {
            Some(given) => Some(Arc::new(lighting_hook(py, given)?)),
            None => None,
        };
        Ok(Overrides {
            width: self.width,
            height: self.height,
            lighting,
            watchdog: self.watchdog,
            traversal: self.traversal.clone(),
            msaa: self.msaa.clone(),
            depth: self.depth,
            bounces: self.bounces,
            photons: self.photons,
            caustics: self.caustics,
            caustic_passes: self.caustic_passes,
            caustic_radius: None,
            cutoff: None,
            samples: self.samples,
            no_shadows: self.shadows == Some(false),
        })
    }

    pub fn budgets(&self) -> Budgets {
        Budgets {
            time: self.time,
            error: self.error,
        }
    }
}
