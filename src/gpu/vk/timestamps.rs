//! Two GPU timestamps around a piece of recorded work.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use crate::gpu::vk::commands::OneShot;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::{GpuError, VkContext};

/// Where a render spent its time.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct GpuTimings {
    /// Host work on the scene before the pipeline: geometry, the BVH and
    /// the records the shaders read.
    pub prepare_ms: f64,
    /// Shader modules and pipeline creation.
    pub pipeline_ms: f64,
    /// Buffers, images and descriptors made and the scene's data uploaded.
    pub upload_ms: f64,
    /// The driver's work at the pipeline's first use, told apart from the
    /// render by a dispatch that does no work (the ray tracer): lavapipe
    /// generates the machine code there, or loads it from Mesa's shader
    /// cache. `None` where it is not told apart (the raster modes: it is
    /// inside `submit_ms`).
    pub codegen_ms: Option<f64>,
    /// GPU time between timestamp queries around the work.
    pub gpu_ms: f64,
    /// Wall time from queue submission to the fence: the GPU's work plus a
    /// small submission overhead. Unlike `gpu_ms` it cannot be fooled by a
    /// driver's timestamp placement (lavapipe 22.3 stamps a compute dispatch
    /// that follows graphics work at ~0.1 ms, whatever it costs).
    pub submit_ms: f64,
    /// The image read back from mapped memory into a `LinearImage`.
    pub readback_ms: f64,
    /// Wall time of the whole render, host work and read-back included.
    pub total_ms: f64,
}

/// Milliseconds since `start`.
pub fn ms_since(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

pub struct Timestamps {
    context: Arc<GpuContext>,
    pool: vk::QueryPool,
}

impl Timestamps {
    pub fn new(context: &Arc<GpuContext>) -> Result<Self, GpuError> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(2);
        // SAFETY: valid device and create info.
        let pool =
            unsafe { context.device.create_query_pool(&info, None) }.during("vkCreateQueryPool")?;
        Ok(Self {
            context: context.clone(),
            pool,
        })
    }

    /// Records the reset and the first timestamp.
    pub fn start(&self, cmd: vk::CommandBuffer) {
        // SAFETY: `cmd` is recording and the pool outlives the submission.
        unsafe {
            self.context
                .device
                .cmd_reset_query_pool(cmd, self.pool, 0, 2);
            self.context.device.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::TOP_OF_PIPE,
                self.pool,
                0,
            );
        }
    }

    /// Records the second timestamp once all earlier work has finished.
    /// (lavapipe 22.3 still stamps a compute dispatch that follows graphics
    /// work at ~0.1 ms; see `GpuTimings::submit_ms`.)
    pub fn stop(&self, cmd: vk::CommandBuffer) {
        // SAFETY: as in `start`.
        unsafe {
            self.context.device.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                1,
            )
        };
    }

    /// Submits the recorded work (which `start` and `stop` bracket), waits
    /// for it, turns any validation message into an error, and returns
    /// `(submit_ms, gpu_ms)` for `GpuTimings`.
    pub fn submit_and_measure(&self, commands: &OneShot) -> Result<(f64, f64), GpuError> {
        let submitted = Instant::now();
        commands.submit_and_wait()?;
        let submit_ms = submitted.elapsed().as_secs_f64() * 1e3;
        self.context.check_validation()?;
        Ok((submit_ms, self.elapsed_ms()?))
    }

    /// Milliseconds between the two, after the submission has completed.
    pub fn elapsed_ms(&self) -> Result<f64, GpuError> {
        let mut stamps = [0u64; 2];
        // SAFETY: both queries were written by the completed submission.
        unsafe {
            self.context.device.get_query_pool_results(
                self.pool,
                0,
                &mut stamps,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .during("vkGetQueryPoolResults")?;
        Ok(stamps[1].saturating_sub(stamps[0]) as f64 * self.context.timestamp_period_ns() * 1e-6)
    }
}

impl Drop for Timestamps {
    fn drop(&mut self) {
        if crate::gpu::vk::watchdog::any_device_stuck() {
            // A shader may still be running: leaked, never freed under it.
            return;
        }
        // SAFETY: the queries are no longer in use.
        unsafe { self.context.device.destroy_query_pool(self.pool, None) };
    }
}
