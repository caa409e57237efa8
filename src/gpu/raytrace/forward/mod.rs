//! Forward ray tracing on the GPU (`shaders/forward.comp.glsl`): photons
//! from the lights through the ray tracer's own records, BVH and buffers,
//! splatted into a fixed-point film (`film_sums`), the twin of
//! `cpu::forward`. The `pipeline` is the ray tracer's specialisation with
//! the photon batch pushed; the `renderer` runs the batches.

mod pipeline;
mod renderer;

pub(in crate::gpu::raytrace) use pipeline::create_photon_pipeline;
pub use pipeline::PhotonBatch;
pub(in crate::gpu::raytrace) use renderer::{refuse_what_cannot_run, PhotonScene};
pub use renderer::{render, ForwardOutput, PHOTONS_PER_LANE};
