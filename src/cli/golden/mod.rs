//! `shadelab golden`: each scene in each mode rendered (the lighting hook in
//! play) and compared with its stored reference image, with limits for a
//! render against a stored render of the same renderer. Missing references
//! fail unless `--create` makes them; `--bless` accepts the renders that
//! changed. References are kept per driver where one needs its own, found
//! before the shared ones.
//!
//! This file runs the steps in order; `args.rs` is the command line,
//! `judging.rs` hands each rendered case to the library's judging
//! (`shadelab::golden`), `print.rs` says each case, `record.rs` writes the
//! run's files (made by `shadelab::golden::record` and `report`) and gives
//! its exit status.

mod args;
mod judging;
mod print;
mod record;

pub use args::GoldenArgs;

use std::time::Instant;

use shadelab::diff::{parse_thresholds, Judging, Preset};
use shadelab::golden::keys::{self, driver_key};
use shadelab::golden::report::{case_records, ReportCase};
use shadelab::golden::{JudgeOptions, Judged, RunRecord};
use shadelab::gpu::GpuOptions;
use shadelab::memory::MemoryLimit;
use shadelab::metrics::Thresholds;
use shadelab::output;

use crate::cli::common::batch::args::RenderArgs;
use crate::cli::common::batch::plan::file_name;
use crate::cli::common::batch::{Batch, CaseView, Made};
use crate::cli::common::failure::Failure;
use judging::judge_case;
use print::print_case;
use record::{conclude, merge};

/// Plan the batch, judge each case as it is rendered, then write the
/// record and reports (`record.rs`); `--merge` joins shards instead.
pub fn run(args: GoldenArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    if !args.merge.is_empty() {
        return merge(&args);
    }
    let started = Instant::now();
    let judging = judging(&args)?;
    check_places(&args)?;
    let bless = args.bless || bless_from_env();
    let render_args = render_args(&args)?;
    Batch::check_flags(&render_args)?;
    refuse_shared_references(&render_args)?;
    output::prepare_output_folder(&args.out)?;
    if let Some(path) = &args.junit {
        output::prepare_output_path(path)?;
    }
    let batch = Batch::plan(&render_args, options, memory)?;
    let (device, driver) = batch.context().map_or_else(
        || ("no device".to_string(), String::new()),
        |c| (c.info.name.clone(), c.info.driver.clone()),
    );
    let key = args
        .key
        .clone()
        .unwrap_or_else(|| driver_key(&device, &driver));
    let plan = JudgeOptions {
        references: args.references().to_path_buf(),
        key,
        judging,
        create: args.create,
        bless,
        per_driver: args.per_driver,
        out: args.out.clone(),
    };
    if !args.json {
        println!(
            "references {} (this driver's: {}); limits {}",
            args.references().display(),
            args.references().join(&plan.key).display(),
            describe_limits(args.preset.preset(), &plan.judging.thresholds)
        );
    }
    let cases = judge_cases(&plan, &args, &batch, &render_args)?;

    let limits = describe_limits(args.preset.preset(), &plan.judging.thresholds);
    let records = case_records(&cases);
    // A shard with no cases opens no device, so has no driver key of its
    // own unless --key gives one: it records none, and merges with any.
    let key_known = args.key.is_some() || batch.len() > 0;
    let run = RunRecord {
        shard: args.shard,
        identity: run_identity(&args, &render_args, &plan.judging.thresholds, bless),
        references: args.references().to_path_buf(),
        key: key_known.then(|| plan.key.clone()),
        device,
        driver,
        preset: args.preset.preset(),
        thresholds: serde_json::to_value(plan.judging.thresholds).unwrap_or_default(),
        limits,
        bless,
        wall_ms: shadelab::gpu::ms_since(started),
    };
    let first_error = cases.iter().find_map(|(_, c)| c.judged.error.clone());
    conclude(&args, &run, records, first_error)
}

/// What the whole run is, for its shards' records (`common/run_digest.rs`): every
/// case of every shard, each scene's and the hook's contents, the flags,
/// the references and limits. Not where it ran or wrote (the device,
/// `--out`, `--junit`), which differ between the shards of one run.
fn run_identity(
    args: &GoldenArgs,
    render_args: &RenderArgs,
    thresholds: &Thresholds,
    bless: bool,
) -> serde_json::Value {
    let keys = render_args.scene_names.as_deref().unwrap_or_default();
    let modes = args.modes.modes();
    let (cases, scenes) =
        crate::cli::common::run_digest::cases_and_scenes(keys, &args.scenes, &modes);
    let flags = &args.settings;
    crate::cli::common::run_digest::run_identity(serde_json::json!({
        "cases": cases,
        "scenes": scenes,
        "name": args.name,
        "references": args.references(),
        "preset": args.preset.preset(),
        "thresholds": thresholds,
        "create": args.create,
        "bless": bless,
        "per_driver": args.per_driver,
        "width": args.size.width,
        "height": args.size.height,
        "flags": crate::cli::common::run_digest::scene_flags(&flags.lighting, &flags.traversal, &flags.msaa, &flags.depth),
    }))
}

/// The limits: the preset's, with `--threshold` on top.
fn judging(args: &GoldenArgs) -> Result<Judging, Failure> {
    let thresholds = parse_thresholds(args.preset.preset().thresholds(), &args.threshold)?;
    Ok(Judging::new(thresholds))
}

/// Refuses a `--key` that is not a folder name, and `--references` that is
/// a file.
fn check_places(args: &GoldenArgs) -> Result<(), Failure> {
    if let Some(key) = &args.key {
        let clean = !key.is_empty() && key != "." && key != ".." && !key.contains(['/', '\\']);
        if !clean {
            return Err(Failure::usage(format!(
                "--key {key:?} must be a folder name (no path)"
            )));
        }
    }
    if args.references().exists() && !args.references().is_dir() {
        return Err(Failure::usage(format!(
            "--references {} is not a folder",
            args.references().display()
        )));
    }
    Ok(())
}

/// The batch `render` would make of these scenes and modes: on the GPU,
/// named by `--name` from the scenes' keys.
fn render_args(args: &GoldenArgs) -> Result<RenderArgs, Failure> {
    Ok(RenderArgs {
        scenes: args.scenes.clone(),
        shading: args.modes.modes(),
        backend: "gpu".to_string(),
        size: args.size.clone(),
        settings: args.settings.clone(),
        cutoff: None,
        samples: None,
        no_shadows: false,
        out: None,
        out_dir: None,
        name: Some(args.name.clone()),
        json: args.json,
        stats: false,
        render_shard: None,
        time: None,
        error_budget: None,
        merge: Vec::new(),
        machine: args.machine.clone(),
        scene_names: Some(keys::scene_keys(&args.scenes, args.root.as_deref())?),
        shard: args.shard,
    })
}

/// Renders and judges every case, each printed as it comes (unless
/// `--json`); the cases with their places in the whole run.
fn judge_cases(
    plan: &JudgeOptions,
    args: &GoldenArgs,
    batch: &Batch,
    render_args: &RenderArgs,
) -> Result<Vec<(usize, ReportCase)>, Failure> {
    let mut cases: Vec<(usize, ReportCase)> = Vec::new();
    let handle =
        |view: &CaseView, made: Result<Made, Failure>| judge_case(plan, view, made, Instant::now());
    let report = |view: &CaseView, judged: Judged| {
        if !args.json {
            print_case(view, &judged, &args.out);
        }
        cases.push((
            view.order,
            ReportCase {
                scene: view.name.to_string(),
                shading: view.shading,
                file: view.file_name.to_string(),
                judged,
            },
        ));
        Ok(())
    };
    batch.run("golden", render_args, handle, report)?;
    Ok(cases)
}

/// `SHADELAB_BLESS` set to anything but empty, 0 or false.
fn bless_from_env() -> bool {
    std::env::var("SHADELAB_BLESS")
        .map(|v| !matches!(v.trim(), "" | "0" | "false"))
        .unwrap_or(false)
}

/// Refuses, before any work, two cases that would read and write one
/// reference (two scenes whose paths differ only in their extension, one
/// scene given twice, a `--name` that leaves the mode out).
fn refuse_shared_references(args: &RenderArgs) -> Result<(), Failure> {
    let names = args.scene_names.as_deref().unwrap_or_default();
    let mut cases = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let scene = args.scenes.get(k).map_or_else(
            || "the default scene".to_string(),
            |p| p.display().to_string(),
        );
        for shading in args.modes() {
            let file = file_name(args.name_pattern(), name, shading);
            cases.push((file, format!("{scene} ({shading})")));
        }
    }
    match keys::first_clash(&cases) {
        Some((file, first, second)) => Err(Failure::usage(format!(
            "{first} and {second} would share the reference {file}; give each scene its own path below --root (or its own file name)"
        ))),
        None => Ok(()),
    }
}

/// The limits for people: the preset's name, then each limit.
fn describe_limits(preset: Preset, t: &Thresholds) -> String {
    let mut parts = vec![
        format!("max_abs {}", t.max_abs),
        format!("p99_abs {}", t.p99_abs),
        format!("flip_mean {}", t.flip_mean),
    ];
    for (name, value) in [
        ("rmse", t.rmse),
        ("fraction_over", t.fraction_over),
        ("count_over", t.count_over),
    ] {
        if let Some(v) = value {
            parts.push(format!("{name} {v}"));
        }
    }
    if let Some(psnr) = t.psnr {
        parts.push(format!("psnr >= {psnr} dB"));
    }
    format!("{} ({})", preset.name(), parts.join(", "))
}
