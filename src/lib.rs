//! shadelab: a headless renderer for the classic shading models (flat,
//! Gouraud and Phong shading, and Whitted ray tracing) on Vulkan, with a
//! double-precision CPU reference that every GPU image is measured against.
//!
//! # How data flows
//!
//! One way, from a scene file to figures. Loaders only produce a
//! [`scene::Scene`] and renderers only read it; renderers produce a
//! [`LinearImage`] that encoders and metrics only read:
//!
//! ```text
//! .toml/.gltf/.glb --scene--> Scene --render: gpu | cpu--> LinearImage --output--> .png/.exr
//!                                                              |
//!                                                              +--metrics--> figures
//! ```
//!
//! [`check`] and [`compare`] drive that whole path for a scene: both
//! backends, then the figures; [`golden`] judges renders against stored
//! references, with [`diff`]'s judging of two images.
//!
//! # Modules
//!
//! - [`scene`] loads TOML scenes and glTF 2.0 files into a validated
//!   [`scene::Scene`] of plain `f64` data, or gives the built-in default
//!   scene.
//! - [`gpu`] renders on Vulkan (Mesa's lavapipe where there is no GPU): the
//!   raster modes flat, Gouraud and Phong through graphics pipelines, and
//!   the ray tracer as a compute shader.
//! - [`cpu`] is the reference: the same raster modes and a twin of the ray
//!   tracer, in `f64` and independent of the shaders.
//! - [`render`] is the one door for both backends: a
//!   [`render::RenderRequest`] read against a scene into a [`render::Plan`]
//!   whose integrator renders it on a [`render::Device`]
//!   ([`render::render`]).
//! - [`output`] encodes a [`LinearImage`] to PNG (8-bit sRGB) or EXR (linear
//!   32-bit float) and decodes image files back.
//! - [`metrics`] compares two images: error statistics, FLIP, heat maps and
//!   silhouette masks.
//! - [`check`] renders a scene on both backends and judges the difference
//!   against thresholds measured on the reference scenes (`shadelab check`).
//! - [`compare`] runs one scene in many shader variants, each timed and
//!   measured, and lays the results out as reports (`shadelab compare`).
//! - [`diff`] judges two images against limits named by purpose (presets,
//!   `FIGURE=X` entries): the figures, each limit's verdict, the failures
//!   (`shadelab diff`, and `golden`'s judging).
//! - [`golden`] judges renders against stored references, finds, makes and
//!   accepts the references, and names them (`shadelab golden`).
//! - [`memory`] estimates the memory a render will take before anything large
//!   is allocated, and holds it to a limit.
//!
//! The rest support these: [`camera`] (the view every renderer shares),
//! [`shading`] (the modes), [`rt_scene`] (the scene as both ray tracers see
//! it), [`huge_sphere`] (how they test spheres large where the eye is), [`narrow_view`] (the narrowest view they can place), [`random_streams`] (the random numbers the tracers draw, named by stream), [`msaa`] (samples per pixel and where they lie), [`cache`] (the folder of compiled modules and Mesa's shader cache), [`linear_image`], [`srgb`], [`junit`], [`markup`] and [`error`].
//!
//! The lighting model every renderer follows, GPU and CPU alike, is specified
//! in `docs/lighting-model.md` in this repository; `cpu::lighting` and
//! `shaders/include/lighting.glsl` are its two implementations.
//!
//! # Example
//!
//! A scene rendered on the GPU and with the CPU reference, and the
//! difference measured (`examples/render_and_compare.rs` is the runnable
//! version):
//!
//! ```no_run
//! use std::path::Path;
//!
//! use shadelab::gpu::GpuOptions;
//! use shadelab::render::{render, Device, RenderRequest};
//! use shadelab::shading::Shading;
//!
//! fn main() -> Result<(), Box<dyn std::error::Error>> {
//!     // Or `shadelab::scene::default_scene()`, the built-in scene.
//!     let scene = shadelab::scene::load(Path::new("assets/spheres.toml"))?;
//!
//!     let device = Device::open(&GpuOptions::from_env())?;
//!     let gpu = render(&device, &scene, &RenderRequest::gpu(Shading::Phong))?;
//!     let cpu = render(&device, &scene, &RenderRequest::cpu(Shading::Phong))?;
//!     let coverage = cpu.coverage.as_ref().expect("the CPU reference knows its pixels");
//!
//!     // The CPU image is the expected one. Pixels near an edge, which two
//!     // correct rasterizers may cover differently, are measured apart.
//!     let mask = Some(coverage.near_edge.as_slice());
//!     let figures = shadelab::metrics::compare(&cpu.image, &gpu.image, mask)?;
//!     if let Some(interior) = &figures.interior {
//!         println!("interior max error {:.2e}", interior.max_abs);
//!     }
//!     println!("FLIP mean {:.2e}", figures.flip.mean);
//!
//!     shadelab::output::write_image(&gpu.image, Path::new("spheres.png"))?;
//!     Ok(())
//! }
//! ```

pub mod backend_choice;
pub mod cache;
pub mod camera;
pub mod check;
pub mod compare;
pub mod cpu;
pub mod diff;
pub mod digest;
pub mod error;
pub mod error_budget;
pub mod film_sums;
pub mod golden;
pub mod gpu;
pub mod huge_sphere;
pub mod junit;
pub mod level_of_detail;
pub mod linear_image;
pub mod markup;
pub mod memory;
pub mod metrics;
pub mod msaa;
pub mod narrow_view;
pub mod output;
pub mod random_streams;
pub mod render;
pub mod rt_scene;
pub mod scene;
mod shader_compile;
pub mod shading;
pub mod srgb;
pub mod work_counter;

pub use error::Error;
pub use linear_image::LinearImage;
