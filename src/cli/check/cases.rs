//! `check`'s cases run: each scene in each mode on the GPU beside its CPU
//! reference, one or two at a time, the progress showing how far a case's
//! CPU reference is, and each case's images written as `--images` keeps
//! them.

use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use shadelab::check::{check_counted, scaled, CheckOutcome, CheckThresholds};
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::metrics::heatmap::flip_heatmap;
use shadelab::msaa::Msaa;
use shadelab::output::write_image;
use shadelab::render::Device;
use shadelab::scene::Scene;
use shadelab::shading::Shading;
use shadelab::work_counter::WorkCounter;

use super::report::{CaseReport, KeepImages};
use crate::cli::common::cases::in_order;
use crate::cli::common::failure::Failure;
use crate::cli::common::progress::Progress;

/// A scene of the run (or why it could not be had) and its name, unique in
/// the run.
pub(super) type NamedScene = (Result<Scene, Failure>, String);

/// A case: its scene's index in the run's scenes, and the mode.
pub(super) type Job = (usize, Shading);

/// The cases of a run: every scene (or why it did not load) with its name,
/// the (scene, mode) pairs this run checks, and where their images go.
pub(super) struct Cases<'a> {
    pub scenes: &'a [NamedScene],
    pub jobs: &'a [Job],
    pub images: KeepImages,
    pub out: &'a Path,
}

impl Cases<'_> {
    /// `scene mode` of the k-th case, for the progress; empty past the last.
    fn name_of(&self, k: usize) -> String {
        self.jobs.get(k).map_or_else(String::new, |&(i, shading)| {
            format!("{} {shading}", self.scenes[i].1)
        })
    }
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

fn io_failure(path: &Path, e: impl std::fmt::Display) -> Failure {
    Failure::usage(format!("cannot write {}: {e}", path.display()))
}

/// Runs every case on `device` (on `workers` devices at once, the others
/// opened with `options`) and hands each outcome to `report` in the cases'
/// order. No device: every case is an error, said once and in the JUnit
/// file.
pub(super) fn run_cases(
    cases: &Cases,
    limits_for: impl Fn(Shading, Msaa) -> CheckThresholds + Sync,
    device: &Result<Arc<GpuContext>, Failure>,
    options: &GpuOptions,
    workers: usize,
    report: &mut CaseReport,
) -> Result<(), Failure> {
    let jobs = cases.jobs;
    // Each case's CPU reference counts its phases here, for the progress.
    let counters: Vec<WorkCounter> = jobs.iter().map(|_| WorkCounter::default()).collect();
    let fallback = WorkCounter::default();
    let counter_of = |job: (usize, Shading)| {
        jobs.iter()
            .position(|j| *j == job)
            .map_or(&fallback, |k| &counters[k])
    };
    let run_case = |context: &Arc<GpuContext>, job: (usize, Shading)| {
        check_case(context, cases, &limits_for, counter_of(job), job)
    };
    let mut on_result =
        |k: usize, result: Result<CheckOutcome, CaseError>| record(report, cases, k, result);
    let progress = Progress::new("check", jobs.len() as u64);
    progress.set(0, &cases.name_of(0));
    match device {
        Ok(context) => {
            let open_another = || GpuContext::new(options).ok();
            // The case waited for, and where its CPU reference is.
            let due = AtomicUsize::new(0);
            let finished = AtomicBool::new(false);
            let on_result = |k: usize, result| {
                due.store(k + 1, Ordering::Relaxed);
                progress.set(k as u64 + 1, &cases.name_of(k + 1));
                progress.suspend(|| on_result(k, result))
            };
            std::thread::scope(|scope| {
                scope.spawn(|| show_references(&progress, cases, &counters, &due, &finished));
                let ran = in_order(context, open_another, jobs, workers, run_case, on_result);
                finished.store(true, Ordering::Relaxed);
                ran
            })?;
        }
        Err(no_device) => {
            for (k, &(i, _)) in jobs.iter().enumerate() {
                let error = match &cases.scenes[i].0 {
                    Err(scene_error) => scene_error.clone(),
                    Ok(_) => no_device.clone(),
                };
                on_result(k, Err(CaseError::Check(error)))?;
            }
        }
    }
    Ok(())
}

/// Until `finished`: the case waited for, with how far its CPU reference
/// is, while that reference counts its phases.
fn show_references(
    progress: &Progress,
    cases: &Cases,
    counters: &[WorkCounter],
    due: &AtomicUsize,
    finished: &AtomicBool,
) {
    while !finished.load(Ordering::Relaxed) {
        let k = due.load(Ordering::Relaxed);
        if let Some(counter) = counters.get(k) {
            let (phase, done, total) = counter.read();
            if !phase.is_empty() && due.load(Ordering::Relaxed) == k {
                let now = format!(
                    "{} (its CPU reference: {phase} {done} of {total})",
                    cases.name_of(k)
                );
                progress.set(k as u64, &now);
            }
        }
        std::thread::sleep(std::time::Duration::from_millis(200));
    }
}

/// One case: the GPU's image against the CPU reference's, and the images
/// written where `--images` keeps them.
fn check_case(
    context: &Arc<GpuContext>,
    cases: &Cases,
    limits_for: &impl Fn(Shading, Msaa) -> CheckThresholds,
    counter: &WorkCounter,
    (i, shading): (usize, Shading),
) -> Result<CheckOutcome, CaseError> {
    let (scene, name) = &cases.scenes[i];
    let scene = scene.as_ref().map_err(|f| CaseError::Check(f.clone()))?;
    let limits = limits_for(shading, scene.render.msaa);
    let outcome = check_counted(
        &Device::with_gpu(context.clone()),
        scene,
        scene,
        shading,
        &limits,
        counter,
    )?;
    let keep = match cases.images {
        KeepImages::All => true,
        KeepImages::Failures => !outcome.passed(),
        KeepImages::None => false,
    };
    if keep {
        let folder = cases.out.join(name);
        std::fs::create_dir_all(&folder).map_err(|e| io_failure(&folder, e))?;
        write_images(&folder, &outcome)?;
    }
    Ok(outcome)
}

/// The k-th case's outcome into the report; an image that could not be
/// written stops the run.
fn record(
    report: &mut CaseReport,
    cases: &Cases,
    k: usize,
    result: Result<CheckOutcome, CaseError>,
) -> Result<(), Failure> {
    let (i, shading) = cases.jobs[k];
    let name = &cases.scenes[i].1;
    match result {
        Ok(outcome) => report.outcome(name, shading, &outcome, cases.out),
        Err(CaseError::Write(failure)) => return Err(failure),
        Err(CaseError::Check(error)) => report.error(name, shading, error),
    }
    Ok(())
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
