//! Buffers with their memory, freed when dropped.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::Allocation;
use gpu_allocator::MemoryLocation;

use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::{GpuError, VkContext};

pub struct Buffer {
    context: Arc<GpuContext>,
    pub raw: vk::Buffer,
    allocation: Option<Allocation>,
}

impl Buffer {
    /// A buffer of `size` bytes (at least 1, since Vulkan forbids empty ones).
    pub fn new(
        context: &Arc<GpuContext>,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self, GpuError> {
        let size = size.max(16);
        let device = &context.device;
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device and create info.
        let raw = unsafe { device.create_buffer(&info, None) }.during("vkCreateBuffer")?;
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(raw) };
        let allocation = match context.allocate(name, requirements, location, true) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: the buffer is unused and owned here.
                unsafe { device.destroy_buffer(raw, None) };
                return Err(e);
            }
        };
        // SAFETY: the allocation satisfies the buffer's requirements.
        let bound =
            unsafe { device.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) };
        let buffer = Self {
            context: context.clone(),
            raw,
            allocation: Some(allocation),
        };
        bound.during("vkBindBufferMemory")?;
        Ok(buffer)
    }

    /// A host-visible buffer filled with `data`.
    pub fn with_data(
        context: &Arc<GpuContext>,
        name: &str,
        data: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self, GpuError> {
        let mut buffer = Self::new(
            context,
            name,
            data.len() as u64,
            usage,
            MemoryLocation::CpuToGpu,
        )?;
        buffer.mapped_mut()[..data.len()].copy_from_slice(data);
        Ok(buffer)
    }

    pub fn mapped(&self) -> &[u8] {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .expect("buffer is host-visible")
    }

    pub fn mapped_mut(&mut self) -> &mut [u8] {
        self.allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .expect("buffer is host-visible")
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        if crate::gpu::vk::watchdog::any_device_stuck() {
            // A shader may still be running: leaked, never freed under it.
            return;
        }
        // SAFETY: the GPU work that used this buffer has completed (every
        // submission waits on its fence before resources are dropped).
        unsafe { self.context.device.destroy_buffer(self.raw, None) };
        if let Some(a) = self.allocation.take() {
            self.context.free(a);
        }
    }
}
