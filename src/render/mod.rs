//! The spine: one door for every render. A caller (a command, a test, the
//! Python package) says what it wants in a [`RenderRequest`]; a [`Plan`]
//! reads it against the scene, choosing the [`Technique`] and running
//! every refusal once; the plan's [`Integrator`] (one per technique and
//! backend, the GPU renderer and its f64 twin in one file) renders; and a
//! [`Device`] keeps the Vulkan context and its pipelines between renders.
//! [`render`] is the three in order.
//!
//! The crate's front page has the example: a scene rendered on the GPU
//! and with the CPU reference on one device, and the two measured.

pub mod caustics;
mod coverage;
pub mod described;
mod device;
mod forward;
mod integrator;
pub mod overrides;
mod plan;
mod raster;
mod raytrace;
mod refusals;
mod rendered;
mod request;

pub use device::Device;
pub use integrator::{Integrator, Work};
pub use plan::{warnings, Plan, Technique};
pub use rendered::{CausticReport, Coverage, FilmRender, Rendered, Timings};
pub use request::{Portion, RenderRequest};

use crate::error::Error;
use crate::scene::Scene;

/// Renders `scene` as `request` asks, on `device`: the plan made (its
/// refusals a usage error before any work), then run.
pub fn render(device: &Device, scene: &Scene, request: &RenderRequest) -> Result<Rendered, Error> {
    Plan::new(scene, request)?.render(device, scene)
}

#[cfg(test)]
mod tests;
