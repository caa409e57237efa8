//! GPU renders in this process, on a device of each test's own with the
//! Khronos validation layer on (`common::gpu`): each against the CPU
//! reference, an exact answer or a hand-worked value. A validation message
//! goes to the log of the context whose device caused it, and fails that
//! test's render (`tests/gpu/validation_layer.rs` proves it is caught).
//!
//! One binary of modules, so that the crate is linked once for all of them;
//! `cpu/` holds the CPU reference's own tests beside these under the same
//! names (`caustics`, `forward`, `raytrace`).

#[path = "../common/mod.rs"]
mod common;

mod caustics;
mod check;
mod compare;
mod exact_agreement;
mod example_render_and_compare;
mod forward;
mod gltf_render;
mod hard_cases;
mod image_textures;
mod khronos_samples;
mod lighting_hook;
mod msaa;
mod paired_rays;
mod path_shards;
mod path_trace;
mod pipeline_reuse;
mod random_scenes;
mod raster_modes;
mod raster_phong;
mod ray_query;
mod raytrace;
mod surface_colour;
mod texture_orientation;
mod validation_layer;
