//! The one error type of the scene loader.
//!
//! Every message is a single sentence that names the file, the line (and
//! column) or key where known, and what was expected. Messages carry no
//! trailing period so callers can embed them.

use thiserror::Error;

/// Why a scene (or a mesh file it refers to) could not be loaded.
#[derive(Debug, Error)]
pub enum SceneError {
    /// The file could not be read at all.
    #[error("{file}: cannot read the file ({reason}); check that the path exists and is readable")]
    Read { file: String, reason: String },

    /// The extension is neither `.toml` nor `.gltf`/`.glb`.
    #[error("{file}: unsupported scene file type; expected a .toml scene or a .gltf/.glb file")]
    UnsupportedFile { file: String },

    /// TOML syntax or shape error (unknown key, missing key, wrong type,
    /// non-finite number) as reported by the TOML parser.
    #[error("{file} line {line}, column {column}: {message}")]
    Syntax {
        file: String,
        line: usize,
        column: usize,
        message: String,
    },

    /// A TOML problem without a position (for example a missing `[camera]`).
    #[error("{file}: {message}")]
    Toml { file: String, message: String },

    /// A value that parsed but makes no sense (out of range, unknown
    /// material name, ...), at a known line.
    #[error("{file} line {line}: {message}")]
    Invalid {
        file: String,
        line: usize,
        message: String,
    },

    /// A problem in a glTF file (used as a scene or as a mesh).
    #[error("{file}: {message}")]
    Mesh { file: String, message: String },

    /// Holding the scene would exceed the memory limit (`footprint`).
    #[error("{file}: {message}")]
    TooLarge { file: String, message: String },

    /// A scene given as a table of values (`from_table`): the key path
    /// of the bad value, as the caller wrote it (`objects[2].radius`), or
    /// empty for the whole table.
    #[error("{}{message}", if key.is_empty() { String::new() } else { format!("{key}: ") })]
    AtKey { key: String, message: String },

    /// A mesh file referenced by `[[objects]]` entry `object` (1-based) of a
    /// scene failed to load.
    #[error("{file} line {line}: object {object} (mesh): {source}")]
    InObject {
        file: String,
        line: usize,
        object: usize,
        #[source]
        source: Box<SceneError>,
    },
}

impl SceneError {
    pub(crate) fn invalid(file: &str, line: usize, message: impl Into<String>) -> Self {
        SceneError::Invalid {
            file: file.to_string(),
            line,
            message: message.into(),
        }
    }

    pub(crate) fn mesh(file: &str, message: impl Into<String>) -> Self {
        SceneError::Mesh {
            file: file.to_string(),
            message: message.into(),
        }
    }
}
