//! The CPU twin of the compute-shader ray tracer: backward (Whitted) ray
//! tracing in `f64`, following `docs/raytracing.md` step for step (sample
//! grid, explicit ray stack and its order, weights, cut-off, offsets,
//! counting), so that the two images can be compared pixel by pixel.
//!
//! Geometry is `cpu::intersect`, the formula `cpu::lighting`; this folder
//! owns the ray tree (`tracer.rs`), its diffuse bounces (`bounce.rs`, whose
//! numbers are `crate::random_streams`'), where a
//! path-traced pixel's samples look (`pixel_samples.rs`), where secondary rays start and go
//! (`secondary_rays.rs`), the per-pixel path signature
//! (`path_signature.rs`) and the parallel loop over rows (`render.rs`). It
//! shares nothing with the shaders but the scene (`rt_scene`) and the camera.

mod bounce;
mod path_signature;
mod pixel_samples;
mod render;
mod secondary_rays;
mod tracer;

pub use bounce::cosine_direction;
pub use path_signature::{PathSignature, RayKind};
pub use pixel_samples::pixel_sample;
pub use render::{render, RayTraced};
pub(crate) use secondary_rays::children;
pub use secondary_rays::{facing_normal, offset_epsilon, offset_origin};
pub use tracer::{sample_offsets, PixelTrace, Tracer};
