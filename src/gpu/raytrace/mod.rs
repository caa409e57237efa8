//! The ray tracer: `shaders/raytrace.comp.glsl` as a compute pipeline. The
//! `renderer` lays the scene out as `records` in the shader's
//! `layout`, with one `bvh` over its triangles and long lists of
//! objects (walked binary, or in its 4-wide form, `wide_bvh`); or, with
//! `--traversal query`, hands the same records to the driver to build
//! acceleration structures (`accel`) that ray queries walk. The records
//! travel in the trace's `buffers`, which `dispatch` binds and runs.
//! `forward` traces the other way, photons from the lights, over the same
//! records and buffers. With diffuse bounces the ray tracer runs a range
//! of samples per submission into fixed-point sums, as the forward tracer
//! runs its photons (`batches`). The kernels' sizes, which build.rs
//! writes into their prelude, are `kernel_sizes`.

mod accel;
mod batches;
mod buffers;
pub mod bvh;
pub mod caustics;
mod dispatch;
pub mod forward;
pub mod kernel_sizes;
pub mod layout;
pub mod pairing;
mod records;
mod renderer;
pub mod wide_bvh;

pub use renderer::{engine_for, render, SampleSums, TraceOptions, TraceOutput};
