//! Reading a lighting hook's file (`--lighting FILE`, `lighting=FILE` in a
//! compare variant). Compiling it is the GPU's business (`gpu::shared::hook`).

use std::path::Path;

use super::{LightingHook, SceneError};

impl LightingHook {
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let file = path.display().to_string();
        let source = std::fs::read_to_string(path).map_err(|e| SceneError::Read {
            file: file.clone(),
            reason: e.to_string(),
        })?;
        Self::from_source(file, source)
    }

    /// A hook from its source text; `label` names it in messages (a file's
    /// path, or where a caller's text came from).
    pub fn from_source(
        label: impl Into<String>,
        source: impl Into<String>,
    ) -> Result<Self, SceneError> {
        let (file, source) = (label.into(), source.into());
        // shadelab writes the hook into its own shader, after its
        // `#version`: one in the hook made glslang say only "'#version' :
        // must occur first".
        if let Some((number, _)) = source
            .lines()
            .enumerate()
            .find(|(_, l)| l.trim_start().starts_with("#version"))
        {
            return Err(SceneError::Invalid {
                file: file.clone(),
                line: number + 1,
                message: "a lighting hook has no #version line (shadelab compiles it into its own shaders, which have one); remove it (docs/lighting-hooks.md)".into(),
            });
        }
        Ok(Self { path: file, source })
    }
}
