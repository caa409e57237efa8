//! The ray tracer's caustics (`render.caustics`, `--caustics N`): the
//! caustic image of a progressive photon map, on the GPU
//! (`gpu::raytrace::caustics`) or with the f64 twin (`cpu::caustics`),
//! added to the backward tracer's image. A scene with no mirror or glass,
//! or no light with power, has no caustic: no photon is traced and no
//! pipeline built, and `no_caustic` says why once.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Instant;

use crate::error::Error;
use crate::film_sums::RenderPart;
use crate::gpu::raytrace::caustics;
use crate::gpu::GpuContext;
use crate::linear_image::LinearImage;
use crate::scene::Scene;
use crate::work_counter::WorkCounter;

use super::coverage::neighbourhoods;
use super::rendered::{CausticReport, Rendered};

/// Why `scene` has no caustic, if it has none: no material reflects or
/// transmits, or no light has power. The one predicate: the plan adds
/// caustics only where this is `None`, warns with it where they were asked
/// for, and `--backend auto` weighs the photon map only where there is one.
pub fn no_caustic(scene: &Scene) -> Option<&'static str> {
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

/// Whether a ray trace of `scene` adds a caustic image: asked for, and
/// the scene has a caustic.
pub(super) fn adds_to(scene: &Scene) -> bool {
    scene.render.caustics.on() && no_caustic(scene).is_none()
}

/// The warning where caustics are asked for and the scene has none.
pub(super) fn nothing_to_gather(scene: &Scene) -> Option<String> {
    if !scene.render.caustics.on() {
        return None;
    }
    let why = no_caustic(scene)?;
    Some(format!(
        "--caustics: {why}, so the scene has no caustic; no photon is traced"
    ))
}

/// The f64 twin numbers its photons in 32 bits across all passes.
pub(super) fn refuse_cpu_photon_count(scene: &Scene) -> Result<(), Error> {
    let settings = scene.render.caustics;
    match settings.total_photons() {
        Some(_) => Ok(()),
        None => Err(Error::Usage(format!(
            "--caustics {} times {} passes is past 4294967295 photons (photons are numbered in 32 bits)",
            settings.photons_per_pass, settings.passes
        ))),
    }
}

/// The photon map's passes: all that `scene` asks for, stopped (after
/// the first) at `deadline` or when `cancel` is set.
pub(super) fn passes(
    scene: &Scene,
    deadline: Option<Instant>,
    cancel: &Option<Arc<AtomicBool>>,
) -> RenderPart {
    RenderPart {
        deadline,
        cancel: cancel.clone(),
        ..RenderPart::all(scene.render.caustics.passes)
    }
}

/// Adds `scene`'s caustic image to `rendered` (the backward tracer's), on
/// the GPU where `gpu` is given, else with the f64 twin, passes counted
/// into `counter`; its time to the render's, its report beside. Where the
/// render knows its coverage (the twin), a caustic's pixels and their
/// neighbours become edge pixels: the GPU gathers the same photons, but
/// f32 rounding can put one on the other side of a pixel's radius, so
/// they are judged by the share that differ (docs/check.md).
pub(super) fn add(
    gpu: Option<&Arc<GpuContext>>,
    scene: &Scene,
    rendered: &mut Rendered,
    passes: &RenderPart,
    counter: &WorkCounter,
) -> Result<(), Error> {
    let started = Instant::now();
    let settings = scene.render.caustics;
    let (caustic, photons, done, gpu_times) = match gpu {
        Some(context) => {
            let out = caustics::render(context, scene, passes, counter)?;
            let times = (out.timings.gpu_ms, out.timings.submit_ms);
            (out.image, Some(out.stats), out.stats.passes, Some(times))
        }
        None => {
            counter.begin("caustic passes", u64::from(settings.passes));
            let image = crate::cpu::caustics::render_caustics(scene, &settings)
                .expect("the plan refuses a photon count past 32 bits");
            counter.add(u64::from(settings.passes));
            (image, None, settings.passes, None)
        }
    };
    for (pixel, add) in rendered.image.pixels.iter_mut().zip(&caustic.pixels) {
        for c in 0..3 {
            pixel[c] += add[c];
        }
    }
    let report = CausticReport {
        photons_per_pass: settings.photons_per_pass,
        passes: done,
        asked_passes: settings.passes,
        ms: started.elapsed().as_secs_f64() * 1e3,
        gpu_ms: gpu_times.map(|g| g.0),
        submit_ms: gpu_times.map(|g| g.1),
        photons,
    };
    let t = &mut rendered.timings;
    t.total_ms += report.ms;
    let sum = |a: Option<f64>, b: Option<f64>| a.map(|a| a + b.unwrap_or(0.0));
    t.gpu_ms = sum(t.gpu_ms, report.gpu_ms);
    t.submit_ms = sum(t.submit_ms, report.submit_ms);
    rendered.caustics = Some(report);
    if let Some(coverage) = &mut rendered.coverage {
        mark_caustic_rims(scene, &caustic, &mut coverage.near_edge);
    }
    Ok(())
}

/// Marks the caustic's lit pixels and their neighbours as near an edge.
fn mark_caustic_rims(scene: &Scene, caustic: &LinearImage, near_edge: &mut [bool]) {
    let lit: Vec<u64> = (caustic.pixels.iter())
        .map(|p| u64::from(p.iter().any(|&c| c != 0.0)))
        .collect();
    let (width, height) = (scene.image.width as usize, scene.image.height as usize);
    for (near, rim) in near_edge
        .iter_mut()
        .zip(neighbourhoods(width, height, &lit))
    {
        *near |= rim;
    }
}
