//! The CPU reference rasterizer: flat, Gouraud and Phong in `f64`, following
//! Vulkan's rules so that it differs from the GPU only by float rounding and
//! the sub-pixel placement of silhouette edges.
//!
//! Conventions it shares with the GPU path: the same tessellation
//! (`scene::tessellate`), camera and projection (`camera.rs`), pixel centres
//! at half-integers, window coordinates snapped to 1/256 pixel (lavapipe's
//! `subPixelPrecisionBits = 8`) for the coverage test, the top-left fill
//! rule, near-plane clipping, a strict "nearer wins" reversed depth test with
//! scene order breaking ties, and no face culling. It shares no shading code
//! with the shaders: the formula is `cpu::lighting`.
//!
//! The steps, a file each: `setup.rs` (triangle setup: tessellate, light
//! the vertices, project, clip) into `triangle.rs`'s window-space
//! triangles; `coverage.rs` (which samples a triangle covers);
//! `shade.rs` (what a covered sample shows); `render.rs` (the loop over
//! bands of rows: depth test, resolve); `edge_marks.rs` (the pixels where
//! another rasterizer may legitimately differ).

mod coverage;
mod edge_marks;
mod render;
mod setup;
mod shade;
mod triangle;

pub use edge_marks::EDGE_MARGIN;
pub use render::{render, CpuRender};
pub use shade::VANISHING_NORMAL;
