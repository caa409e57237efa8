//! What a render's image says of itself, the same wherever it is made
//! (`render`, a batch, `golden`, the Python package): the colour target
//! the raster modes draw into for a file format, and the settings it was
//! made with, as JSON and in the PNG's text.

use std::path::Path;

use crate::backend_choice::Backend;
use crate::gpu::raster::ColorTarget;
use crate::scene::Scene;
use crate::shading::Shading;

/// What the image was made with, overrides applied: `--json`'s
/// `settings` and the PNG's `shadelab:settings` text. The ray tracer's
/// settings only where it ran.
pub fn effective_settings(
    scene_path: Option<&Path>,
    shading: Shading,
    scene: &Scene,
    backend: Backend,
    rendered: &crate::render::Rendered,
    device: &str,
    driver: Option<&str>,
) -> serde_json::Value {
    let ray_traced = shading == Shading::Raytrace;
    let forward = shading == Shading::Forward;
    let r = &scene.render;
    serde_json::json!({
        "scene": scene_path.map_or_else(
            || "built-in default scene".to_string(),
            |p| p.display().to_string(),
        ),
        "shading": shading,
        "backend": backend.name(),
        "width": rendered.image.width,
        "height": rendered.image.height,
        "depth": (ray_traced || forward).then_some(r.depth),
        "samples": ray_traced.then_some(r.samples),
        "bounces": (ray_traced || forward).then_some(r.bounces),
        "photons": forward.then_some(r.photons),
        "caustics": rendered.caustics.map(|c| serde_json::json!({
            "photons_per_pass": c.photons_per_pass,
            "passes": c.passes,
            "initial_radius": r.caustics.initial_radius,
            "alpha": r.caustics.alpha,
        })),
        "shadows": ray_traced.then_some(r.shadows),
        "cutoff": ray_traced.then_some(r.cutoff),
        "traversal": rendered.traversal.map(|t| t.name()),
        "msaa": shading.raster_mode().is_some().then(|| r.msaa.to_string()),
        "lighting": scene.lighting_hook.as_ref().map(|h| h.path.clone()),
        "device": device,
        "driver": driver,
        "shadelab": env!("CARGO_PKG_VERSION"),
    })
}

/// The raster modes' colour target for an output `format`.
pub fn color_target(scene: &Scene, format: crate::output::ImageFormat) -> ColorTarget {
    // A PNG holds 8-bit sRGB: the raster modes render straight into it.
    // A lighting hook is the user's code, and may return NaN: the float
    // target keeps it to be counted, where the 8-bit one turns it into a
    // colour on the way in.
    // Multisampled: the samples are averaged in 16 bits for a PNG
    // (`ColorTarget::drawn_with`).
    match scene.lighting_hook {
        Some(_) => ColorTarget::Float32,
        None => ColorTarget::for_output(format).drawn_with(scene.render.msaa),
    }
}

/// What a rendered PNG says of itself: the scene's name, the device, the
/// settings as a line and as JSON.
pub fn image_metadata(
    stem: &str,
    device: &str,
    settings: &serde_json::Value,
) -> crate::output::ImageMetadata {
    crate::output::ImageMetadata::software()
        .with("Title", stem)
        .with("Source", device)
        .with("Comment", settings_line(settings))
        .with("shadelab:settings", settings.to_string())
}

/// The settings as one line for people: `key=value`, the unset left out.
fn settings_line(settings: &serde_json::Value) -> String {
    settings
        .as_object()
        .map(|o| {
            o.iter()
                .filter(|(_, v)| !v.is_null())
                .map(|(k, v)| match v {
                    serde_json::Value::String(s) => format!("{k}={s}"),
                    other => format!("{k}={other}"),
                })
                .collect::<Vec<_>>()
                .join(" ")
        })
        .unwrap_or_default()
}
