//! What a render runs on and keeps between renders: the Vulkan context
//! (with the pipelines it has built, `vk::pipeline`) where there is a
//! GPU, and always the CPU reference. A command that renders many times
//! (`check`, `compare`, `golden`, a batch) opens one and passes it to
//! every `render`.

use std::sync::Arc;

use crate::error::Error;
use crate::gpu::{GpuContext, GpuError, GpuOptions};

/// The devices a render may run on: the GPU where one was opened, and the
/// CPU reference.
#[derive(Clone)]
pub struct Device {
    gpu: Option<Arc<GpuContext>>,
}

impl Device {
    /// The CPU reference alone: a GPU render on it is refused.
    pub fn cpu_only() -> Self {
        Self { gpu: None }
    }

    /// Opens the GPU `options` select (the CPU reference comes with it).
    pub fn open(options: &GpuOptions) -> Result<Self, GpuError> {
        Ok(Self::with_gpu(GpuContext::new(options)?))
    }

    /// A GPU already opened (as `render` opens it on a thread of its own
    /// while the scene loads).
    pub fn with_gpu(context: Arc<GpuContext>) -> Self {
        Self { gpu: Some(context) }
    }

    /// The GPU where one is open.
    pub fn gpu(&self) -> Option<&Arc<GpuContext>> {
        self.gpu.as_ref()
    }

    /// The GPU, for work only it can do; a usage error where none is open.
    pub fn require_gpu(&self) -> Result<&Arc<GpuContext>, Error> {
        self.gpu.as_ref().ok_or_else(|| {
            Error::Usage(
                "a GPU render on a device opened without a GPU; open one (Device::open) or ask for the CPU backend".into(),
            )
        })
    }
}

impl From<Option<Arc<GpuContext>>> for Device {
    fn from(gpu: Option<Arc<GpuContext>>) -> Self {
        Self { gpu }
    }
}
