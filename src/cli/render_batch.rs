//! `shadelab render` with many scenes or modes (or `--out-dir`): each scene
//! in each mode, on one device whose built pipelines every case shares, the
//! images named by `--name` in `--out-dir`. A case that fails is reported
//! and the others go on; the exit status is the first failed case's.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use shadelab::backend_choice::{self, Backend, Choice};
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::memory::MemoryLimit;
use shadelab::output::ImageFormat;
use shadelab::scene::Scene;
use shadelab::shading::Shading;

use super::cases::{case_workers, in_order};
use super::progress::Progress;
use super::render::{
    apply_overrides, color_target, effective_settings, image_metadata, load_scene, print_stats,
    RenderArgs,
};
use super::Failure;

/// One scene of the batch: loaded with the overrides applied, or why not.
struct PlannedScene {
    path: Option<PathBuf>,
    /// The `{scene}` of the file names: the file's stem, made unique.
    name: String,
    scene: Result<Scene, Failure>,
}

/// One image to make: which scene, which mode, where, on which backend.
struct PlannedCase {
    /// Its place in the whole batch (of every shard).
    order: usize,
    scene: usize,
    shading: Shading,
    /// Its file's name, from `--name`.
    file_name: String,
    /// The backend, or why the case cannot run (over the memory limit).
    backend: Result<Backend, Failure>,
    choice: Option<Choice>,
    /// The memory estimate (0 where the case cannot run).
    estimate: u64,
}

/// What one case came to: the JSON object, the line for people, the ray
/// statistics to print, and the failure if it failed.
struct CaseDone {
    value: serde_json::Value,
    line: Option<String>,
    stats: Option<(shadelab::render::Rendered, Shading)>,
    failure: Option<Failure>,
}

/// The file name `pattern` gives for a scene and a mode.
pub(super) fn file_name(pattern: &str, scene: &str, shading: Shading) -> String {
    pattern
        .replace("{scene}", scene)
        .replace("{mode}", &shading.to_string())
}

/// Refuses a `--name` pattern that would give two cases one file, names a
/// placeholder other than `{scene}` and `{mode}`, or is not a .png/.exr
/// file name in the folder itself.
fn check_pattern(
    pattern: &str,
    scenes: usize,
    modes: usize,
    first: (&str, Shading),
) -> Result<(), Failure> {
    let bad = |why: &str| Err(Failure::usage(format!("--name {pattern:?} {why}")));
    let stripped = pattern.replace("{scene}", "").replace("{mode}", "");
    if stripped.contains(['{', '}']) {
        return bad("has a placeholder other than {scene} and {mode}");
    }
    if pattern.contains(['/', '\\']) {
        return bad("must be a file name, not a path (the folder is --out-dir)");
    }
    if scenes > 1 && !pattern.contains("{scene}") {
        return bad("needs {scene}: there is more than one scene");
    }
    if modes > 1 && !pattern.contains("{mode}") {
        return bad("needs {mode}: there is more than one mode");
    }
    let example = file_name(pattern, first.0, first.1);
    if ImageFormat::from_path(Path::new(&example)).is_err() {
        return bad(&format!(
            "would write {example}: expected a file name ending in .png (8-bit sRGB) or .exr (linear float)"
        ));
    }
    Ok(())
}

fn plan_scenes(args: &RenderArgs, modes: &[Shading], memory: &MemoryLimit) -> Vec<PlannedScene> {
    let paths: Vec<Option<PathBuf>> = if args.scenes.is_empty() {
        vec![None]
    } else {
        args.scenes.iter().cloned().map(Some).collect()
    };
    let mut planned: Vec<PlannedScene> = Vec::new();
    for (k, path) in paths.into_iter().enumerate() {
        let loaded = load_scene(path.as_deref(), memory).and_then(|(mut scene, stem)| {
            apply_overrides(&mut scene, args, modes, false)?;
            Ok((scene, stem))
        });
        let (scene, mut name) = match loaded {
            Ok((scene, stem)) => (Ok(scene), stem),
            Err(failure) => {
                let stem = path.as_ref().and_then(|p| p.file_stem()).map_or_else(
                    || "default".to_string(),
                    |s| s.to_string_lossy().into_owned(),
                );
                (Err(failure), stem)
            }
        };
        if let Some(given) = args.scene_names.as_ref().and_then(|names| names.get(k)) {
            name = given.clone();
        } else if planned.iter().any(|p| p.name == name) {
            name = format!("{name}-{}", planned.len() + 1);
        }
        planned.push(PlannedScene { path, name, scene });
    }
    planned
}

/// The backend each case renders on: `--backend`, or for `auto` the
/// choice made for that scene and mode; the memory estimate held to the
/// limit.
fn plan_case(
    args: &RenderArgs,
    scene: &PlannedScene,
    shading: Shading,
    memory: &MemoryLimit,
) -> (Result<(Backend, u64), Failure>, Option<Choice>) {
    let loaded = match &scene.scene {
        Ok(loaded) => loaded,
        Err(failure) => return (Err(failure.clone()), None),
    };
    let choice = (args.backend == "auto").then(|| backend_choice::choose(loaded, shading));
    let backend = match (&choice, args.backend.as_str()) {
        (Some(choice), _) => choice.backend,
        (None, "cpu") => Backend::Cpu,
        (None, _) => Backend::Gpu,
    };
    let (gpu_modes, cpu_modes): (&[Shading], &[Shading]) = match backend {
        Backend::Gpu => (&[shading], &[]),
        Backend::Cpu => (&[], &[shading]),
    };
    let estimate = memory.check(&scene.name, loaded, gpu_modes, cpu_modes);
    (
        estimate.map(|e| (backend, e)).map_err(Failure::from),
        choice,
    )
}

/// A batch planned: its scenes loaded, its cases' backends chosen, the
/// device opened if a case needs it.
pub(super) struct Batch {
    scenes: Vec<PlannedScene>,
    cases: Vec<PlannedCase>,
    context: Option<Arc<GpuContext>>,
    no_device: Option<Failure>,
    workers: usize,
}

/// One case as the code that handles its image sees it.
pub(super) struct CaseView<'a> {
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
pub(super) struct Made {
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
                if !super::shards::on_shard(&key, args.shard) {
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
                let target = color_target(scene, format);
                let rendered = shadelab::render::render_gpu_to(
                    context,
                    scene,
                    case.shading,
                    args.stats,
                    target,
                )?;
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
                let (rendered, _) = shadelab::render::render_cpu(scene, case.shading)?;
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
pub(super) fn non_finite_failure(made: &Made) -> Option<Failure> {
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

/// `render` with many images: each written into `--out-dir`.
pub fn run(args: &RenderArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    let started = Instant::now();
    let modes = args.modes();
    let scene_count = args.scenes.len().max(1);
    if let Some(out) = &args.out {
        return Err(Failure::usage(format!(
            "--out {} names one image, and this is a batch of {} ({} scene(s) x {} mode(s)): give --out-dir DIR (and --name PATTERN) instead",
            out.display(),
            scene_count * modes.len(),
            scene_count,
            modes.len()
        )));
    }
    Batch::check_flags(args)?;
    let out_dir = args.out_dir.clone().unwrap_or_else(|| PathBuf::from("."));
    shadelab::output::prepare_output_folder(&out_dir)?;
    let batch = Batch::plan(args, options, memory)?;
    let mut failures: Vec<(String, Failure)> = Vec::new();
    let mut values = Vec::new();
    let handle = |view: &CaseView, made: Result<Made, Failure>| {
        let out = out_dir.join(view.file_name);
        let mut value = serde_json::json!({
            "scene": view.path.map_or_else(
                || "built-in default scene".to_string(),
                |p| p.display().to_string(),
            ),
            "name": view.name,
            "shading": view.shading,
            "output": out,
        });
        let written = made.and_then(|made| {
            shadelab::output::write_image_with(&made.rendered.image, &out, &made.metadata)?;
            Ok(made)
        });
        match written {
            Ok(made) => {
                let failure = non_finite_failure(&made);
                describe(args, view, &made, &out, &mut value);
                value["status"] = if failure.is_some() { "failed" } else { "ok" }.into();
                if let Some(failure) = &failure {
                    value["error"] = failure.message.clone().into();
                }
                let line = made_line(view, &made, &out);
                let stats = args.stats.then_some(made.rendered);
                CaseDone {
                    value,
                    line: Some(line),
                    stats: stats.map(|r| (r, view.shading)),
                    failure,
                }
            }
            Err(failure) => {
                value["status"] = "failed".into();
                value["error"] = failure.message.clone().into();
                CaseDone {
                    value,
                    line: None,
                    stats: None,
                    failure: Some(failure),
                }
            }
        }
    };
    let report = |view: &CaseView, done: CaseDone| {
        let label = format!("{}/{}", view.name, view.shading);
        if !args.json {
            if let Some(line) = &done.line {
                println!("{line}");
            }
            if let Some((rendered, shading)) = &done.stats {
                print_stats(rendered.ray_stats.as_ref(), &rendered.timings, *shading);
            }
            if let Some(failure) = &done.failure {
                eprintln!("shadelab: error: {label}: {}", failure.message);
            }
        }
        if let Some(failure) = done.failure {
            failures.push((label, failure));
        }
        values.push(done.value);
        Ok(())
    };
    batch.run("render", args, handle, report)?;

    let (total, failed) = (batch.len(), failures.len());
    if args.json {
        let value = serde_json::json!({
            "out_dir": out_dir,
            "cases": values,
            "rendered": total - failed,
            "failed": failed,
            // Every case on the one device shares what it built: a scene
            // rendered twice in a mode builds one pipeline.
            "pipelines_built": batch.context().map(|c| c.pipelines_kept()),
            "wall_ms": shadelab::gpu::ms_since(started),
        });
        println!("{value}");
    } else {
        println!(
            "rendered {} of {total} images into {} in {:.0} ms{}",
            total - failed,
            out_dir.display(),
            shadelab::gpu::ms_since(started),
            if failed > 0 {
                format!("; {failed} failed")
            } else {
                String::new()
            }
        );
    }
    match failures.into_iter().next() {
        None => Ok(()),
        Some((label, first)) => Err(Failure {
            code: first.code,
            message: format!(
                "{failed} of {total} images failed, the first {label}: {}",
                first.message
            ),
        }),
    }
}

/// Adds `render --json`'s fields for a made image to a case's object.
fn describe(
    args: &RenderArgs,
    view: &CaseView,
    made: &Made,
    out: &Path,
    value: &mut serde_json::Value,
) {
    let r = &made.rendered;
    let extra = serde_json::json!({
        "output": out,
        "backend": made.backend.name(),
        "backend_choice": view.backend_choice,
        "width": r.image.width,
        "height": r.image.height,
        "device": made.device,
        "driver": made.driver,
        "traversal": r.traversal.map(|t| t.name()),
        "timings_ms": r.timings,
        "non_finite_pixels": r.image.non_finite_pixels(),
        "settings": made.settings,
    });
    let object = value.as_object_mut().expect("an object");
    object.extend(extra.as_object().expect("an object").clone());
    if args.stats {
        object.insert(
            "stats".into(),
            serde_json::to_value(r.ray_stats).expect("ray statistics serialise to JSON"),
        );
    }
}

/// `wrote FILE (W x H, mode, ms on device)`, with `auto`'s reason.
fn made_line(view: &CaseView, made: &Made, out: &Path) -> String {
    let auto = view
        .backend_choice
        .map(|c| format!("; backend auto: {}", c.why))
        .unwrap_or_default();
    let r = &made.rendered;
    format!(
        "wrote {} ({}x{}, {}, {:.1} ms on {}{auto})",
        out.display(),
        r.image.width,
        r.image.height,
        view.shading,
        r.timings.total_ms,
        made.device,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_that_would_overwrite_or_misname_are_refused() {
        let first = ("room", Shading::Phong);
        assert!(check_pattern("{scene}-{mode}.png", 3, 4, first).is_ok());
        assert!(check_pattern("{mode}.exr", 1, 4, first).is_ok());
        assert!(check_pattern("{scene}.png", 3, 1, first).is_ok());
        let message = |p: &str, s, m| check_pattern(p, s, m, first).err().map(|f| f.message);
        assert!(message("{scene}.png", 1, 2).is_some_and(|m| m.contains("needs {mode}")));
        assert!(message("{mode}.png", 2, 1).is_some_and(|m| m.contains("needs {scene}")));
        assert!(message("{scene}-{shading}.png", 1, 1).is_some_and(|m| m.contains("placeholder")));
        assert!(message("a/{scene}.png", 1, 1).is_some_and(|m| m.contains("not a path")));
        // The file it would write, named: the scene's, not a placeholder's.
        let jpg = message("{scene}-{mode}.jpg", 1, 1).unwrap_or_default();
        assert!(jpg.contains("would write room-phong.jpg"), "{jpg}");
        assert_eq!(
            file_name("{scene}_{mode}.exr", "room", Shading::Gouraud),
            "room_gouraud.exr"
        );
    }
}
