//! What a caller asks of a render, every option a named field: the one
//! value that crosses from a command (or a test, or the Python package)
//! into the library. `Plan::new` reads it against a scene.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Instant;

use crate::backend_choice::Backend;
use crate::gpu::raster::ColorTarget;
use crate::shading::Shading;
use crate::work_counter::WorkCounter;

/// Which of a render's photons (forward) or samples per pixel (ray
/// tracing with bounces) it traces.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Portion {
    All,
    /// Shard `i` of `n` (1-based): the `i`-th of `n` even runs
    /// (`RenderPart::shard`).
    Shard(u32, u32),
    /// These photons or samples, of all the render has.
    Range(std::ops::Range<u32>),
}

/// One render, as asked for. `RenderRequest::new(shading, backend)` asks
/// for the whole image with no budget; the fields say the rest.
#[derive(Debug, Clone)]
pub struct RenderRequest<'a> {
    pub shading: Shading,
    /// The Vulkan device, or the f64 reference on the CPU.
    pub backend: Backend,
    /// The raster modes on the GPU: the colour target's format (the ray
    /// tracers always write 32-bit floats, the CPU reference f64 rounded
    /// to f32).
    pub target: ColorTarget,
    /// Ray tracing on the GPU: count the rays by kind (a shader variant
    /// with atomics: slower, so asked for).
    pub count_rays: bool,
    /// Ray tracing on the GPU: the pipeline with every feature compiled
    /// in, not the one specialised to the scene (what `bench` measures
    /// specialising against).
    pub every_feature: bool,
    /// The part of the work a render that sums into a film traces: all
    /// its photons or samples per pixel, a shard of them, or a range.
    pub portion: Portion,
    /// A time budget (`--time`): no batch, pass or task starts after it,
    /// and the image is the estimate of what was traced (one batch at
    /// least).
    pub deadline: Option<Instant>,
    /// An error budget (`--error`, GPU): the RMSE, by the render's own
    /// estimate, at which its batches stop.
    pub error: Option<f64>,
    /// Where the render counts its progress, for a caller to show.
    pub progress: Option<&'a WorkCounter>,
    /// Set by a caller to stop the render between batches, passes or
    /// tasks: `render` then answers `Error::Cancelled`.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl RenderRequest<'_> {
    /// The whole image in `shading` on `backend`: float target, no ray
    /// counts, no budget, no progress, no cancel.
    pub fn new(shading: Shading, backend: Backend) -> Self {
        Self {
            shading,
            backend,
            target: ColorTarget::Float32,
            count_rays: false,
            every_feature: false,
            portion: Portion::All,
            deadline: None,
            error: None,
            progress: None,
            cancel: None,
        }
    }

    /// The GPU's render of `shading`, as `new`.
    pub fn gpu(shading: Shading) -> Self {
        Self::new(shading, Backend::Gpu)
    }

    /// The CPU reference's render of `shading`, as `new`.
    pub fn cpu(shading: Shading) -> Self {
        Self::new(shading, Backend::Cpu)
    }
}
