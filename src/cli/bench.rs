//! `shadelab bench`: render times per mode, medians over several runs after
//! a warm-up, as ratios against a baseline measured in the same run (the
//! flat raster render of the same scene), and rays per second for the ray
//! tracer. Shared machines are noisy: compare ratios, not milliseconds.

use std::path::PathBuf;
use std::sync::Arc;

use clap::Args;
use shadelab::compare::run::median_and_spread;
use shadelab::gpu::{raster, raytrace, GpuContext, GpuOptions, GpuTimings};
use shadelab::scene::Scene;
use shadelab::shading::Shading;

use super::args::{check_depth, check_runs, ImageSize};
use super::render::load_scene;
use super::Failure;

#[derive(Args)]
pub struct BenchArgs {
    /// Scene file; the built-in default scene if left out.
    scene: Option<PathBuf>,
    /// Modes to time, comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "flat,gouraud,phong,raytrace"
    )]
    shading: Vec<Shading>,
    /// Timed runs per mode (after one warm-up run).
    #[arg(long, default_value_t = 5)]
    runs: usize,
    #[command(flatten)]
    size: ImageSize,
    /// Ray tracing: maximum depth (overrides the scene).
    #[arg(long)]
    depth: Option<u32>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

fn once(context: &Arc<GpuContext>, scene: &Scene, shading: Shading) -> Result<GpuTimings, Failure> {
    Ok(match shading.raster_mode() {
        Some(mode) => raster::render(context, scene, mode)?.timings,
        None => raytrace::render(context, scene, false)?.timings,
    })
}

#[derive(serde::Serialize)]
struct Row {
    shading: Shading,
    total_ms: f64,
    /// Median wall time from queue submission to completion.
    gpu_ms: f64,
    /// Spread: the slowest minus the fastest run.
    total_spread_ms: f64,
    /// Median total time over the baseline's.
    ratio_to_baseline: f64,
    rays: Option<u64>,
    rays_per_second: Option<f64>,
}

pub fn run(args: BenchArgs, options: &GpuOptions) -> Result<(), Failure> {
    check_runs(args.runs)?;
    let (mut scene, name) = load_scene(args.scene.as_deref())?;
    args.size.apply(&mut scene)?;
    if let Some(d) = args.depth {
        scene.render.depth = check_depth(d)?;
    }
    let context = GpuContext::new(options)?;
    let time = |shading: Shading| -> Result<(f64, f64, f64), Failure> {
        once(&context, &scene, shading)?; // warm-up
        let mut totals = Vec::new();
        let mut gpus = Vec::new();
        for _ in 0..args.runs {
            let t = once(&context, &scene, shading)?;
            totals.push(t.total_ms);
            // Submission to completion: robust where timestamps are not
            // (see GpuTimings::submit_ms).
            gpus.push(t.submit_ms);
        }
        let (total, spread) = median_and_spread(totals);
        Ok((total, median_and_spread(gpus).0, spread))
    };
    // Flat is the baseline; timed once, and reused if it is in the list.
    let flat = time(Shading::Flat)?;
    let baseline = flat.0;
    let mut rows = Vec::new();
    for &shading in &args.shading {
        let (total_ms, gpu_ms, total_spread_ms) = if shading == Shading::Flat {
            flat
        } else {
            time(shading)?
        };
        // Rays are counted in a separate run: counting costs atomics.
        let rays = if shading.raster_mode().is_none() {
            raytrace::render(&context, &scene, true)?
                .stats
                .map(|s| s.total())
        } else {
            None
        };
        rows.push(Row {
            shading,
            total_ms,
            gpu_ms,
            total_spread_ms,
            ratio_to_baseline: total_ms / baseline,
            rays,
            rays_per_second: rays.map(|r| r as f64 / (gpu_ms / 1e3)),
        });
    }
    let (w, h) = (scene.image.width, scene.image.height);
    if args.json {
        let value = serde_json::json!({
            "scene": name,
            "width": w,
            "height": h,
            "device": context.info.name,
            "runs": args.runs,
            "baseline": { "shading": "flat", "total_ms": baseline },
            "results": rows,
        });
        println!("{value}");
        return Ok(());
    }
    println!(
        "{name} at {w}x{h} on {}, median of {} runs after a warm-up; baseline: flat raster, {baseline:.1} ms",
        context.info.name, args.runs
    );
    println!(
        "{:<10} {:>10} {:>10} {:>10} {:>8} {:>14}",
        "mode", "total_ms", "gpu_ms", "spread_ms", "ratio", "Mrays/s"
    );
    for r in &rows {
        let mrays = r
            .rays_per_second
            .map(|v| format!("{:.2}", v / 1e6))
            .unwrap_or_else(|| "-".into());
        println!(
            "{:<10} {:>10.1} {:>10.1} {:>10.1} {:>8.2} {:>14}",
            r.shading.to_string(),
            r.total_ms,
            r.gpu_ms,
            r.total_spread_ms,
            r.ratio_to_baseline,
            mrays
        );
    }
    Ok(())
}
