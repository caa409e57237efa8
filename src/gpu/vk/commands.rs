//! Recording and submitting one-shot command buffers, waiting for them.

use std::sync::Arc;

use ash::vk;

use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::{GpuError, VkContext};
use crate::gpu::vk::watchdog::{self, Watch};

/// The error of a submission that outlived `watch`'s limit.
fn stuck(watch: &Watch) -> GpuError {
    GpuError::Stuck {
        limit_s: watch.limit.map_or(f64::INFINITY, |l| l.as_secs_f64()),
        cause: watch.cause.as_deref().map(str::to_string),
    }
}

/// A command pool with one primary command buffer and a fence.
pub struct OneShot {
    context: Arc<GpuContext>,
    pool: vk::CommandPool,
    pub cmd: vk::CommandBuffer,
    fence: vk::Fence,
}

impl OneShot {
    /// Creates the command buffer and begins recording.
    pub fn begin(context: &Arc<GpuContext>) -> Result<Self, GpuError> {
        let device = &context.device;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(context.queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT);
        // SAFETY: valid device and create info.
        let pool = unsafe { device.create_command_pool(&pool_info, None) }
            .during("vkCreateCommandPool")?;
        let mut this = Self {
            context: context.clone(),
            pool,
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool belongs to this device.
        this.cmd = unsafe { device.allocate_command_buffers(&alloc) }
            .during("vkAllocateCommandBuffers")?[0];
        // SAFETY: valid device.
        this.fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .during("vkCreateFence")?;
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the command buffer is freshly allocated.
        unsafe { device.begin_command_buffer(this.cmd, &begin) }.during("vkBeginCommandBuffer")?;
        Ok(this)
    }

    /// Ends recording, submits, and blocks until the GPU has finished, or
    /// until this thread's watchdog limit has passed: then the device is
    /// stuck (`GpuError::Stuck`) and no later submission is made on it.
    pub fn submit_and_wait(&self) -> Result<(), GpuError> {
        let watch = watchdog::current();
        let device = &self.context.device;
        // SAFETY: the command buffer is recording and owned by this object.
        unsafe { device.end_command_buffer(self.cmd) }.during("vkEndCommandBuffer")?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        let _queue = self
            .context
            .queue_lock
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        // Work queued behind a submission that never ends would never run.
        if watchdog::any_device_stuck() {
            return Err(stuck(&watch));
        }
        // SAFETY: `_queue` serialises access to the queue, and the fence is
        // unsignalled (each OneShot submits once).
        let waited = unsafe {
            device
                .queue_submit2(self.context.queue, &submit, self.fence)
                .during("vkQueueSubmit2")?;
            device.wait_for_fences(&[self.fence], true, watchdog::timeout_ns(watch.limit))
        };
        match waited {
            Ok(()) => Ok(()),
            Err(vk::Result::TIMEOUT) => {
                watchdog::mark_stuck();
                Err(stuck(&watch))
            }
            Err(result) => Err(GpuError::Vulkan {
                call: "vkWaitForFences",
                result,
            }),
        }
    }
}

impl Drop for OneShot {
    fn drop(&mut self) {
        if watchdog::any_device_stuck() {
            // Idling a stuck device never returns; its pool is leaked.
            return;
        }
        // vkDeviceWaitIdle uses every queue: another thread's submission
        // on this device must wait (the validation layer's threading check
        // caught two batch cases idling and submitting at once).
        let _queue = self
            .context
            .queue_lock
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        // SAFETY: submissions are waited for before this object is dropped;
        // after an error the device is idled first so nothing is in flight;
        // `_queue` serialises the idling with other threads' submissions.
        unsafe {
            let _ = self.context.device.device_wait_idle();
            if self.fence != vk::Fence::null() {
                self.context.device.destroy_fence(self.fence, None);
            }
            self.context.device.destroy_command_pool(self.pool, None);
        }
    }
}
