//! The photon map's pipeline: `shaders/caustics.comp.glsl` (its 4-wide
//! BVH walk a module of its own), specialised to the scene as the ray
//! tracer is, its stage and pass pushed, the map's buffers in set 1.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};

use super::map::MAP_BINDINGS;
use crate::gpu::raytrace::layout::{TraceSpecialization, BINDINGS};
use crate::gpu::shared::shader_catalog::{CAUSTICS_COMP, CAUSTICS_WIDE_COMP};
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::descriptors::create_set_layout;
use crate::gpu::vk::error::{GpuError, VkContext};
use crate::gpu::vk::pipeline::PipelineObjects;
use crate::gpu::vk::specialise::specialise;

/// One dispatch of a pass (the shader's `CausticPass`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct CausticPass {
    /// The pass's first photon.
    pub first: u32,
    /// Its photons.
    pub count: u32,
    /// Photons per pass, over which the lights' power is split.
    pub total: u32,
    /// Which of the four stages (`Stage`).
    pub stage: u32,
    /// The pass's number, which keys the eye paths' random numbers.
    pub pass: u32,
    /// The grid's hash buckets.
    pub buckets: u32,
    /// The first radius, in pixel footprints.
    pub initial_radius: f32,
    /// SPPM's alpha.
    pub alpha: f32,
}

/// The four dispatches of a pass, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    VisiblePoints = 0,
    Grid = 1,
    Photons = 2,
    Update = 3,
}

/// The pipeline for `spec`, from the context's cache or built now.
pub fn get_or_build(
    context: &Arc<GpuContext>,
    spec: &TraceSpecialization,
    wide_bvh: bool,
) -> Result<Arc<PipelineObjects>, GpuError> {
    let key = format!(
        "caustics wide {wide_bvh} spec {:?}",
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
    let stage = vk::ShaderStageFlags::COMPUTE;
    let mut p = PipelineObjects::new(device);
    p.set_layout = create_set_layout(context, BINDINGS, stage)?;
    p.extra_set_layout = create_set_layout(context, MAP_BINDINGS, stage)?;
    let set_layouts = [p.set_layout, p.extra_set_layout];
    let push = [vk::PushConstantRange::default()
        .stage_flags(stage)
        .size(std::mem::size_of::<CausticPass>() as u32)];
    let layout_info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&set_layouts)
        .push_constant_ranges(&push);
    // SAFETY: valid device and create infos throughout this function.
    p.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
        .during("vkCreatePipelineLayout")?;
    let shader = if wide_bvh {
        &CAUSTICS_WIDE_COMP
    } else {
        &CAUSTICS_COMP
    };
    let entries = TraceSpecialization::map_entries();
    let spec_data = bytemuck::bytes_of(spec);
    let words = shader.words();
    let specialised = specialise(&words, &entries, spec_data)?;
    // Without `spirv-opt` the driver takes the constants.
    let driver_specialises = specialised.is_none();
    let code = specialised.as_deref().unwrap_or(&words);
    p.create_compute(code, (&entries, spec_data), driver_specialises)?;
    Ok(p)
}
