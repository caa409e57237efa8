//! What can go wrong when a report becomes files: every part of the
//! presentation returns this one error.

use std::path::PathBuf;

use crate::output::OutputError;

#[derive(Debug, thiserror::Error)]
pub enum PresentError {
    #[error("the report has no variants to present")]
    NoVariants,
    #[error("cannot read image {path}: {message}")]
    ReadImage { path: PathBuf, message: String },
    #[error(transparent)]
    Write(#[from] OutputError),
    #[error("cannot draw the {what}: {message}")]
    Draw { what: &'static str, message: String },
}

impl PresentError {
    /// True for problems with the input (no variants, a missing or corrupt
    /// image), false for failures to draw or write.
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            PresentError::NoVariants | PresentError::ReadImage { .. }
        )
    }
}
