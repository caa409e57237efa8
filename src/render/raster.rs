//! Flat, Gouraud and Phong: the raster pipelines on the GPU, and their
//! f64 twin that rasterizes the same triangles.

use std::sync::Arc;
use std::time::Instant;

use super::integrator::{Integrator, Work};
use super::rendered::{Coverage, Rendered, Timings};
use crate::error::Error;
use crate::gpu::{raster, GpuContext};
use crate::shading::RasterMode;

/// A raster mode on the Vulkan pipelines.
pub(super) struct GpuRaster<'d> {
    pub context: &'d Arc<GpuContext>,
    pub mode: RasterMode,
}

impl Integrator for GpuRaster<'_> {
    fn render(&self, work: &Work) -> Result<Rendered, Error> {
        let out = raster::render(self.context, work.scene, self.mode, work.target)?;
        Ok(Rendered::new(out.image, Timings::gpu(&out.timings)))
    }
}

/// A raster mode in f64 on the CPU.
pub(super) struct CpuRaster {
    pub mode: RasterMode,
}

impl Integrator for CpuRaster {
    fn render(&self, work: &Work) -> Result<Rendered, Error> {
        let started = Instant::now();
        let out = crate::cpu::raster::render(work.scene, self.mode, work.counter);
        let mut rendered = Rendered::new(out.image, Timings::cpu(started));
        // Flat shading's colour changes at every triangle edge; the other
        // modes' only at an object's.
        let surface_ids = if self.mode == RasterMode::Flat {
            out.triangle_ids
        } else {
            out.object_ids.clone()
        };
        rendered.coverage = Some(Coverage {
            object_ids: out.object_ids,
            surface_ids,
            near_edge: out.near_edge,
        });
        Ok(rendered)
    }
}
