//! Running a comparison: the two reference images, then every variant of
//! the shard, timed on the GPU and measured against the CPU reference of
//! the same variant (implementation error), the global reference (model
//! error: ray traced, shadows and reflections in) and the local one (the
//! formula per pixel on exact geometry). Images go into the output folder;
//! the figures into a `Report`.

use std::path::Path;

use super::report::{
    file_stem, pareto_front, Budget, Errors, Metric, NotRun, ReferenceChoice, Report, Timing,
    VariantResult,
};
use super::variant::Variant;
use crate::error::Error;
use crate::linear_image::LinearImage;
use crate::metrics::flip::{flip, FlipStats, PIXELS_PER_DEGREE};
use crate::metrics::heatmap::flip_heatmap;
use crate::metrics::stats::ErrorStats;
use crate::output::write_image;
use crate::render::{render, Device, RenderRequest};
use crate::scene::{CausticSettings, Scene};
use crate::shading::Shading;

pub struct CompareOptions {
    /// Timed GPU runs per variant, after one warm-up.
    pub runs: usize,
    /// The i-th (1-based) of n equal, contiguous parts of the variant list.
    pub shard: Option<(usize, usize)>,
    /// What the plot, the Pareto front and the budget measure against.
    pub reference: ReferenceChoice,
    pub metric: Metric,
    /// `--budget E`: name the fastest variant with at most this error.
    pub budget: Option<f64>,
    /// Variants not to run (by canonical name), each with why (over the
    /// memory limit): reported as not run.
    pub skip: std::collections::BTreeMap<String, String>,
}

/// The variants of shard `(i, n)`: the i-th of n contiguous chunks of
/// `ceil(len / n)`, so shards concatenated in order give the whole list.
pub fn shard_of(variants: &[Variant], shard: Option<(usize, usize)>) -> &[Variant] {
    match shard {
        None => variants,
        Some((i, n)) => {
            let size = variants.len().div_ceil(n);
            let start = ((i - 1) * size).min(variants.len());
            let end = (i * size).min(variants.len());
            &variants[start..end]
        }
    }
}

/// The best the model can do: ray traced on the CPU with exact geometry,
/// at least depth 8, 16 samples per pixel, no cut-off.
pub fn reference_scene(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.render.depth = s.render.depth.max(8);
    s.render.samples = 16;
    s.render.cutoff = 0.0;
    s
}

pub const REFERENCE_DESCRIPTION: &str =
    "CPU ray tracer (f64), exact geometry, depth max(scene, 8), 16 samples per pixel, no cut-off";

/// Samples per pixel of the reference of a comparison with secondary
/// illumination: there the reference is itself an estimate, and its noise
/// (1/32 of one sample's at 1024) is what every variant's error is
/// measured through, so it is made once and kept (`cached_reference`).
pub const CONVERGED_SAMPLES: u32 = 1024;

/// The global reference of `scene` for `variants`: `reference_scene`, and
/// where the scene or a variant asks for diffuse bounces (backward or
/// forward), the transport they estimate: as many bounces as the most any
/// asks for, `CONVERGED_SAMPLES` samples a pixel. Its description.
pub fn reference_for(scene: &Scene, variants: &[Variant]) -> (Scene, String) {
    let mut s = reference_scene(scene);
    let bounces = variants
        .iter()
        .filter_map(|v| v.bounces)
        .chain([scene.render.bounces])
        .max()
        .unwrap_or(0);
    let caustics = reference_caustics(scene, variants);
    if let Some(c) = caustics {
        s.render.caustics = c;
    }
    let with_caustics = caustics.map_or(String::new(), |c| {
        format!(
            ", caustics from {} passes of {} photons",
            c.passes, c.photons_per_pass
        )
    });
    if bounces == 0 {
        if caustics.is_some() {
            let description = format!(
                "CPU ray tracer (f64), exact geometry, depth {}, 16 samples per pixel, no cut-off{with_caustics} (made once, kept in the cache folder)",
                s.render.depth
            );
            return (s, description);
        }
        return (s, REFERENCE_DESCRIPTION.to_string());
    }
    s.render.bounces = bounces;
    s.render.depth = (s.render.depth.max(bounces + 8)).min(crate::scene::MAX_DEPTH);
    s.render.samples = CONVERGED_SAMPLES;
    let description = format!(
        "CPU ray tracer (f64) with {bounces} diffuse bounces, exact geometry, depth {}, {CONVERGED_SAMPLES} samples per pixel, no cut-off{with_caustics} (made once, kept in the cache folder)",
        s.render.depth
    );
    (s, description)
}

/// The caustics of the reference of a comparison where the scene or a
/// variant asks for them: SPPM converges as its photons and passes grow,
/// so the reference takes `CAUSTIC_REFERENCE_FACTOR` times the most
/// photons per pass and the most passes any asks for (within 2^32
/// photons in all), from the scene's first radius.
fn reference_caustics(scene: &Scene, variants: &[Variant]) -> Option<CausticSettings> {
    let asked: Vec<(u32, u32)> = variants
        .iter()
        .filter(|v| v.shading == Shading::Raytrace)
        .map(|v| {
            // The variant's own settings over the scene's (`Variant::apply`
            // without cloning the scene for each).
            let c = scene.render.caustics;
            (
                v.caustics.unwrap_or(c.photons_per_pass),
                v.caustic_passes.unwrap_or(c.passes),
            )
        })
        .filter(|&(photons, passes)| photons > 0 && passes > 0)
        .collect();
    let photons = asked.iter().map(|a| a.0).max()?;
    let passes = asked.iter().map(|a| a.1).max()?;
    let mut c = scene.render.caustics;
    c.photons_per_pass = photons.saturating_mul(CAUSTIC_REFERENCE_FACTOR);
    c.passes = passes.saturating_mul(CAUSTIC_REFERENCE_FACTOR).min(1 << 20);
    let most = u32::MAX / c.photons_per_pass.max(1);
    c.passes = c.passes.min(most).max(1);
    Some(c)
}

/// How many times the most photons per pass, and the most passes, a
/// comparison's caustic reference takes: 16 times the work, its error
/// under a third of the best variant's at SPPM's measured rate.
pub const CAUSTIC_REFERENCE_FACTOR: u32 = 4;

/// `reference`'s CPU render, from the cache folder (`references/`, keyed
/// by everything in the scene) when it was made before, else rendered and
/// kept there. A cache that cannot be read or written only costs time.
fn cached_reference(reference: &Scene) -> Result<LinearImage, Error> {
    let key = format!(
        "shadelab {} reference {:?}",
        env!("CARGO_PKG_VERSION"),
        reference
    );
    let path = crate::cache::folder().map(|f| {
        f.join("references")
            .join(format!("{:016x}.exr", crate::cache::digest(&key)))
    });
    if let Some(image) = path
        .as_ref()
        .and_then(|p| crate::output::read_image(p).ok())
    {
        if (image.width, image.height) == (reference.image.width, reference.image.height) {
            return Ok(image);
        }
    }
    let rendered = cpu_render(reference, Shading::Raytrace)?;
    if let Some(p) = &path {
        let written = p.parent().map(std::fs::create_dir_all);
        if written.is_some_and(|w| w.is_ok()) {
            // Only a saving: a failed write leaves the next run to render.
            let _ = crate::output::write_image(&rendered.image, p);
        }
    }
    Ok(rendered.image)
}

/// The local reference: the lecture's formula per pixel on exact geometry
/// with no shadows, reflection or refraction, what Phong shading converges
/// to as the tessellation refines. The CPU ray tracer at depth 0 with
/// shadows off evaluates exactly that at each primary hit.
///
/// It samples where the raster modes do, once at each pixel's centre. A
/// supersampled one was tried: against it every raster variant carries
/// the same aliasing error at the silhouettes (RMSE 0.0156 on the default
/// scene at 160x120, from 64 segments on), which hid the tessellation
/// error the local reference is there to show; aliasing is a property of
/// the sampling, which every raster variant shares, not of the model.
pub fn local_reference_scene(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.render.depth = 0;
    s.render.shadows = false;
    s.render.samples = 1;
    s.render.cutoff = 0.0;
    s
}

pub const LOCAL_REFERENCE_DESCRIPTION: &str =
    "CPU (f64), the formula at each pixel's centre on exact geometry: no shadows, reflection or refraction";

fn errors(expected: &LinearImage, actual: &LinearImage) -> (Errors, FlipStats) {
    let stats = ErrorStats::compute(expected, actual, None, 0.01);
    let flip = flip(expected, actual, PIXELS_PER_DEGREE);
    let e = Errors {
        rmse: stats.rmse,
        max_abs: stats.max_abs,
        psnr: stats.psnr.is_finite().then_some(stats.psnr),
        flip_mean: flip.mean,
    };
    (e, flip)
}

/// The median of timed runs and their spread (slowest minus fastest).
pub fn median_and_spread(mut values: Vec<f64>) -> (f64, f64) {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    let median = if n % 2 == 1 {
        values[n / 2]
    } else {
        (values[n / 2 - 1] + values[n / 2]) / 2.0
    };
    (median, values[n - 1] - values[0])
}

/// What one variant's renders gave: its first render's timings, the timed
/// runs' GPU and frame times, its last image and engine, and the CPU
/// reference's image of it.
type Measured = (
    crate::render::Timings,
    Vec<f64>,
    Vec<f64>,
    LinearImage,
    Option<crate::scene::Traversal>,
    crate::render::Rendered,
);

fn measure(
    device: &Device,
    scene: &Scene,
    shading: Shading,
    runs: usize,
) -> Result<Measured, Error> {
    // The warm-up: the variant's time to image, its pipeline built.
    let first = render(device, scene, &RenderRequest::gpu(shading))?.timings;
    let (mut gpu, mut frame) = (Vec::new(), Vec::new());
    let mut image = None;
    let mut traversal = None;
    for _ in 0..runs.max(1) {
        let r = render(device, scene, &RenderRequest::gpu(shading))?;
        gpu.push(r.timings.work_ms());
        frame.push(r.timings.total_ms);
        image = Some(r.image);
        traversal = r.traversal;
    }
    let image = image.expect("at least one run");
    let cpu = cpu_render(scene, shading)?;
    Ok((first, gpu, frame, image, traversal, cpu))
}

/// Runs the comparison and writes `reference.png` and, per variant,
/// `<stem>.png` and `<stem>-heat.png` into `dir`. `progress(done, total,
/// name)` is called before each step. A variant `options.skip` names (over
/// the memory limit), or one whose render fails, is reported as not run,
/// and the others go on.
pub fn run(
    device: &Device,
    scene: &Scene,
    scene_name: &str,
    variants: &[Variant],
    options: &CompareOptions,
    dir: &Path,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<Report, Error> {
    let gpu = device.require_gpu()?;
    let chosen = shard_of(variants, options.shard);
    // Every variant's scene first: a hook's file that cannot be read fails
    // the run before the reference takes its time.
    let scenes = chosen
        .iter()
        .map(|v| v.apply(scene))
        .collect::<Result<Vec<_>, _>>()?;
    let mut not_run = Vec::new();
    let total = chosen.len() + 2;
    let (reference, reference_description) = reference_for(scene, variants);
    let references = render_references(scene, &reference, dir, total, &mut progress)?;
    let mut results = Vec::with_capacity(chosen.len());
    for (k, (variant, scene_v)) in chosen.iter().zip(&scenes).enumerate() {
        let name = variant.to_string();
        progress(k + 2, total, &name);
        match run_variant(device, variant, scene_v, name, options, &references, dir)? {
            Outcome::Measured(result) => results.push(*result),
            Outcome::NotRun(skipped) => not_run.push(skipped),
        }
    }
    let mut report = Report {
        scene: scene_name.to_string(),
        width: scene.image.width,
        height: scene.image.height,
        device: gpu.info.name.clone(),
        driver: gpu.info.driver.clone(),
        runs: options.runs.max(1),
        reference: reference_description,
        reference_image: "reference.png".to_string(),
        local_reference: LOCAL_REFERENCE_DESCRIPTION.to_string(),
        local_reference_image: "reference-local.png".to_string(),
        plot_reference: options.reference,
        plot_metric: options.metric,
        shard: options.shard,
        variants: results,
        budget: None,
        not_run,
        run: None,
    };
    mark_pareto(&mut report);
    set_budget(&mut report, options.budget);
    Ok(report)
}

/// The global and the local reference images, each written as soon as it
/// is rendered.
struct References {
    global: LinearImage,
    local: LinearImage,
}

fn render_references(
    scene: &Scene,
    reference_scene: &Scene,
    dir: &Path,
    total: usize,
    progress: &mut impl FnMut(usize, usize, &str),
) -> Result<References, Error> {
    progress(0, total, "reference");
    let converged = reference_scene.render.bounces > 0 || reference_scene.render.caustics.on();
    let reference = if converged {
        cached_reference(reference_scene)?
    } else {
        cpu_render(reference_scene, Shading::Raytrace)?.image
    };
    write_image(&reference, &dir.join("reference.png"))?;
    progress(1, total, "local reference");
    let local_reference = cpu_render(&local_reference_scene(scene), Shading::Raytrace)?;
    write_image(&local_reference.image, &dir.join("reference-local.png"))?;
    Ok(References {
        global: reference,
        local: local_reference.image,
    })
}

/// What became of one variant (boxed: a result is large beside a reason).
enum Outcome {
    Measured(Box<VariantResult>),
    NotRun(NotRun),
}

/// One variant: rendered and timed, judged against its CPU reference and
/// both references, its image and heat map written; or not run, with why
/// (skipped, or its render failed: that failure is its own, the others
/// still run). Fails only when an image cannot be written.
fn run_variant(
    device: &Device,
    variant: &Variant,
    scene: &Scene,
    name: String,
    options: &CompareOptions,
    references: &References,
    dir: &Path,
) -> Result<Outcome, Error> {
    if let Some(reason) = options.skip.get(&name).cloned() {
        return Ok(Outcome::NotRun(NotRun {
            name,
            variant: variant.clone(),
            reason,
        }));
    }
    let (first, gpu, frame, image, traversal, cpu) =
        match measure(device, scene, variant.shading, options.runs) {
            Ok(m) => m,
            // No later variant can run on a stuck device.
            Err(e) if e.leaves_device_stuck() => return Err(e),
            Err(e) => {
                return Ok(Outcome::NotRun(NotRun {
                    name,
                    variant: variant.clone(),
                    reason: e.to_string(),
                }))
            }
        };
    let judged = judge(&cpu.image, references, &image);
    let stem = file_stem(&name);
    let (image_file, heat_file) = (format!("{stem}.png"), format!("{stem}-heat.png"));
    write_image(&image, &dir.join(&image_file))?;
    write_image(&flip_heatmap(&judged.model_flip), &dir.join(&heat_file))?;
    let (gpu_ms, gpu_spread_ms) = median_and_spread(gpu);
    let (frame_ms, frame_spread_ms) = median_and_spread(frame);
    Ok(Outcome::Measured(Box::new(VariantResult {
        name,
        variant: variant.clone(),
        image: image_file,
        heatmap: heat_file,
        implementation_error: judged.implementation,
        model_error: judged.model,
        local_error: Some(judged.local),
        timing: Timing {
            gpu_ms,
            gpu_spread_ms,
            frame_ms,
            frame_spread_ms,
            pipeline_ms: first.pipeline_ms.unwrap_or(0.0),
            image_ms: first.total_ms,
        },
        traversal,
        non_finite_pixels: image.non_finite_pixels(),
        pareto: false,
    })))
}

/// A variant's three errors, and the FLIP of the model error that its heat
/// map draws.
struct Judged {
    implementation: Errors,
    model: Errors,
    model_flip: FlipStats,
    local: Errors,
}

/// The GPU image against the CPU reference of the same variant, the
/// global reference and the local one.
fn judge(cpu: &LinearImage, references: &References, image: &LinearImage) -> Judged {
    // Three FLIPs (single-threaded each, most of a variant's time
    // outside the GPU), side by side.
    let ((implementation, _), ((model, model_flip), (local, _))) = rayon::join(
        || errors(cpu, image),
        || {
            rayon::join(
                || errors(&references.global, image),
                || errors(&references.local, image),
            )
        },
    );
    Judged {
        implementation,
        model,
        model_flip,
        local,
    }
}

/// Marks each variant on the Pareto front of (GPU time, plotted error).
pub fn mark_pareto(report: &mut Report) {
    let points: Vec<(f64, f64)> = report
        .variants
        .iter()
        .map(|v| (v.timing.gpu_ms, report.error_of(v)))
        .collect();
    for (v, on) in report.variants.iter_mut().zip(pareto_front(&points)) {
        v.pareto = on;
    }
}

/// Names the fastest variant within `max_error` (of the plotted error) in
/// the report; no budget, no entry.
pub fn set_budget(report: &mut Report, max_error: Option<f64>) {
    report.budget = max_error.map(|max_error| Budget {
        max_error,
        fastest: report.fastest_within(max_error).map(|v| v.name.clone()),
    });
}

/// Joins shard reports (in shard order) into one; fails if they are not
/// shards of the same run.
pub fn merge(mut shards: Vec<Report>) -> Result<Report, String> {
    if shards.is_empty() {
        return Err("no reports to merge".into());
    }
    shards.sort_by_key(|r| r.shard.map(|(i, _)| i).unwrap_or(0));
    let first = shards[0].clone();
    let n = first.shard.map(|(_, n)| n);
    for (k, s) in shards.iter().enumerate() {
        if (s.scene.as_str(), s.width, s.height, s.reference.as_str())
            != (
                first.scene.as_str(),
                first.width,
                first.height,
                first.reference.as_str(),
            )
        {
            return Err(format!(
                "shard {} is of another run ({} {}x{}) than shard 1 ({} {}x{})",
                k + 1,
                s.scene,
                s.width,
                s.height,
                first.scene,
                first.width,
                first.height
            ));
        }
        if s.shard.map(|(_, n2)| n2) != n || s.shard.map(|(i, _)| i) != Some(k + 1) {
            let got = s
                .shard
                .map_or("a whole run (no shard)".to_string(), |(i, n)| {
                    format!("shard {i}/{n}")
                });
            return Err(format!(
                "expected shards 1 to {} of one run, once each; got {got} where shard {} should be",
                n.unwrap_or(0),
                k + 1
            ));
        }
    }
    if Some(shards.len()) != n {
        return Err(format!("got {} of {} shards", shards.len(), n.unwrap_or(0)));
    }
    let budget = first.budget.as_ref().map(|b| b.max_error);
    let not_run = shards.iter().flat_map(|s| s.not_run.clone()).collect();
    let mut merged = Report {
        shard: None,
        variants: shards.into_iter().flat_map(|s| s.variants).collect(),
        not_run,
        ..first
    };
    mark_pareto(&mut merged);
    set_budget(&mut merged, budget);
    Ok(merged)
}

/// The CPU reference's render of `scene` in `shading`.
fn cpu_render(scene: &Scene, shading: Shading) -> Result<crate::render::Rendered, Error> {
    render(&Device::cpu_only(), scene, &RenderRequest::cpu(shading))
}
