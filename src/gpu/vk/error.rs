//! Errors of the Vulkan layer.

use ash::vk;

#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("cannot load the Vulkan loader (libvulkan.so.1): {0}; install it with `apt-get install libvulkan1 mesa-vulkan-drivers` (or run ci/install-deps.sh)")]
    Loader(String),
    #[error("the Khronos validation layer was requested (SHADELAB_VALIDATION=1) but is not installed; install it with `apt-get install vulkan-validationlayers`")]
    ValidationLayerMissing,
    #[error("no Vulkan 1.3 device is available{0}; install lavapipe with `apt-get install mesa-vulkan-drivers`")]
    NoDevice(String),
    #[error("no Vulkan device matches `{wanted}`; available: {available} (see `shadelab info`)")]
    DeviceNotFound { wanted: String, available: String },
    #[error("`{wanted}` matches more than one Vulkan device: {matches}; give its index or more of its name (see `shadelab info`)")]
    DeviceAmbiguous { wanted: String, matches: String },
    #[error("the device `{device}` lacks {feature}, which shadelab needs")]
    MissingFeature {
        device: String,
        feature: &'static str,
    },
    #[error("a {width}x{height} image exceeds {why}; choose a smaller --width/--height")]
    ImageTooLarge {
        width: u32,
        height: u32,
        why: String,
    },
    #[error("msaa {asked} (--msaa or the scene's render.msaa): `{device}` {why}")]
    UnsupportedSamples {
        asked: String,
        device: String,
        why: String,
    },
    #[error("the meshes' BVH is {depth} levels deep, more than the GPU ray tracer's {limit}; render this scene with --backend cpu")]
    BvhTooDeep { depth: usize, limit: usize },
    #[error("the GPU ray tracer cannot run on `{device}`: it {why}; render with --backend cpu")]
    NoRayTracer { device: String, why: String },
    #[error("--traversal query needs ray queries, and the device `{device}` {why}; use --traversal bvh (or auto)")]
    NoRayQuery { device: String, why: String },
    #[error("the scene holds {0}; render it with --backend cpu")]
    SceneTooLarge(String),
    /// Forward ray tracing of a scene whose lights emit nothing.
    #[error("forward ray tracing needs a light that emits: the scene has {0}")]
    NoLightToTraceFrom(String),
    /// A lighting hook that does not compile or oversteps its interface:
    /// the message names the file (and glslang's line).
    #[error("lighting hook {0}")]
    LightingHook(String),
    /// Specialising a built-in module before the driver failed: a bug in
    /// shadelab, not the user's input.
    #[error("specialising a shader module failed: {0}")]
    Specialise(String),
    #[error("Vulkan call {call} failed: {result}")]
    Vulkan {
        call: &'static str,
        result: vk::Result,
    },
    #[error("GPU memory allocation failed: {0}")]
    Allocation(#[from] gpu_allocator::AllocationError),
    /// A render projected from its first batch to run too long
    /// (`RenderPart::refuse_if_too_long` says the figure).
    #[error("{0}")]
    TooLong(String),
    /// A submission outlived the watchdog's limit (`vk::watchdog`): the
    /// device is stuck for the rest of the process, which must end without
    /// waiting for it.
    #[error("a GPU submission ran past the watchdog's {limit_s} s (--watchdog or the scene's render.watchdog); the likely cause is {}; the device is stuck, so shadelab stops", cause.as_ref().map_or_else(|| "a shader that never ends or a driver fault".to_string(), |c| format!("the lighting hook {c}, which never returns (an endless loop?)")))]
    Stuck { limit_s: f64, cause: Option<String> },
    #[error("the Khronos validation layer reported {} message(s):\n{}", .0.len(), .0.join("\n"))]
    Validation(Vec<String>),
}

impl GpuError {
    /// The watchdog's error: nothing more can run on the device, and the
    /// process must end without waiting for it.
    pub fn leaves_device_stuck(&self) -> bool {
        matches!(self, GpuError::Stuck { .. })
    }

    /// Errors that the user's input caused (exit status 2, not 3).
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            GpuError::ImageTooLarge { .. }
                | GpuError::UnsupportedSamples { .. }
                | GpuError::LightingHook(_)
                | GpuError::DeviceNotFound { .. }
                | GpuError::DeviceAmbiguous { .. }
                | GpuError::BvhTooDeep { .. }
                | GpuError::SceneTooLarge(_)
                | GpuError::NoRayQuery { .. }
                | GpuError::NoLightToTraceFrom(_)
                | GpuError::TooLong(_)
        )
    }
}

/// Attaches the name of the failing call to a `vk::Result`.
pub(crate) trait VkContext<T> {
    fn during(self, call: &'static str) -> Result<T, GpuError>;
}

impl<T> VkContext<T> for Result<T, vk::Result> {
    fn during(self, call: &'static str) -> Result<T, GpuError> {
        self.map_err(|result| GpuError::Vulkan { call, result })
    }
}
