//! `shadelab render` with many scenes or modes (or `--out-dir`): each image
//! written into `--out-dir`, named by `--name`; the exit status is the
//! first failed case's.

use std::path::{Path, PathBuf};
use std::time::Instant;

use shadelab::gpu::GpuOptions;
use shadelab::memory::MemoryLimit;
use shadelab::shading::Shading;

use super::stats::print_stats;
use crate::cli::common::batch::args::RenderArgs;
use crate::cli::common::batch::{non_finite_failure, Batch, CaseView, Made};
use crate::cli::common::failure::Failure;

/// What one case came to: the JSON object, the line for people, the ray
/// statistics to print, and the failure if it failed.
struct CaseDone {
    value: serde_json::Value,
    line: Option<String>,
    stats: Option<(shadelab::render::Rendered, Shading)>,
    failure: Option<Failure>,
}

/// `render` with many images: each written into `--out-dir`.
pub(super) fn run(
    args: &RenderArgs,
    options: &GpuOptions,
    memory: &MemoryLimit,
) -> Result<(), Failure> {
    let started = Instant::now();
    refuse_out(args)?;
    Batch::check_flags(args)?;
    let out_dir = args.out_dir.clone().unwrap_or_else(|| PathBuf::from("."));
    shadelab::output::prepare_output_folder(&out_dir)?;
    let batch = Batch::plan(args, options, memory)?;
    let mut failures: Vec<(String, Failure)> = Vec::new();
    let mut values = Vec::new();
    let handle =
        |view: &CaseView, made: Result<Made, Failure>| write_case(args, &out_dir, view, made);
    let report = |view: &CaseView, done: CaseDone| {
        let label = format!("{}/{}", view.name, view.shading);
        if !args.json {
            print_case(&label, &done);
        }
        if let Some(failure) = done.failure {
            failures.push((label, failure));
        }
        values.push(done.value);
        Ok(())
    };
    batch.run("render", args, handle, report)?;

    let (total, failed) = (batch.len(), failures.len());
    print_summary(args, &batch, &out_dir, values, failed, started);
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

/// `--out` names one image: refused for a batch, with what to give.
fn refuse_out(args: &RenderArgs) -> Result<(), Failure> {
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
    Ok(())
}

/// Writes case `view`'s image into `out_dir`; what it came to.
fn write_case(
    args: &RenderArgs,
    out_dir: &Path,
    view: &CaseView,
    made: Result<Made, Failure>,
) -> CaseDone {
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
}

/// A case's lines for people: where its image went, its ray statistics,
/// or its error.
fn print_case(label: &str, done: &CaseDone) {
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

/// The batch's JSON object (every case), or its line for people.
fn print_summary(
    args: &RenderArgs,
    batch: &Batch,
    out_dir: &Path,
    values: Vec<serde_json::Value>,
    failed: usize,
    started: Instant,
) {
    let total = batch.len();
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
