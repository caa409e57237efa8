//! One entry point that renders a scene in a shading mode on a backend:
//! the Vulkan pipelines or the CPU reference.

use std::sync::Arc;
use std::time::Instant;

use crate::cpu;
use crate::error::Error;
use crate::gpu::{raster, GpuContext};
use crate::linear_image::LinearImage;
use crate::scene::Scene;
use crate::shading::{RasterMode, Shading};

/// Where a render spent its time, in milliseconds.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Timings {
    /// The whole render, host work and read-back included.
    pub total_ms: f64,
    /// GPU only: the draw, between timestamp queries.
    pub gpu_ms: Option<f64>,
    /// GPU only: shader modules and pipeline creation.
    pub pipeline_ms: Option<f64>,
}

/// A rendered image and where the time went.
pub struct Rendered {
    pub image: LinearImage,
    pub timings: Timings,
}

fn raster_mode(shading: Shading) -> Result<RasterMode, Error> {
    shading.raster_mode().ok_or_else(|| {
        Error::Usage(
            "--shading raytrace is not available yet (the ray tracer is tracked as issue 4); use flat, gouraud or phong".into(),
        )
    })
}

pub fn render_gpu(
    context: &Arc<GpuContext>,
    scene: &Scene,
    shading: Shading,
) -> Result<Rendered, Error> {
    let out = raster::render(context, scene, raster_mode(shading)?)?;
    Ok(Rendered {
        image: out.image,
        timings: Timings {
            total_ms: out.timings.total_ms,
            gpu_ms: Some(out.timings.gpu_ms),
            pipeline_ms: Some(out.timings.pipeline_ms),
        },
    })
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

/// The CPU reference (`f64`) and what it knows about each pixel.
pub fn render_cpu(scene: &Scene, shading: Shading) -> Result<(Rendered, Coverage), Error> {
    let mode = raster_mode(shading)?;
    let started = Instant::now();
    let out = cpu::raster::render(scene, mode);
    let rendered = Rendered {
        image: out.image,
        timings: Timings {
            total_ms: started.elapsed().as_secs_f64() * 1e3,
            gpu_ms: None,
            pipeline_ms: None,
        },
    };
    let surface_ids = if mode == RasterMode::Flat {
        out.triangle_ids
    } else {
        out.object_ids.clone()
    };
    let coverage = Coverage {
        object_ids: out.object_ids,
        surface_ids,
        near_edge: out.near_edge,
    };
    Ok((rendered, coverage))
}
