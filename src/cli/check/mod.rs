//! `shadelab check`: every scene in every mode, GPU against the CPU
//! reference; images for CI to keep, a verdict line per case, optionally a
//! JUnit report; exit status 1 when any case fails.

mod cases;
mod merge;
mod report;

use std::path::{Path, PathBuf};

use clap::Args;
use shadelab::check::CheckThresholds;
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::junit;
use shadelab::memory::MemoryLimit;
use shadelab::msaa::Msaa;
use shadelab::output::write_atomically;
use shadelab::shading::Shading;

use crate::cli::common::args::{DepthArg, ImageSize, LightingArg, ModeList, MsaaArg, TraversalArg};
use crate::cli::common::batch::scene::load_scene;
use crate::cli::common::cases::case_workers;
use crate::cli::common::failure::Failure;
use cases::{run_cases, Cases, Job, NamedScene};
use merge::{merge, RECORD};
use report::{CaseReport, KeepImages};

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
    #[command(flatten)]
    depth: DepthArg,
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
    /// are added; the shard's record (check.json) goes into --out. `auto`
    /// reads I and N from the CI's own variables (docs/golden.md).
    #[arg(long, value_name = "I/N", value_parser = crate::cli::common::shards::parse_shard)]
    shard: Option<(usize, usize)>,
    /// Join the records of these shard folders (each a shard's --out) into
    /// one report: the images copied into --out, check.json, --junit and
    /// --json as the whole run writes them.
    #[arg(long, num_args = 1.., value_name = "DIR", conflicts_with_all = ["scenes", "shard"])]
    merge: Vec<PathBuf>,
    #[command(flatten)]
    pub machine: crate::cli::common::args::MachineArgs,
}

pub fn run(args: CheckArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    if !args.merge.is_empty() {
        return merge(&args.merge, &args.out, args.junit.as_deref(), args.json);
    }
    let modes = args.modes.modes();
    check_flags(&args)?;
    let (scenes, largest_estimate) = load_scenes(&args, &modes, memory);
    let ignoring = crate::cli::common::ignored::Run {
        modes: &modes,
        backends: crate::cli::common::ignored::Backends::Both,
        caustics: scenes
            .iter()
            .any(|(scene, _)| scene.as_ref().is_ok_and(|s| s.render.caustics.on())),
    };
    crate::cli::common::ignored::warn(
        &crate::cli::common::ignored::scene_flags_given(&args.traversal, &args.msaa, &args.depth),
        ignoring,
    );
    let (orders, jobs) = plan_cases(&args, scenes.len(), &modes)?;
    let device = GpuContext::new(options).map_err(Failure::from);
    if args.images != KeepImages::None && scenes.iter().any(|(scene, _)| scene.is_ok()) {
        // Writable before any case runs; a scene's folder is made when it
        // has images to hold.
        shadelab::output::prepare_output_folder(&args.out)?;
    }
    let workers = case_workers(jobs.len(), largest_estimate, memory);
    let mut report = CaseReport::new(args.json);
    let cases = Cases {
        scenes: &scenes,
        jobs: &jobs,
        images: args.images,
        out: &args.out,
    };
    let limits = |shading: Shading, msaa: Msaa| limits_for(&args, shading, msaa);
    run_cases(&cases, limits, &device, options, workers, &mut report)?;
    if let Some(path) = &args.junit {
        let xml = junit::render("shadelab check", &report.cases);
        write_atomically(path, xml.as_bytes())?;
    }
    if let Some(shard) = args.shard {
        write_shard_record(&args, shard, &modes, &report, &orders)?;
    }
    print_summary(&args, &report);
    report.exit_status()
}

/// The thresholds of a render: the flags where given, else its defaults.
fn limits_for(args: &CheckArgs, shading: Shading, msaa: Msaa) -> CheckThresholds {
    let defaults = CheckThresholds::for_render(shading, msaa);
    CheckThresholds {
        interior_max_abs: args.interior_max_abs.unwrap_or(defaults.interior_max_abs),
        edge_fraction: args.edge_fraction.unwrap_or(defaults.edge_fraction),
        flip_mean: args.flip_mean.unwrap_or(defaults.flip_mean),
        ..defaults
    }
}

/// The flags first: a bad one is a usage error before anything runs. A
/// scene that does not load, or the device, fails its own cases only
/// (JUnit errors); the run goes on with the rest.
fn check_flags(args: &CheckArgs) -> Result<(), Failure> {
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
    args.size.check()?;
    // The flags that apply to every scene, checked once: a bad engine name
    // or a hook file that cannot be read is a usage error, not an error in
    // every case.
    {
        let mut probe = shadelab::scene::default_scene();
        args.lighting.apply(&mut probe)?;
        args.traversal.apply(&mut probe)?;
        args.msaa.apply(&mut probe)?;
        args.depth.apply(&mut probe)?;
    }
    if let Some(path) = &args.junit {
        shadelab::output::prepare_output_path(path)?;
    }
    Ok(())
}

/// Every scene with the flags applied (or why it could not be had) and its
/// name, unique in the run; and the largest memory estimate among them.
fn load_scenes(
    args: &CheckArgs,
    modes: &[Shading],
    memory: &MemoryLimit,
) -> (Vec<NamedScene>, u64) {
    let mut scenes: Vec<NamedScene> = Vec::new();
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
            args.depth.apply(&mut scene)?;
            let estimate = memory.check(&stem, &scene, modes, modes)?;
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
    (scenes, largest_estimate)
}

/// The cases this run checks, (scene, mode), each with its place in the
/// whole run's order: every case, or a shard's own.
fn plan_cases(
    args: &CheckArgs,
    scene_count: usize,
    modes: &[Shading],
) -> Result<(Vec<usize>, Vec<Job>), Failure> {
    let keys = shadelab::golden::keys::scene_keys(&args.scenes, None)?;
    Ok((0..scene_count)
        .flat_map(|i| modes.iter().map(move |&shading| (i, shading)))
        .enumerate()
        .filter(|(_, (i, shading))| {
            crate::cli::common::shards::on_shard(&format!("{}/{shading}", keys[*i]), args.shard)
        })
        .unzip())
}

/// A shard's record in its --out, for `--merge`: every case with its place
/// in the whole run and its JUnit case.
fn write_shard_record(
    args: &CheckArgs,
    (i, n): (usize, usize),
    modes: &[Shading],
    report: &CaseReport,
    orders: &[usize],
) -> Result<(), Failure> {
    let cases: Vec<serde_json::Value> = report
        .json
        .iter()
        .zip(&report.cases)
        .zip(orders)
        .map(|((v, t), order)| {
            let mut v = v.clone();
            v["order"] = (*order).into();
            v["junit"] = t.to_json();
            v
        })
        .collect();
    let record = serde_json::json!({
        "shard": [i, n],
        "run": run_identity(args, modes)?,
        "out": args.out,
        "cases": cases,
    });
    shadelab::output::prepare_output_folder(&args.out)?;
    write_atomically(&args.out.join(RECORD), record.to_string().as_bytes())?;
    Ok(())
}

/// What the whole run is, for its shards' records (`common/run_digest.rs`): every
/// case, each scene's and the hook's contents, the flags and limits; not
/// where it wrote (`--out`, `--junit`), which differ between shards.
fn run_identity(args: &CheckArgs, modes: &[Shading]) -> Result<serde_json::Value, Failure> {
    let keys = shadelab::golden::keys::scene_keys(&args.scenes, None)?;
    let (cases, scenes) =
        crate::cli::common::run_digest::cases_and_scenes(&keys, &args.scenes, modes);
    Ok(crate::cli::common::run_digest::run_identity(
        serde_json::json!({
            "cases": cases,
            "scenes": scenes,
            "width": args.size.width,
            "height": args.size.height,
            "flags": crate::cli::common::run_digest::scene_flags(&args.lighting, &args.traversal, &args.msaa, &args.depth),
            "interior_max_abs": args.interior_max_abs,
            "edge_fraction": args.edge_fraction,
            "flip_mean": args.flip_mean,
            "images": format!("{:?}", args.images),
        }),
    ))
}

/// The run in one JSON object (`--json`), or the count of cases that passed.
fn print_summary(args: &CheckArgs, report: &CaseReport) {
    if args.json {
        let value = serde_json::json!({
            "thresholds": {
                "raster": limits_for(args, Shading::Phong, Default::default()),
                "raster_multisampled": limits_for(args, Shading::Phong, Msaa { samples: 4, per_sample: false }),
                "raytrace": limits_for(args, Shading::Raytrace, Default::default()),
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
}
