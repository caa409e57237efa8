//! `shadelab bench`: render times per mode, medians over several runs after
//! a warm-up, as ratios against a baseline measured in the same run (the
//! flat raster render of the same scene), and rays per second for the ray
//! tracer. With `--cpu`, the CPU reference's time for the same work beside
//! each mode; with `--every-feature`, the ray tracer compiled with every
//! optional feature in, against the one specialised to the scene. Shared
//! machines are noisy: compare ratios, not milliseconds.

mod time_to_image;
mod timing;

use std::ffi::OsString;
use std::path::PathBuf;

use clap::Args;
use shadelab::gpu::raster::ColorTarget;
use shadelab::gpu::{DeviceInfo, GpuOptions};
use shadelab::memory::MemoryLimit;
use shadelab::render::Device;
use shadelab::scene::Scene;
use shadelab::shading::Shading;

use crate::cli::common::args::{check_runs, ImageSize, ModeList, SceneFlags};
use crate::cli::common::batch::scene::load_scene;
use crate::cli::common::failure::Failure;
use crate::cli::common::ignored;
use timing::{measure, Row, Timing};

#[derive(Args)]
pub struct BenchArgs {
    /// Scene file; the built-in default scene if left out.
    scene: Option<PathBuf>,
    #[command(flatten)]
    modes: ModeList,
    /// Timed runs per mode (after one warm-up run).
    #[arg(long, default_value_t = 5)]
    runs: i64,
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
    pub machine: crate::cli::common::args::MachineArgs,
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
        flag(
            "--bounces",
            self.settings.depth.bounces.map(|v| v.to_string()),
        );
        flag(
            "--photons",
            self.settings.depth.photons.map(|v| v.to_string()),
        );
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

pub fn run(args: BenchArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    let runs = check_runs(args.runs)?;
    let modes = args.modes.modes();
    let (mut scene, name) = load(&args, &modes, memory)?;
    // `bench` times each mode's renderer, and its CPU twin's figure is the
    // backward tracer's alone: a scene's photon-map caustics (a pass of
    // their own, seconds on the GPU) are left out on both sides.
    scene.render.caustics.passes = 0;
    let device = Device::open(options)?;
    let context = device.require_gpu()?;
    // Multisampled images are resolved in 16 bits for a PNG
    // (`ColorTarget::drawn_with`).
    let raster_target = args.target.color_target().drawn_with(scene.render.msaa);
    let timing = Timing {
        device: &device,
        scene: &scene,
        runs,
        raster_target,
        cpu: args.cpu,
        every_feature: args.every_feature,
        time_to_image: args.time_to_image.then(|| args.render_args()),
    };
    let (baseline, rows) = measure(&timing, &modes)?;
    let bench = Bench {
        name: &name,
        scene: &scene,
        info: &context.info,
        baseline,
        raster_target,
        rows,
    };
    if args.json {
        print_json(&args, &bench);
    } else {
        print_table(&args, &bench);
    }
    Ok(())
}

/// The scene with the flags applied, and its name; refused where its
/// renders would not fit the memory limit.
fn load(
    args: &BenchArgs,
    modes: &[Shading],
    memory: &MemoryLimit,
) -> Result<(Scene, String), Failure> {
    let s = &args.settings;
    let mut given = ignored::scene_flags_given(&s.traversal, &s.msaa, &s.depth);
    if args.cpu {
        given.push("--cpu");
    }
    let (mut scene, name) = load_scene(args.scene.as_deref(), memory)?;
    args.size.apply(&mut scene)?;
    args.settings.apply(&mut scene)?;
    // Said once the flags are known to be valid: a bad one is the answer.
    let ignoring = ignored::Run {
        modes,
        backends: ignored::Backends::Gpu,
        caustics: scene.render.caustics.on(),
    };
    ignored::warn(&given, ignoring);
    let twins = [Shading::Raytrace, Shading::Forward];
    let cpu_modes: &[Shading] = if args.cpu { &twins } else { &[] };
    let mut gpu_modes = modes.to_vec();
    gpu_modes.push(Shading::Flat);
    memory.check(&name, &scene, &gpu_modes, cpu_modes)?;
    Ok((scene, name))
}

/// What was measured, for the report.
struct Bench<'a> {
    name: &'a str,
    scene: &'a Scene,
    info: &'a DeviceInfo,
    /// The flat raster render's median total time.
    baseline: f64,
    raster_target: ColorTarget,
    rows: Vec<Row>,
}

impl Bench<'_> {
    fn hook_path(&self) -> Option<String> {
        self.scene.lighting_hook.as_ref().map(|h| h.path.clone())
    }
}

/// `--json`: one object on stdout.
fn print_json(args: &BenchArgs, b: &Bench) {
    let value = serde_json::json!({
        "scene": b.name,
        "width": b.scene.image.width,
        "height": b.scene.image.height,
        "device": b.info.name,
        "driver": b.info.driver,
        "runs": args.runs,
        "baseline": { "shading": "flat", "total_ms": b.baseline },
        "raster_target": b.raster_target.name(),
        "msaa": b.scene.render.msaa.to_string(),
        "lighting": b.hook_path(),
        "results": b.rows,
    });
    println!("{value}");
}

/// What was timed, in a few lines, then a table with a row per mode.
fn print_table(args: &BenchArgs, b: &Bench) {
    print_preamble(args, b);
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
    for r in &b.rows {
        println!("{}", table_line(args, r));
    }
}

/// The lines above the table: the scene, device and baseline, the target
/// timed, and what the flags change.
fn print_preamble(args: &BenchArgs, b: &Bench) {
    let (name, w, h, info, baseline) = (
        b.name,
        b.scene.image.width,
        b.scene.image.height,
        b.info,
        b.baseline,
    );
    println!(
        "{name} at {w}x{h} on {} ({}), median of {} runs after a warm-up; baseline: flat raster, {baseline:.1} ms",
        info.name, info.driver, args.runs
    );
    let msaa = b.scene.render.msaa;
    let samples = if msaa.is_multisampled() {
        format!(" at --msaa {msaa}, resolved")
    } else {
        String::new()
    };
    println!(
        "raster modes timed{samples} into the {} target (the path of render --out x.{}); the ray tracer writes rgba32f",
        b.raster_target.name(),
        if args.target.color_target() == ColorTarget::Srgb8 {
            "png"
        } else {
            "exr"
        }
    );
    if let Some(path) = &b.hook_path() {
        println!("lighting hook: {path} (the GPU modes; --cpu times the built-in formula)");
    }
    if args.time_to_image {
        println!(
            "image_*: the whole `render` command in a fresh process (ms): caches filled (warm), empty caches (cold), the CPU twin's (--backend cpu)"
        );
    }
    if let Some(engine) = b.rows.iter().find_map(|r| r.traversal) {
        println!("ray tracer's traversal: {engine}");
    }
}

/// A mode's row of the table; a figure not measured is `-`.
fn table_line(args: &BenchArgs, r: &Row) -> String {
    let figure = |v: Option<f64>, width: usize, digits: usize| match v {
        Some(v) => format!("{v:>width$.digits$}"),
        None => format!("{:>width$}", "-"),
    };
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
    line
}
