//! Reading a lighting hook's file (`--lighting FILE`, `lighting=FILE` in a
//! compare variant). Compiling it is the GPU's business (`gpu::hook`).

use std::path::Path;

use super::{LightingHook, SceneError};

impl LightingHook {
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let file = path.display().to_string();
        let source = std::fs::read_to_string(path).map_err(|e| SceneError::Read {
            file: file.clone(),
            reason: e.to_string(),
        })?;
        Ok(Self { path: file, source })
    }
}
