//! The ray tracer: `shaders/raytrace.comp.glsl`, whose subgroups take the
//! image from a work queue, over the scene's `RtScene` (exact primitives,
//! triangles and BVH uploaded as storage buffers in the layouts of
//! `raytrace::records`), writing linear float pixels to a buffer the host reads
//! back. The algorithm is docs/raytracing.md. Its hits come from the
//! shader's own BVH walk or, with `Traversal::Query`, from ray queries
//! through the structures of `raytrace::accel` (`engine_for` picks).

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::camera::View;
use crate::gpu::raytrace::accel::{self, SceneStructure};
use crate::gpu::raytrace::bvh::BvhKinds;
use crate::gpu::raytrace::layout::*;
use crate::gpu::raytrace::records::{records, v4};
use crate::gpu::shared::hook;
use crate::gpu::shared::image_size::check_image_size;
use crate::gpu::shared::lights::{lights, SceneLighting};
use crate::gpu::shared::shader_catalog::{RAYTRACE_COMP, RAYTRACE_QUERY_COMP, RAYTRACE_WIDE_COMP};
use crate::gpu::vk::buffer::Buffer;
use crate::gpu::vk::commands::OneShot;
use crate::gpu::vk::context::DeviceInfo;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::descriptors::{create_set_layout, Descriptors};
use crate::gpu::vk::error::{GpuError, VkContext};
use crate::gpu::vk::pipeline::{single_pipeline, PipelineObjects};
use crate::gpu::vk::specialise::specialise;
use crate::gpu::vk::timestamps::{ms_since, GpuTimings, Timestamps};
use crate::linear_image::LinearImage;
use crate::rt_scene::{sample_grid, RayStats, RtScene};
use crate::scene::{LightingHook, Scene, Traversal};

pub struct TraceOutput {
    pub image: LinearImage,
    pub timings: GpuTimings,
    /// Present when rays were counted.
    pub stats: Option<RayStats>,
    /// The engine that found the hits: `Bvh` or `Query`, never `Auto`.
    pub traversal: Traversal,
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
/// that a scene without a big tree neither compiles nor carries it.
fn create_pipeline(
    context: &Arc<GpuContext>,
    spec: &TraceSpecialization,
    lighting_hook: Option<&LightingHook>,
    traversal: Traversal,
    wide_bvh: bool,
    driver_specialises: bool,
) -> Result<PipelineObjects, GpuError> {
    let device = &context.device;
    let mut p = PipelineObjects::new(&context.device);
    p.set_layout = create_set_layout(context, BINDINGS, vk::ShaderStageFlags::COMPUTE)?;
    let mut set_layouts = vec![p.set_layout];
    let shader = if traversal == Traversal::Query {
        // Set 1 holds the acceleration structure alone.
        p.extra_set_layout =
            create_set_layout(context, QUERY_BINDINGS, vk::ShaderStageFlags::COMPUTE)?;
        set_layouts.push(p.extra_set_layout);
        &RAYTRACE_QUERY_COMP
    } else if wide_bvh {
        &RAYTRACE_WIDE_COMP
    } else {
        &RAYTRACE_COMP
    };
    let layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
    // SAFETY: valid device and create infos throughout this function.
    p.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
        .during("vkCreatePipelineLayout")?;
    let entries = TraceSpecialization::map_entries();
    let spec_data = bytemuck::bytes_of(spec);
    let mut words = hook::module_words(shader, lighting_hook, &context.info)?;
    let specialised = if driver_specialises {
        None
    } else {
        specialise(&words, &entries, spec_data)?
    };
    // Without `spirv-opt` the driver takes the constants, as asked for
    // with `driver_specialises`.
    let driver_specialises = specialised.is_none();
    if let Some(specialised) = specialised {
        words = specialised;
    }
    let module_info = vk::ShaderModuleCreateInfo::default().code(&words);
    // SAFETY: the words are SPIR-V validated by naga (at build time, or with
    // the hook by `hook::module_words`), or for the ray-query engine by
    // spirv-val at build time, then specialised by SPIRV-Tools' optimizer.
    let module = unsafe { device.create_shader_module(&module_info, None) }
        .during("vkCreateShaderModule")?;
    p.modules.push(module);
    let spec_info = vk::SpecializationInfo::default()
        .map_entries(&entries)
        .data(spec_data);
    let mut stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"main");
    if driver_specialises {
        // Otherwise the constants are in the module already.
        stage = stage.specialization_info(&spec_info);
    }
    let info = vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(p.layout);
    // SAFETY: every pointer in `info` refers to locals alive for the call.
    let created =
        unsafe { device.create_compute_pipelines(vk::PipelineCache::null(), &[info], None) };
    p.pipeline = single_pipeline(created, "vkCreateComputePipelines")?;
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
}

/// Only what the scene uses: the lighting terms every pipeline sets
/// (`SceneLighting`), shadows if on, reflection and
/// refraction if some material has them, the objects tested one by one and
/// the kinds the BVH holds (`BvhKinds`), the materials held in registers
/// if few; or every feature on (`TraceOptions::every_feature`).
fn specialization(scene: &Scene, rt: &RtScene, options: TraceOptions) -> TraceSpecialization {
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

/// Ray traces `scene` at its `image` size; counts rays if `count_rays`.
pub fn render(
    context: &Arc<GpuContext>,
    scene: &Scene,
    count_rays: bool,
) -> Result<TraceOutput, GpuError> {
    let options = TraceOptions {
        count_rays,
        ..TraceOptions::default()
    };
    render_with(context, scene, options)
}

/// Ray traces `scene` at its `image` size as `options` say.
pub fn render_with(
    context: &Arc<GpuContext>,
    scene: &Scene,
    options: TraceOptions,
) -> Result<TraceOutput, GpuError> {
    let count_rays = options.count_rays;
    let started = Instant::now();
    if let Some(why) = &context.info.no_ray_tracer_because {
        return Err(GpuError::NoRayTracer {
            device: context.info.name.clone(),
            why: why.clone(),
        });
    }
    let (width, height) = (scene.image.width, scene.image.height);
    check_image_size(context, width, height)?;
    let view = View::new(scene, width, height);
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
    let prepare_started = Instant::now();
    let rt = RtScene::new(scene);
    // Refuses what the records cannot hold before building the pipeline.
    let mut r = records(&rt)?;
    let meshes = match traversal {
        Traversal::Query => accel::group_by_mesh(&mut r),
        _ => Vec::new(),
    };
    let spec = specialization(scene, &rt, options);
    let prepare_ms = ms_since(prepare_started);
    let pipeline_started = Instant::now();
    let hook = scene.lighting_hook.as_deref();
    let wide = r.bvh.wide.is_some();
    let driver_specialises = options.driver_specialises;
    let key = format!(
        "raytrace {traversal:?} wide {wide} driver {driver_specialises} spec {:?} hook {:016x}",
        bytemuck::bytes_of(&spec),
        crate::cache::digest(&hook.map(|h| &h.source)),
    );
    let pipeline = context.pipelines.get_or_create(key, || {
        create_pipeline(context, &spec, hook, traversal, wide, driver_specialises)
    })?;
    let pipeline_ms = ms_since(pipeline_started);

    let upload_started = Instant::now();
    if spec.has_bvh != 0 && r.bvh.root.is_none() {
        // The BVH walk compiled in for a scene with nothing in its BVH: a
        // leaf of one degenerate triangle, which no ray hits.
        r.add_unhittable_triangle();
    }
    let (kx, ky) = sample_grid(rt.render.samples);
    let uniforms = TraceUniforms {
        ambient_k: v4(rt.lighting.ambient, rt.lighting.k as f32),
        background: v4(rt.background, 0.0),
        right_focal: v4(view.right, view.focal as f32),
        up_aspect: v4(view.up, view.aspect as f32),
        forward_cutoff: v4(view.forward, rt.render.cutoff as f32),
        image: [width, height, rt.render.samples, rt.render.depth],
        grid: [
            kx,
            ky,
            rt.spheres.len() as u32,
            r.bvh.walk_root().unwrap_or(0),
        ],
        leaf_bases: [
            r.bvh.bases.spheres,
            r.bvh.bases.planes,
            r.bvh.bases.boxes,
            0,
        ],
        bvh_sphere: r.bvh.bounding_sphere(),
    };
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let upload = |name: &str, bytes: &[u8]| Buffer::with_data(context, name, bytes, storage);
    let lights = upload("lights", bytemuck::cast_slice(&lights(scene, view.eye)))?;
    let spheres = upload("spheres", bytemuck::cast_slice(&r.spheres))?;
    let planes = upload("planes", bytemuck::cast_slice(&r.planes))?;
    let boxes = upload("boxes", bytemuck::cast_slice(&r.boxes))?;
    let triangles = upload("triangles", bytemuck::cast_slice(&r.triangles))?;
    let nodes = upload("bvh nodes", r.bvh.walk_nodes())?;
    let triangle_shading = upload(
        "triangle shading",
        bytemuck::cast_slice(&r.triangle_shading),
    )?;
    // Bound whether or not the scene has vertex colours, patterns or
    // images: the bindings are in the module either way, read only where
    // VERTEX_COLORS, PATTERNS or TEXTURES is on.
    let triangle_colors = upload("triangle colours", bytemuck::cast_slice(&r.triangle_colors))?;
    let triangle_uvs = upload(
        "triangle texture coordinates",
        bytemuck::cast_slice(&r.triangle_uvs),
    )?;
    let patterns = upload("patterns", bytemuck::cast_slice(&r.patterns))?;
    let texture_records = upload("texture records", bytemuck::cast_slice(&r.texture_records))?;
    let texels = upload("texels", bytemuck::cast_slice(&r.texels))?;
    // Zeroed on the device before the dispatch (below), whatever memory
    // the allocator hands out.
    let work_queue = Buffer::new(
        context,
        "work queue",
        4,
        storage | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )?;
    let materials = upload("materials", bytemuck::cast_slice(&r.materials))?;
    let uniform_buffer = Buffer::with_data(
        context,
        "trace uniforms",
        bytemuck::bytes_of(&uniforms),
        vk::BufferUsageFlags::UNIFORM_BUFFER,
    )?;
    let pixel_bytes = u64::from(width) * u64::from(height) * 16;
    let output = Buffer::new(
        context,
        "pixels",
        pixel_bytes,
        storage,
        MemoryLocation::GpuToCpu,
    )?;
    let mut stats = Buffer::new(context, "ray stats", 32, storage, MemoryLocation::GpuToCpu)?;
    stats.mapped_mut()[..32].fill(0);
    let descriptors = Descriptors::new(
        context,
        pipeline.set_layout,
        BINDINGS,
        &[
            &lights,
            &uniform_buffer,
            &spheres,
            &planes,
            &boxes,
            &triangles,
            &nodes,
            &triangle_shading,
            &materials,
            &output,
            &stats,
            &work_queue,
            &triangle_colors,
            &triangle_uvs,
            &patterns,
            &texture_records,
            &texels,
        ],
    )?;

    // The ray-query engine's structures, built (and waited for) before the
    // timed work, as the compute BVH is built on the host before it.
    let structure: Option<(SceneStructure, Descriptors)> = match traversal {
        Traversal::Query => {
            let built = accel::build(context, &rt, &r, &meshes)?;
            let set = Descriptors::for_structure(
                context,
                pipeline.extra_set_layout,
                QUERY_BINDINGS,
                built.top,
            )?;
            Some((built, set))
        }
        _ => None,
    };

    let (groups_x, groups_y) = workgroups(width, height, context.info.is_cpu(), cpu_threads());
    let bound = BoundTrace {
        pipeline: &pipeline,
        set: descriptors.set,
        structure_set: structure.as_ref().map(|(_, set)| set.set),
        work_queue: work_queue.raw,
    };
    let upload_ms = ms_since(upload_started);
    let codegen_ms = first_use(context, &bound)?;
    let timestamps = Timestamps::new(context)?;
    let commands = OneShot::begin(context)?;
    let cmd = commands.cmd;
    let device = &context.device;
    // SAFETY: every handle recorded here lives until after the submission
    // completes (dropped at the end of this function); the barrier orders
    // the shader's writes before the host reads.
    unsafe {
        bound.record(device, cmd, 0, |cmd| {
            timestamps.start(cmd);
            device.cmd_dispatch(cmd, groups_x, groups_y, 1);
        });
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST | vk::PipelineStageFlags2::ALL_COMMANDS)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&to_host),
        );
        timestamps.stop(cmd);
    }
    let (submit_ms, gpu_ms) = timestamps.submit_and_measure(&commands)?;

    let readback_started = Instant::now();
    let image = LinearImage::from_rgba32f_bytes(width, height, output.mapped());
    let counter = |i: usize| {
        let b = &stats.mapped()[i * 4..i * 4 + 4];
        u32::from_ne_bytes([b[0], b[1], b[2], b[3]])
    };
    let stats = count_rays.then(|| RayStats {
        primary: u64::from(counter(0)),
        shadow: u64::from(counter(1)),
        reflected: u64::from(counter(2)),
        refracted: u64::from(counter(3)),
        pruned: u64::from(counter(4)),
        max_depth_reached: counter(5),
    });
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
    })
}

/// A work-queue head past any image's last item: a dispatch that starts
/// from it takes no item, so every subgroup ends at once.
const QUEUE_EXHAUSTED: u32 = 0x8000_0000;

/// The ray tracer's pipeline and what it reads, bound for a dispatch.
struct BoundTrace<'a> {
    pipeline: &'a PipelineObjects,
    set: vk::DescriptorSet,
    /// The ray-query engine's set of the acceleration structure.
    structure_set: Option<vk::DescriptorSet>,
    work_queue: vk::Buffer,
}

impl BoundTrace<'_> {
    /// Records the work queue set to `queue_head`, the pipeline and its
    /// sets bound, then `dispatch`.
    ///
    /// # Safety
    /// `cmd` is recording, and every handle in `self` lives until the
    /// submission that runs it has completed.
    unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        queue_head: u32,
        dispatch: impl FnOnce(vk::CommandBuffer),
    ) {
        // An earlier dispatch's atomics on the queue (the first use's, in
        // an earlier submission) come before this write.
        let queue_used = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::CLEAR)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_WRITE)];
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&queue_used),
        );
        device.cmd_fill_buffer(cmd, self.work_queue, 0, vk::WHOLE_SIZE, queue_head);
        let queue_set = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::CLEAR)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .dst_access_mask(
                vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            )];
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&queue_set),
        );
        let p = self.pipeline;
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.pipeline);
        let bind = vk::PipelineBindPoint::COMPUTE;
        device.cmd_bind_descriptor_sets(cmd, bind, p.layout, 0, &[self.set], &[]);
        if let Some(structure_set) = self.structure_set {
            // The structures were built by an earlier submission on this
            // queue: their writes must reach the shader's reads.
            let built = [vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::ACCELERATION_STRUCTURE_BUILD_KHR)
                .src_access_mask(vk::AccessFlags2::ACCELERATION_STRUCTURE_WRITE_KHR)
                .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
                .dst_access_mask(vk::AccessFlags2::ACCELERATION_STRUCTURE_READ_KHR)];
            device
                .cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&built));
            device.cmd_bind_descriptor_sets(cmd, bind, p.layout, QUERY_SET, &[structure_set], &[]);
        }
        dispatch(cmd);
    }
}

/// The pipeline's first use, apart from the render, in milliseconds: one
/// workgroup over an exhausted work queue, which traces nothing. Lavapipe
/// generates a pipeline's machine code at its first dispatch (or loads it
/// from Mesa's shader cache), so this is that cost alone, and `gpu_ms`
/// after it is the trace alone, on a cold cache as on a warm one.
fn first_use(context: &Arc<GpuContext>, bound: &BoundTrace) -> Result<f64, GpuError> {
    let started = Instant::now();
    let commands = OneShot::begin(context)?;
    let device = &context.device;
    // SAFETY: `bound`'s handles outlive this function, which waits for the
    // submission; the shader takes no item and writes no pixel.
    unsafe {
        bound.record(device, commands.cmd, QUEUE_EXHAUSTED, |cmd| {
            device.cmd_dispatch(cmd, 1, 1, 1)
        });
    }
    commands.submit_and_wait()?;
    context.check_validation()?;
    Ok(ms_since(started))
}

/// The threads a CPU device (lavapipe) runs a dispatch on: one per CPU,
/// or `LP_NUM_THREADS` where that asks for more.
fn cpu_threads() -> usize {
    let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
    let asked = std::env::var("LP_NUM_THREADS")
        .ok()
        .and_then(|n| n.trim().parse::<usize>().ok());
    cpus.max(asked.unwrap_or(0))
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
        scene.lighting.attenuation = false;
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
