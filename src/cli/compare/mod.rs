//! `shadelab compare`: one scene in many shader variants, each timed and
//! measured against the CPU reference of the same variant and against the
//! scene's reference image; or `--merge` of shard folders into one report.

mod folders;
mod table;
mod variants;

use std::path::{Path, PathBuf};

use clap::Args;
use shadelab::compare::present::write_presentation;
use shadelab::compare::report::{Metric, ReferenceChoice};
use shadelab::compare::run::{mark_pareto, run, set_budget, CompareOptions};
use shadelab::compare::Report;
use shadelab::gpu::GpuOptions;
use shadelab::memory::MemoryLimit;
use shadelab::output::write_atomically;
use shadelab::render::Device;
use shadelab::shading::Shading;

use crate::cli::common::args::{check_runs, DepthArg, ImageSize, MsaaArg, WatchdogArg};
use crate::cli::common::batch::scene::load_scene;
use crate::cli::common::failure::Failure;
use crate::cli::common::run_digest::content_digest;
use folders::{clear_earlier_run, merge_folders, same_folder};
use table::{budget_line, print_table};
use variants::{modes_of, over_the_limit, rendered_by, variants_of};

#[derive(Args)]
pub struct CompareArgs {
    /// Scene file; the built-in default scene if left out.
    scene: Option<PathBuf>,
    /// Folder for the images and reports (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// Variants, separated by `;` (or given several times), e.g.
    /// "flat;gouraud:segments=16;raytrace:depth=3,cutoff=0.01".
    /// Default: a list chosen for the scene (every mode, sweeps).
    #[arg(long, value_delimiter = ';')]
    variants: Vec<String>,
    /// Timed GPU runs per variant, after one warm-up.
    #[arg(long, default_value_t = 3)]
    runs: i64,
    /// Render only part I of N of the variant list, e.g. 2/4; `auto` reads
    /// I and N from the CI's own variables (docs/golden.md).
    #[arg(long, value_name = "I/N", value_parser = crate::cli::common::shards::parse_shard)]
    shard: Option<(usize, usize)>,
    /// Join the reports in these shard folders into one report in --out.
    #[arg(long, num_args = 1.., value_name = "DIR", conflicts_with_all = ["scene", "variants", "shard"])]
    merge: Vec<PathBuf>,
    #[command(flatten)]
    size: ImageSize,
    // Every raster variant's samples per pixel, unless it sets its own
    // (`msaa=N`).
    #[command(flatten)]
    msaa: MsaaArg,
    #[command(flatten)]
    watchdog: WatchdogArg,
    /// The one reference the plot, the Pareto front and the budget measure
    /// every variant against: `global` (the ray-traced reference, the
    /// scene as it should look) or `local` (the formula per pixel on exact
    /// geometry, no shadows or reflections), or `both`: everything against
    /// the global one, and a second plot with its own front against the
    /// local one (speed-vs-error-local.png). `auto` is read as `global`.
    #[arg(long, default_value = "global", value_parser = ["global", "local", "both", "auto"])]
    reference: String,
    /// The error figure they use: `rmse` or `flip` (mean FLIP).
    #[arg(long, default_value = "rmse", value_parser = ["rmse", "flip"])]
    metric: String,
    /// Name the fastest variant whose error (by --reference and --metric)
    /// is at most E, or say that none is.
    #[arg(long, value_name = "E")]
    budget: Option<f64>,
    /// Print the report as one JSON object on stdout.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    pub machine: crate::cli::common::args::MachineArgs,
}

/// The exit status of a comparison that finished without some of its
/// variants (over the memory limit, or failed): the report is whole
/// otherwise.
pub const NOT_EVERY_VARIANT_RAN: u8 = 4;

fn write_report(report: &Report, dir: &Path) -> Result<(), Failure> {
    let json = serde_json::to_string_pretty(report).expect("reports serialise");
    write_atomically(&dir.join("report.json"), json.as_bytes())?;
    Ok(())
}

pub fn run_command(
    args: CompareArgs,
    options: &GpuOptions,
    memory: &MemoryLimit,
) -> Result<(), Failure> {
    shadelab::output::prepare_output_folder(&args.out)?;
    if let Some(e) = args.budget.filter(|e| !e.is_finite() || *e < 0.0) {
        return Err(Failure::usage(format!(
            "--budget {e} is invalid; expected an error >= 0"
        )));
    }
    clear_out(&args);
    let mut report = if args.merge.is_empty() {
        render_variants(&args, options, memory)?
    } else {
        merge_folders(&args.merge, &args.out)?
    };
    // A merge may measure against another reference than its shards did.
    report.plot_reference = reference_of(&args);
    report.plot_metric = metric_of(&args);
    mark_pareto(&mut report);
    set_budget(&mut report, args.budget);
    write_report(&report, &args.out)?;
    let presented = write_presentation(&report, &args.out).map_err(presentation_failure)?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string(&report).expect("reports serialise")
        );
    } else {
        print_table(&report, &args.out);
        println!("html:   {}", presented.html.display());
        println!("plot:   {}", presented.plot_png.display());
        println!("sheet:  {}", presented.contact_sheet.display());
    }
    if args.reference == "both" {
        present_local(&args, &report)?;
    }
    for v in report.variants.iter().filter(|v| v.non_finite_pixels > 0) {
        eprintln!(
            "shadelab: warning: variant {}: {} pixels are not finite (NaN or infinity); its errors are infinite",
            v.name, v.non_finite_pixels
        );
    }
    verdict(&report)
}

/// An earlier run's files in --out would sit beside the new ones (a
/// smaller run left the bigger one's images): they go, and only they,
/// unless --out is one of the folders being merged.
fn clear_out(args: &CompareArgs) {
    let merging_into_a_shard = args.merge.iter().any(|m| same_folder(m, &args.out));
    if !merging_into_a_shard {
        let cleared = clear_earlier_run(&args.out);
        if cleared > 0 {
            eprintln!(
                "shadelab: note: removed {cleared} files of an earlier comparison from {} (files it did not write are kept)",
                args.out.display()
            );
        }
    }
}

fn presentation_failure(e: shadelab::compare::present::PresentError) -> Failure {
    Failure {
        code: if e.is_bad_input() { 2 } else { 3 },
        message: e.to_string(),
    }
}

/// `--reference both`: the local reference's front, drawn apart: never
/// mixed with the global one on one plot.
fn present_local(args: &CompareArgs, report: &Report) -> Result<(), Failure> {
    let mut local = report.clone();
    local.plot_reference = ReferenceChoice::Local;
    mark_pareto(&mut local);
    set_budget(&mut local, args.budget);
    let (png, _) = shadelab::compare::present::write_plot_as(&local, &args.out, "local")
        .map_err(presentation_failure)?;
    if !args.json {
        println!("plot against the local reference: {}", png.display());
        if let Some(budget) = &local.budget {
            println!("{}", budget_line(&local, budget));
        }
    }
    Ok(())
}

/// A budget no variant meets is a failed check, as a threshold is; a
/// report without some of its variants is not whole.
fn verdict(report: &Report) -> Result<(), Failure> {
    if let Some(budget) = report.budget.as_ref().filter(|b| b.fastest.is_none()) {
        return Err(Failure {
            code: 1,
            message: format!(
                "no variant has {} <= {} against the {}",
                report.plot_metric.name(),
                budget.max_error,
                report.plot_reference.describe()
            ),
        });
    }
    if !report.not_run.is_empty() {
        let names: Vec<&str> = report.not_run.iter().map(|v| v.name.as_str()).collect();
        return Err(Failure {
            code: NOT_EVERY_VARIANT_RAN,
            message: format!(
                "{} of {} variants not run ({}); the report has the others and why",
                names.len(),
                names.len() + report.variants.len(),
                names.join(", ")
            ),
        });
    }
    Ok(())
}

/// The reference of the report, its plot, front and budget (`both`: the
/// global one; the local one gets a plot of its own).
fn reference_of(args: &CompareArgs) -> ReferenceChoice {
    if args.reference == "both" {
        return ReferenceChoice::Global;
    }
    ReferenceChoice::from_name(&args.reference).expect("clap checked it")
}

fn metric_of(args: &CompareArgs) -> Metric {
    Metric::from_name(&args.metric).expect("clap checked it")
}

/// The scene's variants rendered, each timed and measured against the
/// references.
fn render_variants(
    args: &CompareArgs,
    options: &GpuOptions,
    memory: &MemoryLimit,
) -> Result<Report, Failure> {
    let runs = check_runs(args.runs)?;
    let (mut scene, name) = load_scene(args.scene.as_deref(), memory)?;
    args.size.apply(&mut scene)?;
    args.msaa.apply(&mut scene)?;
    args.watchdog.apply(&mut scene)?;
    let variants = variants_of(&args.variants, &scene)?;
    let given = crate::cli::common::ignored::scene_flags_given(
        &Default::default(),
        &args.msaa,
        &DepthArg::default(),
    );
    let ignoring = crate::cli::common::ignored::Run {
        modes: &modes_of(&variants),
        backends: crate::cli::common::ignored::Backends::Gpu,
        caustics: scene.render.caustics.on(),
    };
    crate::cli::common::ignored::warn(&given, ignoring);
    // The references alone must fit: without them no variant is measured.
    memory.check(&name, &scene, &[], &[Shading::Raytrace])?;
    let skip = over_the_limit(&scene, &name, &variants, memory)?;
    let device = Device::open(options)?;
    let context = device.require_gpu()?;
    // The list chosen for the scene keeps the sample counts this device
    // renders; a count asked for by name is the device's to refuse.
    let variants = if args.variants.is_empty() {
        rendered_by(&context.info, variants)
    } else {
        variants
    };
    let progress = crate::cli::common::progress::Progress::new("compare", 0);
    let compare_options = CompareOptions {
        runs,
        shard: args.shard,
        reference: reference_of(args),
        metric: metric_of(args),
        budget: args.budget,
        skip,
    };
    let report = run(
        &device,
        &scene,
        &name,
        &variants,
        &compare_options,
        &args.out,
        |done, total, what| {
            progress.set_total(total as u64);
            progress.set(done as u64, what);
        },
    )?;
    progress.finish();
    drop(progress);
    let mut report = report;
    if args.shard.is_some() {
        report.run = Some(run_identity(args, &variants));
    }
    if report.variants.is_empty() {
        let reasons: Vec<String> = report
            .not_run
            .iter()
            .map(|v| format!("{}: {}", v.name, v.reason))
            .collect();
        return Err(Failure {
            code: NOT_EVERY_VARIANT_RAN,
            message: format!("no variant ran ({})", reasons.join("; ")),
        });
    }
    Ok(report)
}

/// What the whole comparison is, for its shards' reports
/// (`common/run_digest.rs`): the scene's contents, every variant of every shard,
/// the runs, size and samples. Not the plot's reference, metric or budget,
/// which a merge may choose afresh.
fn run_identity(args: &CompareArgs, variants: &[shadelab::compare::Variant]) -> serde_json::Value {
    let scene = args
        .scene
        .as_deref()
        .map_or_else(|| "built-in default scene".to_string(), content_digest);
    crate::cli::common::run_digest::run_identity(serde_json::json!({
        "scene": scene,
        "variants": variants.iter().map(ToString::to_string).collect::<Vec<_>>(),
        "runs": args.runs,
        "width": args.size.width,
        "height": args.size.height,
        "msaa": format!("{:?}", args.msaa),
    }))
}
