//! One entry point that renders a scene in a shading mode on a backend:
//! the Vulkan pipelines or the CPU reference.

use std::sync::Arc;
use std::time::Instant;

use crate::caustics::CausticReport;
use crate::cpu;
use crate::error::Error;
use crate::film_sums::{scaled_image, FilmSums, PhotonStats, RenderPart};
use crate::gpu::raster::ColorTarget;
use crate::gpu::shared::image_size::MAX_PIXELS;
use crate::gpu::{raster, raytrace, GpuContext};
use crate::linear_image::LinearImage;
use crate::rt_scene::RayStats;
use crate::scene::{Scene, Traversal};
use crate::shading::{RasterMode, Shading};
use crate::work_counter::WorkCounter;

/// Where a render spent its time, in milliseconds.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Timings {
    /// The whole render, host work and read-back included.
    pub total_ms: f64,
    /// GPU only: the work, between timestamp queries.
    pub gpu_ms: Option<f64>,
    /// GPU only: queue submission to completion (`GpuTimings::submit_ms`).
    pub submit_ms: Option<f64>,
    /// GPU only: shader modules and pipeline creation.
    pub pipeline_ms: Option<f64>,
    /// GPU only: the host's work on the scene before the pipeline
    /// (geometry, BVH, records: `GpuTimings::prepare_ms`).
    pub prepare_ms: Option<f64>,
    /// GPU only: buffers, images and descriptors, the data uploaded.
    pub upload_ms: Option<f64>,
    /// GPU ray tracing only: the driver's code generation (or its shader
    /// cache's load) at the pipeline's first dispatch.
    pub codegen_ms: Option<f64>,
    /// GPU only: the image read back into a `LinearImage`.
    pub readback_ms: Option<f64>,
}

impl Timings {
    /// The CPU reference's timings: wall time since `started`, nothing else.
    fn cpu(started: Instant) -> Self {
        Self {
            total_ms: started.elapsed().as_secs_f64() * 1e3,
            ..Self::default()
        }
    }

    /// A GPU render's timings.
    fn gpu(t: &crate::gpu::GpuTimings) -> Self {
        Self {
            total_ms: t.total_ms,
            gpu_ms: Some(t.gpu_ms),
            submit_ms: Some(t.submit_ms),
            pipeline_ms: Some(t.pipeline_ms),
            prepare_ms: Some(t.prepare_ms),
            upload_ms: Some(t.upload_ms),
            codegen_ms: t.codegen_ms,
            readback_ms: Some(t.readback_ms),
        }
    }

    /// The time the rendering work itself took: submission to completion
    /// on the GPU, the whole render on the CPU.
    pub fn work_ms(&self) -> f64 {
        self.submit_ms.unwrap_or(self.total_ms)
    }
}

/// A rendered image and where the time went.
pub struct Rendered {
    pub image: LinearImage,
    pub timings: Timings,
    /// Rays traced, by kind: ray tracing only.
    pub ray_stats: Option<RayStats>,
    /// The engine that found the hits: GPU ray tracing only.
    pub traversal: Option<Traversal>,
    /// Forward ray tracing, and ray tracing with bounces: the film's
    /// fixed-point sums (which shards add up: `film_sums`) and what was
    /// traced.
    pub film: Option<FilmRender>,
    /// Ray tracing with caustics: what the photon map took (its image is
    /// in `image`, not in `film`).
    pub caustics: Option<CausticReport>,
}

/// A render summed in fixed point: its film, beside its image, and what
/// made it.
pub struct FilmRender {
    pub film: FilmSums,
    /// Of the part asked for, the photons or samples per pixel traced
    /// (fewer where a time budget stopped it).
    pub traced: u64,
    /// Forward only: what the photons did.
    pub photons: Option<PhotonStats>,
    /// Under an error budget (GPU only), the render's last estimate of its
    /// RMSE (`error_budget`).
    pub estimated_rmse: Option<f64>,
}

/// Whether a render in `shading` sums into a film, so that it can be
/// split into shards, stopped at a time budget and shows its progress in
/// photons or samples: forward tracing, and ray tracing with bounces.
pub fn sums_in_film(scene: &Scene, shading: Shading) -> bool {
    shading == Shading::Forward || (shading == Shading::Raytrace && scene.render.bounces > 0)
}

/// The photons (forward) or samples per pixel (ray tracing with bounces)
/// a render in `shading` splits into parts.
pub fn part_total(scene: &Scene, shading: Shading) -> u32 {
    if shading == Shading::Forward {
        scene.render.photons
    } else {
        scene.render.samples.max(1)
    }
}

/// Renders on the GPU: the raster pipelines, or the ray-tracing compute
/// shader for `Shading::Raytrace`.
pub fn render_gpu(
    context: &Arc<GpuContext>,
    scene: &Scene,
    shading: Shading,
) -> Result<Rendered, Error> {
    render_gpu_to(context, scene, shading, false, ColorTarget::Float32)
}

/// As `render_gpu`, the raster modes rendering into `target` (the ray
/// tracer always writes 32-bit floats); for ray tracing, also counts the
/// rays by kind when `count_rays` (the shader variant with atomics: slower,
/// so opt-in).
pub fn render_gpu_to(
    context: &Arc<GpuContext>,
    scene: &Scene,
    shading: Shading,
    count_rays: bool,
    target: ColorTarget,
) -> Result<Rendered, Error> {
    render_gpu_until(context, scene, shading, (count_rays, target), None)
}

/// As `render_gpu_to`, a Whitted trace's caustics (`render.caustics`)
/// gathered in the passes that start before `deadline` (one at least).
pub fn render_gpu_until(
    context: &Arc<GpuContext>,
    scene: &Scene,
    shading: Shading,
    (count_rays, target): (bool, ColorTarget),
    deadline: Option<Instant>,
) -> Result<Rendered, Error> {
    if sums_in_film(scene, shading) {
        let part = RenderPart::all(part_total(scene, shading));
        let counter = WorkCounter::default();
        return render_film_part(Some(context), scene, shading, (&part, &counter), count_rays);
    }
    refuse_beyond_f32(scene)?;
    let (image, timings, ray_stats, traversal) = match shading.raster_mode() {
        Some(mode) => {
            let out = raster::render_to(context, scene, mode, target)?;
            (out.image, out.timings, None, None)
        }
        None => {
            let out = raytrace::render(context, scene, count_rays)?;
            (out.image, out.timings, out.stats, Some(out.traversal))
        }
    };
    let mut rendered = Rendered {
        image,
        timings: Timings::gpu(&timings),
        ray_stats,
        traversal,
        film: None,
        caustics: None,
    };
    if shading == Shading::Raytrace {
        let counter = WorkCounter::default();
        with_caustics(Some(context), scene, &mut rendered, (&counter, deadline))?;
    }
    Ok(rendered)
}

/// Forward ray tracing of `job`'s photons (all of them, or a shard's) on
/// the GPU where `context` is given, else with the CPU twin; the image is
/// the film's (a shard's share of the whole).
pub fn render_forward(
    context: Option<&Arc<GpuContext>>,
    scene: &Scene,
    job: &RenderPart,
    counter: &WorkCounter,
) -> Result<Rendered, Error> {
    refuse_beyond_f32(scene)?;
    refuse_forward_without_light(scene)?;
    let Some(context) = context else {
        return Ok(forward_cpu(scene, job, counter).0);
    };
    let out = raytrace::forward::render(context, scene, job, counter)?;
    Ok(Rendered {
        image: scaled_image(&out.film, out.stats.emitted, job.count()),
        timings: Timings::gpu(&out.timings),
        ray_stats: None,
        traversal: Some(Traversal::Bvh),
        film: Some(FilmRender {
            film: out.film,
            traced: out.stats.emitted,
            photons: Some(out.stats),
            estimated_rmse: out.estimate,
        }),
        caustics: None,
    })
}

/// A render that sums into a film (`sums_in_film`): forward, or ray
/// tracing with bounces of `part`'s samples per pixel, progress counted
/// into its counter; on the GPU where `context` is given, else with the
/// CPU twin (which traces all of the part: a time budget is the GPU's).
/// Rays are counted by kind where `count_rays` (ray tracing on the GPU).
pub fn render_film_part(
    context: Option<&Arc<GpuContext>>,
    scene: &Scene,
    shading: Shading,
    (part, counter): (&RenderPart, &WorkCounter),
    count_rays: bool,
) -> Result<Rendered, Error> {
    if shading == Shading::Forward {
        return render_forward(context, scene, part, counter);
    }
    refuse_beyond_f32(scene)?;
    let Some(context) = context else {
        let mut rendered = raytrace_cpu(scene, part, counter).0;
        with_caustics(None, scene, &mut rendered, (counter, None))?;
        return Ok(rendered);
    };
    let options = raytrace::TraceOptions {
        count_rays,
        ..raytrace::TraceOptions::default()
    };
    let out = raytrace::render_part(context, scene, options, part, counter)?;
    let film = out.sums.map(|sums| FilmRender {
        film: sums.film,
        traced: u64::from(sums.traced),
        photons: None,
        estimated_rmse: sums.estimate,
    });
    let mut rendered = Rendered {
        image: out.image,
        timings: Timings::gpu(&out.timings),
        ray_stats: out.stats,
        traversal: Some(out.traversal),
        film,
        caustics: None,
    };
    with_caustics(
        Some(context),
        scene,
        &mut rendered,
        (counter, part.deadline),
    )?;
    Ok(rendered)
}

/// Adds the caustic image where the scene asks for caustics (and has
/// some: `caustics::pointless`), its passes stopped at `deadline` where
/// given, its time to the render's; the caustic image, where one was
/// added.
fn with_caustics(
    context: Option<&Arc<GpuContext>>,
    scene: &Scene,
    rendered: &mut Rendered,
    budget: (&WorkCounter, Option<Instant>),
) -> Result<Option<LinearImage>, Error> {
    let Some((report, caustic)) =
        crate::caustics::add(context, scene, &mut rendered.image, budget)?
    else {
        return Ok(None);
    };
    let t = &mut rendered.timings;
    t.total_ms += report.ms;
    let add = |a: Option<f64>, b: Option<f64>| a.map(|a| a + b.unwrap_or(0.0));
    t.gpu_ms = add(t.gpu_ms, report.gpu_ms);
    t.submit_ms = add(t.submit_ms, report.submit_ms);
    rendered.caustics = Some(report);
    Ok(Some(caustic))
}

/// Forward tracing starts from the lights: a scene with none that emits
/// has nothing to trace; and it splats the contract's formula, not a
/// hook's (usage, exit 2). (It walks the compute BVH whatever the
/// traversal asked for: the CLI says it ignores `--traversal`.)
fn refuse_forward_without_light(scene: &Scene) -> Result<(), Error> {
    let emits = |l: &crate::scene::PointLight| {
        let i = l.intensity;
        (i.x + i.y + i.z) > 0.0
    };
    if let Some(hook) = &scene.lighting_hook {
        return Err(Error::Usage(format!(
            "--lighting {}: a lighting hook replaces the local model's light at a surface, which forward tracing does not use (its splats follow docs/lighting-model.md); leave --lighting out",
            hook.path
        )));
    }
    if !scene.lights.iter().any(emits) {
        let what = if scene.lights.is_empty() {
            "no light"
        } else {
            "only lights of zero intensity"
        };
        return Err(Error::Usage(format!(
            "--shading forward traces light from the lights, and the scene has {what}; add a [[lights]] entry with an intensity above 0"
        )));
    }
    Ok(())
}

/// What forward tracing leaves black in `scene`, said as a warning: a
/// pinhole eye cannot be reached through a mirror or glass, so what those
/// surfaces reflect or transmit is missing from the image (their own
/// diffuse light still shows). `None` where no object has `kr` or `kt`.
pub fn forward_blind_spots(scene: &Scene) -> Option<String> {
    let blind: Vec<String> = scene
        .objects
        .iter()
        .enumerate()
        .filter_map(|(i, o)| {
            let m = &scene.materials[o.material];
            (m.kr > 0.0 || m.kt > 0.0).then(|| format!("{} ({})", i + 1, m.name))
        })
        .collect();
    if blind.is_empty() {
        return None;
    }
    Some(format!(
        "forward ray tracing cannot see through mirrors or glass with a pinhole eye: what object{} {} reflect{} or transmit{} is black (their light on other surfaces, caustics included, shows); render with --shading raytrace to see it",
        if blind.len() == 1 { "" } else { "s" },
        blind.join(", "),
        if blind.len() == 1 { "s" } else { "" },
        if blind.len() == 1 { "s" } else { "" },
    ))
}

/// What the loader refuses (`narrow_view::refusal`,
/// `huge_sphere::refusal`), checked again at the size and scene a render
/// gets: `--height` can narrow a pixel's angle, and a glTF scene or a
/// built scene never passed the TOML loader.
fn refuse_beyond_f32(scene: &Scene) -> Result<(), Error> {
    let narrow = crate::narrow_view::refusal(scene.camera.fov_y_deg, scene.image.height);
    let sphere = scene
        .objects
        .iter()
        .enumerate()
        .find_map(|(i, o)| match o.shape {
            crate::scene::Shape::Sphere { center, radius, .. } => {
                crate::huge_sphere::refusal(scene.camera.position, center, radius)
                    .map(|why| format!("object {} (sphere): {why}", i + 1))
            }
            _ => None,
        });
    match narrow.or(sphere) {
        Some(why) => Err(Error::Usage(why)),
        None => Ok(()),
    }
}

/// What the CPU reference knows about each pixel besides its colour.
pub struct Coverage {
    /// `scene.objects` index per pixel (`None`: background).
    pub object_ids: Vec<Option<u32>>,
    /// The surface of constant shading rules per pixel: the triangle in flat
    /// mode (its colour changes at every triangle edge), else the object.
    pub surface_ids: Vec<Option<u32>>,
    /// Samples so close to a visible edge that another conforming
    /// rasterizer may cover them differently (`cpu::raster::EDGE_MARGIN`).
    pub near_edge: Vec<bool>,
}

/// The CPU reference (`f64`) and what it knows about each pixel. Refuses an
/// image over the GPU's pixel cap (`MAX_PIXELS`): the reference holds
/// it in f64 with per-pixel coverage, and every caller (`render --backend
/// cpu`, `check`, `compare`) should fail fast rather than run out of memory.
pub fn render_cpu(scene: &Scene, shading: Shading) -> Result<(Rendered, Coverage), Error> {
    render_cpu_counted(scene, shading, &WorkCounter::default())
}

/// [`render_cpu`], counting its rows into `counter` as they finish (for a
/// caller to show progress).
pub fn render_cpu_counted(
    scene: &Scene,
    shading: Shading,
    counter: &WorkCounter,
) -> Result<(Rendered, Coverage), Error> {
    let (width, height) = (scene.image.width, scene.image.height);
    if u64::from(width) * u64::from(height) > MAX_PIXELS {
        return Err(Error::Usage(format!(
            "a {width}x{height} image exceeds the limit of {} pixels (8192 x 8192); choose a smaller --width/--height",
            MAX_PIXELS
        )));
    }
    refuse_beyond_f32(scene)?;
    if shading == Shading::Forward {
        refuse_forward_without_light(scene)?;
        let job = RenderPart::all(scene.render.photons);
        return Ok(forward_cpu(scene, &job, counter));
    }
    let Some(mode) = shading.raster_mode() else {
        let part = RenderPart::all(part_total(scene, shading));
        let (mut rendered, mut coverage) = raytrace_cpu(scene, &part, counter);
        if let Some(caustic) = with_caustics(None, scene, &mut rendered, (counter, None))? {
            // The GPU gathers the same photons, but f32 rounding can put
            // one on the other side of a pixel's radius: a caustic's
            // pixels and their neighbours (a photon at a caustic's rim)
            // are judged as edge pixels, by the share that differ
            // (docs/check.md).
            let lit: Vec<u64> = (caustic.pixels.iter())
                .map(|p| u64::from(p.iter().any(|&c| c != 0.0)))
                .collect();
            let (width, height) = (scene.image.width as usize, scene.image.height as usize);
            for (near, rim) in coverage
                .near_edge
                .iter_mut()
                .zip(neighbourhoods(width, height, &lit))
            {
                *near |= rim;
            }
        }
        return Ok((rendered, coverage));
    };
    let msaa = scene.render.msaa;
    if msaa.positions().is_none() {
        return Err(Error::Usage(format!(
            "{} samples per pixel: the CPU reference renders 1, 2, 4, 8 or 16 (the counts with standard sample locations)",
            msaa.samples
        )));
    }
    let started = Instant::now();
    let out = cpu::raster::render_counted(scene, mode, counter);
    let rendered = Rendered {
        image: out.image,
        timings: Timings::cpu(started),
        ray_stats: None,
        traversal: None,
        film: None,
        caustics: None,
    };
    let surface_ids = if mode == RasterMode::Flat {
        out.triangle_ids
    } else {
        out.object_ids.clone()
    };
    let coverage = Coverage {
        object_ids: out.object_ids,
        surface_ids,
        near_edge: out.near_edge,
    };
    Ok((rendered, coverage))
}

/// The CPU ray tracer. A pixel is near an edge when its 3x3 neighbourhood
/// (within the image) holds more than one path signature: there a
/// reflected, refracted or shadow edge, or a silhouette, passes close by,
/// and another tracer's rounding may put it on the other side.
fn raytrace_cpu(scene: &Scene, part: &RenderPart, counter: &WorkCounter) -> (Rendered, Coverage) {
    let started = Instant::now();
    let out = cpu::raytrace::render_part(scene, part, counter);
    let rendered = Rendered {
        image: out.image,
        timings: Timings::cpu(started),
        ray_stats: Some(out.stats),
        traversal: None,
        film: out.film.map(|film| FilmRender {
            film,
            traced: u64::from(part.count()),
            photons: None,
            estimated_rmse: None,
        }),
        caustics: None,
    };
    let near_edge = signature_edges(
        scene.image.width as usize,
        scene.image.height as usize,
        &out.path_signatures,
    );
    let coverage = Coverage {
        object_ids: out.primary_object_ids.clone(),
        surface_ids: out.primary_object_ids,
        near_edge,
    };
    (rendered, coverage)
}

/// The CPU forward tracer. The GPU traces its photons one by one, but a
/// photon that f32 rounding sends another way moves a splat to any pixel
/// at all: every pixel is marked as an edge one, and `check` bounds the
/// share that differ and the images' means (`check::FORWARD_*`).
fn forward_cpu(scene: &Scene, job: &RenderPart, counter: &WorkCounter) -> (Rendered, Coverage) {
    let started = Instant::now();
    let out = cpu::forward::render_job(scene, job, counter)
        .expect("refuse_forward_without_light let only scenes with light through");
    let pixels = out.film.width as usize * out.film.height as usize;
    let rendered = Rendered {
        image: scaled_image(&out.film, out.stats.emitted, job.count()),
        timings: Timings::cpu(started),
        ray_stats: None,
        traversal: None,
        film: Some(FilmRender {
            film: out.film,
            traced: out.stats.emitted,
            photons: Some(out.stats),
            estimated_rmse: None,
        }),
        caustics: None,
    };
    let coverage = Coverage {
        object_ids: vec![None; pixels],
        surface_ids: vec![None; pixels],
        near_edge: vec![true; pixels],
    };
    (rendered, coverage)
}

/// Whether each pixel's 3x3 neighbourhood, clipped to the image, holds more
/// than one signature.
fn signature_edges(width: usize, height: usize, signatures: &[u64]) -> Vec<bool> {
    neighbourhood_any(width, height, |own, other| {
        signatures[own] != signatures[other]
    })
}

/// Whether each pixel's 3x3 neighbourhood, clipped to the image, holds a
/// pixel whose `marks` is not 0.
fn neighbourhoods(width: usize, height: usize, marks: &[u64]) -> Vec<bool> {
    neighbourhood_any(width, height, |_, other| marks[other] != 0)
}

/// Whether `test(pixel, neighbour)` holds for a pixel of each pixel's 3x3
/// neighbourhood, clipped to the image (indices `y * width + x`).
fn neighbourhood_any(
    width: usize,
    height: usize,
    test: impl Fn(usize, usize) -> bool,
) -> Vec<bool> {
    let mut found = vec![false; width * height];
    for y in 0..height {
        for x in 0..width {
            let own = y * width + x;
            let ys = y.saturating_sub(1)..(y + 2).min(height);
            found[own] = ys.into_iter().any(|ny| {
                (x.saturating_sub(1)..(x + 2).min(width)).any(|nx| test(own, ny * width + nx))
            });
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::signature_edges;

    #[test]
    fn signature_edges_mark_the_3x3_neighbourhood_of_a_change() {
        // 4 x 3, one odd pixel at (3, 0): its neighbours (2, 0), (2, 1),
        // (3, 1) and itself are marked, nothing else.
        let mut sigs = vec![7u64; 12];
        sigs[3] = 9;
        let edges = signature_edges(4, 3, &sigs);
        let marked: Vec<usize> = (0..12).filter(|&i| edges[i]).collect();
        assert_eq!(marked, vec![2, 3, 6, 7]);
        assert!(signature_edges(4, 3, &[1; 12]).iter().all(|e| !e));
    }
}
