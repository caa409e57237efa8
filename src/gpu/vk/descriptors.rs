//! Descriptor set layouts and the one descriptor set a dispatch or draw
//! binds, built from a list of `(binding, type)` pairs (a pipeline's
//! `BINDINGS`, which tests/cpu/shader_interface.rs checks against the shaders).

use std::sync::Arc;

use ash::vk;

use crate::gpu::vk::buffer::Buffer;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::{GpuError, VkContext};

pub fn create_set_layout(
    context: &GpuContext,
    bindings: &[(u32, vk::DescriptorType)],
    stages: vk::ShaderStageFlags,
) -> Result<vk::DescriptorSetLayout, GpuError> {
    let bindings: Vec<_> = bindings
        .iter()
        .map(|&(binding, ty)| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(ty)
                .descriptor_count(1)
                .stage_flags(stages)
        })
        .collect();
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
    // SAFETY: valid device and create info.
    unsafe { context.device.create_descriptor_set_layout(&info, None) }
        .during("vkCreateDescriptorSetLayout")
}

/// A descriptor pool holding exactly one set, freed together.
pub struct Descriptors {
    context: Arc<GpuContext>,
    pool: vk::DescriptorPool,
    pub set: vk::DescriptorSet,
}

impl Descriptors {
    /// A pool with room for one set of `layout` holding `bindings`' types,
    /// and that set, not yet written.
    fn allocate(
        context: &Arc<GpuContext>,
        layout: vk::DescriptorSetLayout,
        bindings: &[(u32, vk::DescriptorType)],
    ) -> Result<Self, GpuError> {
        let device = &context.device;
        let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
        for &(_, ty) in bindings {
            match sizes.iter_mut().find(|s| s.ty == ty) {
                Some(s) => s.descriptor_count += 1,
                None => sizes.push(vk::DescriptorPoolSize::default().ty(ty).descriptor_count(1)),
            }
        }
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: valid device and create info.
        let pool = unsafe { device.create_descriptor_pool(&pool_info, None) }
            .during("vkCreateDescriptorPool")?;
        let mut d = Descriptors {
            context: context.clone(),
            pool,
            set: vk::DescriptorSet::null(),
        };
        let layouts = [layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        // SAFETY: the pool has room for exactly this set.
        d.set = unsafe { device.allocate_descriptor_sets(&alloc) }
            .during("vkAllocateDescriptorSets")?[0];
        Ok(d)
    }

    /// A set for `layout` with `buffers[i]` bound whole at `bindings[i]`.
    pub fn new(
        context: &Arc<GpuContext>,
        layout: vk::DescriptorSetLayout,
        bindings: &[(u32, vk::DescriptorType)],
        buffers: &[&Buffer],
    ) -> Result<Self, GpuError> {
        assert_eq!(bindings.len(), buffers.len(), "one buffer per binding");
        let d = Self::allocate(context, layout, bindings)?;
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
            .iter()
            .map(|b| {
                [vk::DescriptorBufferInfo::default()
                    .buffer(b.raw)
                    .range(vk::WHOLE_SIZE)]
            })
            .collect();
        let writes: Vec<_> = bindings
            .iter()
            .zip(&infos)
            .map(|(&(binding, ty), info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(d.set)
                    .dst_binding(binding)
                    .descriptor_type(ty)
                    .buffer_info(info)
            })
            .collect();
        // SAFETY: the writes match the layout built from the same bindings.
        unsafe { context.device.update_descriptor_sets(&writes, &[]) };
        Ok(d)
    }

    /// A set for `layout` (`bindings`: one acceleration structure) holding
    /// `structure`.
    pub fn for_structure(
        context: &Arc<GpuContext>,
        layout: vk::DescriptorSetLayout,
        bindings: &[(u32, vk::DescriptorType)],
        structure: vk::AccelerationStructureKHR,
    ) -> Result<Self, GpuError> {
        assert_eq!(
            bindings,
            [(
                bindings[0].0,
                vk::DescriptorType::ACCELERATION_STRUCTURE_KHR
            )],
            "one acceleration structure"
        );
        let d = Self::allocate(context, layout, bindings)?;
        let structures = [structure];
        let mut write_structure = vk::WriteDescriptorSetAccelerationStructureKHR::default()
            .acceleration_structures(&structures);
        let write = vk::WriteDescriptorSet::default()
            .dst_set(d.set)
            .dst_binding(bindings[0].0)
            .descriptor_type(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
            .descriptor_count(1)
            .push_next(&mut write_structure);
        // SAFETY: the write matches the layout's one binding; `structure`
        // outlives the set (the caller drops the set first).
        unsafe { context.device.update_descriptor_sets(&[write], &[]) };
        Ok(d)
    }
}

impl Drop for Descriptors {
    fn drop(&mut self) {
        if crate::gpu::vk::watchdog::any_device_stuck() {
            // A shader may still be running: leaked, never freed under it.
            return;
        }
        // SAFETY: the GPU work using the set has completed.
        unsafe { self.context.device.destroy_descriptor_pool(self.pool, None) };
    }
}
