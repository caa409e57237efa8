//! The forward tracer's pipeline: `shaders/forward.comp.glsl` (its 4-wide
//! BVH walk a module of its own, as the ray tracer's), specialised to the
//! scene as the ray tracer is, with the photon batch as push constants.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};

use crate::gpu::raytrace::layout::{TraceSpecialization, BINDINGS};
use crate::gpu::shared::shader_catalog::{FORWARD_COMP, FORWARD_WIDE_COMP};
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::descriptors::create_set_layout;
use crate::gpu::vk::error::{GpuError, VkContext};
use crate::gpu::vk::pipeline::{single_pipeline, PipelineObjects};
use crate::gpu::vk::specialise::specialise;

/// The batch a dispatch traces (the shader's `PhotonBatch`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct PhotonBatch {
    /// The batch's first photon.
    pub first: u32,
    /// Its photons.
    pub count: u32,
    /// The render's photons, over which the lights' power is split.
    pub total: u32,
    pub unused: u32,
}

/// The pipeline for `spec`, from the context's cache or built now.
pub fn get_or_build(
    context: &Arc<GpuContext>,
    spec: &TraceSpecialization,
    wide_bvh: bool,
) -> Result<Arc<PipelineObjects>, GpuError> {
    let key = format!(
        "forward wide {wide_bvh} spec {:?}",
        bytemuck::bytes_of(spec)
    );
    context
        .pipelines
        .get_or_create(key, || create(context, spec, wide_bvh))
}

fn create(
    context: &Arc<GpuContext>,
    spec: &TraceSpecialization,
    wide_bvh: bool,
) -> Result<PipelineObjects, GpuError> {
    let device = &context.device;
    let mut p = PipelineObjects::new(device);
    p.set_layout = create_set_layout(context, BINDINGS, vk::ShaderStageFlags::COMPUTE)?;
    let set_layouts = [p.set_layout];
    let push = [vk::PushConstantRange::default()
        .stage_flags(vk::ShaderStageFlags::COMPUTE)
        .size(std::mem::size_of::<PhotonBatch>() as u32)];
    let layout_info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&set_layouts)
        .push_constant_ranges(&push);
    // SAFETY: valid device and create infos throughout this function.
    p.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
        .during("vkCreatePipelineLayout")?;
    let shader = if wide_bvh {
        &FORWARD_WIDE_COMP
    } else {
        &FORWARD_COMP
    };
    let entries = TraceSpecialization::map_entries();
    let spec_data = bytemuck::bytes_of(spec);
    let words = shader.words();
    let specialised = specialise(&words, &entries, spec_data)?;
    let code = specialised.as_deref().unwrap_or(&words);
    let module_info = vk::ShaderModuleCreateInfo::default().code(code);
    // SAFETY: the words are SPIR-V validated by naga at build time, then
    // specialised by SPIRV-Tools' optimizer.
    let module = unsafe { device.create_shader_module(&module_info, None) }
        .during("vkCreateShaderModule")?;
    p.modules.push(module);
    let spec_info = vk::SpecializationInfo::default()
        .map_entries(&entries)
        .data(spec_data);
    let mut stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"main");
    if specialised.is_none() {
        // Without `spirv-opt` the driver takes the constants.
        stage = stage.specialization_info(&spec_info);
    }
    let info = vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(p.layout);
    // SAFETY: every pointer in `info` refers to locals alive for the call.
    let created =
        unsafe { device.create_compute_pipelines(vk::PipelineCache::null(), &[info], None) };
    p.pipeline = single_pipeline(created, "vkCreateComputePipelines")?;
    Ok(p)
}
