//! The ray tracer's caustics (`render.caustics`, `--caustics N`): the
//! caustic image of a progressive photon map, on the GPU
//! (`gpu::raytrace::caustics`) or with the f64 twin (`cpu::caustics`),
//! added to the backward tracer's image. A scene with no mirror or glass,
//! or no light with power, has no caustic: no photon is traced and no
//! pipeline built, and `pointless` says why once.

use std::sync::Arc;
use std::time::Instant;

use crate::error::Error;
use crate::film_sums::RenderPart;
use crate::gpu::raytrace::caustics::{self, CausticStats};
use crate::gpu::GpuContext;
use crate::linear_image::LinearImage;
use crate::scene::Scene;
use crate::work_counter::WorkCounter;

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

/// Whether `scene` has caustics to gather: a mirror or glass, and a light
/// with power.
pub fn has_caustics(scene: &Scene) -> bool {
    why_none(scene).is_none()
}

/// Why `scene`'s caustics add nothing, where they are asked for: no
/// material reflects or transmits, or no light has power.
pub fn pointless(scene: &Scene) -> Option<String> {
    if !scene.render.caustics.on() {
        return None;
    }
    let why = why_none(scene)?;
    Some(format!(
        "--caustics: {why}, so the scene has no caustic; no photon is traced"
    ))
}

/// Why `scene` has no caustic, if it has none.
fn why_none(scene: &Scene) -> Option<&'static str> {
    let redirects = scene.objects.iter().any(|o| {
        let m = &scene.materials[o.material];
        m.kr > 0.0 || m.kt > 0.0
    });
    let emits = scene
        .lights
        .iter()
        .any(|l| l.intensity.x + l.intensity.y + l.intensity.z > 0.0);
    if !redirects {
        Some("no object has a mirror (kr) or glass (kt) to send light on")
    } else if !emits {
        Some("no light has an intensity above 0")
    } else {
        None
    }
}

/// Adds `scene`'s caustic image to `image` (the backward tracer's), on the
/// GPU where `context` is given, else with the f64 twin, passes counted
/// into `counter`; on the GPU the passes that start before `deadline`
/// (one at least). What it took and the caustic image it added, or `None`
/// where the scene asks for none or has none (`pointless`).
pub fn add(
    context: Option<&Arc<GpuContext>>,
    scene: &Scene,
    image: &mut LinearImage,
    (counter, deadline): (&WorkCounter, Option<Instant>),
) -> Result<Option<(CausticReport, LinearImage)>, Error> {
    let settings = scene.render.caustics;
    if !settings.on() || pointless(scene).is_some() {
        return Ok(None);
    }
    let started = Instant::now();
    let passes = RenderPart {
        deadline,
        ..RenderPart::all(settings.passes)
    };
    let (caustic, photons, done, gpu) = match context {
        Some(context) => {
            let out = caustics::render(context, scene, &passes, counter)?;
            let gpu = (out.timings.gpu_ms, out.timings.submit_ms);
            (out.image, Some(out.stats), out.stats.passes, Some(gpu))
        }
        None => {
            counter.begin("caustic passes", u64::from(settings.passes));
            let image = crate::cpu::caustics::render_caustics(scene, &settings).ok_or_else(|| {
                Error::Usage(format!(
                    "--caustics {} times {} passes is past 4294967295 photons (photons are numbered in 32 bits)",
                    settings.photons_per_pass, settings.passes
                ))
            })?;
            counter.add(u64::from(settings.passes));
            (image, None, settings.passes, None)
        }
    };
    for (pixel, add) in image.pixels.iter_mut().zip(&caustic.pixels) {
        for c in 0..3 {
            pixel[c] += add[c];
        }
    }
    let report = CausticReport {
        photons_per_pass: settings.photons_per_pass,
        passes: done,
        asked_passes: settings.passes,
        ms: started.elapsed().as_secs_f64() * 1e3,
        gpu_ms: gpu.map(|g| g.0),
        submit_ms: gpu.map(|g| g.1),
        photons,
    };
    Ok(Some((report, caustic)))
}
