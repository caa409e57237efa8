//! What a render gives back: its image, where the time went, and what
//! each technique adds (ray counts, the film and its photons, the
//! caustics' report, the CPU reference's knowledge of each pixel).

use std::time::Instant;

use crate::film_sums::{FilmSums, PhotonStats};
use crate::gpu::raytrace::caustics::CausticStats;
use crate::linear_image::LinearImage;
use crate::rt_scene::RayStats;
use crate::scene::Traversal;

/// Where a render spent its time, in milliseconds.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Timings {
    /// The whole render, host work and read-back included.
    pub total_ms: f64,
    /// GPU only: the work, between timestamp queries.
    pub gpu_ms: Option<f64>,
    /// GPU only: queue submission to completion (`GpuTimings::submit_ms`).
    pub submit_ms: Option<f64>,
    /// GPU only: shader modules and pipeline creation.
    pub pipeline_ms: Option<f64>,
    /// GPU only: the host's work on the scene before the pipeline
    /// (geometry, BVH, records: `GpuTimings::prepare_ms`).
    pub prepare_ms: Option<f64>,
    /// GPU only: buffers, images and descriptors, the data uploaded.
    pub upload_ms: Option<f64>,
    /// GPU ray tracing only: the driver's code generation (or its shader
    /// cache's load) at the pipeline's first dispatch.
    pub codegen_ms: Option<f64>,
    /// GPU only: the image read back into a `LinearImage`.
    pub readback_ms: Option<f64>,
    /// The CPU ray tracers only: the tracing alone, after the scene and
    /// its BVH are built (what the GPU's dispatch time compares with).
    pub trace_ms: Option<f64>,
}

impl Timings {
    /// The CPU reference's timings: wall time since `started`, nothing else.
    pub(super) fn cpu(started: Instant) -> Self {
        Self {
            total_ms: started.elapsed().as_secs_f64() * 1e3,
            ..Self::default()
        }
    }

    /// A GPU render's timings.
    pub(super) fn gpu(t: &crate::gpu::GpuTimings) -> Self {
        Self {
            total_ms: t.total_ms,
            gpu_ms: Some(t.gpu_ms),
            submit_ms: Some(t.submit_ms),
            pipeline_ms: Some(t.pipeline_ms),
            prepare_ms: Some(t.prepare_ms),
            upload_ms: Some(t.upload_ms),
            codegen_ms: t.codegen_ms,
            readback_ms: Some(t.readback_ms),
            trace_ms: None,
        }
    }

    /// The time the rendering work itself took: submission to completion
    /// on the GPU, the whole render on the CPU.
    pub fn work_ms(&self) -> f64 {
        self.submit_ms.unwrap_or(self.total_ms)
    }
}

/// A rendered image and where the time went.
pub struct Rendered {
    pub image: LinearImage,
    pub timings: Timings,
    /// Rays traced, by kind: ray tracing only.
    pub ray_stats: Option<RayStats>,
    /// The engine that found the hits: GPU ray tracing only.
    pub traversal: Option<Traversal>,
    /// Forward ray tracing, and ray tracing with bounces: the film's
    /// fixed-point sums (which shards add up: `film_sums`) and what was
    /// traced.
    pub film: Option<FilmRender>,
    /// Ray tracing with caustics: what the photon map took (its image is
    /// in `image`, not in `film`).
    pub caustics: Option<CausticReport>,
    /// The CPU reference only: what it knows about each pixel besides its
    /// colour (which pixels another renderer may see otherwise).
    pub coverage: Option<Coverage>,
}

impl Rendered {
    /// `image`, rendered in `timings`, with nothing else to say yet.
    pub(super) fn new(image: LinearImage, timings: Timings) -> Self {
        Self {
            image,
            timings,
            ray_stats: None,
            traversal: None,
            film: None,
            caustics: None,
            coverage: None,
        }
    }
}

/// A render summed in fixed point: its film, beside its image, and what
/// made it.
pub struct FilmRender {
    pub film: FilmSums,
    /// Of the part asked for, the photons or samples per pixel traced
    /// (fewer where a time budget stopped it).
    pub traced: u64,
    /// Forward only: what the photons did.
    pub photons: Option<PhotonStats>,
    /// Under an error budget (GPU only), the render's last estimate of its
    /// RMSE (`error_budget`).
    pub estimated_rmse: Option<f64>,
}

/// What the CPU reference knows about each pixel besides its colour.
pub struct Coverage {
    /// `scene.objects` index per pixel (`None`: background).
    pub object_ids: Vec<Option<u32>>,
    /// The surface of constant shading rules per pixel: the triangle in flat
    /// mode (its colour changes at every triangle edge), else the object.
    pub surface_ids: Vec<Option<u32>>,
    /// Samples so close to a visible edge that another conforming
    /// rasterizer may cover them differently (`cpu::raster::EDGE_MARGIN`).
    pub near_edge: Vec<bool>,
}

/// What a render's caustics took.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CausticReport {
    pub photons_per_pass: u32,
    /// Passes run: those asked for, or fewer where a time budget stopped
    /// them (at least one).
    pub passes: u32,
    pub asked_passes: u32,
    /// The photon map's whole time, in milliseconds.
    pub ms: f64,
    /// The GPU's only: its passes' GPU time and submit-to-completion time
    /// (added to the render's `gpu_ms` and `submit_ms`).
    pub gpu_ms: Option<f64>,
    pub submit_ms: Option<f64>,
    /// The GPU's only: what the photons did.
    pub photons: Option<CausticStats>,
}
