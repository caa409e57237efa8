//! `--backend auto`: the GPU or the CPU reference, whichever should give
//! the image first.
//!
//! On lavapipe a GPU render pays fixed costs before its first pixel: the
//! device, pipeline creation, and on a machine whose driver cache is empty
//! the driver's code generation (half a second a ray tracer variant,
//! docs/performance.md "Time to image"). For small work the f64 CPU
//! reference is done before that. The CPU's time is measured, not guessed:
//! a pilot renders a sparse part of the image on one thread and is scaled
//! up; the GPU's is its fixed cost (measured on the 2-core CI machine,
//! warm or cold by whether the driver's cache holds anything) plus the
//! CPU's work divided by how much faster the GPU does it (the low end of
//! what the benchmarks measure, so that a close call goes to the GPU).
//! The choice and both estimates are printed; it is never silent.

use std::path::PathBuf;
use std::time::Instant;

use crate::camera::View;
use crate::cpu;
use crate::gpu::raytrace::bvh::BvhKinds;
use crate::rt_scene::{RayStats, RtScene};
use crate::scene::{GeometrySize, Scene, Traversal};
use crate::shading::Shading;

/// A backend `render` can run on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Backend {
    Gpu,
    Cpu,
}

impl Backend {
    pub fn name(self) -> &'static str {
        match self {
            Backend::Gpu => "gpu",
            Backend::Cpu => "cpu",
        }
    }
}

/// What `--backend auto` chose, and on what grounds.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Choice {
    pub backend: Backend,
    /// One line for the user: the estimates, or why none was needed.
    pub why: String,
    /// The CPU reference's render, estimated from the pilot (ms).
    pub cpu_estimate_ms: Option<f64>,
    /// The GPU's render with its fixed costs (ms).
    pub gpu_estimate_ms: Option<f64>,
    /// The pilot's own time (ms), spent whichever backend renders.
    pub pilot_ms: Option<f64>,
    /// Whether the driver's cache held code already (the GPU's warm case).
    pub driver_cache_filled: bool,
    /// Whether only the GPU can render it (a lighting hook, the ray-query
    /// engine): then no GPU is an error, not a fall back to the CPU.
    pub needs_gpu: bool,
}

/// The GPU's fixed costs (warm, cold), from `render --json`'s phases on
/// the 2-core CI machine (Mesa 25.0.7): device, pipeline, upload, code
/// generation and read-back. The ray tracer without a BVH walk (the
/// default scene): 80 to 100 ms warm, 600 to 860 ms with an empty driver
/// cache; with one (meshes: the 40k sphere, rt-mesh, the teapot): 130 to
/// 180 warm, 1000 to 1350 cold; raster (the default scene): 50 to 85 ms
/// warm, 230 to 280 cold. The low ends, so that a close call goes to the
/// GPU.
const RAY_TRACE_FIXED_MS: (f64, f64) = (80.0, 600.0);
const BVH_RAY_TRACE_FIXED_MS: (f64, f64) = (130.0, 1000.0);
const RASTER_FIXED_MS: (f64, f64) = (50.0, 230.0);
/// How many times faster the GPU does the work itself than the CPU
/// reference on all cores: the ray tracer 4 to 16 (`ci/bench-peers.sh`'s
/// twin rows), the raster modes about 2 (the default scene's Phong, 20
/// against 42 ms). The low ends again.
const RAY_TRACE_GPU_SPEEDUP: f64 = 4.0;
const RASTER_GPU_SPEEDUP: f64 = 2.0;
/// The photon map's own fixed costs on the GPU (warm, cold: its pipeline's
/// code generation, about 3 s on lavapipe with an empty cache) and how
/// many times faster the GPU runs its passes than the CPU twin on all
/// cores (`assets/caustics.toml`: 730 against 1790 ms; the low end).
const CAUSTICS_FIXED_MS: (f64, f64) = (20.0, 2500.0);
const CAUSTICS_GPU_SPEEDUP: f64 = 2.0;
/// Caustic photons the pilot traces on one thread to time them.
const CAUSTIC_PILOT_PHOTONS: u32 = 4096;
/// Work past which the GPU is taken without a pilot: the CPU reference
/// takes seconds there, and building its acceleration structure alone
/// would cost the GPU path time.
const PILOT_MAX_TRIANGLES: u64 = 50_000;
const PILOT_MAX_SAMPLES: u64 = 4 << 20;
/// The pilot traces one pixel in `PILOT_STRIDE` squared; the raster pilot
/// renders at 1 / `PILOT_STRIDE` of the width and height.
const PILOT_STRIDE: u32 = 8;
const RASTER_PILOT_STRIDE: u32 = 4;

/// Chooses the backend for `scene` in `shading`.
pub fn choose(scene: &Scene, shading: Shading) -> Choice {
    let driver_cache_filled = driver_cache_filled();
    let gpu_only = |why: &str, needs_gpu: bool| Choice {
        backend: Backend::Gpu,
        why: why.to_string(),
        cpu_estimate_ms: None,
        gpu_estimate_ms: None,
        pilot_ms: None,
        driver_cache_filled,
        needs_gpu,
    };
    if scene.lighting_hook.is_some() {
        return gpu_only("a lighting hook (--lighting) runs on the GPU only", true);
    }
    if shading == Shading::Raytrace && scene.render.traversal == Traversal::Query {
        return gpu_only("--traversal query is a GPU engine", true);
    }
    let triangles = GeometrySize::of_scene(scene, shading != Shading::Raytrace).triangles;
    let samples = u64::from(scene.image.width)
        * u64::from(scene.image.height)
        * if shading == Shading::Raytrace {
            u64::from(scene.render.samples.max(1))
        } else {
            1
        };
    if triangles > PILOT_MAX_TRIANGLES || samples > PILOT_MAX_SAMPLES {
        return gpu_only(
            "large work (more than 50k triangles or 4M samples): the GPU",
            false,
        );
    }
    let started = Instant::now();
    let warm_or_cold = |(warm, cold): (f64, f64)| if driver_cache_filled { warm } else { cold };
    let (cpu_estimate_ms, fixed_ms, speedup, caustics) = if shading == Shading::Raytrace {
        let rt = RtScene::new(scene);
        let walks_bvh = !rt.triangles.is_empty() || BvhKinds::of(&rt) != BvhKinds::default();
        let fixed_ms = warm_or_cold(if walks_bvh {
            BVH_RAY_TRACE_FIXED_MS
        } else {
            RAY_TRACE_FIXED_MS
        });
        // The CPU is faster while cpu < fixed + cpu / speedup: a pilot that
        // shows more than this may stop early, the GPU chosen.
        let break_even_ms = fixed_ms / (1.0 - 1.0 / RAY_TRACE_GPU_SPEEDUP);
        let build_ms = started.elapsed().as_secs_f64() * 1e3;
        let cpu_ms = build_ms + ray_trace_pilot(scene, &rt, break_even_ms - build_ms);
        let caustics = caustics_pilot(scene, &rt, cpu_ms);
        (cpu_ms, fixed_ms, RAY_TRACE_GPU_SPEEDUP, caustics)
    } else {
        let fixed_ms = warm_or_cold(RASTER_FIXED_MS);
        (
            raster_pilot(scene, shading),
            fixed_ms,
            RASTER_GPU_SPEEDUP,
            None,
        )
    };
    let mut gpu_estimate_ms = fixed_ms + cpu_estimate_ms / speedup;
    let mut cpu_estimate_ms = cpu_estimate_ms;
    if let Some(caustics_ms) = caustics {
        cpu_estimate_ms += caustics_ms;
        gpu_estimate_ms += warm_or_cold(CAUSTICS_FIXED_MS) + caustics_ms / CAUSTICS_GPU_SPEEDUP;
    }
    let pilot_ms = started.elapsed().as_secs_f64() * 1e3;
    let backend = if cpu_estimate_ms < gpu_estimate_ms {
        Backend::Cpu
    } else {
        Backend::Gpu
    };
    let cache = if driver_cache_filled {
        "the driver's cache filled"
    } else {
        "the driver's cache empty: code to generate"
    };
    Choice {
        backend,
        why: format!(
            "estimated {:.0} ms on the CPU reference against {:.0} ms on the GPU ({cache})",
            cpu_estimate_ms, gpu_estimate_ms
        ),
        cpu_estimate_ms: Some(cpu_estimate_ms),
        gpu_estimate_ms: Some(gpu_estimate_ms),
        pilot_ms: Some(pilot_ms),
        driver_cache_filled,
        needs_gpu: false,
    }
}

/// The CPU ray tracer's render of `scene` (whose `rt` is built), estimated:
/// its acceleration structure built, then one pixel in 64 traced on this
/// thread, scaled to the image and shared out over the cores. Stops once
/// the estimate passes `enough_ms`.
fn ray_trace_pilot(scene: &Scene, rt: &RtScene, enough_ms: f64) -> f64 {
    let started = Instant::now();
    let (width, height) = (scene.image.width, scene.image.height);
    let tracer = cpu::raytrace::Tracer::new(rt, View::new(scene, width, height));
    let build_ms = started.elapsed().as_secs_f64() * 1e3;
    let threads = rayon::current_num_threads().max(1) as f64;
    let scale = f64::from(PILOT_STRIDE * PILOT_STRIDE) / threads;
    let mut stats = RayStats::default();
    let traced = Instant::now();
    let mut estimate = build_ms;
    // Rows spread over the image, a pixel in PILOT_STRIDE across each, so
    // that the empty sky and the busy middle are both sampled.
    for y in (PILOT_STRIDE / 2..height).step_by(PILOT_STRIDE as usize) {
        for x in (PILOT_STRIDE / 2..width).step_by(PILOT_STRIDE as usize) {
            tracer.pixel(x, y, &mut stats);
        }
        estimate = build_ms + traced.elapsed().as_secs_f64() * 1e3 * scale;
        if estimate > enough_ms {
            return estimate.max(enough_ms);
        }
    }
    // An image smaller than the stride traces no pixel: its work is nil.
    estimate
}

/// The CPU twin's photon map for `scene` (whose `rt` is built), estimated where it asks for
/// caustics and has some: its photons, `CAUSTIC_PILOT_PHOTONS` of them
/// timed on this thread and scaled to all of them over the cores; and
/// each pass's eye paths, counted as a ray trace of the image
/// (`trace_ms`, the pilot's estimate), which they cost no more than.
fn caustics_pilot(scene: &Scene, rt: &RtScene, trace_ms: f64) -> Option<f64> {
    let settings = scene.render.caustics;
    if !settings.on() || crate::render::caustics::no_caustic(scene).is_some() {
        return None;
    }
    let count = CAUSTIC_PILOT_PHOTONS.min(settings.photons_per_pass);
    let started = Instant::now();
    cpu::caustics::caustic_photons(rt, 0..count, settings.photons_per_pass)?;
    let per_photon_ms = started.elapsed().as_secs_f64() * 1e3 / f64::from(count.max(1));
    let threads = rayon::current_num_threads().max(1) as f64;
    let photons = f64::from(settings.total_photons()?);
    Some(per_photon_ms * photons / threads + trace_ms * f64::from(settings.passes))
}

/// The CPU raster render, estimated from two small ones, at an eighth and
/// a quarter of the width and height: their times fit a fixed part (the
/// triangles) and a part per pixel, which is scaled to the image.
fn raster_pilot(scene: &Scene, shading: Shading) -> f64 {
    let Some(mode) = shading.raster_mode() else {
        return 0.0;
    };
    let pixels = |s: &Scene| f64::from(s.image.width) * f64::from(s.image.height);
    let timed = |divisor: u32| {
        let mut small = scene.clone();
        small.image.width = (scene.image.width / divisor).max(1);
        small.image.height = (scene.image.height / divisor).max(1);
        let started = Instant::now();
        drop(cpu::raster::render(&small, mode, &Default::default()));
        (pixels(&small), started.elapsed().as_secs_f64() * 1e3)
    };
    // Once untimed first: the first render starts the thread pool and
    // touches fresh memory, which the two timed ones must not count.
    timed(2 * RASTER_PILOT_STRIDE);
    let (p1, t1) = timed(2 * RASTER_PILOT_STRIDE);
    let (p2, t2) = timed(RASTER_PILOT_STRIDE);
    raster_fit((p1, t1), (p2, t2), pixels(scene))
}

/// The time at `pixels` of the line through two (pixels, ms) points; the
/// larger render scaled by the pixels where the two do not give a line
/// that rises (noise, or an image too small to shrink).
fn raster_fit((p1, t1): (f64, f64), (p2, t2): (f64, f64), pixels: f64) -> f64 {
    if p2 > p1 && t2 > t1 {
        let per_pixel = (t2 - t1) / (p2 - p1);
        let fixed = (t1 - per_pixel * p1).max(0.0);
        fixed + per_pixel * pixels
    } else {
        t2 * pixels / p2
    }
}

/// Whether the driver's shader cache holds anything: on a fresh machine
/// (or with `MESA_SHADER_CACHE_DISABLE`) every pipeline's code is
/// generated at its first dispatch. Mesa's folder as `main` set it
/// (`cache::use_for_mesa_shader_cache`), else Mesa's own default.
pub fn driver_cache_filled() -> bool {
    let env = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
    if env("MESA_SHADER_CACHE_DISABLE").is_some_and(|v| v != "false" && v != "0") {
        return false;
    }
    let folder = env("MESA_SHADER_CACHE_DIR")
        .map(PathBuf::from)
        .or_else(|| env("XDG_CACHE_HOME").map(|d| PathBuf::from(d).join("mesa_shader_cache")))
        .or_else(|| env("HOME").map(|d| PathBuf::from(d).join(".cache/mesa_shader_cache")));
    folder.is_some_and(|f| holds_a_file(&f, 3))
}

/// Whether `folder` or a folder under it, `depth` levels down at most, holds
/// a file that is not empty.
fn holds_a_file(folder: &std::path::Path, depth: u32) -> bool {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return false;
    };
    entries.flatten().any(|entry| match entry.metadata() {
        Ok(m) if m.is_file() => m.len() > 0,
        Ok(m) if m.is_dir() && depth > 0 => holds_a_file(&entry.path(), depth - 1),
        _ => false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_with_only_empty_files_or_none_holds_no_code() {
        let dir = std::env::temp_dir().join(format!("shadelab-choice-{}", std::process::id()));
        let nested = dir.join("a/b");
        std::fs::create_dir_all(&nested).unwrap();
        assert!(!holds_a_file(&dir, 3));
        std::fs::write(nested.join("index"), b"").unwrap();
        assert!(!holds_a_file(&dir, 3));
        std::fs::write(nested.join("entry"), b"code").unwrap();
        assert!(holds_a_file(&dir, 3));
        assert!(!holds_a_file(&dir, 1), "two levels down is past depth 1");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_hook_or_the_query_engine_keeps_the_gpu_without_a_pilot() {
        let mut scene = crate::scene::default_scene();
        scene.render.traversal = Traversal::Query;
        let choice = choose(&scene, Shading::Raytrace);
        assert_eq!(choice.backend, Backend::Gpu);
        assert!(choice.pilot_ms.is_none());
        assert!(choice.why.contains("query"));
    }

    /// The photon map's passes count: 16 passes of 262144 photons on the
    /// caustic asset take the CPU twin seconds (1.8 s measured on two
    /// cores), far past the small image's Whitted trace alone.
    #[test]
    fn caustics_count_in_the_estimates() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/caustics.toml");
        let mut scene = crate::scene::load(std::path::Path::new(path)).unwrap();
        let with = choose(&scene, Shading::Raytrace);
        scene.render.caustics.photons_per_pass = 0;
        let without = choose(&scene, Shading::Raytrace);
        let (a, b) = (
            with.cpu_estimate_ms.unwrap(),
            without.cpu_estimate_ms.unwrap(),
        );
        assert!(a > b + 200.0, "{a} against {b}");
        assert!(with.gpu_estimate_ms.unwrap() > without.gpu_estimate_ms.unwrap());
    }

    #[test]
    fn large_work_keeps_the_gpu_without_a_pilot() {
        let mut scene = crate::scene::default_scene();
        scene.image.width = 4096;
        scene.image.height = 2048;
        let choice = choose(&scene, Shading::Raytrace);
        assert_eq!(choice.backend, Backend::Gpu);
        assert!(choice.pilot_ms.is_none());
    }

    #[test]
    fn the_raster_fit_separates_the_triangles_from_the_pixels() {
        // 10 ms of triangles and 1 ms per 1000 pixels.
        let at = |p: f64| (p, 10.0 + p / 1000.0);
        let estimate = raster_fit(at(1000.0), at(4000.0), 64_000.0);
        assert!((estimate - 74.0).abs() < 1e-9, "{estimate}");
        // No rise between the two: the larger one scaled, an overestimate.
        assert_eq!(raster_fit((1000.0, 12.0), (4000.0, 11.0), 64_000.0), 176.0);
    }

    #[test]
    fn the_ray_trace_pilot_scales_with_the_pixels_and_stops_at_enough() {
        let mut scene = crate::scene::default_scene();
        scene.image.width = 320;
        scene.image.height = 240;
        let rt = RtScene::new(&scene);
        // The fastest of three: a single short timing on a shared machine
        // can be off by more than the factors below.
        let pilot = |scene: &Scene| {
            (0..3)
                .map(|_| ray_trace_pilot(scene, &rt, f64::INFINITY))
                .fold(f64::INFINITY, f64::min)
        };
        let small = pilot(&scene);
        scene.image.width = 1280;
        scene.image.height = 960;
        let big = pilot(&scene);
        // 16 times the pixels; timing noise on a shared machine allows a
        // factor of 2 either side, which a pilot that ignored the pixel
        // count (or traced every pixel) would still miss by far.
        assert!(
            big > 4.0 * small && big < 64.0 * small,
            "{small} ms, {big} ms"
        );
        let stopped = ray_trace_pilot(&scene, &rt, 0.001);
        assert!(stopped >= 0.001 && stopped < big, "{stopped} against {big}");
    }
}
