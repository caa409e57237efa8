//! The Vulkan objects one pipeline owns (its set layout, layout, shader
//! modules and the pipeline itself), destroyed together; and the pipelines
//! a device has built, kept for the renders after the first.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use ash::vk;

use crate::gpu::vk::error::{GpuError, VkContext};

pub struct PipelineObjects {
    /// The device's handle, not the context: the context keeps built
    /// pipelines (`BuiltPipelines`), and an `Arc` back to it would keep it
    /// alive forever. The context drops its pipelines before the device.
    device: ash::Device,
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
    pub fn new(device: &ash::Device) -> Self {
        Self {
            device: device.clone(),
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

impl PipelineObjects {
    /// The compute pipeline of `words` (validated SPIR-V) in `self.layout`,
    /// its module kept in `self.modules`: with the specialization constants
    /// of `entries`/`data` handed to the driver where `driver_specialises`,
    /// else already in the module (`specialise`).
    pub fn create_compute(
        &mut self,
        words: &[u32],
        (entries, data): (&[vk::SpecializationMapEntry], &[u8]),
        driver_specialises: bool,
    ) -> Result<(), GpuError> {
        let device = &self.device;
        let module_info = vk::ShaderModuleCreateInfo::default().code(words);
        // SAFETY: the callers pass SPIR-V validated at build time (naga, or
        // spirv-val for ray queries) or by `hook::module_words`, possibly
        // specialised by SPIRV-Tools' optimizer.
        let module = unsafe { device.create_shader_module(&module_info, None) }
            .during("vkCreateShaderModule")?;
        self.modules.push(module);
        let spec_info = vk::SpecializationInfo::default()
            .map_entries(entries)
            .data(data);
        let mut stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(c"main");
        if driver_specialises {
            // Otherwise the constants are in the module already.
            stage = stage.specialization_info(&spec_info);
        }
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(self.layout);
        // SAFETY: every pointer in `info` refers to locals alive for the call.
        let created =
            unsafe { device.create_compute_pipelines(vk::PipelineCache::null(), &[info], None) };
        self.pipeline = single_pipeline(created, "vkCreateComputePipelines")?;
        Ok(())
    }
}

impl Drop for PipelineObjects {
    fn drop(&mut self) {
        if crate::gpu::vk::watchdog::any_device_stuck() {
            // A shader may still be running: leaked, never freed under it.
            return;
        }
        let device = &self.device;
        // SAFETY: the GPU work using these objects has completed (a render
        // waits for its submission, the context idles the device before
        // dropping the kept ones) and the device still exists; null
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

/// How many pipelines a device keeps: a sweep of variants or scenes
/// longer than this starts again from none (each holds lavapipe's
/// translated shader, a few megabytes).
const KEPT_PIPELINES: usize = 64;

/// The pipelines built on one device, by everything that went into them
/// (module, constants, layout, target): `check`, `compare` and `bench`
/// render the same variant many times, and lavapipe's pipeline creation
/// (35 to 100 ms for the ray tracer) is then paid once. A render that finds
/// its pipeline here reports `pipeline_ms` near zero.
#[derive(Default)]
pub struct BuiltPipelines {
    kept: Mutex<HashMap<String, Arc<PipelineObjects>>>,
}

impl BuiltPipelines {
    /// The pipeline built under `key`, or `create`'s, kept for next time.
    /// The lock is not held while creating, so renders on other threads
    /// wait for none of it (two may then build the same pipeline once each).
    pub fn get_or_create(
        &self,
        key: String,
        create: impl FnOnce() -> Result<PipelineObjects, GpuError>,
    ) -> Result<Arc<PipelineObjects>, GpuError> {
        let lock = || self.kept.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(found) = lock().get(&key) {
            return Ok(found.clone());
        }
        let built = Arc::new(create()?);
        let mut kept = lock();
        if kept.len() >= KEPT_PIPELINES {
            kept.clear();
        }
        kept.insert(key, built.clone());
        Ok(built)
    }

    /// How many are kept.
    pub fn len(&self) -> usize {
        self.kept.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    /// Drops every kept pipeline: before the device is destroyed.
    pub fn clear(&self) {
        self.kept.lock().unwrap_or_else(|e| e.into_inner()).clear();
    }
}
