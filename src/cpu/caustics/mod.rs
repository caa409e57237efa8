//! The backward tracer's caustics from a photon map (issue 46), in f64:
//! `photons` traces the caustic photons; `sppm` gathers them at the eye's
//! first diffuse hits within a radius that shrinks pass by pass
//! (progressive photon mapping, Hachisuka and Jensen's SPPM), into the
//! caustic image that adds to the backward tracer's.

mod photons;
mod sppm;

pub use crate::scene::CausticSettings;
pub use photons::{caustic_photons, trace_caustic_photon, CausticPhoton};
pub use sppm::render_caustics;
