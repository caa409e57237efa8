//! One entry point that renders a scene in a shading mode on a backend.

use std::sync::Arc;

use crate::error::Error;
use crate::gpu::{raster, GpuContext, RasterMode, RasterTimings};
use crate::linear_image::LinearImage;
use crate::scene::Scene;
use crate::shading::Shading;

/// A rendered image and where the time went.
pub struct Rendered {
    pub image: LinearImage,
    pub timings: RasterTimings,
}

pub fn render_gpu(
    context: &Arc<GpuContext>,
    scene: &Scene,
    shading: Shading,
) -> Result<Rendered, Error> {
    let mode = match shading {
        Shading::Flat => RasterMode::Flat,
        Shading::Gouraud => RasterMode::Gouraud,
        Shading::Phong => RasterMode::Phong,
        Shading::Raytrace => {
            return Err(Error::Usage(
                "--shading raytrace is not available yet (the ray tracer is tracked as issue 4); use flat, gouraud or phong".into(),
            ))
        }
    };
    let out = raster::render(context, scene, mode)?;
    Ok(Rendered {
        image: out.image,
        timings: out.timings,
    })
}
