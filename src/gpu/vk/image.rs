//! 2D images (colour and depth targets) with their memory and view.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::Allocation;
use gpu_allocator::MemoryLocation;

use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::{GpuError, VkContext};

pub struct Image {
    context: Arc<GpuContext>,
    pub raw: vk::Image,
    pub view: vk::ImageView,
    allocation: Option<Allocation>,
}

impl Image {
    pub fn new(
        context: &Arc<GpuContext>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Self, GpuError> {
        Self::multisampled(context, name, extent, (format, 1), usage, aspect)
    }

    /// An image of `samples` samples per pixel (a power of two the device
    /// takes for `format`).
    pub fn multisampled(
        context: &Arc<GpuContext>,
        name: &str,
        extent: vk::Extent2D,
        (format, samples): (vk::Format, u32),
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Self, GpuError> {
        let device = &context.device;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::from_raw(samples))
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device and create info.
        let raw = unsafe { device.create_image(&info, None) }.during("vkCreateImage")?;
        let mut image = Self {
            context: context.clone(),
            raw,
            view: vk::ImageView::null(),
            allocation: None,
        };
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.get_image_memory_requirements(raw) };
        let allocation = context.allocate(name, requirements, MemoryLocation::GpuOnly, false)?;
        // SAFETY: the allocation satisfies the image's requirements.
        unsafe { device.bind_image_memory(raw, allocation.memory(), allocation.offset()) }
            .during("vkBindImageMemory")?;
        image.allocation = Some(allocation);
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(subresource_range(aspect));
        // SAFETY: the image is bound to memory and the view matches it.
        image.view =
            unsafe { device.create_image_view(&view_info, None) }.during("vkCreateImageView")?;
        Ok(image)
    }
}

pub fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .level_count(1)
        .layer_count(1)
}

impl Drop for Image {
    fn drop(&mut self) {
        if crate::gpu::vk::watchdog::any_device_stuck() {
            // A shader may still be running: leaked, never freed under it.
            return;
        }
        // SAFETY: the GPU work that used this image has completed.
        unsafe {
            if self.view != vk::ImageView::null() {
                self.context.device.destroy_image_view(self.view, None);
            }
            self.context.device.destroy_image(self.raw, None);
        }
        if let Some(a) = self.allocation.take() {
            self.context.free(a);
        }
    }
}

/// A layout transition (and the work it waits on) of one image's whole
/// `aspect`.
pub fn image_barrier(
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    (old, new): (vk::ImageLayout, vk::ImageLayout),
    (src_stage, src_access): (vk::PipelineStageFlags2, vk::AccessFlags2),
    (dst_stage, dst_access): (vk::PipelineStageFlags2, vk::AccessFlags2),
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .image(image)
        .subresource_range(subresource_range(aspect))
        .old_layout(old)
        .new_layout(new)
        .src_stage_mask(src_stage)
        .src_access_mask(src_access)
        .dst_stage_mask(dst_stage)
        .dst_access_mask(dst_access)
}
