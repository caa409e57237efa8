//! `shadelab render`: one scene, one mode, one image file; more scenes or
//! modes, or `--out-dir`, make a batch (`render_batch.rs`).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use clap::Args;
use shadelab::backend_choice::{self, Backend, Choice};
use shadelab::gpu::raster::ColorTarget;
use shadelab::gpu::{ms_since, GpuContext, GpuError, GpuOptions};
use shadelab::memory::MemoryLimit;
use shadelab::render::Timings;
use shadelab::rt_scene::RayStats;
use shadelab::scene::{self, Scene};
use shadelab::shading::Shading;

use super::args::{ImageSize, SceneFlags};
use super::ignored::{self, Backends};
use super::Failure;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene files (.toml, .gltf or .glb); the built-in default scene if
    /// left out. More than one makes a batch (see --out-dir).
    #[arg(value_name = "SCENE")]
    pub(super) scenes: Vec<PathBuf>,
    /// Shading mode, or modes comma-separated (a batch: each scene in each).
    #[arg(long, value_delimiter = ',', default_value = "phong")]
    pub(super) shading: Vec<Shading>,
    /// Renderer: the Vulkan pipelines (gpu), the CPU reference (cpu), or
    /// whichever should give the image first (auto: a short CPU pilot set
    /// against the GPU's fixed costs; the choice is printed).
    #[arg(long, default_value = "gpu", value_parser = ["gpu", "cpu", "auto"])]
    pub(super) backend: String,
    #[command(flatten)]
    pub(super) size: ImageSize,
    #[command(flatten)]
    pub(super) settings: SceneFlags,
    /// Ray tracing: adaptive depth cut-off on the ray weight.
    #[arg(long)]
    pub(super) cutoff: Option<f64>,
    /// Ray tracing: samples per pixel.
    #[arg(long)]
    pub(super) samples: Option<u32>,
    /// Ray tracing: no shadow rays.
    #[arg(long)]
    pub(super) no_shadows: bool,
    /// Output image: .png (8-bit sRGB) or .exr (linear 32-bit float).
    /// Default: <scene name>-<mode>.png in the current folder.
    #[arg(long, short)]
    pub(super) out: Option<PathBuf>,
    /// A batch: the folder the images go into, named by --name (created if
    /// missing). Implied (the current folder) by more than one scene or mode.
    #[arg(long, value_name = "DIR")]
    pub(super) out_dir: Option<PathBuf>,
    /// A batch: each image's file name, from {scene} (the scene file's
    /// name without its extension) and {mode}; .png or .exr [default:
    /// {scene}-{mode}.png]. Makes a batch of even one image.
    #[arg(long, value_name = "PATTERN")]
    pub(super) name: Option<String>,
    /// Print one JSON object describing the render on stdout (a batch: one
    /// object with a case per image).
    #[arg(long)]
    pub(super) json: bool,
    /// Ray tracing: print the rays traced, by kind (a table, or "stats" in
    /// the --json object).
    #[arg(long)]
    pub(super) stats: bool,
    #[command(flatten)]
    pub machine: super::args::MachineArgs,
    /// A batch: each scene's `{scene}` in file names, given by the caller
    /// (`golden`'s keys), in place of the file's stem made unique.
    #[arg(skip)]
    pub(super) scene_names: Option<Vec<String>>,
    /// A batch: only the cases of shard I of N (`golden --shard`), dealt
    /// out by `{scene}/{mode}`.
    #[arg(skip)]
    pub(super) shard: Option<(usize, usize)>,
}

/// Loads `path` (the default scene when `None`), refusing a glTF file whose
/// geometry alone would exceed `memory`, and returns it with its name.
pub fn load_scene(path: Option<&Path>, memory: &MemoryLimit) -> Result<(Scene, String), Failure> {
    match path {
        None => Ok((scene::default_scene(), "default".to_string())),
        Some(p) => {
            let scene = scene::load_within(p, &memory.load_limits())?;
            let stem = p
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scene".into());
            Ok((scene, stem))
        }
    }
}

impl RenderArgs {
    /// The modes asked for, each once, in the order first given.
    pub(super) fn modes(&self) -> Vec<Shading> {
        let mut modes = Vec::new();
        for &shading in &self.shading {
            if !modes.contains(&shading) {
                modes.push(shading);
            }
        }
        modes
    }

    /// More than one image, `--out-dir` or `--name`: a batch.
    fn is_batch(&self) -> bool {
        self.scenes.len() > 1
            || self.modes().len() > 1
            || self.out_dir.is_some()
            || self.name.is_some()
    }

    /// The batch's file name pattern.
    pub(super) fn name_pattern(&self) -> &str {
        self.name.as_deref().unwrap_or("{scene}-{mode}.png")
    }
}

/// Applies the command-line overrides to the scene, checking their ranges as
/// the scene loader checks the file's; warns once (`warn`) of ray-tracing
/// flags that no mode in `modes` uses.
pub(super) fn apply_overrides(
    scene: &mut Scene,
    args: &RenderArgs,
    modes: &[Shading],
    warn: bool,
) -> Result<(), Failure> {
    args.size.apply(scene)?;
    if args.settings.lighting.lighting.is_some() && args.backend == "cpu" {
        return Err(Failure::usage(
            "--lighting is for the GPU backend; the CPU reference always evaluates the built-in formula".to_string(),
        ));
    }
    args.settings.apply(scene)?;
    if let Some(c) = args.cutoff {
        if !c.is_finite() || c < 0.0 {
            return Err(Failure::usage(format!(
                "--cutoff {c} is invalid; expected a number >= 0"
            )));
        }
        scene.render.cutoff = c;
    }
    if let Some(s) = args.samples {
        if s == 0 || s > 1024 {
            return Err(Failure::usage(format!(
                "--samples {s} is out of range; expected 1 to 1024"
            )));
        }
        scene.render.samples = s;
    }
    if args.no_shadows {
        scene.render.shadows = false;
    }
    // Said once the flags are known to be valid: a bad one is the answer.
    if warn {
        let backends = match args.backend.as_str() {
            "cpu" => Backends::Cpu,
            "auto" => Backends::Both,
            _ => Backends::Gpu,
        };
        ignored::warn(&options_given(args), modes, backends);
    }
    Ok(())
}

/// What the image was made with, overrides applied: `--json`'s
/// `settings` and the PNG's `shadelab:settings` text. The ray tracer's
/// settings only where it ran.
pub(super) fn effective_settings(
    scene_path: Option<&Path>,
    shading: Shading,
    scene: &Scene,
    backend: Backend,
    rendered: &shadelab::render::Rendered,
    device: &str,
    driver: Option<&str>,
) -> serde_json::Value {
    let ray_traced = shading == Shading::Raytrace;
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
        "depth": ray_traced.then_some(r.depth),
        "samples": ray_traced.then_some(r.samples),
        "shadows": ray_traced.then_some(r.shadows),
        "cutoff": ray_traced.then_some(r.cutoff),
        "traversal": rendered.traversal.map(|t| t.name()),
        "msaa": (!ray_traced).then(|| r.msaa.to_string()),
        "lighting": scene.lighting_hook.as_ref().map(|h| h.path.clone()),
        "device": device,
        "driver": driver,
        "shadelab": env!("CARGO_PKG_VERSION"),
    })
}

/// The raster modes' colour target for an output `format`.
pub(super) fn color_target(scene: &Scene, format: shadelab::output::ImageFormat) -> ColorTarget {
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
pub(super) fn image_metadata(
    stem: &str,
    device: &str,
    settings: &serde_json::Value,
) -> shadelab::output::ImageMetadata {
    shadelab::output::ImageMetadata::software()
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

/// The options on the command line that a mode or a backend may ignore,
/// by flag: those every command shares and render's own.
fn options_given(args: &RenderArgs) -> Vec<&'static str> {
    let s = &args.settings;
    let mut given = ignored::scene_flags_given(&s.traversal, &s.msaa, s.depth.depth);
    for (flag, present) in [
        ("--cutoff", args.cutoff.is_some()),
        ("--samples", args.samples.is_some()),
        ("--no-shadows", args.no_shadows),
    ] {
        if present {
            given.push(flag);
        }
    }
    given
}

/// The GPU opened on a thread of its own while the scene loads (on a
/// 2-core machine the two overlap): `ms` is how long the opening took.
struct OpeningDevice {
    thread: std::thread::JoinHandle<(Result<Arc<GpuContext>, GpuError>, f64)>,
}

impl OpeningDevice {
    fn start(options: &GpuOptions) -> Self {
        let options = options.clone();
        let thread = std::thread::spawn(move || {
            let started = Instant::now();
            let context = GpuContext::new(&options);
            (context, ms_since(started))
        });
        Self { thread }
    }

    /// The device and the time it took to open.
    fn finish(self) -> (Result<Arc<GpuContext>, GpuError>, f64) {
        self.thread
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    }
}

/// `--out`, or `<scene name>-<mode>.png` in the current folder.
fn output_path(args: &RenderArgs, stem: &str, shading: Shading) -> PathBuf {
    args.out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{stem}-{shading}.png")))
}

/// A scene ready to render: overrides applied, the backend chosen, the
/// memory estimate held to the limit.
struct Loaded {
    scene: Scene,
    stem: String,
    estimate: u64,
    backend: Backend,
    /// `--backend auto`'s choice and its grounds.
    choice: Option<Choice>,
}

/// The scene with the overrides applied, its name, the backend (chosen
/// here for `auto`) and the memory estimate held to the limit; the output's
/// name checked too, all before any rendering work.
fn load_and_check(
    args: &RenderArgs,
    path: Option<&Path>,
    shading: Shading,
    memory: &MemoryLimit,
) -> Result<Loaded, Failure> {
    let (mut scene, stem) = load_scene(path, memory)?;
    apply_overrides(&mut scene, args, &[shading], true)?;
    // The output's name and folder, before any rendering: its folder is
    // created, and a folder that cannot be written fails now, not after
    // the render.
    let out = output_path(args, &stem, shading);
    shadelab::output::ImageFormat::from_path(&out)?;
    shadelab::output::prepare_output_path(&out)?;
    let choice = (args.backend == "auto").then(|| backend_choice::choose(&scene, shading));
    let backend = match (&choice, args.backend.as_str()) {
        (Some(choice), _) => choice.backend,
        (None, "cpu") => Backend::Cpu,
        (None, _) => Backend::Gpu,
    };
    let estimate = match backend {
        Backend::Cpu => memory.check(&stem, &scene, &[], &[shading])?,
        Backend::Gpu => memory.check(&stem, &scene, &[shading], &[])?,
    };
    Ok(Loaded {
        scene,
        stem,
        estimate,
        backend,
        choice,
    })
}

pub fn run(args: RenderArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    if args.is_batch() {
        return super::render_batch::run(&args, options, memory);
    }
    let command_started = Instant::now();
    let path = args.scenes.first().map(PathBuf::as_path);
    let shading = args.modes()[0];
    // `auto` chooses once the scene is loaded; `gpu` opens the device
    // meanwhile.
    let opening = (args.backend == "gpu").then(|| OpeningDevice::start(options));
    let loaded = load_and_check(&args, path, shading, memory);
    let Loaded {
        scene,
        stem,
        mut estimate,
        mut backend,
        mut choice,
    } = match loaded {
        Ok(loaded) => loaded,
        Err(failure) => {
            // The scene's error is the answer; the device is closed before
            // the process exits (not while its driver is still loading).
            if let Some(opening) = opening {
                drop(opening.finish());
            }
            return Err(failure);
        }
    };
    let scene_ms = ms_since(command_started);
    for warning in &scene.warnings {
        eprintln!("shadelab: warning: {warning}");
    }
    let out = output_path(&args, &stem, shading);
    let format = shadelab::output::ImageFormat::from_path(&out)?;
    let target = color_target(&scene, format);
    let mut device_ms = None;
    let mut context = None;
    if backend == Backend::Gpu {
        let opening = opening.unwrap_or_else(|| OpeningDevice::start(options));
        let (opened, opened_ms) = opening.finish();
        device_ms = Some(opened_ms);
        match opened {
            Ok(opened) => context = Some(opened),
            // `auto` renders on the CPU where there is no GPU to open, and
            // says so, unless only the GPU can render it; `gpu` fails.
            Err(e) if choice.as_ref().is_some_and(|c| !c.needs_gpu) => {
                eprintln!("shadelab: warning: --backend auto: no GPU ({e}); rendering on the CPU reference");
                backend = Backend::Cpu;
                estimate = memory.check(&stem, &scene, &[], &[shading])?;
                if let Some(choice) = &mut choice {
                    choice.backend = Backend::Cpu;
                    choice.why = format!("no GPU to open ({e})");
                }
            }
            Err(e) => return Err(e.into()),
        }
    }
    if let Some(choice) = &choice {
        if !args.json {
            println!("backend auto: {}: {}", backend.name(), choice.why);
        }
    }
    let (rendered, device, driver) = if let Some(context) = context {
        let rendered =
            shadelab::render::render_gpu_to(&context, &scene, shading, args.stats, target)?;
        let info = &context.info;
        (rendered, info.name.clone(), Some(info.driver.clone()))
    } else {
        let label = format!("{shading} on the CPU reference");
        let (rendered, _) = super::progress::counted(&label, |counter| {
            shadelab::render::render_cpu_counted(&scene, shading, counter)
        })?;
        (rendered, "CPU reference (f64)".to_string(), None)
    };
    let settings = effective_settings(
        path,
        shading,
        &scene,
        backend,
        &rendered,
        &device,
        driver.as_deref(),
    );
    let metadata = image_metadata(&stem, &device, &settings);
    let encode_started = Instant::now();
    shadelab::output::write_image_with(&rendered.image, &out, &metadata)?;
    let non_finite = rendered.image.non_finite_pixels();
    let t = &rendered.timings;
    let phases = serde_json::json!({
        "scene_ms": scene_ms,
        "device_ms": device_ms,
        "prepare_ms": t.prepare_ms,
        "pipeline_ms": t.pipeline_ms,
        "upload_ms": t.upload_ms,
        "codegen_ms": t.codegen_ms,
        "render_ms": t.work_ms(),
        "readback_ms": t.readback_ms,
        "encode_ms": ms_since(encode_started),
        "wall_ms": ms_since(command_started),
    });
    if args.json {
        let value = serde_json::json!({
            "output": out,
            "shading": shading,
            "backend": backend.name(),
            "backend_choice": choice,
            "width": rendered.image.width,
            "height": rendered.image.height,
            "device": device,
            "driver": driver,
            "color_target": (backend == Backend::Gpu && shading.raster_mode().is_some())
                .then(|| target.name()),
            "traversal": rendered.traversal.map(|t| t.name()),
            "timings_ms": rendered.timings,
            "phases_ms": phases,
            "non_finite_pixels": non_finite,
            "settings": settings,
            "memory": {
                "estimate_bytes": estimate,
                "peak_bytes": shadelab::memory::peak_resident_bytes(),
                "limit_bytes": memory.bytes,
            },
        });
        let mut value = value;
        if args.stats {
            value["stats"] =
                serde_json::to_value(rendered.ray_stats).expect("ray statistics serialise to JSON");
        }
        println!("{value}");
    } else {
        let engine = rendered
            .traversal
            .map(|t| format!(", traversal {}", t.name()))
            .unwrap_or_default();
        println!(
            "wrote {} ({}x{}, {}{engine}, {:.1} ms on {})",
            out.display(),
            rendered.image.width,
            rendered.image.height,
            shading,
            rendered.timings.total_ms,
            device
        );
        if args.stats {
            print_stats(rendered.ray_stats.as_ref(), &rendered.timings, shading);
        }
    }
    if non_finite > 0 {
        // The image is written, to see where; the run is not a success.
        let hint = if scene.lighting_hook.is_some() {
            " (the lighting hook returned them)"
        } else {
            ""
        };
        return Err(Failure {
            code: 1,
            message: format!(
                "{non_finite} of {} pixels are not finite (NaN or infinity){hint}; {} holds them as {}",
                rendered.image.pixels.len(),
                out.display(),
                if format == shadelab::output::ImageFormat::Exr {
                    "they are"
                } else {
                    "0 or 1 (PNG cannot hold them)"
                }
            ),
        });
    }
    Ok(())
}

/// The ray statistics as a two-column table (`docs/raytracing.md`,
/// "Counting"). A raster render has none.
pub(super) fn print_stats(stats: Option<&RayStats>, timings: &Timings, shading: Shading) {
    let Some(s) = stats else {
        println!("stats: none ({shading} casts no rays)");
        return;
    };
    if let Some(gpu) = timings.gpu_ms {
        println!("{:<18} {:>12.1}", "gpu_ms (timestamps)", gpu);
    }
    let work = timings.work_ms();
    println!("{:<18} {:>12.1}", "work_ms", work);
    println!(
        "{:<18} {:>12.0}",
        "rays_per_second",
        s.total() as f64 / (work / 1e3)
    );
    let rows = [
        ("primary", s.primary),
        ("shadow", s.shadow),
        ("reflected", s.reflected),
        ("refracted", s.refracted),
        ("total", s.total()),
        ("pruned", s.pruned),
        ("max_depth_reached", u64::from(s.max_depth_reached)),
    ];
    for (name, value) in rows {
        println!("{name:<18} {value:>12}");
    }
}
