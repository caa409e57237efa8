//! The library on the CPU alone, no Vulkan device: the double-precision
//! reference against values worked by hand (its tracers beside their GPU
//! twins' tests in `gpu/`, under the same names), the camera, the glTF and
//! texture importers against oracles, `check`'s thresholds, the shaders'
//! host-side interfaces, and `compare`'s presentation.

#[path = "../common/mod.rs"]
mod common;

mod camera_oracle;
mod caustics;
mod check_thresholds;
mod compare_present;
mod forward;
mod gltf_oracle;
mod raytrace;
mod shader_interface;
mod texture_import;
mod texture_sampling;
