//! The Vulkan instance, device, queue and memory allocator.
//!
//! Owns device selection (lavapipe by default, so images are reproducible
//! across machines; `--device` or `SHADELAB_DEVICE` picks another) and the
//! optional Khronos validation layer. Knows nothing about scenes or shading.

use std::ffi::{c_char, CStr};
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::gpu::vk::error::{GpuError, VkContext};
use crate::gpu::vk::pipeline::BuiltPipelines;
use crate::gpu::vk::ray_query;
use crate::gpu::vk::validation::{messenger_info, MessageLog};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How to open the GPU.
#[derive(Debug, Clone, Default)]
pub struct GpuOptions {
    /// A device index (as `shadelab info` lists them) or part of its name.
    pub device: Option<String>,
    /// Enable the Khronos validation layer; its messages become errors.
    pub validation: bool,
}

impl GpuOptions {
    /// Reads `SHADELAB_DEVICE` and `SHADELAB_VALIDATION` (`1` enables it).
    pub fn from_env() -> Self {
        Self {
            device: std::env::var("SHADELAB_DEVICE")
                .ok()
                .filter(|s| !s.is_empty()),
            validation: std::env::var("SHADELAB_VALIDATION").is_ok_and(|v| v == "1"),
        }
    }
}

/// What `shadelab info` reports about one physical device.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DeviceInfo {
    pub index: usize,
    pub name: String,
    pub driver: String,
    pub device_type: String,
    pub api_version: String,
    pub is_lavapipe: bool,
    /// 16-bit float arithmetic in shaders (enabled where offered, for
    /// lighting hooks in half precision).
    pub shader_float16: bool,
    /// The samples per pixel its raster modes render (`--msaa`): the
    /// counts its colour and depth targets both take, where it places
    /// them at Vulkan's standard locations (else 1 alone).
    pub msaa_counts: Vec<u32>,
    /// The fraction of a pixel a viewport's origin keeps
    /// (`viewportSubPixelBits`): per-sample passes shift it by sample
    /// offsets, sixteenths of a pixel for 8 and 16 samples.
    pub viewport_subpixel_bits: u32,
    /// `None` when shadelab can use the device, else why not.
    pub unusable_because: Option<String>,
    /// `None` when the GPU ray tracer runs on the device, else why not
    /// (the raster modes may still run).
    pub no_ray_tracer_because: Option<String>,
    /// `None` when the ray-query engine (`--traversal query`) runs on the
    /// device, else why not (`ray_query::missing`).
    pub no_ray_query_because: Option<String>,
    /// `None` when forward ray tracing (`--shading forward`) runs on the
    /// device: it needs the ray tracer and 64-bit integer atomics on
    /// storage buffers, for its film's fixed-point sums. Else why not.
    pub no_forward_because: Option<String>,
}

impl DeviceInfo {
    /// A CPU device (lavapipe): it runs a dispatch's workgroups on a few
    /// threads, not across a GPU's many cores.
    pub fn is_cpu(&self) -> bool {
        self.device_type == format!("{:?}", vk::PhysicalDeviceType::CPU)
    }
}

/// An open device. Shared (`Arc`) by every resource made on it, so it is
/// destroyed only after the last of them.
pub struct GpuContext {
    _entry: ash::Entry,
    pub(crate) instance: ash::Instance,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Boxed so its address, given to the validation callback, never moves.
    log: Box<MessageLog>,
    pub(crate) device: ash::Device,
    pub(crate) queue: vk::Queue,
    pub(crate) queue_family: u32,
    /// Vulkan requires external synchronisation of queue submissions.
    pub(crate) queue_lock: Mutex<()>,
    pub(crate) allocator: ManuallyDrop<Mutex<Allocator>>,
    pub(crate) limits: vk::PhysicalDeviceLimits,
    /// The ray-query engine's entry points and limits, where the device
    /// offers it (`info.no_ray_query_because` is `None`).
    pub(crate) ray_query: Option<ray_query::Support>,
    pub info: DeviceInfo,
    pub validation: bool,
    /// The pipelines built on this device, for the renders after the first.
    pub(crate) pipelines: BuiltPipelines,
}

/// Loads Vulkan and creates an instance, with validation if asked.
fn create_instance(
    validation: bool,
    log: &MessageLog,
) -> Result<(ash::Entry, ash::Instance), GpuError> {
    // SAFETY: loading libvulkan runs its initialisers; the library is the
    // system's Vulkan loader, which is designed to be loaded this way.
    let entry = unsafe { ash::Entry::load() }.map_err(|e| GpuError::Loader(e.to_string()))?;
    if validation {
        // SAFETY: plain query on a valid entry.
        let layers = unsafe { entry.enumerate_instance_layer_properties() }
            .during("vkEnumerateInstanceLayerProperties")?;
        let found = layers
            .iter()
            .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER));
        if !found {
            return Err(GpuError::ValidationLayerMissing);
        }
    }
    let app = vk::ApplicationInfo::default()
        .application_name(c"shadelab")
        .api_version(vk::API_VERSION_1_3);
    let layers: Vec<*const c_char> = if validation {
        vec![VALIDATION_LAYER.as_ptr()]
    } else {
        Vec::new()
    };
    let extensions: Vec<*const c_char> = if validation {
        vec![ash::ext::debug_utils::NAME.as_ptr()]
    } else {
        Vec::new()
    };
    let mut messenger = messenger_info(log);
    let mut create = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    if validation {
        create = create.push_next(&mut messenger);
    }
    // SAFETY: every pointer in `create` refers to locals that outlive the call.
    let instance = unsafe { entry.create_instance(&create, None) }.map_err(|result| {
        // The loader's way of saying no driver is installed: say what to
        // install, as for no device.
        if result == vk::Result::ERROR_INCOMPATIBLE_DRIVER {
            GpuError::NoDevice(" (the Vulkan loader found no driver)".into())
        } else {
            GpuError::Vulkan {
                call: "vkCreateInstance",
                result,
            }
        }
    })?;
    Ok((entry, instance))
}

struct Candidate {
    info: DeviceInfo,
    physical: vk::PhysicalDevice,
    queue_family: Option<u32>,
    limits: vk::PhysicalDeviceLimits,
}

fn describe_devices(instance: &ash::Instance) -> Result<Vec<Candidate>, GpuError> {
    // SAFETY: queries on a valid instance.
    let physicals =
        unsafe { instance.enumerate_physical_devices() }.during("vkEnumeratePhysicalDevices")?;
    let mut out = Vec::new();
    for (index, physical) in physicals.into_iter().enumerate() {
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default()
            .push_next(&mut driver)
            .push_next(&mut subgroup);
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut f2 = vk::PhysicalDeviceFeatures2::default()
            .push_next(&mut f13)
            .push_next(&mut f12);
        // SAFETY: `physical` came from this instance; the chains are local.
        let families = unsafe {
            instance.get_physical_device_properties2(physical, &mut props2);
            instance.get_physical_device_features2(physical, &mut f2);
            instance.get_physical_device_queue_family_properties(physical)
        };
        let props = props2.properties;
        let core_features = f2.features;
        let name = props
            .device_name_as_c_str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let driver_name = driver
            .driver_info_as_c_str()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let queue_family = families
            .iter()
            .position(|f| {
                f.queue_flags
                    .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
            })
            .map(|i| i as u32);
        let api = props.api_version;
        let missing = if api < vk::API_VERSION_1_3 {
            Some("Vulkan 1.3".to_string())
        } else if f13.dynamic_rendering == vk::FALSE {
            Some("dynamic rendering".to_string())
        } else if f13.synchronization2 == vk::FALSE {
            Some("synchronization2".to_string())
        } else if queue_family.is_none() {
            Some("a graphics and compute queue".to_string())
        } else {
            None
        };
        out.push(Candidate {
            info: DeviceInfo {
                index,
                name,
                driver: driver_name,
                device_type: format!("{:?}", props.device_type),
                api_version: format!(
                    "{}.{}.{}",
                    vk::api_version_major(api),
                    vk::api_version_minor(api),
                    vk::api_version_patch(api)
                ),
                is_lavapipe: driver.driver_id == vk::DriverId::MESA_LLVMPIPE,
                shader_float16: f12.shader_float16 == vk::TRUE,
                msaa_counts: msaa_counts(&props.limits),
                // lavapipe reports 0 bits, yet applies the viewport in
                // floats and snaps after it, to 1/256 of a pixel; the edge
                // test of tests/gpu/msaa.rs at 8 and 16 samples per sample
                // fails if that stops being so.
                viewport_subpixel_bits: if driver.driver_id == vk::DriverId::MESA_LLVMPIPE {
                    props.limits.viewport_sub_pixel_bits.max(8)
                } else {
                    props.limits.viewport_sub_pixel_bits
                },
                unusable_because: missing.map(|m| format!("lacks {m}")),
                no_ray_tracer_because: (!packet_tracing_supported(&subgroup)).then(|| {
                    "lacks subgroup shuffles in compute shaders, 4 to 64 invocations wide"
                        .to_string()
                }),
                no_ray_query_because: ray_query::missing(instance, physical),
                no_forward_because: forward_missing(&core_features, &f12),
            },
            physical,
            queue_family,
            limits: props.limits,
        });
    }
    Ok(out)
}

/// What forward tracing needs that the device lacks (beyond the ray
/// tracer's own needs), or `None`.
fn forward_missing(
    features: &vk::PhysicalDeviceFeatures,
    f12: &vk::PhysicalDeviceVulkan12Features,
) -> Option<String> {
    if features.shader_int64 == vk::FALSE {
        Some("lacks 64-bit integers in shaders (shaderInt64)".into())
    } else if f12.shader_buffer_int64_atomics == vk::FALSE {
        Some("lacks 64-bit integer atomics on storage buffers (shaderBufferInt64Atomics)".into())
    } else {
        None
    }
}

/// The sample counts both the colour and the depth target take, where the
/// device places samples at the standard locations the CPU reference uses.
fn msaa_counts(limits: &vk::PhysicalDeviceLimits) -> Vec<u32> {
    let both = limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
    crate::msaa::STANDARD_COUNTS
        .into_iter()
        .filter(|&n| {
            n == 1
                || (limits.standard_sample_locations == vk::TRUE
                    && both.contains(vk::SampleCountFlags::from_raw(n)))
        })
        .collect()
}

/// The ray tracer walks its BVH a subgroup at a time, the lanes sharing
/// each node's words by shuffles (`shaders/raytrace.comp.glsl`): it needs
/// them in compute shaders, a subgroup of at least 4 lanes holds a 4-wide
/// node's 8 quads of words in two registers, and a subgroup no wider than the
/// workgroup is full (every lane present for its shuffles, and for its
/// share of a work item's pixels).
fn packet_tracing_supported(subgroup: &vk::PhysicalDeviceSubgroupProperties) -> bool {
    (4..=crate::gpu::raytrace::layout::WORKGROUP_SIZE).contains(&subgroup.subgroup_size)
        && subgroup
            .supported_stages
            .contains(vk::ShaderStageFlags::COMPUTE)
        && subgroup
            .supported_operations
            .contains(vk::SubgroupFeatureFlags::BASIC | vk::SubgroupFeatureFlags::SHUFFLE)
}

/// Lists every Vulkan device, usable or not (for `shadelab info`).
pub fn list_devices() -> Result<Vec<DeviceInfo>, GpuError> {
    let log = MessageLog::default();
    let (_entry, instance) = create_instance(false, &log)?;
    let described = describe_devices(&instance);
    // SAFETY: nothing created from the instance outlives this point.
    unsafe { instance.destroy_instance(None) };
    Ok(described?.into_iter().map(|c| c.info).collect())
}

/// The position in `devices` (index, name) of the one `wanted` names: a
/// number is an index and nothing else (a name holding the digit does not
/// count), text is a case-insensitive part of one device's name. `Err`
/// lists the devices that match (none, or more than one: ambiguous).
fn pick_device(devices: &[(usize, &str)], wanted: &str) -> Result<usize, Vec<String>> {
    let wanted = wanted.trim();
    if let Ok(index) = wanted.parse::<usize>() {
        return devices
            .iter()
            .position(|&(i, _)| i == index)
            .ok_or_else(Vec::new);
    }
    let lower = wanted.to_lowercase();
    let matching: Vec<usize> = (0..devices.len())
        .filter(|&p| devices[p].1.to_lowercase().contains(&lower))
        .collect();
    match matching[..] {
        [one] => Ok(one),
        _ => Err(matching
            .iter()
            .map(|&p| format!("{}: {}", devices[p].0, devices[p].1))
            .collect()),
    }
}

fn choose(candidates: Vec<Candidate>, wanted: Option<&str>) -> Result<Candidate, GpuError> {
    let listing = || {
        candidates
            .iter()
            .map(|c| format!("{}: {}", c.info.index, c.info.name))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let picked = match wanted {
        Some(w) => {
            let names: Vec<(usize, &str)> = candidates
                .iter()
                .map(|c| (c.info.index, c.info.name.as_str()))
                .collect();
            match pick_device(&names, w) {
                Ok(p) => p,
                Err(matches) if matches.is_empty() => {
                    return Err(GpuError::DeviceNotFound {
                        wanted: w.to_string(),
                        available: listing(),
                    })
                }
                Err(matches) => {
                    return Err(GpuError::DeviceAmbiguous {
                        wanted: w.to_string(),
                        matches: matches.join(", "),
                    })
                }
            }
        }
        None => candidates
            .iter()
            .position(|c| c.info.is_lavapipe && c.info.unusable_because.is_none())
            .or_else(|| {
                candidates
                    .iter()
                    .position(|c| c.info.unusable_because.is_none())
            })
            .ok_or_else(|| {
                let found = if candidates.is_empty() {
                    " (none found)".to_string()
                } else {
                    format!(" (found {})", listing())
                };
                GpuError::NoDevice(found)
            })?,
    };
    let candidate = candidates.into_iter().nth(picked).expect("index in range");
    if let Some(why) = &candidate.info.unusable_because {
        return Err(GpuError::NoDevice(format!(
            " (`{}` {why})",
            candidate.info.name
        )));
    }
    Ok(candidate)
}

impl GpuContext {
    /// How many built pipelines the device keeps for later renders.
    pub fn pipelines_kept(&self) -> usize {
        self.pipelines.len()
    }

    pub fn new(options: &GpuOptions) -> Result<Arc<Self>, GpuError> {
        let log = Box::<MessageLog>::default();
        let (entry, instance) = create_instance(options.validation, &log)?;
        // From here on, `instance` must be destroyed on every error path.
        let result = Self::open_device(&entry, &instance, options, &log);
        let (physical, device, queue_family, info, limits, debug) = match result {
            Ok(v) => v,
            Err(e) => {
                // SAFETY: open_device destroyed whatever it created.
                unsafe { instance.destroy_instance(None) };
                return Err(e);
            }
        };
        let allocator = match Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: info.no_ray_query_because.is_none(),
            allocation_sizes: Default::default(),
        }) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: nothing else was created on the device yet.
                unsafe {
                    device.destroy_device(None);
                    if let Some((utils, messenger)) = debug {
                        utils.destroy_debug_utils_messenger(messenger, None);
                    }
                    instance.destroy_instance(None);
                }
                return Err(GpuError::Allocation(e));
            }
        };
        // SAFETY: the queue family was requested at device creation.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let ray_query = info
            .no_ray_query_because
            .is_none()
            .then(|| ray_query::Support::new(&instance, physical, &device));
        let context = Self {
            _entry: entry,
            instance,
            debug,
            log,
            device,
            queue,
            queue_family,
            queue_lock: Mutex::new(()),
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            limits,
            ray_query,
            info,
            validation: options.validation,
            pipelines: BuiltPipelines::default(),
        };
        Ok(Arc::new(context))
    }

    #[allow(clippy::type_complexity)]
    fn open_device(
        entry: &ash::Entry,
        instance: &ash::Instance,
        options: &GpuOptions,
        log: &MessageLog,
    ) -> Result<
        (
            vk::PhysicalDevice,
            ash::Device,
            u32,
            DeviceInfo,
            vk::PhysicalDeviceLimits,
            Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
        ),
        GpuError,
    > {
        let chosen = choose(describe_devices(instance)?, options.device.as_deref())?;
        let queue_family = chosen.queue_family.expect("checked by choose");
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true);
        // Optional: what a lighting hook in half precision needs, and what
        // the ray-query engine needs, wherever the device offers it.
        let ray_query = chosen.info.no_ray_query_because.is_none();
        // And forward tracing's 64-bit atomics.
        let forward = chosen.info.no_forward_because.is_none();
        let mut f12 = vk::PhysicalDeviceVulkan12Features::default()
            .shader_float16(chosen.info.shader_float16)
            .buffer_device_address(ray_query)
            .shader_buffer_int64_atomics(forward);
        let core = vk::PhysicalDeviceFeatures::default().shader_int64(forward);
        let mut structures = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default()
            .acceleration_structure(true);
        let mut query = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
        let extensions: Vec<*const c_char> = if ray_query {
            ray_query::EXTENSIONS.iter().map(|n| n.as_ptr()).collect()
        } else {
            Vec::new()
        };
        let mut create = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&extensions)
            .enabled_features(&core)
            .push_next(&mut f13)
            .push_next(&mut f12);
        if ray_query {
            create = create.push_next(&mut structures).push_next(&mut query);
        }
        // SAFETY: the create info refers to locals that outlive the call and
        // the features were checked as supported in describe_devices.
        let device = unsafe { instance.create_device(chosen.physical, &create, None) }
            .during("vkCreateDevice")?;
        let debug = if options.validation {
            let utils = ash::ext::debug_utils::Instance::new(entry, instance);
            let info = messenger_info(log);
            // SAFETY: `log` is boxed by the caller and outlives the messenger,
            // which Drop destroys before the log is freed.
            match unsafe { utils.create_debug_utils_messenger(&info, None) } {
                Ok(m) => Some((utils, m)),
                Err(result) => {
                    // SAFETY: nothing has been created on the device yet.
                    unsafe { device.destroy_device(None) };
                    return Err(GpuError::Vulkan {
                        call: "vkCreateDebugUtilsMessengerEXT",
                        result,
                    });
                }
            }
        } else {
            None
        };
        Ok((
            chosen.physical,
            device,
            queue_family,
            chosen.info,
            chosen.limits,
            debug,
        ))
    }

    /// Drains the validation messages logged since the last call.
    pub fn take_validation_messages(&self) -> Vec<String> {
        self.log.take()
    }

    /// Fails with every validation message logged since the last check.
    pub fn check_validation(&self) -> Result<(), GpuError> {
        let messages = self.take_validation_messages();
        if messages.is_empty() {
            Ok(())
        } else {
            Err(GpuError::Validation(messages))
        }
    }

    /// Sub-allocates device memory for a buffer or image.
    pub(crate) fn allocate(
        &self,
        name: &str,
        requirements: vk::MemoryRequirements,
        location: gpu_allocator::MemoryLocation,
        linear: bool,
    ) -> Result<gpu_allocator::vulkan::Allocation, GpuError> {
        let desc = gpu_allocator::vulkan::AllocationCreateDesc {
            name,
            requirements,
            location,
            linear,
            allocation_scheme: gpu_allocator::vulkan::AllocationScheme::GpuAllocatorManaged,
        };
        Ok(self
            .allocator
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .allocate(&desc)?)
    }

    /// Returns memory from `allocate`; called from destructors, so a failure
    /// (which would mean a double free) is ignored rather than panicking.
    pub(crate) fn free(&self, allocation: gpu_allocator::vulkan::Allocation) {
        let _ = self
            .allocator
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .free(allocation);
    }

    /// Makes one deliberately invalid Vulkan call (a buffer with no usage
    /// flags) and returns what the validation layer logged about it. Tests
    /// use it to prove that the layer is loaded and its messages are caught;
    /// without validation it returns nothing.
    #[doc(hidden)]
    pub fn provoke_validation_message(&self) -> Vec<String> {
        self.take_validation_messages();
        let info = vk::BufferCreateInfo::default()
            .size(16)
            .usage(vk::BufferUsageFlags::empty());
        // SAFETY: an empty usage mask is invalid usage that the validation
        // layer reports; lavapipe and every driver we target still create (or
        // refuse) the buffer without harm, and it is destroyed at once.
        unsafe {
            if let Ok(buffer) = self.device.create_buffer(&info, None) {
                self.device.destroy_buffer(buffer, None);
            }
        }
        self.take_validation_messages()
    }

    pub fn max_image_dimension(&self) -> u32 {
        self.limits.max_image_dimension2_d
    }

    pub fn timestamp_period_ns(&self) -> f64 {
        f64::from(self.limits.timestamp_period)
    }
}

impl Drop for GpuContext {
    fn drop(&mut self) {
        if crate::gpu::vk::watchdog::any_device_stuck() {
            // A stuck device cannot be idled or torn down (both wait for
            // the shader that never ends): it is left to the process's end.
            return;
        }
        // SAFETY: every resource made on this device holds an Arc to it, so
        // when this runs nothing else uses the device; destruction follows
        // creation in reverse.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.pipelines.clear();
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((utils, messenger)) = self.debug.take() {
                utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DEVICES: [(usize, &str); 3] = [
        (0, "llvmpipe (LLVM 15.0.6, 256 bits)"),
        (1, "NVIDIA H200"),
        (2, "NVIDIA GeForce RTX 4090"),
    ];

    /// A number is an index only: "5" and "1" are in lavapipe's name, and
    /// once picked it for any digit in it (issue 30).
    #[test]
    fn a_number_picks_by_index_and_never_by_name() {
        assert_eq!(pick_device(&DEVICES, "1"), Ok(1));
        assert_eq!(pick_device(&DEVICES, " 2 "), Ok(2));
        assert_eq!(pick_device(&DEVICES, "5"), Err(vec![]));
        assert_eq!(pick_device(&DEVICES, "15"), Err(vec![]));
    }

    #[test]
    fn text_picks_the_one_device_whose_name_holds_it_and_refuses_an_ambiguous_one() {
        assert_eq!(pick_device(&DEVICES, "LLVMpipe"), Ok(0));
        assert_eq!(pick_device(&DEVICES, "h200"), Ok(1));
        assert_eq!(pick_device(&DEVICES, "radeon"), Err(vec![]));
        assert_eq!(
            pick_device(&DEVICES, "nvidia"),
            Err(vec![
                "1: NVIDIA H200".to_string(),
                "2: NVIDIA GeForce RTX 4090".to_string()
            ])
        );
    }

    fn subgroup(
        size: u32,
        stages: vk::ShaderStageFlags,
        operations: vk::SubgroupFeatureFlags,
    ) -> vk::PhysicalDeviceSubgroupProperties<'static> {
        vk::PhysicalDeviceSubgroupProperties {
            subgroup_size: size,
            supported_stages: stages,
            supported_operations: operations,
            ..Default::default()
        }
    }

    /// What the ray tracer's packets need: shuffles in compute shaders, and
    /// 4 lanes or more (a 4-wide node's 8 quads of words in two registers), but no
    /// more than a workgroup holds (a subgroup of 128 would be half empty).
    #[test]
    fn packet_tracing_needs_compute_shuffles_four_to_sixty_four_lanes_wide() {
        let compute = vk::ShaderStageFlags::COMPUTE;
        let ops = vk::SubgroupFeatureFlags::BASIC | vk::SubgroupFeatureFlags::SHUFFLE;
        assert!(packet_tracing_supported(&subgroup(8, compute, ops)));
        assert!(packet_tracing_supported(&subgroup(4, compute, ops)));
        assert!(packet_tracing_supported(&subgroup(64, compute, ops)));
        assert!(!packet_tracing_supported(&subgroup(2, compute, ops)));
        assert!(!packet_tracing_supported(&subgroup(128, compute, ops)));
        let fragment = vk::ShaderStageFlags::FRAGMENT;
        assert!(!packet_tracing_supported(&subgroup(8, fragment, ops)));
        let basic = vk::SubgroupFeatureFlags::BASIC | vk::SubgroupFeatureFlags::BALLOT;
        assert!(!packet_tracing_supported(&subgroup(8, compute, basic)));
    }
}
