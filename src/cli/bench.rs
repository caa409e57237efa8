//! `shadelab bench`: render times per mode, medians over several runs after
//! a warm-up, as ratios against a baseline measured in the same run (the
//! flat raster render of the same scene), and rays per second for the ray
//! tracer. With `--cpu`, the CPU reference's time for the same work beside
//! each mode; with `--every-feature`, the ray tracer compiled with every
//! optional feature in, against the one specialised to the scene. Shared
//! machines are noisy: compare ratios, not milliseconds.

use std::ffi::OsString;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use clap::Args;
use shadelab::compare::run::median_and_spread;
use shadelab::gpu::raster::ColorTarget;
use shadelab::gpu::raytrace::TraceOptions;
use shadelab::gpu::{raster, raytrace, GpuContext, GpuOptions, GpuTimings};
use shadelab::memory::MemoryLimit;
use shadelab::scene::Scene;
use shadelab::shading::Shading;

use super::args::{check_runs, ImageSize, ModeList, SceneFlags};
use super::ignored;
use super::render::load_scene;
use super::time_to_image::{self, TimeToImage};
use super::Failure;

#[derive(Args)]
pub struct BenchArgs {
    /// Scene file; the built-in default scene if left out.
    scene: Option<PathBuf>,
    #[command(flatten)]
    modes: ModeList,
    /// Timed runs per mode (after one warm-up run).
    #[arg(long, default_value_t = 5)]
    runs: usize,
    #[command(flatten)]
    size: ImageSize,
    #[command(flatten)]
    settings: SceneFlags,
    /// Also time the CPU reference on the same work (the ray tracer's
    /// tracing alone, as the GPU's dispatch; the raster modes' whole
    /// render), and print the GPU's speed-up over it.
    #[arg(long)]
    cpu: bool,
    /// Also time the ray tracer compiled with every optional feature in
    /// (reflection, refraction, the specular term, the BVH walk), as an
    /// uber-shader would, against the pipeline specialised to the scene.
    #[arg(long)]
    every_feature: bool,
    /// The output the raster modes are timed for: `png` renders into an
    /// 8-bit sRGB target, as `render --out x.png` does; `exr` into the
    /// 32-bit float target of `render --out x.exr`, `check` and `compare`.
    /// (The ray tracer always writes floats.)
    #[arg(long, value_enum, default_value = "png")]
    target: TargetFor,
    /// Also time the whole `render` command per mode, as fresh processes:
    /// cold (empty shadelab and Mesa caches, as on a fresh CI runner), warm
    /// (caches filled), and the CPU twin's command (`--backend cpu`).
    #[arg(long)]
    time_to_image: bool,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    pub machine: super::args::MachineArgs,
}

impl BenchArgs {
    /// The scene and the overrides as `render` takes them, and the
    /// GPU-only ones (a lighting hook) apart.
    fn render_args(&self) -> (Vec<OsString>, Vec<OsString>) {
        let mut args: Vec<OsString> = self.scene.iter().map(|p| p.into()).collect();
        let mut flag = |name: &str, value: Option<String>| {
            if let Some(v) = value {
                args.push(name.into());
                args.push(v.into());
            }
        };
        flag("--width", self.size.width.map(|v| v.to_string()));
        flag("--height", self.size.height.map(|v| v.to_string()));
        flag("--depth", self.settings.depth.depth.map(|v| v.to_string()));
        flag("--traversal", self.settings.traversal.traversal.clone());
        let gpu = match &self.settings.lighting.lighting {
            Some(hook) => vec!["--lighting".into(), hook.into()],
            None => Vec::new(),
        };
        (args, gpu)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum TargetFor {
    Png,
    Exr,
}

impl TargetFor {
    fn color_target(self) -> ColorTarget {
        match self {
            TargetFor::Png => ColorTarget::Srgb8,
            TargetFor::Exr => ColorTarget::Float32,
        }
    }
}

fn once(
    context: &Arc<GpuContext>,
    scene: &Scene,
    shading: Shading,
    every_feature: bool,
    target: ColorTarget,
) -> Result<GpuTimings, Failure> {
    Ok(match shading.raster_mode() {
        Some(mode) => raster::render_to(context, scene, mode, target)?.timings,
        None => {
            let options = TraceOptions {
                every_feature,
                ..TraceOptions::default()
            };
            raytrace::render_with(context, scene, options)?.timings
        }
    })
}

/// One timed render of the CPU reference, in milliseconds: the ray
/// tracer's tracing (its BVH built beforehand, as the GPU's is before its
/// dispatch), or a raster mode's whole render.
fn cpu_once(scene: &Scene, shading: Shading) -> Result<f64, Failure> {
    if shading.raster_mode().is_none() {
        return Ok(shadelab::cpu::raytrace::render(scene).trace_ms);
    }
    let started = Instant::now();
    shadelab::render::render_cpu(scene, shading)?;
    Ok(started.elapsed().as_secs_f64() * 1e3)
}

#[derive(serde::Serialize)]
struct Row {
    shading: Shading,
    /// The colour target timed (`ColorTarget::name`).
    color_target: &'static str,
    /// The ray tracer's engine (`bvh` or `query`); raster modes have none.
    traversal: Option<&'static str>,
    total_ms: f64,
    /// Median wall time from queue submission to completion.
    gpu_ms: f64,
    /// Spread: the slowest minus the fastest run.
    total_spread_ms: f64,
    /// Median total time over the baseline's.
    ratio_to_baseline: f64,
    rays: Option<u64>,
    rays_per_second: Option<f64>,
    /// `--cpu`: the CPU reference's median time for the same work.
    cpu_ms: Option<f64>,
    /// `--cpu`: `cpu_ms / gpu_ms`.
    gpu_speedup_over_cpu: Option<f64>,
    /// `--every-feature`: the ray tracer with every optional feature in.
    every_feature_gpu_ms: Option<f64>,
    /// `--every-feature`: `every_feature_gpu_ms / gpu_ms`, what
    /// specialising to the scene saves.
    every_feature_ratio: Option<f64>,
    /// `--time-to-image`: the whole command's wall clock, cold and warm,
    /// and the CPU twin's.
    time_to_image: Option<TimeToImage>,
}

pub fn run(args: BenchArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    check_runs(args.runs)?;
    let modes = args.modes.modes();
    let s = &args.settings;
    let mut given = ignored::scene_flags_given(&s.traversal, &s.msaa, s.depth.depth);
    if args.cpu {
        given.push("--cpu");
    }
    let (mut scene, name) = load_scene(args.scene.as_deref(), memory)?;
    args.size.apply(&mut scene)?;
    args.settings.apply(&mut scene)?;
    // Said once the flags are known to be valid: a bad one is the answer.
    ignored::warn(&given, &modes, ignored::Backends::Gpu);
    let hook_path = scene.lighting_hook.as_ref().map(|h| h.path.clone());
    let cpu_modes: &[Shading] = if args.cpu { &[Shading::Raytrace] } else { &[] };
    let mut gpu_modes = modes.clone();
    gpu_modes.push(Shading::Flat);
    memory.check(&name, &scene, &gpu_modes, cpu_modes)?;
    let context = GpuContext::new(options)?;
    // Multisampled images are resolved in 16 bits for a PNG
    // (`ColorTarget::drawn_with`).
    let raster_target = args.target.color_target().drawn_with(scene.render.msaa);
    let target_of = |shading: Shading| match shading.raster_mode() {
        Some(_) => raster_target,
        None => ColorTarget::Float32,
    };
    let time = |shading: Shading, every_feature: bool| -> Result<(f64, f64, f64), Failure> {
        let target = target_of(shading);
        once(&context, &scene, shading, every_feature, target)?; // warm-up
        let mut totals = Vec::new();
        let mut gpus = Vec::new();
        for _ in 0..args.runs {
            let t = once(&context, &scene, shading, every_feature, target)?;
            totals.push(t.total_ms);
            // Submission to completion: robust where timestamps are not
            // (see GpuTimings::submit_ms).
            gpus.push(t.submit_ms);
        }
        let (total, spread) = median_and_spread(totals);
        Ok((total, median_and_spread(gpus).0, spread))
    };
    // Flat is the baseline; timed once, and reused if it is in the list.
    let flat = time(Shading::Flat, false)?;
    let baseline = flat.0;
    let mut rows = Vec::new();
    for &shading in &modes {
        let traced = shading.raster_mode().is_none();
        let (total_ms, gpu_ms, total_spread_ms) = if shading == Shading::Flat {
            flat
        } else {
            time(shading, false)?
        };
        // Rays are counted in a separate run: counting costs atomics.
        let (rays, traversal) = if traced {
            let counted = raytrace::render(&context, &scene, true)?;
            (
                counted.stats.map(|s| s.total()),
                Some(counted.traversal.name()),
            )
        } else {
            (None, None)
        };
        let cpu_ms = if args.cpu {
            let runs = (0..args.runs)
                .map(|_| cpu_once(&scene, shading))
                .collect::<Result<Vec<_>, _>>()?;
            Some(median_and_spread(runs).0)
        } else {
            None
        };
        let every_feature_gpu_ms = if args.every_feature && traced {
            Some(time(shading, true)?.1)
        } else {
            None
        };
        let time_to_image = if args.time_to_image {
            let (render_args, gpu_args) = args.render_args();
            Some(time_to_image::measure(
                &render_args,
                &gpu_args,
                shading,
                args.runs,
            )?)
        } else {
            None
        };
        rows.push(Row {
            shading,
            color_target: target_of(shading).name(),
            traversal,
            total_ms,
            gpu_ms,
            total_spread_ms,
            ratio_to_baseline: total_ms / baseline,
            rays,
            rays_per_second: rays.map(|r| r as f64 / (gpu_ms / 1e3)),
            cpu_ms,
            gpu_speedup_over_cpu: cpu_ms.map(|c| c / gpu_ms),
            every_feature_gpu_ms,
            every_feature_ratio: every_feature_gpu_ms.map(|e| e / gpu_ms),
            time_to_image,
        });
    }
    let (w, h) = (scene.image.width, scene.image.height);
    let info = &context.info;
    if args.json {
        let value = serde_json::json!({
            "scene": name,
            "width": w,
            "height": h,
            "device": info.name,
            "driver": info.driver,
            "runs": args.runs,
            "baseline": { "shading": "flat", "total_ms": baseline },
            "raster_target": raster_target.name(),
            "msaa": scene.render.msaa.to_string(),
            "lighting": hook_path,
            "results": rows,
        });
        println!("{value}");
        return Ok(());
    }
    println!(
        "{name} at {w}x{h} on {} ({}), median of {} runs after a warm-up; baseline: flat raster, {baseline:.1} ms",
        info.name, info.driver, args.runs
    );
    let msaa = scene.render.msaa;
    let samples = if msaa.is_multisampled() {
        format!(" at --msaa {msaa}, resolved")
    } else {
        String::new()
    };
    println!(
        "raster modes timed{samples} into the {} target (the path of render --out x.{}); the ray tracer writes rgba32f",
        raster_target.name(),
        if args.target.color_target() == ColorTarget::Srgb8 {
            "png"
        } else {
            "exr"
        }
    );
    if let Some(path) = &hook_path {
        println!("lighting hook: {path} (the GPU modes; --cpu times the built-in formula)");
    }
    if args.time_to_image {
        println!(
            "image_*: the whole `render` command in a fresh process (ms): caches filled (warm), empty caches (cold), the CPU twin's (--backend cpu)"
        );
    }
    if let Some(engine) = rows.iter().find_map(|r| r.traversal) {
        println!("ray tracer's traversal: {engine}");
    }
    let mut header = format!(
        "{:<10} {:>10} {:>10} {:>10} {:>8} {:>10}",
        "mode", "total_ms", "gpu_ms", "spread_ms", "ratio", "Mrays/s"
    );
    if args.cpu {
        header += &format!(" {:>10} {:>8}", "cpu_ms", "gpu_x");
    }
    if args.every_feature {
        header += &format!(" {:>12} {:>8}", "uber_gpu_ms", "uber_x");
    }
    if args.time_to_image {
        header += &format!(
            " {:>10} {:>10} {:>10}",
            "image_warm", "image_cold", "image_cpu"
        );
    }
    println!("{header}");
    let figure = |v: Option<f64>, width: usize, digits: usize| match v {
        Some(v) => format!("{v:>width$.digits$}"),
        None => format!("{:>width$}", "-"),
    };
    for r in &rows {
        let mut line = format!(
            "{:<10} {:>10.1} {:>10.1} {:>10.1} {:>8.2} {}",
            r.shading.to_string(),
            r.total_ms,
            r.gpu_ms,
            r.total_spread_ms,
            r.ratio_to_baseline,
            figure(r.rays_per_second.map(|v| v / 1e6), 10, 2)
        );
        if args.cpu {
            line += &format!(
                " {} {}",
                figure(r.cpu_ms, 10, 1),
                figure(r.gpu_speedup_over_cpu, 8, 2)
            );
        }
        if args.every_feature {
            line += &format!(
                " {} {}",
                figure(r.every_feature_gpu_ms, 12, 1),
                figure(r.every_feature_ratio, 8, 2)
            );
        }
        if let Some(t) = &r.time_to_image {
            line += &format!(
                " {:>10.1} {:>10.1} {:>10.1}",
                t.warm_ms, t.cold_ms, t.cpu_ms
            );
        }
        println!("{line}");
    }
    Ok(())
}
