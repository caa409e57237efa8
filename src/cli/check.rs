//! `shadelab check`: every scene in every mode, GPU against the CPU
//! reference; images for CI to keep, a verdict line per case, optionally a
//! JUnit report; exit status 1 when any case fails.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use clap::Args;
use shadelab::check::{check_counted, scaled, CheckOutcome, CheckThresholds};
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::junit;
use shadelab::memory::MemoryLimit;
use shadelab::metrics::heatmap::flip_heatmap;
use shadelab::output::{write_atomically, write_image};
use shadelab::shading::Shading;
use shadelab::work_counter::WorkCounter;

use super::args::{ImageSize, LightingArg, ModeList, MsaaArg, TraversalArg};
use super::cases::{case_workers, in_order};
use super::check_report::{CaseReport, KeepImages};
use super::progress::Progress;
use super::render::load_scene;
use super::Failure;

#[derive(Args)]
pub struct CheckArgs {
    /// Scene files; the built-in default scene if none.
    scenes: Vec<PathBuf>,
    #[command(flatten)]
    modes: ModeList,
    /// Folder for <scene>/<mode>-{expected,actual,diff}.png.
    #[arg(long, default_value = "check-out")]
    out: PathBuf,
    /// Also write a JUnit XML report here.
    #[arg(long)]
    junit: Option<PathBuf>,
    /// Which cases' images to write into --out: all, failures (only the
    /// cases that failed their thresholds) or none.
    #[arg(long, value_enum, default_value = "all")]
    images: KeepImages,
    /// Print one JSON object with every figure on stdout.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    size: ImageSize,
    #[command(flatten)]
    lighting: LightingArg,
    #[command(flatten)]
    traversal: TraversalArg,
    #[command(flatten)]
    msaa: MsaaArg,
    /// Largest error allowed at an interior pixel [default: 1e-3, and 5e-3
    /// for raytrace].
    #[arg(long)]
    interior_max_abs: Option<f64>,
    /// Largest share (0-1) of the image allowed to be edge pixels that differ
    /// by more than 0.01 [default: 5e-4, and 5e-3 for raytrace].
    #[arg(long)]
    edge_fraction: Option<f64>,
    /// Largest mean FLIP allowed over the image [default: 1e-3, and 5e-3 for
    /// raytrace].
    #[arg(long)]
    flip_mean: Option<f64>,
    /// Run only the cases of shard I of N (1 <= I <= N), dealt out by each
    /// scene's path and mode so that a case stays on its shard when others
    /// are added; the shard's record (check.json) goes into --out.
    #[arg(long, value_name = "I/N", value_parser = super::shards::parse_shard)]
    shard: Option<(usize, usize)>,
    /// Join the records of these shard folders (each a shard's --out) into
    /// one report: the images copied into --out, check.json, --junit and
    /// --json as the whole run writes them.
    #[arg(long, num_args = 1.., value_name = "DIR", conflicts_with_all = ["scenes", "shard"])]
    merge: Vec<PathBuf>,
    #[command(flatten)]
    pub machine: super::args::MachineArgs,
}

/// The record a shard of `check` leaves in its --out for `--merge`.
const RECORD: &str = "check.json";

/// Why a case gave no outcome: it could not be checked (reported as a case
/// that failed, the run goes on), or its images could not be written (the
/// run stops).
enum CaseError {
    Check(Failure),
    Write(Failure),
}

impl From<shadelab::Error> for CaseError {
    fn from(e: shadelab::Error) -> Self {
        CaseError::Check(e.into())
    }
}

impl From<Failure> for CaseError {
    fn from(f: Failure) -> Self {
        CaseError::Write(f)
    }
}

fn io_failure(path: &Path, e: impl std::fmt::Display) -> Failure {
    Failure::usage(format!("cannot write {}: {e}", path.display()))
}

pub fn run(args: CheckArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    if !args.merge.is_empty() {
        return merge(&args);
    }
    let modes = args.modes.modes();
    super::ignored::warn(
        &super::ignored::scene_flags_given(&args.traversal, &args.msaa, None),
        &modes,
        super::ignored::Backends::Both,
    );
    let limits_for = |shading: Shading, msaa: shadelab::msaa::Msaa| {
        let defaults = CheckThresholds::for_render(shading, msaa);
        CheckThresholds {
            interior_max_abs: args.interior_max_abs.unwrap_or(defaults.interior_max_abs),
            edge_fraction: args.edge_fraction.unwrap_or(defaults.edge_fraction),
            flip_mean: args.flip_mean.unwrap_or(defaults.flip_mean),
            ..defaults
        }
    };
    for (name, v) in [
        ("--interior-max-abs", args.interior_max_abs.unwrap_or(0.0)),
        ("--edge-fraction", args.edge_fraction.unwrap_or(0.0)),
        ("--flip-mean", args.flip_mean.unwrap_or(0.0)),
    ] {
        if !v.is_finite() || v < 0.0 {
            return Err(Failure::usage(format!(
                "{name} {v} is invalid; expected a number >= 0"
            )));
        }
    }
    // The flags first: a bad one is a usage error before anything runs. A
    // scene that does not load, or the device, fails its own cases only
    // (JUnit errors); the run goes on with the rest.
    args.size.check()?;
    // The flags that apply to every scene, checked once: a bad engine name
    // or a hook file that cannot be read is a usage error, not an error in
    // every case.
    {
        let mut probe = shadelab::scene::default_scene();
        args.lighting.apply(&mut probe)?;
        args.traversal.apply(&mut probe)?;
        args.msaa.apply(&mut probe)?;
    }
    if let Some(path) = &args.junit {
        shadelab::output::prepare_output_path(path)?;
    }
    let mut scenes: Vec<(Result<shadelab::scene::Scene, Failure>, String)> = Vec::new();
    let mut largest_estimate = 0u64;
    let paths: Vec<Option<&Path>> = if args.scenes.is_empty() {
        vec![None]
    } else {
        args.scenes.iter().map(|p| Some(p.as_path())).collect()
    };
    for path in paths {
        let stem_of = |p: &Path| {
            p.file_stem()
                .map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned())
        };
        let loaded = load_scene(path, memory).and_then(|(mut scene, stem)| {
            args.size.apply(&mut scene)?;
            args.lighting.apply(&mut scene)?;
            args.traversal.apply(&mut scene)?;
            args.msaa.apply(&mut scene)?;
            let estimate = memory.check(&stem, &scene, &modes, &modes)?;
            Ok((scene, stem, estimate))
        });
        let (scene, mut name) = match loaded {
            Ok((scene, stem, estimate)) => {
                largest_estimate = largest_estimate.max(estimate);
                (Ok(scene), stem)
            }
            Err(failure) => (Err(failure), path.map_or_else(|| "default".into(), stem_of)),
        };
        if scenes.iter().any(|(_, n)| *n == name) {
            name = format!("{name}-{}", scenes.len() + 1);
        }
        scenes.push((scene, name));
    }
    // Every case of the whole run, in order; a shard keeps its own.
    let keys = super::golden_keys::scene_keys(&args.scenes, None)?;
    let (orders, jobs): (Vec<usize>, Vec<(usize, Shading)>) = (0..scenes.len())
        .flat_map(|i| modes.iter().map(move |&shading| (i, shading)))
        .enumerate()
        .filter(|(_, (i, shading))| {
            super::shards::on_shard(&format!("{}/{shading}", keys[*i]), args.shard)
        })
        .unzip();
    // No device: every case is an error, said once and in the JUnit file.
    let (context, no_device) = match GpuContext::new(options) {
        Ok(context) => (Some(context), None),
        Err(e) => (None, Some(Failure::from(e))),
    };
    if args.images != KeepImages::None && scenes.iter().any(|(scene, _)| scene.is_ok()) {
        // Writable before any case runs; a scene's folder is made when it
        // has images to hold.
        shadelab::output::prepare_output_folder(&args.out)?;
    }
    let workers = case_workers(jobs.len(), largest_estimate, memory);
    let mut report = CaseReport::new(args.json);
    // Each case's CPU reference counts its phases here, for the progress.
    let counters: Vec<WorkCounter> = jobs.iter().map(|_| WorkCounter::default()).collect();
    let fallback = WorkCounter::default();
    let counter_of = |job: (usize, Shading)| {
        jobs.iter()
            .position(|j| *j == job)
            .map_or(&fallback, |k| &counters[k])
    };
    let run_case = |context: &Arc<GpuContext>, (i, shading): (usize, Shading)| {
        let (scene, name) = &scenes[i];
        let scene = scene.as_ref().map_err(|f| CaseError::Check(f.clone()))?;
        let limits = limits_for(shading, scene.render.msaa);
        let counter = counter_of((i, shading));
        let outcome = check_counted(context, scene, scene, shading, &limits, counter)?;
        let keep = match args.images {
            KeepImages::All => true,
            KeepImages::Failures => !outcome.passed(),
            KeepImages::None => false,
        };
        if keep {
            let folder = args.out.join(name);
            std::fs::create_dir_all(&folder).map_err(|e| io_failure(&folder, e))?;
            write_images(&folder, &outcome)?;
        }
        Ok::<_, CaseError>(outcome)
    };
    let mut on_result = |k: usize, result: Result<CheckOutcome, CaseError>| {
        let (i, shading) = jobs[k];
        let name = &scenes[i].1;
        match result {
            Ok(outcome) => report.outcome(name, shading, &outcome, &args.out),
            Err(CaseError::Write(failure)) => return Err(failure),
            Err(CaseError::Check(error)) => report.error(name, shading, error),
        }
        Ok(())
    };
    let progress = Progress::new("check", jobs.len() as u64);
    let case_name = |k: usize| {
        jobs.get(k).map_or_else(String::new, |&(i, shading)| {
            format!("{} {shading}", scenes[i].1)
        })
    };
    progress.set(0, &case_name(0));
    match &context {
        Some(context) => {
            let open_another = || GpuContext::new(options).ok();
            // The case waited for, and where its CPU reference is.
            let due = AtomicUsize::new(0);
            let finished = AtomicBool::new(false);
            let on_result = |k: usize, result| {
                due.store(k + 1, Ordering::Relaxed);
                progress.set(k as u64 + 1, &case_name(k + 1));
                progress.suspend(|| on_result(k, result))
            };
            std::thread::scope(|scope| {
                scope.spawn(|| {
                    while !finished.load(Ordering::Relaxed) {
                        let k = due.load(Ordering::Relaxed);
                        if let Some(counter) = counters.get(k) {
                            let (phase, done, total) = counter.read();
                            if !phase.is_empty() && due.load(Ordering::Relaxed) == k {
                                let now = format!(
                                    "{} (its CPU reference: {phase} {done} of {total})",
                                    case_name(k)
                                );
                                progress.set(k as u64, &now);
                            }
                        }
                        std::thread::sleep(std::time::Duration::from_millis(200));
                    }
                });
                let ran = in_order(context, open_another, &jobs, workers, run_case, on_result);
                finished.store(true, Ordering::Relaxed);
                ran
            })?;
        }
        None => {
            let no_device = no_device.expect("no context, so an error");
            for (k, &(i, _)) in jobs.iter().enumerate() {
                let error = match &scenes[i].0 {
                    Err(scene_error) => scene_error.clone(),
                    Ok(_) => no_device.clone(),
                };
                on_result(k, Err(CaseError::Check(error)))?;
            }
        }
    }
    drop(progress);
    if let Some(path) = &args.junit {
        let xml = junit::render("shadelab check", &report.cases);
        write_atomically(path, xml.as_bytes())?;
    }
    if let Some((i, n)) = args.shard {
        let cases: Vec<serde_json::Value> = report
            .json
            .iter()
            .zip(&report.cases)
            .zip(&orders)
            .map(|((v, t), order)| {
                let mut v = v.clone();
                v["order"] = (*order).into();
                v["junit"] = super::golden_report::junit_json(t);
                v
            })
            .collect();
        let record = serde_json::json!({
            "shard": [i, n],
            "run": {"modes": modes},
            "out": args.out,
            "cases": cases,
        });
        shadelab::output::prepare_output_folder(&args.out)?;
        write_atomically(&args.out.join(RECORD), record.to_string().as_bytes())?;
    }
    if args.json {
        let value = serde_json::json!({
            "thresholds": {
                "raster": limits_for(Shading::Phong, Default::default()),
                "raster_multisampled": limits_for(Shading::Phong, shadelab::msaa::Msaa { samples: 4, per_sample: false }),
                "raytrace": limits_for(Shading::Raytrace, Default::default()),
            },
            "cases": report.json,
            "failed": report.failed,
            "errors": report.errors,
        });
        println!("{value}");
    } else {
        let errors = if report.errors > 0 {
            format!(", {} could not run", report.errors)
        } else {
            String::new()
        };
        println!(
            "{} of {} cases passed{errors}; images in {}",
            report.cases.len() - report.failed - report.errors,
            report.cases.len(),
            args.out.display()
        );
    }
    report.exit_status()
}

/// `--merge DIR...`: the shards' records joined in the whole run's order,
/// their images copied into --out, and the JUnit file, the record and the
/// summary written as the whole run writes them.
fn merge(args: &CheckArgs) -> Result<(), Failure> {
    if let Some(path) = &args.junit {
        shadelab::output::prepare_output_path(path)?;
    }
    let shards = super::shards::read_shards(&args.merge, RECORD)?;
    shadelab::output::prepare_output_folder(&args.out)?;
    let cases = super::shards::merged_cases(&shards);
    for (dir, shard) in &shards {
        let shard_out = shard["out"].as_str().map(PathBuf::from);
        for case in shard["cases"].as_array().into_iter().flatten() {
            let Some(images) = case["images"].as_str().map(Path::new) else {
                continue;
            };
            // `OUT/scene/mode`: its three images, where they were kept.
            let relative = shard_out
                .as_deref()
                .and_then(|o| images.strip_prefix(o).ok())
                .unwrap_or(images);
            for what in ["expected", "actual", "diff"] {
                let name = relative.with_file_name(format!(
                    "{}-{what}.png",
                    relative
                        .file_name()
                        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
                ));
                if dir.join(&name).is_file() {
                    super::shards::copy_into(dir, &args.out, &name)?;
                }
            }
        }
    }
    let junit: Vec<_> = cases
        .iter()
        .map(|v| super::golden_report::junit_from_json(&v["junit"]))
        .collect();
    if let Some(path) = &args.junit {
        write_atomically(path, junit::render("shadelab check", &junit).as_bytes())?;
    }
    let failed = cases
        .iter()
        .filter(|v| v["passed"] == false && v.get("error").is_none())
        .count();
    let errors = cases.iter().filter(|v| v.get("error").is_some()).count();
    let record = serde_json::json!({"shard": null, "run": shards[0].1["run"], "out": args.out, "cases": cases});
    write_atomically(&args.out.join(RECORD), record.to_string().as_bytes())?;
    if args.json {
        let value = serde_json::json!({"cases": cases, "failed": failed, "errors": errors});
        println!("{value}");
    } else {
        println!(
            "{} of {} cases passed{}; merged from {} shards into {}",
            cases.len() - failed - errors,
            cases.len(),
            if errors > 0 {
                format!(", {errors} could not run")
            } else {
                String::new()
            },
            shards.len(),
            args.out.display()
        );
    }
    if failed + errors == 0 {
        return Ok(());
    }
    Err(Failure {
        code: 1,
        message: format!(
            "{failed} of {} cases failed their thresholds{}",
            cases.len(),
            if errors > 0 {
                format!(" and {errors} could not run")
            } else {
                String::new()
            }
        ),
    })
}

/// The images as compared: in units of `o.judgement.scale`, so that a scene lit at
/// 1e30 is not written all white.
fn write_images(folder: &Path, o: &CheckOutcome) -> Result<(), Failure> {
    let mode = o.shading.to_string();
    let expected = scaled(&o.expected, o.judgement.scale);
    let actual = scaled(&o.actual, o.judgement.scale);
    // Three encodings, each on one thread: side by side.
    let heat = || {
        write_image(
            &flip_heatmap(&o.judgement.flip),
            &folder.join(format!("{mode}-diff.png")),
        )
    };
    let ((e, a), h) = rayon::join(
        || {
            rayon::join(
                || write_image(&expected, &folder.join(format!("{mode}-expected.png"))),
                || write_image(&actual, &folder.join(format!("{mode}-actual.png"))),
            )
        },
        heat,
    );
    e?;
    a?;
    h?;
    Ok(())
}
