//! Caustics from a progressive photon map on the GPU
//! (`shaders/caustics.comp.glsl`): each pass, the eye's visible points, a
//! hashed grid of them, the caustic photons traced from the lights and
//! gathered in fixed point, and SPPM's update of every pixel; the twin of
//! `cpu::caustics`. The `pipeline` is the ray tracer's specialisation with
//! the map's buffers as a second set, the `map` those buffers, the
//! `renderer` runs the passes.

mod map;
mod pipeline;
mod renderer;

pub use map::{BYTES_PER_PIXEL, MAP_BINDINGS, MAP_RECORD_SIZES};
pub use pipeline::CausticPass;
pub use renderer::{render, CausticOutput, CausticStats, PER_LANE};
