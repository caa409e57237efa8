//! `shadelab check`: every scene in every mode, GPU against the CPU
//! reference; images for CI to keep, a verdict line per case, optionally a
//! JUnit report; exit status 1 when any case fails.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};

use clap::Args;
use shadelab::check::{check, scaled, CheckOutcome, CheckThresholds};
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::junit;
use shadelab::memory::MemoryLimit;
use shadelab::metrics::heatmap::flip_heatmap;
use shadelab::output::{write_atomically, write_image};
use shadelab::shading::Shading;

use super::args::{ImageSize, LightingArg, ModeList, TraversalArg};
use super::check_report::{CaseReport, KeepImages};
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
    #[command(flatten)]
    pub machine: super::args::MachineArgs,
}

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

/// How many cases run at once, each on a device of its own: two where there
/// are two cores and the memory limit holds two of the largest case. Each
/// case is mostly single-threaded work (lavapipe's pipeline creation and
/// code generation, FLIP, PNG encoding), so a second case fills the other
/// core: on a fresh machine, whose code generation is most of the time,
/// the cases' pipelines are generated two at a time.
fn case_workers(cases: usize, largest_estimate: u64, memory: &MemoryLimit) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let fits_two = largest_estimate.saturating_mul(2) <= memory.bytes;
    if cases >= 2 && cores >= 2 && fits_two {
        2
    } else {
        1
    }
}

/// Runs `run` on every job, on `workers` threads (the first with `context`,
/// each other with one of its own from `open_another`, or none if that
/// gives none),
/// and hands each result to `report` in the jobs' order as soon as those
/// before it are in. An error from `report` stops the workers after their
/// current job and is returned.
fn in_order<C: Sync, J: Copy + Sync, T: Send>(
    context: &C,
    open_another: impl Fn() -> Option<C> + Sync,
    jobs: &[J],
    workers: usize,
    run: impl Fn(&C, J) -> T + Sync,
    mut report: impl FnMut(usize, T) -> Result<(), Failure>,
) -> Result<(), Failure> {
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let (sender, received) = mpsc::channel::<(usize, T)>();
    let work = |context: &C, sender: mpsc::Sender<(usize, T)>| loop {
        let k = next.fetch_add(1, Ordering::Relaxed);
        if k >= jobs.len() || stop.load(Ordering::Relaxed) {
            break;
        }
        if sender.send((k, run(context, jobs[k]))).is_err() {
            break;
        }
    };
    let work = &work;
    std::thread::scope(|scope| {
        for _ in 1..workers {
            let sender = sender.clone();
            let open_another = &open_another;
            scope.spawn(move || {
                if let Some(own) = open_another() {
                    work(&own, sender);
                }
            });
        }
        let sender_main = sender;
        let main_worker = scope.spawn(move || work(context, sender_main));
        let mut waiting = BTreeMap::new();
        let mut due = 0;
        let mut outcome = Ok(());
        for (k, result) in received.iter() {
            waiting.insert(k, result);
            while let Some(result) = waiting.remove(&due) {
                due += 1;
                if outcome.is_ok() {
                    outcome = report(due - 1, result);
                    if outcome.is_err() {
                        stop.store(true, Ordering::Relaxed);
                    }
                }
            }
        }
        let _ = main_worker.join();
        outcome
    })
}

fn io_failure(path: &Path, e: impl std::fmt::Display) -> Failure {
    Failure::usage(format!("cannot write {}: {e}", path.display()))
}

pub fn run(args: CheckArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    let modes = args.modes.modes();
    args.modes
        .warn_unused(&super::args::ray_trace_flags(None, &args.traversal, false));
    let limits_for = |shading: Shading| {
        let defaults = CheckThresholds::for_shading(shading);
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
    let jobs: Vec<(usize, Shading)> = (0..scenes.len())
        .flat_map(|i| modes.iter().map(move |&shading| (i, shading)))
        .collect();
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
    let run_case = |context: &Arc<GpuContext>, (i, shading): (usize, Shading)| {
        let (scene, name) = &scenes[i];
        let scene = scene.as_ref().map_err(|f| CaseError::Check(f.clone()))?;
        let outcome = check(context, scene, scene, shading, &limits_for(shading))?;
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
    match &context {
        Some(context) => {
            let open_another = || GpuContext::new(options).ok();
            in_order(context, open_another, &jobs, workers, run_case, on_result)?;
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
    if let Some(path) = &args.junit {
        let xml = junit::render("shadelab check", &report.cases);
        write_atomically(path, xml.as_bytes())?;
    }
    if args.json {
        let value = serde_json::json!({
            "thresholds": {
                "raster": limits_for(Shading::Phong),
                "raytrace": limits_for(Shading::Raytrace),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Results come back in the jobs' order however the workers finish:
    /// here the early jobs take the longest, so they finish last.
    #[test]
    fn results_are_reported_in_the_jobs_order() {
        let jobs: Vec<u64> = (0..12).collect();
        let slow_first = |_: &(), j: u64| {
            std::thread::sleep(std::time::Duration::from_millis(2 * (12 - j)));
            j * 10
        };
        let mut seen = Vec::new();
        in_order(
            &(),
            || Some(()),
            &jobs,
            2,
            slow_first,
            |k, t| {
                seen.push((k, t));
                Ok(())
            },
        )
        .unwrap_or_else(|f| panic!("{}", f.message));
        let expected: Vec<(usize, u64)> = (0..12).map(|j| (j as usize, j * 10)).collect();
        assert_eq!(seen, expected);
    }

    /// An error from the report stops the run: it is returned, and no later
    /// result is reported.
    #[test]
    fn a_report_error_stops_the_run() {
        let jobs: Vec<u64> = (0..50).collect();
        let mut reported = 0;
        let result = in_order(
            &(),
            || Some(()),
            &jobs,
            2,
            |_, j| j,
            |k, _| {
                reported += 1;
                if k == 3 {
                    Err(Failure::usage("stop".into()))
                } else {
                    Ok(())
                }
            },
        );
        assert_eq!(result.err().map(|f| f.message), Some("stop".to_string()));
        assert_eq!(reported, 4);
    }

    /// Without a second context the first worker does every job.
    #[test]
    fn one_worker_does_all_when_no_other_opens() {
        let jobs: Vec<u64> = (0..5).collect();
        let mut seen = Vec::new();
        in_order(
            &(),
            || None,
            &jobs,
            2,
            |_, j| j,
            |_, t| {
                seen.push(t);
                Ok(())
            },
        )
        .unwrap_or_else(|f| panic!("{}", f.message));
        assert_eq!(seen, jobs);
    }
}
