//! The caustic image on the GPU: the scene laid out for photons (as the
//! forward tracer lays it out), the map's buffers beside it, then one
//! submission per pass of its four dispatches; the image is read from the
//! pixels' states at the end, `flux / (passes pi r^2)`.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use super::map::MapBuffers;
use super::pipeline::{self, CausticPass, Stage};
use crate::camera::View;
use crate::film_sums::RenderPart;
use crate::gpu::raytrace::dispatch::QUEUE_EXHAUSTED;
use crate::gpu::raytrace::dispatch::{cpu_threads, record_writes_to_host, BoundTrace};
use crate::gpu::raytrace::forward::{refuse_what_cannot_run, PhotonScene};
use crate::gpu::raytrace::layout::WORKGROUP_SIZE;
use crate::gpu::vk::commands::OneShot;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::GpuError;
use crate::gpu::vk::timestamps::{ms_since, GpuTimings, Timestamps};
use crate::linear_image::LinearImage;
use crate::scene::Scene;
use crate::work_counter::WorkCounter;

/// Pixels or photons each lane takes per work item (the shader is built
/// with it, as `CAUSTIC_PER_LANE`).
pub const PER_LANE: u32 = crate::gpu::raytrace::kernel_sizes::CAUSTIC_PER_LANE;

/// The most workgroups one dimension of a dispatch takes (Vulkan's
/// guaranteed minimum of `maxComputeWorkGroupCount`).
const MAX_GROUPS: u32 = 65_535;

/// What the passes' photons did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct CausticStats {
    /// Passes run (fewer than asked where a time budget stopped them).
    pub passes: u32,
    /// Photons emitted from the lights.
    pub emitted: u64,
    /// Surfaces the photons hit.
    pub hits: u64,
    /// Landings on a diffuse surface after a mirror or glass (each
    /// gathered where a visible point is near).
    pub landed: u64,
    /// Photons added to a pixel: landings times the visible points they
    /// were within the radius of.
    pub gathered: u64,
}

/// The caustic image, what made it, where the time went.
pub struct CausticOutput {
    pub image: LinearImage,
    pub stats: CausticStats,
    pub timings: GpuTimings,
}

/// The caustic image of `scene` (`scene.render.caustics`), passes counted
/// into `counter` as they finish; under a time budget in `passes`, the
/// passes that start before it, one at least.
pub fn render(
    context: &Arc<GpuContext>,
    scene: &Scene,
    passes: &RenderPart,
    counter: &WorkCounter,
) -> Result<CausticOutput, GpuError> {
    let _watch = crate::gpu::shared::watch::watch_render(scene);
    let started = Instant::now();
    refuse_what_cannot_run(context, scene)?;
    let settings = scene.render.caustics;
    let (width, height) = (scene.image.width, scene.image.height);
    let pixels = u64::from(width) * u64::from(height);
    let view = View::new(scene, width, height);

    let prepare_started = Instant::now();
    let prepared = PhotonScene::prepare(scene)?;
    let prepare_ms = ms_since(prepare_started);

    let pipeline_started = Instant::now();
    let wide = prepared.records.bvh.wide.is_some();
    let pipeline = pipeline::get_or_build(context, &prepared.spec, wide)?;
    let pipeline_ms = ms_since(pipeline_started);

    let upload_started = Instant::now();
    let buffers = prepared.upload(context, scene, &view, 3 * 8 * pixels)?;
    let descriptors = buffers.bind(context, pipeline.set_layout)?;
    let map = MapBuffers::new(context, pixels)?;
    let map_descriptors = map.bind(context, pipeline.extra_set_layout)?;
    let run = PassRun {
        bound: BoundTrace {
            pipeline: &pipeline,
            set: descriptors.set,
            structure_set: None,
            work_queue: buffers.work_queue.raw,
            push_constants: &[],
        },
        map_set: map_descriptors.set,
        groups: PassGroups::new(pixels, settings.photons_per_pass, context.info.is_cpu()),
    };
    let upload_ms = ms_since(upload_started);

    let codegen_started = Instant::now();
    run.first_use(context)?;
    let codegen_ms = ms_since(codegen_started);

    counter.begin("caustic passes", u64::from(passes.count()));
    let timestamps = Timestamps::new(context)?;
    let (mut submit_ms, mut gpu_ms, mut done) = (0.0, 0.0, 0u32);
    for pass in passes.range.clone() {
        if !passes.may_start(done == 0) {
            break;
        }
        let push = CausticPass {
            first: pass * settings.photons_per_pass,
            count: settings.photons_per_pass,
            total: settings.photons_per_pass,
            stage: 0,
            pass,
            buckets: map.buckets,
            initial_radius: settings.initial_radius as f32,
            alpha: settings.alpha as f32,
        };
        let (submit, gpu) = run.submit_pass(context, &timestamps, push)?;
        if done == 0 {
            passes
                .refuse_if_too_long(1, submit / 1e3, "caustic passes")
                .map_err(GpuError::TooLong)?;
        }
        submit_ms += submit;
        gpu_ms += gpu;
        done += 1;
        counter.add(1);
    }

    let readback_started = Instant::now();
    let image = caustic_image(&map, (width, height), done);
    let stats = caustic_stats(buffers.counters(), done);
    Ok(CausticOutput {
        image,
        stats,
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
    })
}

/// The workgroups of each stage: the traced ones (visible points,
/// photons) take work from a queue, so any count covers them; the others
/// run one invocation a pixel, rows of `MAX_GROUPS` groups.
struct PassGroups {
    points: u32,
    photons: u32,
    per_pixel: (u32, u32),
}

impl PassGroups {
    fn new(pixels: u64, photons: u32, on_cpu: bool) -> Self {
        let per_item = u64::from(WORKGROUP_SIZE * PER_LANE);
        let queued = |work: u64| {
            let needed = u32::try_from(work.div_ceil(per_item).max(1)).unwrap_or(u32::MAX);
            // On a CPU device a few per thread (the ray tracer's
            // `workgroups` says why).
            let cap = if on_cpu {
                u32::try_from(cpu_threads().max(1) * 8).unwrap_or(MAX_GROUPS)
            } else {
                MAX_GROUPS
            };
            needed.min(cap)
        };
        let groups = pixels.div_ceil(u64::from(WORKGROUP_SIZE)).max(1);
        let across = groups.min(u64::from(MAX_GROUPS));
        let down = groups.div_ceil(across);
        PassGroups {
            points: queued(pixels),
            photons: queued(u64::from(photons)),
            per_pixel: (across as u32, down as u32),
        }
    }
}

/// The pipeline and both sets, bound for a pass.
struct PassRun<'a> {
    bound: BoundTrace<'a>,
    map_set: vk::DescriptorSet,
    groups: PassGroups,
}

impl PassRun<'_> {
    /// The pipeline's first use, apart from the passes: a photon stage
    /// over an exhausted queue, which traces nothing, so that the driver's
    /// code generation is timed alone.
    fn first_use(&self, context: &Arc<GpuContext>) -> Result<(), GpuError> {
        let commands = OneShot::begin(context)?;
        let push = CausticPass {
            stage: Stage::Photons as u32,
            ..bytemuck::Zeroable::zeroed()
        };
        // SAFETY: every handle lives until the submission completes (this
        // function waits for it); the stage takes no item.
        unsafe {
            self.record_stage(context, commands.cmd, push, Some(QUEUE_EXHAUSTED), (1, 1));
        }
        commands.submit_and_wait()?;
        context.check_validation()
    }

    /// One pass, `push` with each stage's number in turn, in one
    /// submission between `timestamps`; its submit and GPU milliseconds.
    fn submit_pass(
        &self,
        context: &Arc<GpuContext>,
        timestamps: &Timestamps,
        push: CausticPass,
    ) -> Result<(f64, f64), GpuError> {
        let commands = OneShot::begin(context)?;
        let cmd = commands.cmd;
        let g = &self.groups;
        let stages = [
            (Stage::VisiblePoints, (g.points, 1)),
            (Stage::Grid, g.per_pixel),
            (Stage::Photons, (g.photons, 1)),
            (Stage::Update, g.per_pixel),
        ];
        timestamps.start(cmd);
        for (stage, groups) in stages {
            let push = CausticPass {
                stage: stage as u32,
                ..push
            };
            // The traced stages take work from the queue, set afresh; the
            // others run one invocation a pixel on what is bound already.
            let queue_head = matches!(stage, Stage::VisiblePoints | Stage::Photons).then_some(0);
            // SAFETY: every handle lives until the submission completes
            // (`submit_and_measure` waits for it).
            unsafe {
                self.record_stage(context, cmd, push, queue_head, groups);
                record_stage_done(&context.device, cmd);
            }
        }
        // SAFETY: `cmd` is recording.
        unsafe { record_writes_to_host(&context.device, cmd) };
        timestamps.stop(cmd);
        timestamps.submit_and_measure(&commands)
    }

    /// Records one stage: where `queue_head` is given, the work queue set
    /// to it and the pipeline and both sets bound (else they are bound
    /// already, by an earlier stage in `cmd`); `push` pushed, `groups`
    /// dispatched.
    ///
    /// # Safety
    /// `cmd` is recording, and every handle in `self` lives until the
    /// submission that runs it has completed.
    unsafe fn record_stage(
        &self,
        context: &Arc<GpuContext>,
        cmd: vk::CommandBuffer,
        push: CausticPass,
        queue_head: Option<u32>,
        (groups_x, groups_y): (u32, u32),
    ) {
        let device = &context.device;
        let layout = self.bound.pipeline.layout;
        let dispatch = |cmd| {
            let stage = vk::ShaderStageFlags::COMPUTE;
            device.cmd_push_constants(cmd, layout, stage, 0, bytemuck::bytes_of(&push));
            device.cmd_dispatch(cmd, groups_x, groups_y, 1);
        };
        let Some(head) = queue_head else {
            dispatch(cmd);
            return;
        };
        self.bound.record(device, cmd, head, |cmd| {
            let bind = vk::PipelineBindPoint::COMPUTE;
            device.cmd_bind_descriptor_sets(cmd, bind, layout, 1, &[self.map_set], &[]);
            dispatch(cmd);
        });
    }
}

/// Records a barrier that orders a stage's writes before the next stage's
/// reads and writes.
///
/// # Safety
/// `cmd` is recording.
unsafe fn record_stage_done(device: &ash::Device, cmd: vk::CommandBuffer) {
    let access = vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE;
    let done = [vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
        .src_access_mask(access)
        .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
        .dst_access_mask(access)];
    device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&done));
}

/// Each pixel's `flux / (passes pi r^2)`: black where it gathered nothing.
fn caustic_image(map: &MapBuffers, (width, height): (u32, u32), passes: u32) -> LinearImage {
    let passes = f64::from(passes.max(1));
    let pixels = map
        .states()
        .take(width as usize * height as usize)
        .map(|(flux, count, radius)| {
            if count == 0.0 {
                return [0.0; 3];
            }
            let area = std::f64::consts::PI * f64::from(radius) * f64::from(radius) * passes;
            flux.map(|f| (f64::from(f) / area) as f32)
        })
        .collect();
    LinearImage {
        width,
        height,
        pixels,
    }
}

/// The shader's counters: emitted, gathered, landed, hits.
fn caustic_stats(bytes: &[u8], passes: u32) -> CausticStats {
    let word = |i: usize| u64::from_ne_bytes(bytes[i * 8..i * 8 + 8].try_into().expect("8 bytes"));
    CausticStats {
        passes,
        emitted: word(0),
        gathered: word(1),
        landed: word(2),
        hits: word(3),
    }
}
