//! How a trace runs on the device: its pipeline and sets `BoundTrace`
//! (the work queue reset first), a first dispatch that does no work so
//! that the driver's code generation is timed apart, then the image's
//! workgroups between two timestamps; and how many threads a CPU device
//! spreads them over.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use crate::gpu::raytrace::layout::QUERY_SET;
use crate::gpu::vk::commands::OneShot;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::GpuError;
use crate::gpu::vk::pipeline::PipelineObjects;
use crate::gpu::vk::timestamps::{ms_since, Timestamps};

/// A work-queue head past any image's last item: a dispatch that starts
/// from it takes no item, so every subgroup ends at once.
pub(super) const QUEUE_EXHAUSTED: u32 = 0x8000_0000;

/// The ray tracer's pipeline and what it reads, bound for a dispatch.
pub(super) struct BoundTrace<'a> {
    pub pipeline: &'a PipelineObjects,
    pub set: vk::DescriptorSet,
    /// The ray-query engine's set of the acceleration structure.
    pub structure_set: Option<vk::DescriptorSet>,
    pub work_queue: vk::Buffer,
    /// Push constants set after binding (empty: none), so that every
    /// dispatch of a pipeline that has them (the first use's too) has them
    /// set; a dispatch may push its own over them.
    pub push_constants: &'a [u8],
}

impl BoundTrace<'_> {
    /// Records the work queue set to `queue_head`, the pipeline and its
    /// sets bound, then `dispatch`.
    ///
    /// # Safety
    /// `cmd` is recording, and every handle in `self` lives until the
    /// submission that runs it has completed.
    pub(super) unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        queue_head: u32,
        dispatch: impl FnOnce(vk::CommandBuffer),
    ) {
        // An earlier dispatch's atomics on the queue (the first use's, in
        // an earlier submission) come before this write.
        let queue_used = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::CLEAR)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_WRITE)];
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&queue_used),
        );
        device.cmd_fill_buffer(cmd, self.work_queue, 0, vk::WHOLE_SIZE, queue_head);
        let queue_set = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::CLEAR)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .dst_access_mask(
                vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            )];
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&queue_set),
        );
        let p = self.pipeline;
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.pipeline);
        let bind = vk::PipelineBindPoint::COMPUTE;
        device.cmd_bind_descriptor_sets(cmd, bind, p.layout, 0, &[self.set], &[]);
        if let Some(structure_set) = self.structure_set {
            // The structures were built by an earlier submission on this
            // queue: their writes must reach the shader's reads.
            let built = [vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::ACCELERATION_STRUCTURE_BUILD_KHR)
                .src_access_mask(vk::AccessFlags2::ACCELERATION_STRUCTURE_WRITE_KHR)
                .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
                .dst_access_mask(vk::AccessFlags2::ACCELERATION_STRUCTURE_READ_KHR)];
            device
                .cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&built));
            device.cmd_bind_descriptor_sets(cmd, bind, p.layout, QUERY_SET, &[structure_set], &[]);
        }
        if !self.push_constants.is_empty() {
            let stage = vk::ShaderStageFlags::COMPUTE;
            device.cmd_push_constants(cmd, p.layout, stage, 0, self.push_constants);
        }
        dispatch(cmd);
    }

    /// Records the trace of the whole image, `groups` workgroups wide and
    /// high, between `timestamps`' two stamps.
    ///
    /// # Safety
    /// As for `record`; `timestamps` too lives until the submission has
    /// completed.
    pub(super) unsafe fn record_image(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        timestamps: &Timestamps,
        (groups_x, groups_y): (u32, u32),
    ) {
        self.record(device, cmd, 0, |cmd| {
            timestamps.start(cmd);
            device.cmd_dispatch(cmd, groups_x, groups_y, 1);
        });
        record_writes_to_host(device, cmd);
        timestamps.stop(cmd);
    }
}

/// One submission of `bound`: the work queue set to `queue_head`, `push`
/// pushed over the bound constants, `groups` workgroups dispatched (between
/// `timestamps`' stamps where given), its writes made visible to the host;
/// its submit and GPU milliseconds (GPU 0 without timestamps). A batch of
/// the forward tracer's photons, or of the ray tracer's samples.
pub(super) fn submit_batch(
    context: &Arc<GpuContext>,
    bound: &BoundTrace,
    timestamps: Option<&Timestamps>,
    push: &[u8],
    (queue_head, (groups_x, groups_y)): (u32, (u32, u32)),
) -> Result<(f64, f64), GpuError> {
    let device = &context.device;
    let commands = OneShot::begin(context)?;
    let layout = bound.pipeline.layout;
    // SAFETY: every handle recorded here lives until the submission has
    // completed (this function waits for it).
    unsafe {
        bound.record(device, commands.cmd, queue_head, |cmd| {
            let stage = vk::ShaderStageFlags::COMPUTE;
            device.cmd_push_constants(cmd, layout, stage, 0, push);
            if let Some(t) = timestamps {
                t.start(cmd);
            }
            device.cmd_dispatch(cmd, groups_x, groups_y, 1);
        });
        // Before the host reads, and before the next batch adds to what
        // this one wrote.
        record_writes_to_host(device, commands.cmd);
        if let Some(t) = timestamps {
            t.stop(commands.cmd);
        }
    }
    match timestamps {
        Some(t) => t.submit_and_measure(&commands),
        None => {
            let started = Instant::now();
            commands.submit_and_wait()?;
            context.check_validation()?;
            Ok((ms_since(started), 0.0))
        }
    }
}

/// Records a barrier that orders the shader's writes before the host's
/// reads (and before later work on the queue).
///
/// # Safety
/// `cmd` is recording.
pub(super) unsafe fn record_writes_to_host(device: &ash::Device, cmd: vk::CommandBuffer) {
    let to_host = [vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
        .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::HOST | vk::PipelineStageFlags2::ALL_COMMANDS)
        .dst_access_mask(vk::AccessFlags2::HOST_READ)];
    device.cmd_pipeline_barrier2(
        cmd,
        &vk::DependencyInfo::default().memory_barriers(&to_host),
    );
}

/// The pipeline's first use, apart from the render, in milliseconds: one
/// workgroup over an exhausted work queue, which traces nothing. Lavapipe
/// generates a pipeline's machine code at its first dispatch (or loads it
/// from Mesa's shader cache), so this is that cost alone, and `gpu_ms`
/// after it is the trace alone, on a cold cache as on a warm one.
pub(super) fn first_use(context: &Arc<GpuContext>, bound: &BoundTrace) -> Result<f64, GpuError> {
    let started = Instant::now();
    let commands = OneShot::begin(context)?;
    let device = &context.device;
    // SAFETY: `bound`'s handles outlive this function, which waits for the
    // submission; the shader takes no item and writes no pixel.
    unsafe {
        bound.record(device, commands.cmd, QUEUE_EXHAUSTED, |cmd| {
            device.cmd_dispatch(cmd, 1, 1, 1)
        });
    }
    commands.submit_and_wait()?;
    context.check_validation()?;
    Ok(ms_since(started))
}

/// The threads a CPU device (lavapipe) runs a dispatch on: one per CPU,
/// or `LP_NUM_THREADS` where that asks for more.
pub(super) fn cpu_threads() -> usize {
    let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
    let asked = std::env::var("LP_NUM_THREADS")
        .ok()
        .and_then(|n| n.trim().parse::<usize>().ok());
    cpus.max(asked.unwrap_or(0))
}
