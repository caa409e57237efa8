//! The library's error type and the exit status each kind maps to.
//!
//! Exit statuses (interface.md): 2 bad input or usage, 3 a Vulkan or internal
//! failure. Status 1 (a failed comparison) is decided by the commands that
//! compare, not by an error.

use crate::gpu::GpuError;
use crate::metrics::MetricsError;
use crate::output::OutputError;
use crate::scene::SceneError;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error(transparent)]
    Output(#[from] OutputError),
    #[error(transparent)]
    Metrics(#[from] MetricsError),
    #[error("{0}")]
    Usage(String),
    /// A render whose estimate is over the memory limit (`memory`),
    /// refused before anything large is allocated.
    #[error("{0}")]
    OverMemory(String),
    /// The caller set the request's cancel flag.
    #[error("the render was cancelled")]
    Cancelled,
}

impl Error {
    /// The GPU watchdog's error (`GpuError::Stuck`): the process must end
    /// without waiting for the device.
    pub fn leaves_device_stuck(&self) -> bool {
        matches!(self, Error::Gpu(e) if e.leaves_device_stuck())
    }

    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Scene(_)
            | Error::Output(_)
            | Error::Metrics(_)
            | Error::Usage(_)
            | Error::OverMemory(_) => 2,
            Error::Gpu(e) if e.is_bad_input() => 2,
            Error::Gpu(_) => 3,
            // As a shell reports a command stopped by Ctrl-C (128 + SIGINT).
            Error::Cancelled => 130,
        }
    }
}
