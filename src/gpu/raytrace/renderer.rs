//! The ray tracer: `shaders/raytrace.comp.glsl`, whose subgroups take the
//! image from a work queue, over the scene's `RtScene` (exact primitives,
//! triangles and BVH uploaded as storage buffers in the layouts of
//! `records`), writing linear float pixels to a buffer the host reads
//! back. The algorithm is docs/raytracing.md. Its hits come from the
//! shader's own BVH walk or, with `Traversal::Query`, from ray queries
//! through the structures of `accel` (`engine_for` picks). A render plans
//! the scene, gets or builds its pipeline, uploads the `buffers`, then
//! binds and dispatches them (`dispatch`) and reads the pixels back.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use crate::camera::View;
use crate::film_sums::{FilmSums, RenderPart};
use crate::gpu::raytrace::accel::{self, SceneStructure};
use crate::gpu::raytrace::batches;
use crate::gpu::raytrace::buffers::TraceBuffers;
use crate::gpu::raytrace::bvh::BvhKinds;
use crate::gpu::raytrace::dispatch::{cpu_threads, first_use, submit_batch, BoundTrace};
use crate::gpu::raytrace::layout::*;
use crate::gpu::raytrace::pairing;
use crate::gpu::raytrace::records::{records, SceneRecords};
use crate::gpu::shared::hook;
use crate::gpu::shared::image_size::check_image_size;
use crate::gpu::shared::lights::SceneLighting;
use crate::gpu::shared::shader_catalog::{
    RAYTRACE_COMP, RAYTRACE_PATHS_COMP, RAYTRACE_QUERY_COMP, RAYTRACE_QUERY_PATHS_COMP,
    RAYTRACE_WIDE_COMP, RAYTRACE_WIDE_PAIRED_COMP, RAYTRACE_WIDE_PATHS_COMP,
};
use crate::gpu::vk::commands::OneShot;
use crate::gpu::vk::context::DeviceInfo;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::descriptors::{create_set_layout, Descriptors};
use crate::gpu::vk::error::{GpuError, VkContext};
use crate::gpu::vk::pipeline::PipelineObjects;
use crate::gpu::vk::specialise::{specialise, Lowering};
use crate::gpu::vk::timestamps::{ms_since, GpuTimings, Timestamps};
use crate::linear_image::LinearImage;
use crate::rt_scene::{RayStats, RtScene};
use crate::scene::{LightingHook, Scene, Traversal};
use crate::work_counter::WorkCounter;

pub struct TraceOutput {
    pub image: LinearImage,
    pub timings: GpuTimings,
    /// Present when rays were counted.
    pub stats: Option<RayStats>,
    /// The engine that found the hits: `Bvh` or `Query`, never `Auto`.
    pub traversal: Traversal,
    /// With diffuse bounces: the pixels' fixed-point sums of the samples
    /// traced (`image` is their estimate of the part asked for).
    pub sums: Option<SampleSums>,
}

/// A render with bounces: its sums, and how many of the samples per pixel
/// asked for they hold.
pub struct SampleSums {
    pub film: FilmSums,
    pub traced: u32,
    /// Under an error budget, the render's last estimate of its RMSE.
    pub estimate: Option<f64>,
}

/// The engine a render uses: the one asked for, or for `Auto` the rule
/// measured in docs/raytracing.md ("The ray-query engine"): ray queries on
/// a device that offers them and is not a CPU (where the driver's traversal
/// runs in hardware), else the compute BVH. On lavapipe the compute BVH is
/// the faster of the two on every scene measured. Asking for `Query` on a
/// device without it is an error that says why.
pub fn engine_for(asked: Traversal, info: &DeviceInfo) -> Result<Traversal, GpuError> {
    let query_why_not = || info.no_ray_query_because.clone();
    match asked {
        Traversal::Bvh => Ok(Traversal::Bvh),
        Traversal::Query => match query_why_not() {
            None => Ok(Traversal::Query),
            Some(why) => Err(GpuError::NoRayQuery {
                device: info.name.clone(),
                why,
            }),
        },
        Traversal::Auto => Ok(if !info.is_cpu() && query_why_not().is_none() {
            Traversal::Query
        } else {
            Traversal::Bvh
        }),
    }
}

/// The ray tracer's pipeline for `traversal`; `wide_bvh`: the BVH walk
/// compiled for the tree's 4-wide form (`raytrace::wide_bvh`), a module of its own so
/// that a scene without a big tree neither compiles nor carries it; `paths`:
/// with diffuse bounces, likewise a module of its own.
fn create_pipeline(
    context: &Arc<GpuContext>,
    spec: &TraceSpecialization,
    lighting_hook: Option<&LightingHook>,
    choice: PipelineChoice,
    driver_specialises: bool,
) -> Result<PipelineObjects, GpuError> {
    let PipelineChoice {
        traversal,
        wide: wide_bvh,
        paths,
        paired,
    } = choice;
    let device = &context.device;
    let mut p = PipelineObjects::new(&context.device);
    p.set_layout = create_set_layout(context, BINDINGS, vk::ShaderStageFlags::COMPUTE)?;
    let mut set_layouts = vec![p.set_layout];
    // Each module with what `specialise` does for the driver: SSA form
    // only for the Whitted tracer's 4-wide walk, where it was measured not
    // to slow the trace (`Lowering`).
    let (shader, lowering) = if traversal == Traversal::Query {
        // Set 1 holds the acceleration structure alone.
        p.extra_set_layout =
            create_set_layout(context, QUERY_BINDINGS, vk::ShaderStageFlags::COMPUTE)?;
        set_layouts.push(p.extra_set_layout);
        if paths {
            (&RAYTRACE_QUERY_PATHS_COMP, Lowering::Inlined)
        } else {
            (&RAYTRACE_QUERY_COMP, Lowering::Inlined)
        }
    } else {
        match (wide_bvh, paths) {
            (true, true) => (&RAYTRACE_WIDE_PATHS_COMP, Lowering::Inlined),
            (true, false) if paired => (&RAYTRACE_WIDE_PAIRED_COMP, Lowering::InlinedSsa),
            (true, false) => (&RAYTRACE_WIDE_COMP, Lowering::InlinedSsa),
            (false, true) => (&RAYTRACE_PATHS_COMP, Lowering::Inlined),
            (false, false) => (&RAYTRACE_COMP, Lowering::Inlined),
        }
    };
    // With bounces, each dispatch's range of samples.
    let push = [vk::PushConstantRange::default()
        .stage_flags(vk::ShaderStageFlags::COMPUTE)
        .size(std::mem::size_of::<SampleRange>() as u32)];
    let push: &[vk::PushConstantRange] = if paths { &push } else { &[] };
    let layout_info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&set_layouts)
        .push_constant_ranges(push);
    // SAFETY: valid device and create infos throughout this function.
    p.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
        .during("vkCreatePipelineLayout")?;
    let entries = TraceSpecialization::map_entries();
    let spec_data = bytemuck::bytes_of(spec);
    let mut words = hook::module_words(shader, lighting_hook, &context.info)?;
    let specialised = if driver_specialises {
        None
    } else {
        specialise(&words, &entries, spec_data, lowering)?
    };
    // Without `spirv-opt` the driver takes the constants, as asked for
    // with `driver_specialises`.
    let driver_specialises = specialised.is_none();
    if let Some(specialised) = specialised {
        words = specialised;
    }
    p.create_compute(&words, (&entries, spec_data), driver_specialises)?;
    Ok(p)
}

/// How to trace: what `render` does beyond the image.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TraceOptions {
    /// Count rays by kind (`--stats`): atomics, so a little slower.
    pub count_rays: bool,
    /// Compile every optional feature in (reflection, refraction, the
    /// specular term, the BVH walk) whether the scene uses it or not, as an
    /// uber-shader would: what specialising saves (`bench
    /// --every-feature`). The image is the same. Switches that change the
    /// image (shadows, attenuation) stay as the scene sets them.
    pub every_feature: bool,
    /// Hand the driver the module with its specialization constants and
    /// their values, as before `specialise` (what specialising before the
    /// driver saves, and the test that it changes no pixel).
    pub driver_specialises: bool,
    /// Two eye rays a lane (`pairing`): None for the device's choice.
    pub pair_eye_rays: Option<bool>,
}

/// Only what the scene uses: the lighting terms every pipeline sets
/// (`SceneLighting`), shadows if on, reflection and
/// refraction if some material has them, the objects tested one by one and
/// the kinds the BVH holds (`BvhKinds`), the materials held in registers
/// if few; or every feature on (`TraceOptions::every_feature`).
pub(super) fn specialization(
    scene: &Scene,
    rt: &RtScene,
    options: TraceOptions,
) -> TraceSpecialization {
    let lighting = SceneLighting::of(scene);
    let on = |used: bool| u32::from(used || options.every_feature);
    let in_bvh = BvhKinds::of(rt);
    let listed = |in_bvh: bool, count: usize| if in_bvh { 0 } else { count as i32 };
    let materials_listed = lists_materials(rt.materials.len());
    let fixed_sampler = if options.every_feature {
        None
    } else {
        crate::gpu::shared::texture_table::TextureTable::common_sampler(&rt.materials)
    };
    TraceSpecialization {
        light_count: lighting.light_count,
        use_specular: on(lighting.use_specular),
        use_attenuation: u32::from(lighting.use_attenuation),
        inverse_square: u32::from(lighting.inverse_square),
        shadows: u32::from(rt.render.shadows && !rt.lights.is_empty()),
        has_reflection: on(rt.has_reflection() && rt.render.depth > 0),
        has_transmission: on(rt.has_transmission() && rt.render.depth > 0),
        sphere_count: listed(in_bvh.spheres, rt.spheres.len()),
        plane_count: listed(in_bvh.planes, rt.planes.len()),
        box_count: listed(in_bvh.boxes, rt.boxes.len()),
        has_bvh: on(!rt.triangles.is_empty() || in_bvh != BvhKinds::default()),
        count_rays: u32::from(options.count_rays),
        bvh_spheres: on(in_bvh.spheres),
        bvh_planes: on(in_bvh.planes),
        bvh_boxes: on(in_bvh.boxes),
        materials_listed: u32::from(materials_listed),
        material_count: if materials_listed {
            rt.materials.len() as i32
        } else {
            0
        },
        vertex_colors: u32::from(!rt.triangle_colors.is_empty()),
        patterns: u32::from(rt.materials.iter().any(|m| m.pattern.is_some())),
        textures: u32::from(
            rt.materials
                .iter()
                .any(|m| matches!(m.pattern, Some(crate::scene::Pattern::Image(_)))),
        ),
        sampler_fixed: u32::from(fixed_sampler.is_some()),
        fixed_sampler: fixed_sampler.unwrap_or(0),
        huge_sphere_count: rt.huge_spheres.len() as i32,
    }
}

/// Ray traces `scene` at its `image` size as `options` say: `part`'s
/// samples of each pixel (all of them, a shard's, or with diffuse bounces
/// those before a time budget), counted into `counter` as batches finish.
pub fn render(
    context: &Arc<GpuContext>,
    scene: &Scene,
    options: TraceOptions,
    part: &RenderPart,
    counter: &WorkCounter,
) -> Result<TraceOutput, GpuError> {
    let _watch = crate::gpu::shared::watch::watch_render(scene);
    let started = Instant::now();
    let (width, height) = (scene.image.width, scene.image.height);
    let traversal = check_and_choose_engine(context, scene)?;
    let view = View::new(scene, width, height);

    let lights = crate::gpu::shared::lights::lights(scene, view.eye);
    let pixels = u64::from(width) * u64::from(height);
    let upload = |plan: &mut TracePlan| {
        if plan.spec.has_bvh != 0 && plan.records.bvh.root.is_none() {
            // The BVH walk compiled in for a scene with nothing in its BVH:
            // a leaf of one degenerate triangle, which no ray hits.
            plan.records.add_unhittable_triangle();
        }
        // Four floats a pixel, or with bounces three 64-bit sums.
        let pixel_bytes = pixels * if plan.rt.render.bounces > 0 { 24 } else { 16 };
        TraceBuffers::upload(
            context,
            &lights,
            &view,
            &plan.rt,
            &plan.records,
            pixel_bytes,
        )
    };
    let Prepared {
        plan,
        mut buffers,
        pipeline,
        prepare_ms,
        upload_ms,
        pipeline_ms,
    } = plan_and_pipeline(context, scene, options, traversal, upload)?;

    let binding_started = Instant::now();
    let paths = plan.rt.render.bounces > 0;
    if paths {
        buffers.zero_output();
    }
    let descriptors = buffers.bind(context, pipeline.set_layout)?;
    let structure = build_structure(context, &plan, &pipeline)?;
    let groups = workgroups(width, height, context.info.is_cpu(), cpu_threads());
    let bound = BoundTrace {
        pipeline: &pipeline,
        set: descriptors.set,
        structure_set: structure.as_ref().map(|(_, set)| set.set),
        work_queue: buffers.work_queue.raw,
        // With bounces, an empty range for the first use (which takes
        // no item); each batch pushes its own.
        push_constants: if paths { EMPTY_RANGE } else { &[] },
    };
    let upload_ms = upload_ms + ms_since(binding_started);

    let codegen_ms = first_use(context, &bound)?;
    let (submit_ms, gpu_ms, traced, estimate) = if paths {
        let work = sample_work(&buffers, (width, height), plan.rt.render.bounces);
        let run = trace_samples(context, (&bound, groups), &work, part, counter)?;
        (run.submit_ms, run.gpu_ms, run.traced, run.estimate)
    } else {
        let (submit_ms, gpu_ms) = trace_image(context, &bound, groups)?;
        (submit_ms, gpu_ms, scene.render.samples, None)
    };

    let readback_started = Instant::now();
    let sums = paths.then(|| SampleSums {
        film: FilmSums::from_ne_bytes(width, height, buffers.output()),
        traced,
        estimate,
    });
    let image = match &sums {
        Some(s) => crate::film_sums::scaled_image(&s.film, u64::from(s.traced), part.count()),
        None => buffers.image(width, height),
    };
    let stats = options.count_rays.then(|| buffers.ray_stats());
    Ok(TraceOutput {
        image,
        timings: GpuTimings {
            prepare_ms,
            pipeline_ms,
            upload_ms,
            codegen_ms: Some(codegen_ms),
            gpu_ms,
            submit_ms,
            readback_ms: ms_since(readback_started),
            total_ms: ms_since(started),
        },
        stats,
        traversal,
        sums,
    })
}

/// The film of a ray trace with bounces: its samples per pixel in batches
/// of about the same work, its halves the sequence's two streams.
fn sample_work(
    buffers: &TraceBuffers,
    (width, height): (u32, u32),
    bounces: u32,
) -> batches::FilmWork<'_> {
    let pixels = u64::from(width) * u64::from(height);
    batches::FilmWork {
        buffers,
        size: (width, height),
        unit: "samples per pixel",
        batch: batches::batch_samples(pixels, bounces),
        halves: batches::Halves::ByStream,
    }
}

/// With bounces, `part`'s samples of every pixel, a range of them per
/// dispatch of `groups` workgroups (`batches`).
fn trace_samples(
    context: &Arc<GpuContext>,
    (bound, groups): (&BoundTrace, (u32, u32)),
    work: &batches::FilmWork,
    part: &RenderPart,
    counter: &WorkCounter,
) -> Result<batches::BatchesRun, GpuError> {
    batches::run(
        context,
        work,
        part,
        counter,
        &mut |timestamps, first, end, step| {
            let range = SampleRange {
                first,
                end,
                step,
                unused: 0,
            };
            let push = bytemuck::bytes_of(&range);
            submit_batch(context, bound, Some(timestamps), push, (0, groups))
        },
    )
}

/// The whole image in one dispatch of `groups` workgroups (the Whitted
/// tracer): its submit and GPU milliseconds.
fn trace_image(
    context: &Arc<GpuContext>,
    bound: &BoundTrace,
    groups: (u32, u32),
) -> Result<(f64, f64), GpuError> {
    let timestamps = Timestamps::new(context)?;
    let commands = OneShot::begin(context)?;
    // SAFETY: every handle recorded here lives until after the submission
    // completes (this function waits for it).
    unsafe { bound.record_image(&context.device, commands.cmd, &timestamps, groups) };
    timestamps.submit_and_measure(&commands)
}

/// The push constants of a dispatch that traces no sample.
const EMPTY_RANGE: &[u8] = &[0; std::mem::size_of::<SampleRange>()];

/// The engine that traces `scene`, after refusing what cannot be traced
/// here: a device without the ray tracer, an image over the device's
/// limits, an engine the device lacks, or a hook on ray queries.
fn check_and_choose_engine(
    context: &Arc<GpuContext>,
    scene: &Scene,
) -> Result<Traversal, GpuError> {
    if let Some(why) = &context.info.no_ray_tracer_because {
        return Err(GpuError::NoRayTracer {
            device: context.info.name.clone(),
            why: why.clone(),
        });
    }
    check_image_size(context, scene.image.width, scene.image.height)?;
    // `auto` with a hook takes the BVH engine, which is the one a hook can
    // run on (below), where a GPU's `auto` would take ray queries.
    let traversal = match (scene.render.traversal, &scene.lighting_hook) {
        (Traversal::Auto, Some(_)) => Traversal::Bvh,
        (asked, _) => engine_for(asked, &context.info)?,
    };
    if let (Traversal::Query, Some(hook)) = (traversal, &scene.lighting_hook) {
        return Err(GpuError::LightingHook(format!(
            "{} cannot run with --traversal query: a hook's module is checked by naga, which cannot \
             read ray queries; use --traversal bvh",
            hook.path
        )));
    }
    Ok(traversal)
}

/// The host's work on the scene before any Vulkan call: the scene both
/// tracers read, its records, and what the pipeline specialises on.
struct TracePlan {
    traversal: Traversal,
    rt: RtScene,
    records: SceneRecords,
    /// Each mesh's run of triangle records, for the ray-query engine's
    /// structures; empty for the BVH engine.
    meshes: Vec<(u32, u32)>,
    spec: TraceSpecialization,
}

impl TracePlan {
    /// The plan over `rt`, its tree built: the records, refused where they
    /// cannot hold the scene (before the pipeline is waited for).
    fn new(rt: RtScene, spec: TraceSpecialization, traversal: Traversal) -> Result<Self, GpuError> {
        let mut records = records(&rt)?;
        let meshes = match traversal {
            Traversal::Query => accel::group_by_mesh(&mut records),
            _ => Vec::new(),
        };
        Ok(Self {
            traversal,
            rt,
            records,
            meshes,
            spec,
        })
    }
}

/// Primitives in the BVH from which its tree is taken to be walked 4-wide
/// before it is built, so that the pipeline can be built meanwhile
/// (`wide_bvh::widen` decides; where it does not widen such a tree, the
/// binary walk's pipeline is built after). Far above `WIDE_MIN_INNER_NODES`
/// nodes' worth: below it the tree takes under a millisecond.
const WIDE_GUESS_MIN_PRIMITIVES: usize = 1024;

/// The plan, its buffers as `upload` fills them, and its pipeline, with the
/// time each took from this thread. The pipeline (lavapipe's translation
/// of the module, tens of milliseconds) is built on a thread of its own
/// while this one uploads; for a big tree, whose build or read from the
/// cache is tens of milliseconds too, it is started before the tree, as
/// the 4-wide walk's, and rebuilt as the binary walk's after it where
/// `widen` does not widen the tree. `pipeline_ms` is the wait for it after
/// the plan and the upload.
fn plan_and_pipeline(
    context: &Arc<GpuContext>,
    scene: &Scene,
    options: TraceOptions,
    traversal: Traversal,
    upload: impl FnOnce(&mut TracePlan) -> Result<TraceBuffers, GpuError>,
) -> Result<Prepared, GpuError> {
    let started = Instant::now();
    let mut rt = RtScene::without_tree(scene);
    let spec = specialization(scene, &rt, options);
    let paths = rt.render.bounces > 0;
    let in_bvh = BvhKinds::of(&rt).primitives(&rt);
    let eye_rays = u64::from(scene.image.width)
        * u64::from(scene.image.height)
        * u64::from(scene.render.samples.max(1));
    let pairs = options
        .pair_eye_rays
        .unwrap_or_else(|| pairing::pairs_eye_rays(&context.info, eye_rays));
    let build_pipeline = |wide: bool| {
        let choice = PipelineChoice {
            traversal,
            wide,
            paths,
            // Over the wide walk, for Whitted's tracer (its eye rays).
            paired: pairs && wide && !paths && traversal == Traversal::Bvh,
        };
        get_or_build_pipeline(context, scene, &spec, choice, options)
    };
    let build = &build_pipeline;
    let guess_wide = traversal == Traversal::Bvh && in_bvh >= WIDE_GUESS_MIN_PRIMITIVES;
    let join = |handle: std::thread::ScopedJoinHandle<'_, _>| {
        handle
            .join()
            .unwrap_or_else(|p| std::panic::resume_unwind(p))
    };
    std::thread::scope(|threads| {
        let early = guess_wide.then(|| threads.spawn(move || build(true)));
        rt.add_cached_tree();
        let mut plan = TracePlan::new(rt, spec, traversal)?;
        let prepare_ms = ms_since(started);
        let wide = plan.records.bvh.wide.is_some();
        let late = match early {
            Some(_) if wide => None,
            _ => Some(threads.spawn(move || build(wide))),
        };
        let upload_started = Instant::now();
        let buffers = upload(&mut plan);
        let upload_ms = ms_since(upload_started);
        let pipeline_started = Instant::now();
        // A guess the tree did not bear out is waited for, not used.
        let early = early.map(join);
        let pipeline = match late {
            Some(late) => join(late),
            None => early.expect("no late pipeline where the guess held"),
        }?;
        Ok(Prepared {
            buffers: buffers?,
            plan,
            pipeline,
            prepare_ms,
            upload_ms,
            pipeline_ms: ms_since(pipeline_started),
        })
    })
}

/// What `plan_and_pipeline` gives.
struct Prepared {
    plan: TracePlan,
    buffers: TraceBuffers,
    pipeline: Arc<PipelineObjects>,
    prepare_ms: f64,
    upload_ms: f64,
    pipeline_ms: f64,
}

/// Which of the ray tracer's modules a pipeline is built from.
#[derive(Clone, Copy, Debug)]
struct PipelineChoice {
    traversal: Traversal,
    /// The 4-wide walk (`wide_bvh`).
    wide: bool,
    /// With diffuse bounces.
    paths: bool,
    /// Two eye rays a lane (`pairing`).
    paired: bool,
}

/// The pipeline for `spec` and `choice`, from the context's cache or built
/// now.
fn get_or_build_pipeline(
    context: &Arc<GpuContext>,
    scene: &Scene,
    spec: &TraceSpecialization,
    choice: PipelineChoice,
    options: TraceOptions,
) -> Result<Arc<PipelineObjects>, GpuError> {
    let PipelineChoice {
        traversal,
        wide,
        paths,
        paired,
    } = choice;
    let hook = scene.lighting_hook.as_deref();
    let driver_specialises = options.driver_specialises;
    let key = format!(
        "raytrace {traversal:?} wide {wide} paths {paths} paired {paired} driver {driver_specialises} spec {:?} hook {:016x}",
        bytemuck::bytes_of(spec),
        crate::cache::digest(&hook.map(|h| &h.source)),
    );
    context.pipelines.get_or_create(key, || {
        create_pipeline(context, spec, hook, choice, driver_specialises)
    })
}

/// The ray-query engine's structures, built (and waited for) before the
/// timed work, as the compute BVH is built on the host before it; with
/// the set that binds them. None for the BVH engine.
fn build_structure(
    context: &Arc<GpuContext>,
    plan: &TracePlan,
    pipeline: &PipelineObjects,
) -> Result<Option<(SceneStructure, Descriptors)>, GpuError> {
    match plan.traversal {
        Traversal::Query => {
            let built = accel::build(context, &plan.rt, &plan.records, &plan.meshes)?;
            let set = Descriptors::for_structure(
                context,
                pipeline.extra_set_layout,
                QUERY_BINDINGS,
                built.top,
            )?;
            Ok(Some((built, set)))
        }
        _ => Ok(None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{default_scene, Shape};

    fn device(device_type: vk::PhysicalDeviceType, ray_query: bool) -> DeviceInfo {
        DeviceInfo {
            index: 0,
            name: "test device".into(),
            driver: String::new(),
            device_type: format!("{device_type:?}"),
            api_version: "1.3.0".into(),
            is_lavapipe: false,
            shader_float16: false,
            msaa_counts: vec![1],
            viewport_subpixel_bits: 8,
            unusable_because: None,
            no_ray_tracer_because: None,
            no_ray_query_because: (!ray_query).then(|| "lacks VK_KHR_ray_query".into()),
            no_forward_because: None,
        }
    }

    /// `auto`: ray queries on a GPU that has them, the compute BVH on a CPU
    /// device (lavapipe) or without them; an engine asked for is the one
    /// used, and `query` without support is refused with the reason.
    #[test]
    fn the_engine_follows_the_request_and_the_rule() {
        use vk::PhysicalDeviceType as T;
        let cases = [
            (T::DISCRETE_GPU, true, Traversal::Query),
            (T::INTEGRATED_GPU, true, Traversal::Query),
            (T::DISCRETE_GPU, false, Traversal::Bvh),
            (T::CPU, true, Traversal::Bvh),
            (T::CPU, false, Traversal::Bvh),
        ];
        for (ty, query, auto) in cases {
            let info = device(ty, query);
            assert_eq!(
                engine_for(Traversal::Auto, &info).unwrap(),
                auto,
                "{ty:?} {query}"
            );
            assert_eq!(engine_for(Traversal::Bvh, &info).unwrap(), Traversal::Bvh);
            match engine_for(Traversal::Query, &info) {
                Ok(engine) => assert!(query && engine == Traversal::Query),
                Err(e) => {
                    assert!(!query);
                    let message = e.to_string();
                    assert!(message.contains("lacks VK_KHR_ray_query"), "{message}");
                    assert!(e.is_bad_input());
                }
            }
        }
    }

    /// `every_feature` turns on every switch that leaves the image alone and
    /// none that would change it; without it, only what the scene uses.
    #[test]
    fn every_feature_turns_on_what_the_scene_leaves_out_and_no_more() {
        let mut scene = default_scene();
        scene
            .objects
            .retain(|o| matches!(o.shape, Shape::Sphere { .. }));
        for m in &mut scene.materials {
            (m.ks, m.kr, m.kt) = (0.0, 0.0, 0.0);
        }
        scene.lighting.falloff = crate::scene::Falloff::None;
        scene.render.depth = 3;
        let rt = RtScene::new(&scene);
        let plain = specialization(&scene, &rt, TraceOptions::default());
        let every = specialization(
            &scene,
            &rt,
            TraceOptions {
                every_feature: true,
                ..TraceOptions::default()
            },
        );
        let switches = |s: &TraceSpecialization| {
            [
                s.use_specular,
                s.has_reflection,
                s.has_transmission,
                s.has_bvh,
                s.bvh_spheres,
                s.bvh_planes,
                s.bvh_boxes,
            ]
        };
        assert_eq!(switches(&plain), [0; 7], "the scene uses none");
        assert_eq!(switches(&every), [1; 7]);
        // Shadows and attenuation change the image: they stay the scene's.
        assert_eq!(every.shadows, plain.shadows);
        assert_eq!(plain.shadows, 1);
        assert_eq!(every.use_attenuation, 0);
        assert_eq!(every.sphere_count, plain.sphere_count);
    }

    /// The ray tracer compiles vertex colours and patterns in only for a
    /// scene that has them.
    #[test]
    fn colour_features_are_specialised_on_only_where_used() {
        let mut scene = default_scene();
        let spec = |scene: &Scene| {
            let rt = RtScene::new(scene);
            specialization(scene, &rt, TraceOptions::default())
        };
        let plain = spec(&scene);
        assert_eq!((plain.vertex_colors, plain.patterns), (0, 0));
        scene.materials[0].pattern = Some(crate::scene::Pattern::Checker {
            scale: 2.0,
            colors: [glam::DVec3::ONE, glam::DVec3::ZERO],
        });
        assert_eq!(spec(&scene).patterns, 1);
        assert_eq!(spec(&scene).vertex_colors, 0);
        let mut mesh = crate::scene::tessellate(&scene.objects[0].shape);
        mesh.colors = vec![glam::DVec3::ONE; mesh.positions.len()];
        scene.objects[0].shape = Shape::Mesh(mesh);
        assert_eq!(spec(&scene).vertex_colors, 1);
    }
}
