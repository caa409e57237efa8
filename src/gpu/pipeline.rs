//! The Vulkan objects one pipeline owns (its set layout, layout, shader
//! modules and the pipeline itself), destroyed together.

use std::sync::Arc;

use ash::vk;

use super::context::GpuContext;
use super::error::GpuError;

pub struct PipelineObjects {
    context: Arc<GpuContext>,
    pub set_layout: vk::DescriptorSetLayout,
    /// A second set's layout, where the pipeline has one (null otherwise).
    pub extra_set_layout: vk::DescriptorSetLayout,
    pub layout: vk::PipelineLayout,
    pub pipeline: vk::Pipeline,
    pub modules: Vec<vk::ShaderModule>,
}

impl PipelineObjects {
    /// Empty (null) handles, filled in as creation proceeds; whatever was
    /// created is destroyed if a later step fails.
    pub fn new(context: &Arc<GpuContext>) -> Self {
        Self {
            context: context.clone(),
            set_layout: vk::DescriptorSetLayout::null(),
            extra_set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            modules: Vec::new(),
        }
    }
}

/// The one pipeline a `vkCreate*Pipelines` call made, or its error named
/// after `call`.
pub fn single_pipeline(
    created: Result<Vec<vk::Pipeline>, (Vec<vk::Pipeline>, vk::Result)>,
    call: &'static str,
) -> Result<vk::Pipeline, GpuError> {
    created
        .map(|pipelines| pipelines[0])
        .map_err(|(_, result)| GpuError::Vulkan { call, result })
}

impl Drop for PipelineObjects {
    fn drop(&mut self) {
        let device = &self.context.device;
        // SAFETY: the GPU work using these objects has completed; null
        // handles (from a failed creation) are ignored by Vulkan.
        unsafe {
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
            device.destroy_descriptor_set_layout(self.extra_set_layout, None);
            for m in &self.modules {
                device.destroy_shader_module(*m, None);
            }
        }
    }
}
