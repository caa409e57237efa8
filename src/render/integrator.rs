//! The one interface every renderer offers the spine: an integrator (as
//! pbrt calls the object that turns a scene into an image) renders the
//! work a plan hands it. Each technique is one file with its GPU
//! integrator and its CPU twin (`raster.rs`, `raytrace.rs`,
//! `forward.rs`); a new one is a file beside them and a `Technique`.

use super::rendered::Rendered;
use crate::error::Error;
use crate::film_sums::RenderPart;
use crate::gpu::raster::ColorTarget;
use crate::scene::Scene;
use crate::work_counter::WorkCounter;

/// What a plan hands its integrator: the scene, the photons or samples to
/// trace (with their budgets and cancel flag), and the options a
/// technique may read.
pub struct Work<'a> {
    pub scene: &'a Scene,
    /// The part of the work (a raster image is one piece, `0..1`).
    pub part: &'a RenderPart,
    /// The raster modes on the GPU: the colour target's format.
    pub target: ColorTarget,
    /// Ray tracing on the GPU: the shader variant that counts rays.
    pub count_rays: bool,
    /// Ray tracing on the GPU: the pipeline with every feature.
    pub every_feature: bool,
    /// Where progress is counted.
    pub counter: &'a WorkCounter,
}

/// A technique on one backend.
pub trait Integrator {
    /// Renders `work`: the image, its timings, and what the technique
    /// adds (the CPU twins: the coverage `check` judges edges by).
    fn render(&self, work: &Work) -> Result<Rendered, Error>;
}
