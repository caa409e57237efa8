//! The forward tracer's pipeline: `shaders/forward.comp.glsl` (its 4-wide
//! BVH walk a module of its own, as the ray tracer's), specialised to the
//! scene as the ray tracer is, with the photon batch as push constants.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};

use crate::gpu::raytrace::layout::{TraceSpecialization, BINDINGS};
use crate::gpu::shared::shader_catalog::{ShaderBlob, FORWARD_COMP, FORWARD_WIDE_COMP};
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::descriptors::create_set_layout;
use crate::gpu::vk::error::{GpuError, VkContext};
use crate::gpu::vk::pipeline::PipelineObjects;
use crate::gpu::vk::specialise::{specialise, Lowering};

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
    let shader = if wide_bvh {
        &FORWARD_WIDE_COMP
    } else {
        &FORWARD_COMP
    };
    let push = std::mem::size_of::<PhotonBatch>() as u32;
    create_photon_pipeline(context, (shader, spec), push, None)
}

/// A compute pipeline over the ray tracer's set 0 (and `extra`'s set 1
/// where given), `shader` specialised to `spec`, `push_size` bytes of
/// push constants: the forward tracer's, and the photon map's.
pub(in crate::gpu::raytrace) fn create_photon_pipeline(
    context: &Arc<GpuContext>,
    (shader, spec): (&ShaderBlob, &TraceSpecialization),
    push_size: u32,
    extra: Option<&[(u32, vk::DescriptorType)]>,
) -> Result<PipelineObjects, GpuError> {
    let device = &context.device;
    let stage = vk::ShaderStageFlags::COMPUTE;
    let mut p = PipelineObjects::new(device);
    p.set_layout = create_set_layout(context, BINDINGS, stage)?;
    let mut set_layouts = vec![p.set_layout];
    if let Some(bindings) = extra {
        p.extra_set_layout = create_set_layout(context, bindings, stage)?;
        set_layouts.push(p.extra_set_layout);
    }
    let push = [vk::PushConstantRange::default()
        .stage_flags(stage)
        .size(push_size)];
    let layout_info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&set_layouts)
        .push_constant_ranges(&push);
    // SAFETY: valid device and create infos throughout this function.
    p.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
        .during("vkCreatePipelineLayout")?;
    let entries = TraceSpecialization::map_entries();
    let spec_data = bytemuck::bytes_of(spec);
    let words = shader.words();
    let specialised = specialise(&words, &entries, spec_data, Lowering::Inlined)?;
    // Without `spirv-opt` the driver takes the constants.
    let driver_specialises = specialised.is_none();
    let code = specialised.as_deref().unwrap_or(&words);
    p.create_compute(code, (&entries, spec_data), driver_specialises)?;
    Ok(p)
}
