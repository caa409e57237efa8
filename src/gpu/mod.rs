//! The Vulkan side: it reads a `Scene` and returns a `LinearImage`; it
//! never reads or writes files. Three rooms (docs/architecture.md):
//!
//! - `vk`: how Vulkan gives us things (device and queues, memory,
//!   buffers, images, commands, descriptors, pipelines and their cache,
//!   specialisation, timestamps, validation, errors). It knows no scene.
//! - `shared`: what every renderer compiles and uploads alike (the
//!   shader catalogue, a user's lighting hook, lights, textures, the image
//!   size limits).
//! - One folder per renderer, each reading `vk` and `shared` and never
//!   another renderer: `raster` (flat, Gouraud and Phong through graphics
//!   pipelines) and `raytrace` (the compute tracer and its ray-query
//!   engine). A new renderer is a folder beside them.

pub mod raster;
pub mod raytrace;
pub mod shared;
pub(crate) mod vk;

pub use raster::RasterOutput;
pub use vk::context::{list_devices, DeviceInfo, GpuContext, GpuOptions};
pub use vk::error::GpuError;
pub use vk::timestamps::{ms_since, GpuTimings};
pub use vk::watchdog::any_device_stuck;
