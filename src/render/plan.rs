//! A request read against a scene: which technique renders it, on which
//! backend, over which photons or samples, with or without caustics;
//! every refusal run once, here, before any work starts; and the
//! integrator that does the work.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use super::caustics;
use super::device::Device;
use super::forward::{CpuForward, GpuForward};
use super::integrator::{Integrator, Work};
use super::raster::{CpuRaster, GpuRaster};
use super::raytrace::{CpuRayTrace, GpuRayTrace};
use super::refusals;
use super::rendered::Rendered;
use super::request::{Portion, RenderRequest};
use crate::backend_choice::Backend;
use crate::error::Error;
use crate::film_sums::RenderPart;
use crate::gpu::raster::ColorTarget;
use crate::scene::Scene;
use crate::shading::{RasterMode, Shading};
use crate::work_counter::WorkCounter;

/// How an image is made: one integrator (and its CPU twin) each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Technique {
    /// Flat, Gouraud or Phong on the raster pipelines (the CPU twin
    /// rasterizes the same triangles in f64).
    Raster(RasterMode),
    /// Backward ray tracing with no diffuse bounce: exact per sample, its
    /// image the mean of a pixel's fixed sample grid.
    Whitted,
    /// Backward ray tracing with diffuse bounces (`render.bounces`): a
    /// Monte Carlo estimate summed into a film.
    Paths,
    /// Forward ray tracing: photons from the lights splatted into a film.
    Forward,
}

impl Technique {
    /// The technique `shading` takes in `scene`.
    pub fn of(scene: &Scene, shading: Shading) -> Self {
        match shading.raster_mode() {
            Some(mode) => Technique::Raster(mode),
            None if shading == Shading::Forward => Technique::Forward,
            None if scene.render.bounces > 0 => Technique::Paths,
            None => Technique::Whitted,
        }
    }

    /// Whether the render sums into a film, so that it can be split into
    /// shards, stopped at a budget, and counts its progress in photons or
    /// samples.
    pub fn sums_in_film(self) -> bool {
        matches!(self, Technique::Paths | Technique::Forward)
    }

    /// The photons (forward) or samples per pixel (backward) the work is
    /// made of; a raster image is one piece.
    pub fn work_total(self, scene: &Scene) -> u32 {
        match self {
            Technique::Forward => scene.render.photons,
            Technique::Whitted | Technique::Paths => scene.render.samples.max(1),
            Technique::Raster(_) => 1,
        }
    }

    /// What the work is counted in, for a caller's messages.
    pub fn work_unit(self) -> &'static str {
        match self {
            Technique::Forward => "photons",
            _ => "samples per pixel",
        }
    }
}

/// A render resolved: what `Plan::render` will do, refusals passed.
pub struct Plan<'a> {
    pub technique: Technique,
    pub backend: Backend,
    /// Whether the photon map's caustics are added to the image: ray
    /// tracing, caustics asked for, and the scene has some.
    pub caustics: bool,
    /// The photons or samples traced: the request's shard of them, or
    /// all; its budgets the request's.
    pub part: RenderPart,
    /// What the caller should say before the image is trusted: what the
    /// technique cannot show, or options that have nothing to act on.
    pub warnings: Vec<String>,
    target: ColorTarget,
    count_rays: bool,
    every_feature: bool,
    /// The caustics' passes stop at the request's time budget whatever
    /// the technique (a Whitted trace itself has none).
    deadline: Option<Instant>,
    progress: Option<&'a WorkCounter>,
    cancel: Option<Arc<AtomicBool>>,
}

impl<'a> Plan<'a> {
    /// Reads `request` against `scene`: the technique, the part of its
    /// work, and every refusal (a usage error, before any work).
    pub fn new(scene: &Scene, request: &RenderRequest<'a>) -> Result<Self, Error> {
        let shading = request.shading;
        let technique = Technique::of(scene, shading);
        refusals::beyond_f32(scene)?;
        if technique == Technique::Forward {
            refusals::forward_without_light(scene)?;
        }
        if request.backend == Backend::Cpu {
            refusals::cpu_image_size(scene)?;
            if let Technique::Raster(_) = technique {
                refusals::cpu_sample_count(scene)?;
            }
        }
        let total = technique.work_total(scene);
        if request.portion != Portion::All {
            refusals::unsplittable(scene, shading, technique.sums_in_film())?;
        }
        let mut part = match &request.portion {
            Portion::All => RenderPart::all(total),
            Portion::Shard(i, n) => RenderPart::shard(total, (*i, *n)),
            Portion::Range(range) => RenderPart {
                range: range.start.min(total)..range.end.min(total),
                ..RenderPart::all(total)
            },
        };
        if technique.sums_in_film() {
            part.deadline = request.deadline;
            part.error = request.error;
        }
        part.cancel = request.cancel.clone();
        let caustics = shading == Shading::Raytrace && caustics::adds_to(scene);
        if caustics && request.backend == Backend::Cpu {
            caustics::refuse_cpu_photon_count(scene)?;
        }
        Ok(Self {
            technique,
            backend: request.backend,
            caustics,
            part,
            warnings: warnings(scene, shading),
            target: request.target,
            count_rays: request.count_rays,
            every_feature: request.every_feature,
            deadline: request.deadline,
            progress: request.progress,
            cancel: request.cancel.clone(),
        })
    }

    /// Runs the plan on `device`: the technique's integrator, then the
    /// caustics where planned. `Error::Cancelled` where the request's
    /// cancel flag was set meanwhile.
    pub fn render(&self, device: &Device, scene: &Scene) -> Result<Rendered, Error> {
        let own_counter = WorkCounter::default();
        let counter = self.progress.unwrap_or(&own_counter);
        let integrator = self.integrator(device)?;
        let work = Work {
            scene,
            part: &self.part,
            target: self.target,
            count_rays: self.count_rays,
            every_feature: self.every_feature,
            counter,
        };
        let mut rendered = integrator.render(&work)?;
        if self.caustics {
            let gpu = match self.backend {
                Backend::Gpu => device.gpu(),
                Backend::Cpu => None,
            };
            let passes = caustics::passes(scene, self.deadline, &self.cancel);
            caustics::add(gpu, scene, &mut rendered, &passes, counter)?;
        }
        if self
            .cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
        {
            return Err(Error::Cancelled);
        }
        Ok(rendered)
    }

    /// The integrator of the technique on the backend.
    fn integrator<'d>(&self, device: &'d Device) -> Result<Box<dyn Integrator + 'd>, Error> {
        if self.backend == Backend::Cpu {
            return Ok(match self.technique {
                Technique::Raster(mode) => Box::new(CpuRaster { mode }),
                Technique::Whitted | Technique::Paths => Box::new(CpuRayTrace),
                Technique::Forward => Box::new(CpuForward),
            });
        }
        let context = device.require_gpu()?;
        Ok(match self.technique {
            Technique::Raster(mode) => Box::new(GpuRaster { context, mode }),
            Technique::Whitted | Technique::Paths => Box::new(GpuRayTrace { context }),
            Technique::Forward => Box::new(GpuForward { context }),
        })
    }
}

/// The warnings a render of `scene` in `shading` comes with (a plan's
/// `warnings`; a batch says them once per scene and mode, before it
/// renders).
pub fn warnings(scene: &Scene, shading: Shading) -> Vec<String> {
    let forward = (shading == Shading::Forward)
        .then(|| refusals::forward_blind_spots(scene))
        .flatten();
    let caustics = (shading == Shading::Raytrace)
        .then(|| caustics::nothing_to_gather(scene))
        .flatten();
    forward.into_iter().chain(caustics).collect()
}
