//! The photon map's buffers (set 1 of `shaders/caustics.comp.glsl`): each
//! pixel's visible point and state over the passes, the grid's buckets and
//! nodes, and the photons each pixel gathered this pass. The shader keeps
//! them ready pass after pass (its update stage clears the pass's sums and
//! grid), so the host sets them once.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::gpu::vk::buffer::Buffer;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::descriptors::Descriptors;
use crate::gpu::vk::error::GpuError;

const STORAGE: vk::DescriptorType = vk::DescriptorType::STORAGE_BUFFER;

/// Set 1: visible points, pixel states, grid, grid nodes, photons found.
pub const MAP_BINDINGS: &[(u32, vk::DescriptorType)] = &[
    (0, STORAGE),
    (1, STORAGE),
    (2, STORAGE),
    (3, STORAGE),
    (4, STORAGE),
];

/// The record each binding of `MAP_BINDINGS` holds, in bytes: a quad of
/// a point or a state, a bucket's head, a node, a count
/// (tests/cpu/shader_interface.rs holds the shader to them).
pub const MAP_RECORD_SIZES: [usize; 5] = [16, 16, 4, 8, 4];

/// Hash buckets per pixel: a visible point goes into up to 8 cells' buckets,
/// so lists stay a few nodes long.
pub const BUCKETS_PER_PIXEL: u64 = 2;

/// Bytes per pixel of the map (`memory` estimates a render by it): a visible point (3 quads), a state (2),
/// grid nodes for 8 cells (8 bytes each), buckets and a count.
pub const BYTES_PER_PIXEL: u64 = 48 + 32 + 64 + 4 * BUCKETS_PER_PIXEL + 4;

/// The map's buffers, freed in the reverse of their creation.
pub struct MapBuffers {
    found: Buffer,
    nodes: Buffer,
    grid: Buffer,
    states: Buffer,
    points: Buffer,
    pub buckets: u32,
}

impl MapBuffers {
    /// The buffers for `pixels` pixels: states and counts zeroed, every
    /// bucket empty.
    pub fn new(context: &Arc<GpuContext>, pixels: u64) -> Result<Self, GpuError> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let make =
            |name: &str, bytes: u64, location| Buffer::new(context, name, bytes, storage, location);
        let buckets = pixels * BUCKETS_PER_PIXEL;
        let points = make("visible points", 48 * pixels, MemoryLocation::GpuOnly)?;
        let mut states = make("pixel states", 32 * pixels, MemoryLocation::GpuToCpu)?;
        states.mapped_mut().fill(0);
        let mut grid = make("grid", 16 + 4 * buckets, MemoryLocation::CpuToGpu)?;
        let bytes = grid.mapped_mut();
        bytes[..16].fill(0);
        bytes[16..].fill(0xff);
        let nodes = make("grid nodes", 64 * pixels, MemoryLocation::GpuOnly)?;
        let mut found = make("photons found", 4 * pixels, MemoryLocation::CpuToGpu)?;
        found.mapped_mut().fill(0);
        Ok(Self {
            found,
            nodes,
            grid,
            states,
            points,
            buckets: u32::try_from(buckets).unwrap_or(u32::MAX),
        })
    }

    /// The descriptor set of `set_layout` (`MAP_BINDINGS`).
    pub fn bind(
        &self,
        context: &Arc<GpuContext>,
        set_layout: vk::DescriptorSetLayout,
    ) -> Result<Descriptors, GpuError> {
        Descriptors::new(
            context,
            set_layout,
            MAP_BINDINGS,
            &[
                &self.points,
                &self.states,
                &self.grid,
                &self.nodes,
                &self.found,
            ],
        )
    }

    /// Each pixel's flux so far, count and radius, after the last pass has
    /// completed: `(flux, count, radius)`.
    pub fn states(&self) -> impl Iterator<Item = ([f32; 3], f32, f32)> + '_ {
        let floats: &[f32] = bytemuck::cast_slice(self.states.mapped());
        floats
            .chunks_exact(8)
            .map(|s| ([s[0], s[1], s[2]], s[3], s[4]))
    }
}
