//! A forward render on the GPU: the scene laid out as the ray tracer lays
//! it out (the same records, BVH and buffers, the lights' shares of the
//! photons in their records' w), then the photons traced in batches, each
//! one submission, into one fixed-point film read back at the end.

use std::sync::Arc;
use std::time::Instant;

use super::pipeline::{self, PhotonBatch};
use crate::camera::View;
use crate::film_sums::{FilmSums, PhotonStats, RenderPart};
use crate::gpu::raytrace::batches;
use crate::gpu::raytrace::buffers::TraceBuffers;
use crate::gpu::raytrace::dispatch::{cpu_threads, submit_batch, BoundTrace, QUEUE_EXHAUSTED};
use crate::gpu::raytrace::layout::TraceSpecialization;
use crate::gpu::raytrace::layout::WORKGROUP_SIZE;
use crate::gpu::raytrace::records::{records, SceneRecords};
use crate::gpu::raytrace::renderer::{specialization, TraceOptions};
use crate::gpu::shared::image_size::check_image_size;
use crate::gpu::shared::lights::lights;
use crate::gpu::vk::context::GpuContext;
use crate::gpu::vk::error::GpuError;
use crate::gpu::vk::timestamps::{ms_since, GpuTimings, Timestamps};
use crate::rt_scene::{LightShares, RtScene};
use crate::scene::Scene;
use crate::work_counter::WorkCounter;

// Photons each lane traces per work item (the shader is built with it).
pub use crate::gpu::raytrace::kernel_sizes::PHOTONS_PER_LANE;

/// Photons per submission: about a second of lavapipe's time on the
/// diffuse box, so that progress moves and a render can be stopped
/// between batches. The film does not depend on it.
const BATCH: u32 = 1 << 20;

/// A forward render: its film, what its photons did, where the time went.
pub struct ForwardOutput {
    pub film: FilmSums,
    pub stats: PhotonStats,
    pub timings: GpuTimings,
    /// Under an error budget, the render's last estimate of its RMSE.
    pub estimate: Option<f64>,
}

/// Traces `part`'s photons through `scene` at its image size, counting
/// them into `counter` as batches finish; under a time budget, the batches
/// that start before it (the film holds their sums: `stats.emitted` says
/// how many photons that is).
pub fn render(
    context: &Arc<GpuContext>,
    scene: &Scene,
    part: &RenderPart,
    counter: &WorkCounter,
) -> Result<ForwardOutput, GpuError> {
    let _watch = crate::gpu::shared::watch::watch_render(scene);
    let started = Instant::now();
    refuse_what_cannot_run(context, scene)?;
    let (width, height) = (scene.image.width, scene.image.height);
    let view = View::new(scene, width, height);

    let prepare_started = Instant::now();
    let prepared = PhotonScene::prepare(scene)?;
    let prepare_ms = ms_since(prepare_started);

    let pipeline_started = Instant::now();
    let wide = prepared.records.bvh.wide.is_some();
    let pipeline = pipeline::get_or_build(context, &prepared.spec, wide)?;
    let pipeline_ms = ms_since(pipeline_started);

    let upload_started = Instant::now();
    let film_bytes = 3 * 8 * u64::from(width) * u64::from(height);
    let buffers = prepared.upload(context, scene, &view, film_bytes)?;
    let descriptors = buffers.bind(context, pipeline.set_layout)?;
    let bound = BoundTrace {
        pipeline: &pipeline,
        set: descriptors.set,
        structure_set: None,
        work_queue: buffers.work_queue.raw,
        // Each batch pushes its own (`run_batch`).
        push_constants: &[],
    };
    let upload_ms = ms_since(upload_started);

    let codegen_started = Instant::now();
    run_batch(context, &bound, None, PhotonBatch::zeroed_for(part.total))?;
    let codegen_ms = ms_since(codegen_started);

    let work = batches::FilmWork {
        buffers: &buffers,
        size: (width, height),
        unit: "photons",
        batch: BATCH,
        halves: batches::Halves::ByBatch,
    };
    let batches = batches::run(
        context,
        &work,
        part,
        counter,
        &mut |timestamps, first, end, _| {
            let batch = PhotonBatch {
                first,
                count: end - first,
                total: part.total,
                unused: 0,
            };
            run_batch(context, &bound, Some(timestamps), batch)
        },
    )?;
    let (submit_ms, gpu_ms) = (batches.submit_ms, batches.gpu_ms);

    let readback_started = Instant::now();
    let film = FilmSums::from_ne_bytes(width, height, buffers.output());
    let stats = photon_stats(buffers.counters());
    Ok(ForwardOutput {
        film,
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
        estimate: batches.estimate,
    })
}

/// A scene laid out for photons: as the ray tracer lays it out, the
/// lights' shares of the photons beside (also the photon map's).
pub(in crate::gpu::raytrace) struct PhotonScene {
    pub rt: RtScene,
    pub shares: LightShares,
    pub records: SceneRecords,
    pub spec: TraceSpecialization,
}

impl PhotonScene {
    /// The records of `scene`; refused where no light has power.
    pub fn prepare(scene: &Scene) -> Result<Self, GpuError> {
        let rt = RtScene::with_cached_tree(scene);
        let shares = LightShares::of(&rt).ok_or_else(|| {
            GpuError::NoLightToTraceFrom(if rt.lights.is_empty() {
                "no light".into()
            } else {
                "only lights of zero intensity".into()
            })
        })?;
        let records = records(&rt)?;
        let spec = specialization(scene, &rt, TraceOptions::default());
        Ok(Self {
            rt,
            shares,
            records,
            spec,
        })
    }

    /// The trace's buffers, each light's running share of the photons in
    /// its record's w, a zeroed film of `film_bytes` as the output.
    pub fn upload(
        mut self,
        context: &Arc<GpuContext>,
        scene: &Scene,
        view: &View,
        film_bytes: u64,
    ) -> Result<TraceBuffers, GpuError> {
        if self.spec.has_bvh != 0 && self.records.bvh.root.is_none() {
            self.records.add_unhittable_triangle();
        }
        let mut light_records = lights(scene, view.eye);
        for (j, light) in light_records.iter_mut().enumerate() {
            light.position[3] = self.shares.end(j);
        }
        let mut buffers = TraceBuffers::upload(
            context,
            &light_records,
            view,
            &self.rt,
            &self.records,
            film_bytes,
        )?;
        buffers.zero_output();
        Ok(buffers)
    }
}

/// Refuses a device without the forward tracer's needs, and an image over
/// its limits (also the photon map's).
pub(in crate::gpu::raytrace) fn refuse_what_cannot_run(
    context: &Arc<GpuContext>,
    scene: &Scene,
) -> Result<(), GpuError> {
    let info = &context.info;
    let why_not = info.no_ray_tracer_because.as_ref();
    if let Some(why) = why_not.or(info.no_forward_because.as_ref()) {
        return Err(GpuError::NoRayTracer {
            device: info.name.clone(),
            why: why.clone(),
        });
    }
    check_image_size(context, scene.image.width, scene.image.height)
}

impl PhotonBatch {
    /// A batch of no photons: the pipeline's first use, which the driver's
    /// code generation is timed by.
    fn zeroed_for(total: u32) -> Self {
        PhotonBatch {
            first: 0,
            count: 0,
            total,
            unused: 0,
        }
    }
}

/// One submission of `batch` (between `timestamps`' stamps where given);
/// its submit and GPU milliseconds.
fn run_batch(
    context: &Arc<GpuContext>,
    bound: &BoundTrace,
    timestamps: Option<&Timestamps>,
    batch: PhotonBatch,
) -> Result<(f64, f64), GpuError> {
    let groups = workgroups(batch.count, context.info.is_cpu(), cpu_threads());
    let queue_head = if batch.count == 0 { QUEUE_EXHAUSTED } else { 0 };
    let push = bytemuck::bytes_of(&batch);
    submit_batch(context, bound, timestamps, push, (queue_head, (groups, 1)))
}

/// Workgroups for a batch of `photons`. The subgroups take photons from a
/// queue until it is empty, so any count covers them: on a GPU one item
/// per subgroup; on a CPU device a few per thread (as the ray tracer's
/// `workgroups` says why).
fn workgroups(photons: u32, on_cpu: bool, cpus: usize) -> u32 {
    let needed = photons.div_ceil(WORKGROUP_SIZE * PHOTONS_PER_LANE).max(1);
    if !on_cpu {
        return needed;
    }
    needed.min(u32::try_from(cpus.max(1) * 8).unwrap_or(u32::MAX))
}

/// The shader's counters: emitted, splats, seen, hits.
fn photon_stats(bytes: &[u8]) -> PhotonStats {
    let word = |i: usize| u64::from_ne_bytes(bytes[i * 8..i * 8 + 8].try_into().expect("8 bytes"));
    PhotonStats {
        emitted: word(0),
        splats: word(1),
        seen: word(2),
        hits: word(3),
    }
}
