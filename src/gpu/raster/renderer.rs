//! The raster renderer: flat, Gouraud and Phong through one Vulkan graphics
//! pipeline per (mode, interpolation, specialization), dynamic rendering into
//! a colour target (32-bit float, or 8-bit sRGB for PNG output) with a
//! reversed-Z depth buffer, then a copy back to the host.

use std::sync::Arc;
use std::time::Instant;

use crate::camera::View;
use crate::gpu::raster::frame::Frame;
use crate::gpu::raster::layout::Specialization;
use crate::gpu::raster::pipeline::{create_pipeline, SurfaceFeatures};
use crate::gpu::raster::samples::{check_samples, SampleDrawing};
use crate::gpu::raster::scene::{build_geometry, specialization};
use crate::gpu::raster::target::{ColorTarget, RasterOutput};
use crate::gpu::shared::image_size::check_image_size;
use crate::gpu::vk::commands::OneShot;
use crate::gpu::vk::context::{DeviceInfo, GpuContext};
use crate::gpu::vk::error::GpuError;
use crate::gpu::vk::timestamps::{ms_since, GpuTimings, Timestamps};
use crate::msaa::Msaa;
use crate::scene::Scene;
use crate::shading::RasterMode;

/// Whether the device renders `msaa`: a count it multisamples, or shaded
/// per sample, a standard count its viewport can be shifted by.
pub fn renders_samples(info: &DeviceInfo, msaa: Msaa) -> bool {
    check_samples(info, msaa).is_ok()
}

/// Renders `scene` at its `image` size in `mode`, into `target`.
pub fn render(
    context: &Arc<GpuContext>,
    scene: &Scene,
    mode: RasterMode,
    target: ColorTarget,
) -> Result<RasterOutput, GpuError> {
    let _watch = crate::gpu::shared::watch::watch_render(scene);
    let started = Instant::now();
    let (width, height) = (scene.image.width, scene.image.height);
    check_image_size(context, width, height)?;
    let msaa = scene.render.msaa;
    check_samples(&context.info, msaa)?;
    let drawing = SampleDrawing::of(msaa);
    let target = target.drawn_with(msaa);
    let view = View::new(scene, width, height);
    let geometry = build_geometry(scene, &view, mode == RasterMode::Flat);
    let spec = Specialization {
        output_scale: target.output_scale(),
        at_least_zero: u32::from(matches!(drawing, SampleDrawing::Multisampled(_))),
        ..geometry.with_back_faces(specialization(scene))
    };
    let prepare_ms = ms_since(started);

    let pipeline_started = Instant::now();
    let hook = scene.lighting_hook.as_deref();
    let interpolation = scene.lighting.interpolation;
    let features = SurfaceFeatures {
        colors: !geometry.vertex_colors.is_empty() || !geometry.face_colors.is_empty(),
        pattern: !geometry.vertex_uvs.is_empty(),
        texture: !geometry.textures.is_empty(),
    };
    let key = format!(
        "raster {mode:?} {interpolation:?} {target:?} msaa {msaa} spec {:?} hook {:016x} {features:?}",
        bytemuck::bytes_of(&spec),
        crate::cache::digest(&hook.map(|h| &h.source)),
    );
    let pipeline = context.pipelines.get_or_create(key, || {
        create_pipeline(
            context,
            mode,
            interpolation,
            &spec,
            (target, drawing),
            hook,
            features,
        )
    })?;
    let pipeline_ms = ms_since(pipeline_started);

    let upload_started = Instant::now();
    let frame = Frame::new(
        context,
        (scene, &view, &geometry),
        (mode, features),
        (target, drawing),
        &pipeline,
    )?;
    let timestamps = Timestamps::new(context)?;
    let upload_ms = ms_since(upload_started);

    let commands = OneShot::begin(context)?;
    // SAFETY: the frame, the pipeline and the timestamps live until after
    // the submission completes (they are dropped at the end of this
    // function).
    unsafe {
        frame.record(
            &context.device,
            commands.cmd,
            &pipeline,
            (scene, &view, &geometry),
            &timestamps,
        );
    }
    let (submit_ms, gpu_ms) = timestamps.submit_and_measure(&commands)?;

    let readback_started = Instant::now();
    let image = frame.image();
    Ok(RasterOutput {
        image,
        timings: GpuTimings {
            prepare_ms,
            pipeline_ms,
            upload_ms,
            codegen_ms: None,
            gpu_ms,
            submit_ms,
            readback_ms: ms_since(readback_started),
            total_ms: ms_since(started),
        },
    })
}
