//! The photon map's pipeline: `shaders/caustics.comp.glsl` (its 4-wide
//! BVH walk a module of its own), specialised to the scene as the ray
//! tracer is, its stage and pass pushed, the map's buffers in set 1.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};

use super::map::MAP_BINDINGS;
use crate::gpu::raytrace::forward::create_photon_pipeline;
use crate::gpu::raytrace::layout::TraceSpecialization;
use crate::gpu::shared::shader_catalog::{CAUSTICS_COMP, CAUSTICS_WIDE_COMP};
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::GpuError;
use crate::gpu::vk::pipeline::PipelineObjects;

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
    let shader = if wide_bvh {
        &CAUSTICS_WIDE_COMP
    } else {
        &CAUSTICS_COMP
    };
    let push = std::mem::size_of::<CausticPass>() as u32;
    create_photon_pipeline(context, (shader, spec), push, Some(MAP_BINDINGS))
}
