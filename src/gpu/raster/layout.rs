//! The host's side of the raster shader interface
//! (`shaders/include/raster_interface.glsl`): binding numbers and types,
//! the byte layout of every buffer record and of the push constants, and the
//! specialization constants. tests/cpu/shader_interface.rs checks each of these
//! against naga's reflection of the compiled shaders.

use ash::vk;
use bytemuck::{Pod, Zeroable};

use crate::gpu::shared::lights::{GpuLight, PatternConstants};

pub const LIGHTS_BINDING: u32 = 0;
pub const FRAME_BINDING: u32 = 1;
pub const FACES_BINDING: u32 = 2;
/// The image textures (`TEXTURE` variants, `gpu::shared::texture_table`).
pub const TEXTURE_RECORDS_BINDING: u32 = 3;
pub const TEXELS_BINDING: u32 = 4;

/// Set 0 of the raster pipelines: (binding, type). Flat shading binds all
/// of it; Gouraud and Phong the part without the faces, `SMOOTH_BINDINGS`.
pub const BINDINGS: &[(u32, vk::DescriptorType)] = &[
    (LIGHTS_BINDING, vk::DescriptorType::STORAGE_BUFFER),
    (FRAME_BINDING, vk::DescriptorType::UNIFORM_BUFFER),
    (FACES_BINDING, vk::DescriptorType::STORAGE_BUFFER),
];

/// What Gouraud and Phong bind: the lights and the frame.
pub const SMOOTH_BINDINGS: &[(u32, vk::DescriptorType)] = BINDINGS.split_at(2).0;

/// What Gouraud and Phong bind with image textures: the lights, the frame,
/// the texture records and the texels.
pub const TEXTURED_BINDINGS: &[(u32, vk::DescriptorType)] = &[
    (LIGHTS_BINDING, vk::DescriptorType::STORAGE_BUFFER),
    (FRAME_BINDING, vk::DescriptorType::UNIFORM_BUFFER),
    (TEXTURE_RECORDS_BINDING, vk::DescriptorType::STORAGE_BUFFER),
    (TEXELS_BINDING, vk::DescriptorType::STORAGE_BUFFER),
];

/// The size of the record the host writes to each binding: one element of
/// a runtime array, or the whole uniform block.
pub fn record_size(binding: u32) -> usize {
    match binding {
        LIGHTS_BINDING => std::mem::size_of::<GpuLight>(),
        FRAME_BINDING => std::mem::size_of::<FrameUniforms>(),
        FACES_BINDING => std::mem::size_of::<GpuFace>(),
        TEXTURE_RECORDS_BINDING | TEXELS_BINDING => 16,
        _ => 0,
    }
}

/// Specialization constants: (constant_id, name in GLSL).
pub const SPEC_CONSTANTS: &[(u16, &str)] = &[
    (0, "LIGHT_COUNT"),
    (1, "USE_SPECULAR"),
    (2, "USE_ATTENUATION"),
    (3, "SAMPLER_FIXED"),
    (4, "FIXED_SAMPLER"),
    (5, "BACK_FACES"),
    (6, "OUTPUT_SCALE"),
    (7, "AT_LEAST_ZERO"),
    (32, "INVERSE_SQUARE"),
];

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct Vertex {
    /// Camera-relative position.
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct FrameUniforms {
    /// rgb: Ia, w: k.
    pub ambient_k: [f32; 4],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuFace {
    pub center: [f32; 4],
    pub normal: [f32; 4],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct DrawConstants {
    /// Column-major.
    pub clip_from_relative: [[f32; 4]; 4],
    pub color_ka: [f32; 4],
    pub kd_ks_p: [f32; 4],
}

/// The push constants of the `PATTERN` variants: 128 bytes, the least every
/// Vulkan device holds.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct PatternDrawConstants {
    pub draw: DrawConstants,
    pub pattern: PatternConstants,
}

/// Values for `SPEC_CONSTANTS`, in order; each is 4 bytes (bools as VkBool32).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Specialization {
    pub light_count: i32,
    pub use_specular: u32,
    pub use_attenuation: u32,
    pub sampler_fixed: u32,
    pub fixed_sampler: u32,
    /// Whether some draw may show its back (`raster::cull`): then Gouraud's
    /// vertex stage lights each vertex's back too.
    pub back_faces: u32,
    /// What the fragment stages multiply their colour by: 1, or 1/16 for
    /// the scaled 16-bit target (`ColorTarget::ScaledUnorm16`).
    pub output_scale: f32,
    /// Multisampled and shaded per pixel: a colour below 0 (extrapolated
    /// inputs) is written as 0.
    pub at_least_zero: u32,
    pub inverse_square: u32,
}

impl Specialization {
    pub fn map_entries() -> [vk::SpecializationMapEntry; 9] {
        let entry = |index: usize| vk::SpecializationMapEntry {
            constant_id: u32::from(SPEC_CONSTANTS[index].0),
            offset: index as u32 * 4,
            size: 4,
        };
        [
            entry(0),
            entry(1),
            entry(2),
            entry(3),
            entry(4),
            entry(5),
            entry(6),
            entry(7),
            entry(8),
        ]
    }
}
