//! `shadelab render` of one scene in one mode into one image file: the
//! device opened while the scene loads, then render, write, report. More
//! scenes or modes, `--out-dir` or `--name` make a batch (`out_dir.rs`).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use shadelab::backend_choice::{self, Backend, Choice};
use shadelab::gpu::raster::ColorTarget;
use shadelab::gpu::{ms_since, GpuContext, GpuError, GpuOptions};
use shadelab::memory::MemoryLimit;
use shadelab::output::ImageFormat;
use shadelab::render::{Device, FilmRender, Plan, RenderRequest, Rendered, Technique, Timings};
use shadelab::scene::Scene;
use shadelab::shading::Shading;

use super::stats::{print_photons, print_stats};
use crate::cli::common::batch::args::RenderArgs;
use crate::cli::common::batch::scene::{apply_overrides, load_scene};
use crate::cli::common::failure::Failure;
use shadelab::render::described::{color_target, effective_settings, image_metadata};

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
    ImageFormat::from_path(&out)?;
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

/// One image: the scene loaded while the device opens, then render, write
/// and report; a batch handed to `out_dir.rs`.
pub fn run(args: RenderArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    if !args.merge.is_empty() {
        return super::shard::run_merge(&args);
    }
    if let Some(shard) = args.render_shard {
        return super::shard::run_shard(&args, shard, options, memory);
    }
    if args.is_batch() {
        return super::out_dir::run(&args, options, memory);
    }
    let command_started = Instant::now();
    let path = args.scenes.first().map(PathBuf::as_path);
    let shading = args.modes()[0];
    // `auto` chooses once the scene is loaded; `gpu` opens the device
    // meanwhile.
    let opening = (args.backend == "gpu").then(|| OpeningDevice::start(options));
    let mut loaded = match load_and_check(&args, path, shading, memory) {
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
    for warning in &loaded.scene.warnings {
        eprintln!("shadelab: warning: {warning}");
    }

    let out = output_path(&args, &loaded.stem, shading);
    let format = ImageFormat::from_path(&out)?;
    let target = color_target(&loaded.scene, format);
    let (context, device_ms) = open_device(&mut loaded, opening, options, shading, memory)?;
    if let Some(choice) = &loaded.choice {
        if !args.json {
            println!("backend auto: {}: {}", loaded.backend.name(), choice.why);
        }
    }
    let (rendered, device, driver) = render(&args, &loaded, shading, context, target)?;
    let settings = effective_settings(
        path,
        shading,
        &loaded.scene,
        loaded.backend,
        &rendered,
        &device,
        driver.as_deref(),
    );
    let metadata = image_metadata(&loaded.stem, &device, &settings);
    let encode_started = Instant::now();
    shadelab::output::write_image_with(&rendered.image, &out, &metadata)?;
    let image = Written {
        non_finite: rendered.image.non_finite_pixels(),
        out,
        format,
        target,
        rendered,
        device,
        driver,
        settings,
    };
    let phases = phases(
        &image.rendered.timings,
        scene_ms,
        device_ms,
        encode_started,
        command_started,
    );
    if args.json {
        print_json(&args, &loaded, shading, &image, phases, memory);
    } else {
        print_line(&args, shading, &image);
    }
    refuse_non_finite(&loaded.scene, &image)
}

/// Opens the device for a GPU render (or waits for the one opening):
/// `auto` falls back to the CPU reference where there is no GPU, unless
/// only the GPU can render the scene. The device, and how long opening it
/// took.
fn open_device(
    loaded: &mut Loaded,
    opening: Option<OpeningDevice>,
    options: &GpuOptions,
    shading: Shading,
    memory: &MemoryLimit,
) -> Result<(Option<Arc<GpuContext>>, Option<f64>), Failure> {
    if loaded.backend != Backend::Gpu {
        return Ok((None, None));
    }
    let opening = opening.unwrap_or_else(|| OpeningDevice::start(options));
    let (opened, opened_ms) = opening.finish();
    match opened {
        Ok(opened) => return Ok((Some(opened), Some(opened_ms))),
        // `auto` renders on the CPU where there is no GPU to open, and
        // says so, unless only the GPU can render it; `gpu` fails.
        Err(e) if loaded.choice.as_ref().is_some_and(|c| !c.needs_gpu) => {
            eprintln!(
                "shadelab: warning: --backend auto: no GPU ({e}); rendering on the CPU reference"
            );
            loaded.backend = Backend::Cpu;
            loaded.estimate = memory.check(&loaded.stem, &loaded.scene, &[], &[shading])?;
            if let Some(choice) = &mut loaded.choice {
                choice.backend = Backend::Cpu;
                choice.why = format!("no GPU to open ({e})");
            }
        }
        Err(e) => return Err(e.into()),
    }
    Ok((None, Some(opened_ms)))
}

/// Renders on the device where there is one, else on the CPU reference,
/// with a progress line (in photons or samples for a render that sums
/// into a film, which `--time` and `--error` stop and which says what it
/// traced); the image, the device's name and its driver.
fn render(
    args: &RenderArgs,
    loaded: &Loaded,
    shading: Shading,
    context: Option<Arc<GpuContext>>,
    target: ColorTarget,
) -> Result<(Rendered, String, Option<String>), Failure> {
    let scene = &loaded.scene;
    let backend = if context.is_some() {
        Backend::Gpu
    } else {
        Backend::Cpu
    };
    let on = match backend {
        Backend::Gpu => "GPU",
        Backend::Cpu => "CPU reference",
    };
    let device = Device::from(context.clone());
    // Progress where there is some to show: the CPU reference's, and a
    // film's photons or samples (a GPU image in one dispatch has none).
    let counts = backend == Backend::Cpu || Technique::of(scene, shading).sums_in_film();
    let label = format!("{shading} on the {on}");
    let rendered = crate::cli::common::progress::counted(&label, |counter| {
        let request = RenderRequest {
            target,
            count_rays: args.stats,
            deadline: args.deadline(),
            error: args.error_budget,
            progress: counts.then_some(counter),
            ..RenderRequest::new(shading, backend)
        };
        let plan = Plan::new(scene, &request)?;
        for warning in &plan.warnings {
            eprintln!("shadelab: warning: {warning}");
        }
        let rendered = plan.render(&device, scene)?;
        if let Some(film) = &rendered.film {
            say_budget(args, plan.technique, film, plan.part.count());
        }
        Ok::<_, shadelab::error::Error>(rendered)
    })?;
    Ok(match &context {
        Some(c) => (rendered, c.info.name.clone(), Some(c.info.driver.clone())),
        None => (rendered, "CPU reference (f64)".to_string(), None),
    })
}

/// What a budget did: where it stopped the render, with the estimate of
/// the error where there was an error budget, or that the error budget
/// was not reached.
fn say_budget(args: &RenderArgs, technique: Technique, film: &FilmRender, asked: u32) {
    let what = technique.work_unit();
    let traced = film.traced;
    let estimate = film
        .estimated_rmse
        .map(|e| format!(" (estimated RMSE {e:.3e})"))
        .unwrap_or_default();
    match (args.error_budget, args.time) {
        (Some(target), _) if film.estimated_rmse.is_some_and(|e| e <= target) => eprintln!(
            "shadelab: --error {target}: reached after {traced} of {asked} {what}{estimate}; the image is their estimate"
        ),
        (Some(target), _) => eprintln!(
            "shadelab: warning: --error {target}: not reached after {traced} of {asked} {what}{estimate}; give more {what}, or a looser budget"
        ),
        (None, Some(time)) if traced < u64::from(asked) => eprintln!(
            "shadelab: --time {time}: stopped after {traced} of {asked} {what}; the image is their estimate"
        ),
        _ => {}
    }
}

/// The image written, and what it was made with.
struct Written {
    out: PathBuf,
    format: ImageFormat,
    target: ColorTarget,
    rendered: Rendered,
    device: String,
    driver: Option<String>,
    settings: serde_json::Value,
    /// The pixels that are not finite (NaN or infinity).
    non_finite: usize,
}

/// The command's time by phase, for `--json`: the encoding and the whole
/// command measured up to now.
fn phases(
    t: &Timings,
    scene_ms: f64,
    device_ms: Option<f64>,
    encode_started: Instant,
    command_started: Instant,
) -> serde_json::Value {
    serde_json::json!({
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
    })
}

/// `--json`: the render described in one object.
fn print_json(
    args: &RenderArgs,
    loaded: &Loaded,
    shading: Shading,
    image: &Written,
    phases: serde_json::Value,
    memory: &MemoryLimit,
) {
    let rendered = &image.rendered;
    let backend = loaded.backend;
    let value = serde_json::json!({
        "output": image.out,
        "shading": shading,
        "backend": backend.name(),
        "backend_choice": loaded.choice,
        "width": rendered.image.width,
        "height": rendered.image.height,
        "device": image.device,
        "driver": image.driver,
        "color_target": (backend == Backend::Gpu && shading.raster_mode().is_some())
            .then(|| image.target.name()),
        "traversal": rendered.traversal.map(|t| t.name()),
        "timings_ms": rendered.timings,
        "phases_ms": phases,
        "non_finite_pixels": image.non_finite,
        "settings": image.settings,
        "memory": {
            "estimate_bytes": loaded.estimate,
            "peak_bytes": shadelab::memory::peak_resident_bytes(),
            "limit_bytes": memory.bytes,
        },
    });
    let mut value = value;
    if args.stats {
        value["stats"] =
            serde_json::to_value(rendered.ray_stats).expect("ray statistics serialise to JSON");
    }
    if let Some(film) = &rendered.film {
        if let Some(photons) = film.photons {
            value["photons"] =
                serde_json::to_value(photons).expect("photon counts serialise to JSON");
        }
        value["traced"] = film.traced.into();
        value["estimated_rmse"] = film.estimated_rmse.into();
    }
    if let Some(caustics) = &rendered.caustics {
        value["caustics"] =
            serde_json::to_value(caustics).expect("the photon map's report serialises to JSON");
    }
    println!("{value}");
}

/// `wrote FILE (W x H, mode, ms on device)`, and the ray statistics.
fn print_line(args: &RenderArgs, shading: Shading, image: &Written) {
    let rendered = &image.rendered;
    let engine = rendered
        .traversal
        .map(|t| format!(", traversal {}", t.name()))
        .unwrap_or_default();
    println!(
        "wrote {} ({}x{}, {}{engine}, {:.1} ms on {})",
        image.out.display(),
        rendered.image.width,
        rendered.image.height,
        shading,
        rendered.timings.total_ms,
        image.device
    );
    if let Some(photons) = rendered.film.as_ref().and_then(|f| f.photons) {
        print_photons(&photons);
    }
    if let Some(caustics) = &rendered.caustics {
        super::stats::print_caustics(caustics);
    }
    if args.stats {
        print_stats(rendered.ray_stats.as_ref(), &rendered.timings, shading);
    }
}

/// Pixels that are not finite fail the run, the image written to see
/// where.
fn refuse_non_finite(scene: &Scene, image: &Written) -> Result<(), Failure> {
    let rendered = &image.rendered;
    let non_finite = image.non_finite;
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
                image.out.display(),
                if image.format == ImageFormat::Exr {
                    "they are"
                } else {
                    "0 or 1 (PNG cannot hold them)"
                }
            ),
        });
    }
    Ok(())
}
