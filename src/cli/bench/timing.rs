//! What `bench` times: each mode's render on the GPU, median and spread
//! over the runs after a warm-up, against the flat raster baseline; with
//! the flags, the CPU reference's time for the same work, the ray tracer
//! with every feature in, and the whole `render` command in a fresh process.

use std::ffi::OsString;

use shadelab::compare::run::median_and_spread;
use shadelab::gpu::raster::ColorTarget;
use shadelab::render::{render, Device, RenderRequest, Timings};
use shadelab::scene::Scene;
use shadelab::shading::Shading;

use super::time_to_image::{self, TimeToImage};
use crate::cli::common::failure::Failure;

/// What to time, and on what.
pub(super) struct Timing<'a> {
    pub device: &'a Device,
    pub scene: &'a Scene,
    /// Timed runs per mode (after one warm-up run).
    pub runs: usize,
    /// The raster modes' colour target (the ray tracer's is always
    /// `ColorTarget::Float32`).
    pub raster_target: ColorTarget,
    /// `--cpu`.
    pub cpu: bool,
    /// `--every-feature`.
    pub every_feature: bool,
    /// `--time-to-image`: the scene and overrides as `render` takes them,
    /// and the GPU-only ones apart.
    pub time_to_image: Option<(Vec<OsString>, Vec<OsString>)>,
}

impl Timing<'_> {
    /// The colour target `shading` renders into.
    fn target_of(&self, shading: Shading) -> ColorTarget {
        match shading.raster_mode() {
            Some(_) => self.raster_target,
            None => ColorTarget::Float32,
        }
    }

    /// The median total and GPU times of `shading` and the total's spread,
    /// after a warm-up run.
    fn time(&self, shading: Shading, every_feature: bool) -> Result<(f64, f64, f64), Failure> {
        let target = self.target_of(shading);
        once(self.device, self.scene, shading, every_feature, target)?; // warm-up
        let mut totals = Vec::new();
        let mut gpus = Vec::new();
        for _ in 0..self.runs {
            let t = once(self.device, self.scene, shading, every_feature, target)?;
            totals.push(t.total_ms);
            // Submission to completion: robust where timestamps are not
            // (see GpuTimings::submit_ms).
            gpus.push(t.work_ms());
        }
        let (total, spread) = median_and_spread(totals);
        Ok((total, median_and_spread(gpus).0, spread))
    }
}

/// The flat raster baseline's median total time, and a row per mode.
pub(super) fn measure(t: &Timing, modes: &[Shading]) -> Result<(f64, Vec<Row>), Failure> {
    // Flat is the baseline; timed once, and reused if it is in the list.
    let flat = t.time(Shading::Flat, false)?;
    let baseline = flat.0;
    let mut rows = Vec::new();
    for &shading in modes {
        let times = if shading == Shading::Flat {
            flat
        } else {
            t.time(shading, false)?
        };
        rows.push(row(t, shading, times, baseline)?);
    }
    Ok((baseline, rows))
}

/// One mode's row: its times, and what the flags add.
fn row(
    t: &Timing,
    shading: Shading,
    (total_ms, gpu_ms, total_spread_ms): (f64, f64, f64),
    baseline: f64,
) -> Result<Row, Failure> {
    let traced = shading.raster_mode().is_none();
    // Rays are counted in a separate run: counting costs atomics. Forward
    // tracing counts photons, not rays, and walks the compute BVH.
    let (rays, traversal) = if shading == Shading::Forward {
        (None, Some("bvh"))
    } else if traced {
        let request = RenderRequest {
            count_rays: true,
            ..RenderRequest::gpu(shading)
        };
        let counted = render(t.device, t.scene, &request)?;
        (
            counted.ray_stats.map(|s| s.total()),
            counted.traversal.map(|t| t.name()),
        )
    } else {
        (None, None)
    };
    let cpu_ms = if t.cpu {
        let runs = (0..t.runs)
            .map(|_| cpu_once(t.scene, shading))
            .collect::<Result<Vec<_>, _>>()?;
        Some(median_and_spread(runs).0)
    } else {
        None
    };
    let every_feature_gpu_ms = if t.every_feature && shading == Shading::Raytrace {
        Some(t.time(shading, true)?.1)
    } else {
        None
    };
    let time_to_image = match &t.time_to_image {
        Some((render_args, gpu_args)) => Some(time_to_image::measure(
            render_args,
            gpu_args,
            shading,
            t.runs,
        )?),
        None => None,
    };
    Ok(Row {
        shading,
        color_target: t.target_of(shading).name(),
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
    })
}

fn once(
    device: &Device,
    scene: &Scene,
    shading: Shading,
    every_feature: bool,
    target: ColorTarget,
) -> Result<Timings, Failure> {
    let request = RenderRequest {
        target,
        every_feature,
        ..RenderRequest::gpu(shading)
    };
    Ok(render(device, scene, &request)?.timings)
}

/// One timed render of the CPU reference, in milliseconds: the ray
/// tracer's tracing (its BVH built beforehand, as the GPU's is before its
/// dispatch), or a raster mode's whole render.
fn cpu_once(scene: &Scene, shading: Shading) -> Result<f64, Failure> {
    let timings = render(&Device::cpu_only(), scene, &RenderRequest::cpu(shading))?.timings;
    Ok(timings.trace_ms.unwrap_or(timings.total_ms))
}

#[derive(serde::Serialize)]
pub(super) struct Row {
    pub shading: Shading,
    /// The colour target timed (`ColorTarget::name`).
    pub color_target: &'static str,
    /// The ray tracer's engine (`bvh` or `query`); raster modes have none.
    pub traversal: Option<&'static str>,
    pub total_ms: f64,
    /// Median wall time from queue submission to completion.
    pub gpu_ms: f64,
    /// Spread: the slowest minus the fastest run.
    pub total_spread_ms: f64,
    /// Median total time over the baseline's.
    pub ratio_to_baseline: f64,
    pub rays: Option<u64>,
    pub rays_per_second: Option<f64>,
    /// `--cpu`: the CPU reference's median time for the same work.
    pub cpu_ms: Option<f64>,
    /// `--cpu`: `cpu_ms / gpu_ms`.
    pub gpu_speedup_over_cpu: Option<f64>,
    /// `--every-feature`: the ray tracer with every optional feature in.
    pub every_feature_gpu_ms: Option<f64>,
    /// `--every-feature`: `every_feature_gpu_ms / gpu_ms`, what
    /// specialising to the scene saves.
    pub every_feature_ratio: Option<f64>,
    /// `--time-to-image`: the whole command's wall clock, cold and warm,
    /// and the CPU twin's.
    pub time_to_image: Option<TimeToImage>,
}
