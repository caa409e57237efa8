//! shadelab: a headless renderer for the classic shading models.
//!
//! Data flows one way: a scene file becomes a validated `scene::Scene`; a
//! renderer (`gpu` raster today) turns it into a `LinearImage`; `output`
//! encodes that to PNG or EXR; `metrics` compares two such images. The
//! lighting model every renderer follows is `docs/lighting-model.md` of the
//! shared contracts.

pub mod camera;
pub mod check;
pub mod compare;
pub mod cpu;
pub mod error;
pub mod gpu;
pub mod junit;
pub mod linear_image;
pub mod markup;
pub mod memory;
pub mod metrics;
pub mod output;
pub mod render;
pub mod rt_scene;
pub mod scene;
mod shader_compile;
pub mod shading;
pub mod srgb;

pub use error::Error;
pub use linear_image::LinearImage;
