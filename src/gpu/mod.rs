//! The Vulkan side: device, memory, shaders, pipelines, and the renderers
//! built from them. It reads a `Scene` and returns a `LinearImage`; it never
//! reads or writes files.

mod buffer;
mod commands;
mod context;
mod descriptors;
mod error;
pub mod hook;
mod image;
mod pipeline;
pub mod raster;
mod raster_cull;
mod raster_flat;
mod raster_frame;
pub mod raster_layout;
mod raster_samples;
mod raster_scene;
mod ray_query;
pub mod raytrace;
mod rt_accel;
pub mod rt_bvh;
pub mod rt_layout;
mod rt_records;
pub mod rt_wide;
pub mod shader_catalog;
mod specialise;
pub mod texture_table;
mod timestamps;
mod validation;

pub use context::{list_devices, DeviceInfo, GpuContext, GpuOptions};
pub use error::GpuError;
pub use raster::RasterOutput;
pub use timestamps::{ms_since, GpuTimings};
