//! What the ray-query engine needs of a device (`--traversal query`): the
//! extensions and features that let a compute shader cast rays through an
//! acceleration structure the driver builds, and whether a device has them.
//! `context` enables them wherever they are offered; `raytrace::accel` builds the
//! structures; `raytrace` picks the engine.

use std::ffi::CStr;

use ash::vk;

/// The device extensions the engine needs: ray queries, and what they
/// depend on (acceleration structures, which need deferred host
/// operations). A device lacking several is said to lack the first.
pub const EXTENSIONS: [&CStr; 3] = [
    ash::khr::ray_query::NAME,
    ash::khr::acceleration_structure::NAME,
    ash::khr::deferred_host_operations::NAME,
];

/// `None` when `physical` can run the ray-query engine, else why not (the
/// first thing it lacks).
pub fn missing(instance: &ash::Instance, physical: vk::PhysicalDevice) -> Option<String> {
    // SAFETY: `physical` came from this instance.
    let offered =
        unsafe { instance.enumerate_device_extension_properties(physical) }.unwrap_or_default();
    for name in EXTENSIONS {
        let found = offered
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(name));
        if !found {
            return Some(format!("lacks {}", name.to_string_lossy()));
        }
    }
    // The feature structures are chained only now that their extensions
    // are known to be there.
    let mut structures = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut query = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut f2 = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut structures)
        .push_next(&mut query)
        .push_next(&mut f12);
    // SAFETY: `physical` came from this instance; the chain is local.
    unsafe { instance.get_physical_device_features2(physical, &mut f2) };
    if structures.acceleration_structure == vk::FALSE {
        Some("lacks the accelerationStructure feature".into())
    } else if query.ray_query == vk::FALSE {
        Some("lacks the rayQuery feature".into())
    } else if f12.buffer_device_address == vk::FALSE {
        Some("lacks the bufferDeviceAddress feature".into())
    } else {
        None
    }
}

/// The engine's entry points on an open device that enabled `EXTENSIONS`,
/// and the limit its builds must respect.
pub struct Support {
    pub structures: ash::khr::acceleration_structure::Device,
    /// Scratch memory for a build must start at a multiple of this.
    pub scratch_alignment: u64,
}

impl Support {
    pub fn new(
        instance: &ash::Instance,
        physical: vk::PhysicalDevice,
        device: &ash::Device,
    ) -> Self {
        let mut properties = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
        let mut p2 = vk::PhysicalDeviceProperties2::default().push_next(&mut properties);
        // SAFETY: `physical` came from this instance; the chain is local.
        unsafe { instance.get_physical_device_properties2(physical, &mut p2) };
        Self {
            structures: ash::khr::acceleration_structure::Device::new(instance, device),
            scratch_alignment: u64::from(
                properties.min_acceleration_structure_scratch_offset_alignment,
            )
            .max(1),
        }
    }
}
