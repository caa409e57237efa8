//! The raster renderer: flat, Gouraud and Phong through Vulkan graphics
//! pipelines. The `renderer` turns a scene into its geometry
//! (`scene`, with back faces `cull`ed where they cannot show and
//! `flat` shading's vertex per face), picks its `pipeline` (the shader
//! variants the scene needs, with the `layout` the shaders declare), draws
//! a `frame` (its buffers and images made in `frame_resources`) into a
//! colour `target`, and averages `samples` where a pixel takes several.

mod cull;
mod flat;
mod frame;
mod frame_resources;
pub mod layout;
mod pipeline;
mod renderer;
mod samples;
mod scene;
mod target;

pub use renderer::{render, renders_samples};
pub use target::{ColorTarget, RasterOutput, DEPTH_FORMAT, SCALED_UNORM16_RANGE};
