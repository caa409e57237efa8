//! A batch of renders: each scene in each mode, on one device whose built
//! pipelines every case shares, two cases at a time where memory allows,
//! each image handed to the caller (`render --out-dir` writes it, `golden`
//! judges it) and the results reported in the cases' order. A case that
//! fails is reported and the others go on.

pub(in crate::cli) mod args;
pub(in crate::cli) mod plan;
pub(in crate::cli) mod scene;

use std::path::Path;
use std::sync::Arc;

use shadelab::backend_choice::{Backend, Choice};
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::memory::MemoryLimit;
use shadelab::output::ImageFormat;
use shadelab::render::{Device, RenderRequest};
use shadelab::shading::Shading;

use crate::cli::common::cases::{case_workers, in_order};
use crate::cli::common::failure::Failure;
use crate::cli::common::progress::Progress;
use args::RenderArgs;
use plan::{check_pattern, file_name, plan_case, plan_scenes, PlannedCase, PlannedScene};
use scene::apply_overrides;
use shadelab::render::described::{color_target, effective_settings, image_metadata};

/// A batch planned: its scenes loaded, its cases' backends chosen, the
/// device opened if a case needs it.
pub struct Batch {
    scenes: Vec<PlannedScene>,
    cases: Vec<PlannedCase>,
    context: Option<Arc<GpuContext>>,
    no_device: Option<Failure>,
    workers: usize,
}

/// One case as the code that handles its image sees it.
pub struct CaseView<'a> {
    /// The scene's name in file names (`{scene}`).
    pub name: &'a str,
    pub path: Option<&'a Path>,
    pub shading: Shading,
    /// The file name `--name` gives it.
    pub file_name: &'a str,
    /// Its place in the whole batch (of every shard).
    pub order: usize,
    pub backend_choice: Option<&'a Choice>,
}

/// A case's image as rendered, and what it says of itself.
pub struct Made {
    pub rendered: shadelab::render::Rendered,
    pub backend: Backend,
    pub device: String,
    pub driver: Option<String>,
    /// `render --json`'s `settings`, also in the PNG.
    pub settings: serde_json::Value,
    pub metadata: shadelab::output::ImageMetadata,
    pub lighting_hook: bool,
    /// The lighting hook's GLSL, where there is one.
    pub hook_source: Option<String>,
}

impl Batch {
    /// The flags a batch takes, checked before anything is written: the
    /// file name pattern, and those that apply to every scene (on the
    /// default scene), so that a bad value is one usage error, not an error
    /// in every case, and leaves no folder behind.
    pub fn check_flags(args: &RenderArgs) -> Result<(), Failure> {
        let modes = args.modes();
        let first_scene = match (&args.scene_names, args.scenes.first()) {
            (Some(names), _) if !names.is_empty() => names[0].clone(),
            (_, Some(path)) => path
                .file_stem()
                .map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned()),
            _ => "default".to_string(),
        };
        let first = (
            first_scene.as_str(),
            modes.first().copied().unwrap_or(Shading::Phong),
        );
        check_pattern(
            args.name_pattern(),
            args.scenes.len().max(1),
            modes.len(),
            first,
        )?;
        apply_overrides(&mut shadelab::scene::default_scene(), args, &modes, true)
    }

    /// Loads the scenes, chooses each case's backend, opens the device if
    /// a case needs it. A scene that does not load fails its own cases.
    /// The flags are `check_flags`'.
    pub fn plan(
        args: &RenderArgs,
        options: &GpuOptions,
        memory: &MemoryLimit,
    ) -> Result<Batch, Failure> {
        let modes = args.modes();
        let scenes = plan_scenes(args, &modes, memory);
        let mut cases = Vec::new();
        let mut order = 0;
        for (i, scene) in scenes.iter().enumerate() {
            for &shading in &modes {
                order += 1;
                let key = format!("{}/{shading}", scene.name);
                if !crate::cli::common::shards::on_shard(&key, args.shard) {
                    continue;
                }
                let (planned, choice) = plan_case(args, scene, shading, memory);
                cases.push(PlannedCase {
                    order: order - 1,
                    scene: i,
                    shading,
                    file_name: file_name(args.name_pattern(), &scene.name, shading),
                    estimate: planned.as_ref().map_or(0, |&(_, e)| e),
                    backend: planned.map(|(b, _)| b),
                    choice,
                });
            }
        }
        for scene in &scenes {
            if let Ok(loaded) = &scene.scene {
                for warning in &loaded.warnings {
                    eprintln!("shadelab: warning: {}: {warning}", scene.name);
                }
                let said = [Shading::Forward, Shading::Raytrace].into_iter();
                for shading in said.filter(|s| modes.contains(s)) {
                    for warning in shadelab::render::warnings(loaded, shading) {
                        eprintln!("shadelab: warning: {}: {warning}", scene.name);
                    }
                }
            }
        }
        // One device for the batch, opened only if a case renders on it.
        let wants_gpu = cases.iter().any(|c| matches!(c.backend, Ok(Backend::Gpu)));
        let (context, no_device) = if wants_gpu {
            match GpuContext::new(options) {
                Ok(context) => (Some(context), None),
                Err(e) => (None, Some(Failure::from(e))),
            }
        } else {
            (None, None)
        };
        if let Some(no_device) = &no_device {
            // `auto` renders on the CPU where there is no GPU, as for one image.
            for case in &mut cases {
                if let Some(choice) = case.choice.as_mut().filter(|c| !c.needs_gpu) {
                    if matches!(case.backend, Ok(Backend::Gpu)) {
                        choice.backend = Backend::Cpu;
                        choice.why = format!("no GPU to open ({})", no_device.message);
                        case.backend = Ok(Backend::Cpu);
                    }
                }
            }
        }
        let largest = cases.iter().map(|c| c.estimate).max().unwrap_or(0);
        let workers = case_workers(cases.len(), largest, memory);
        Ok(Batch {
            scenes,
            cases,
            context,
            no_device,
            workers,
        })
    }

    pub fn len(&self) -> usize {
        self.cases.len()
    }

    /// The device every GPU case renders on, where one was opened.
    pub fn context(&self) -> Option<&Arc<GpuContext>> {
        self.context.as_ref()
    }

    fn view(&self, k: usize) -> CaseView<'_> {
        let case = &self.cases[k];
        let scene = &self.scenes[case.scene];
        CaseView {
            name: &scene.name,
            path: scene.path.as_deref(),
            shading: case.shading,
            file_name: &case.file_name,
            order: case.order,
            backend_choice: case.choice.as_ref(),
        }
    }

    /// Renders every case, two at a time where that fits, and hands each
    /// image (or why there is none) to `handle` on the worker, then its
    /// result to `report` in the cases' order.
    /// `what` names the work in progress lines (`render`, `golden`).
    pub fn run<T: Send>(
        &self,
        what: &str,
        args: &RenderArgs,
        handle: impl Fn(&CaseView, Result<Made, Failure>) -> T + Sync,
        mut report: impl FnMut(&CaseView, T) -> Result<(), Failure>,
    ) -> Result<(), Failure> {
        let jobs: Vec<usize> = (0..self.cases.len()).collect();
        let run_case = |context: &Option<Arc<GpuContext>>, k: usize| {
            let made = self.make(args, k, context.as_ref());
            handle(&self.view(k), made)
        };
        let shared = self.context.clone();
        let progress = Progress::new(what, jobs.len() as u64);
        let case_name = |k: usize| {
            if k < self.cases.len() {
                self.view(k).file_name.to_string()
            } else {
                String::new()
            }
        };
        progress.set(0, &case_name(0));
        in_order(
            &self.context,
            || Some(shared.clone()),
            &jobs,
            self.workers,
            run_case,
            |k, t| {
                progress.set(k as u64 + 1, &case_name(k + 1));
                progress.suspend(|| report(&self.view(k), t))
            },
        )
    }

    /// Renders case `k`.
    fn make(
        &self,
        args: &RenderArgs,
        k: usize,
        context: Option<&Arc<GpuContext>>,
    ) -> Result<Made, Failure> {
        let case = &self.cases[k];
        let planned = &self.scenes[case.scene];
        let scene = planned.scene.as_ref().map_err(Clone::clone)?;
        let backend = case.backend.clone()?;
        let format = ImageFormat::from_path(Path::new(&case.file_name))?;
        let (rendered, device, driver) = match (backend, context) {
            (Backend::Gpu, Some(context)) => {
                let request = RenderRequest {
                    target: color_target(scene, format),
                    count_rays: args.stats,
                    ..RenderRequest::gpu(case.shading)
                };
                let device = Device::with_gpu(context.clone());
                let rendered = shadelab::render::render(&device, scene, &request)?;
                let info = &context.info;
                (rendered, info.name.clone(), Some(info.driver.clone()))
            }
            (Backend::Gpu, None) => {
                return Err(self
                    .no_device
                    .clone()
                    .unwrap_or_else(|| Failure::usage("no device".into())))
            }
            (Backend::Cpu, _) => {
                let request = RenderRequest::cpu(case.shading);
                let rendered = shadelab::render::render(&Device::cpu_only(), scene, &request)?;
                (rendered, "CPU reference (f64)".to_string(), None)
            }
        };
        let settings = effective_settings(
            planned.path.as_deref(),
            case.shading,
            scene,
            backend,
            &rendered,
            &device,
            driver.as_deref(),
        );
        let metadata = image_metadata(&planned.name, &device, &settings);
        Ok(Made {
            rendered,
            backend,
            device,
            driver,
            settings,
            metadata,
            lighting_hook: scene.lighting_hook.is_some(),
            hook_source: scene.lighting_hook.as_ref().map(|h| h.source.clone()),
        })
    }
}

/// The pixels that are not finite, as a case's failure.
pub fn non_finite_failure(made: &Made) -> Option<Failure> {
    let image = &made.rendered.image;
    let non_finite = image.non_finite_pixels();
    (non_finite > 0).then(|| Failure {
        code: 1,
        message: format!(
            "{non_finite} of {} pixels are not finite (NaN or infinity){}",
            image.pixels.len(),
            if made.lighting_hook {
                " (the lighting hook returned them)"
            } else {
                ""
            }
        ),
    })
}
