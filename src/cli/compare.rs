//! `shadelab compare`: one scene in many shader variants, each timed and
//! measured against the CPU reference of the same variant and against the
//! scene's reference image; or `--merge` of shard folders into one report.

use std::path::{Component, Path, PathBuf};

use clap::Args;
use shadelab::compare::present::write_presentation;
use shadelab::compare::report::{Metric, ReferenceChoice};
use shadelab::compare::run::{mark_pareto, merge, run, set_budget, CompareOptions};
use shadelab::compare::{default_variants, Report, Variant};
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::memory::MemoryLimit;
use shadelab::output::write_atomically;
use shadelab::shading::Shading;

use super::args::{check_runs, ImageSize, MsaaArg};
use super::render::load_scene;
use super::Failure;

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
    runs: usize,
    /// Render only part I of N of the variant list, e.g. 2/4.
    #[arg(long, value_name = "I/N", value_parser = super::shards::parse_shard)]
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
    pub machine: super::args::MachineArgs,
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
    // An earlier run's files in --out would sit beside the new ones (a
    // smaller run left the bigger one's images): they go, and only they,
    // unless --out is one of the folders being merged.
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
    let mut report = if args.merge.is_empty() {
        render_variants(&args, options, memory)?
    } else {
        merge_folders(&args)?
    };
    // A merge may measure against another reference than its shards did.
    report.plot_reference = reference_of(&args);
    report.plot_metric = metric_of(&args);
    mark_pareto(&mut report);
    set_budget(&mut report, args.budget);
    write_report(&report, &args.out)?;
    let presented = write_presentation(&report, &args.out).map_err(|e| Failure {
        code: if e.is_bad_input() { 2 } else { 3 },
        message: e.to_string(),
    })?;
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
        // The local reference's front, drawn apart: never mixed with the
        // global one on one plot.
        let mut local = report.clone();
        local.plot_reference = ReferenceChoice::Local;
        mark_pareto(&mut local);
        set_budget(&mut local, args.budget);
        let (png, _) = shadelab::compare::present::write_plot_as(&local, &args.out, "local")
            .map_err(|e| Failure {
                code: if e.is_bad_input() { 2 } else { 3 },
                message: e.to_string(),
            })?;
        if !args.json {
            println!("plot against the local reference: {}", png.display());
            if let Some(budget) = &local.budget {
                println!("{}", budget_line(&local, budget));
            }
        }
    }
    for v in report.variants.iter().filter(|v| v.non_finite_pixels > 0) {
        eprintln!(
            "shadelab: warning: variant {}: {} pixels are not finite (NaN or infinity); its errors are infinite",
            v.name, v.non_finite_pixels
        );
    }
    // A budget no variant meets is a failed check, as a threshold is.
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

/// Whether two paths name one folder.
fn same_folder(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Removes the files an earlier comparison wrote into `dir`: those its
/// `report.json` names and the presentation's; nothing else. Returns how
/// many went. A folder with no readable report is left as it is.
fn clear_earlier_run(dir: &Path) -> usize {
    let Ok(text) = std::fs::read_to_string(dir.join("report.json")) else {
        return 0;
    };
    let Ok(earlier) = serde_json::from_str::<Report>(&text) else {
        return 0;
    };
    let mut files: Vec<String> = vec![earlier.reference_image, earlier.local_reference_image];
    for v in earlier.variants {
        files.push(v.image);
        files.push(v.heatmap);
    }
    files.extend(
        [
            shadelab::compare::present::CONTACT_SHEET,
            shadelab::compare::present::PLOT_PNG,
            shadelab::compare::present::PLOT_SVG,
            shadelab::compare::present::CSV,
            shadelab::compare::present::HTML,
            "report.json",
            "speed-vs-error-local.png",
            "speed-vs-error-local.svg",
        ]
        .map(String::from),
    );
    files
        .iter()
        // Names only, never paths out of the folder.
        .filter(|f| !f.is_empty() && Path::new(f).file_name() == Some(std::ffi::OsStr::new(f)))
        .filter(|f| std::fs::remove_file(dir.join(f)).is_ok())
        .count()
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

fn render_variants(
    args: &CompareArgs,
    options: &GpuOptions,
    memory: &MemoryLimit,
) -> Result<Report, Failure> {
    check_runs(args.runs)?;
    let (mut scene, name) = load_scene(args.scene.as_deref(), memory)?;
    args.size.apply(&mut scene)?;
    args.msaa.apply(&mut scene)?;
    let chosen_for_the_scene = args.variants.is_empty();
    let variants: Vec<Variant> = if chosen_for_the_scene {
        default_variants(&scene)
    } else {
        args.variants
            .iter()
            .map(|v| v.trim())
            .filter(|v| !v.is_empty())
            .map(|v| v.parse::<Variant>().map_err(Failure::usage))
            .collect::<Result<_, _>>()?
    };
    if variants.is_empty() {
        return Err(Failure::usage("--variants names no variant".into()));
    }
    refuse_repeats(&variants)?;
    let mut modes: Vec<Shading> = Vec::new();
    for v in &variants {
        if !modes.contains(&v.shading) {
            modes.push(v.shading);
        }
    }
    let given = super::ignored::scene_flags_given(&Default::default(), &args.msaa, None);
    super::ignored::warn(&given, &modes, super::ignored::Backends::Gpu);
    // The references alone must fit: without them no variant is measured.
    memory.check(&name, &scene, &[], &[Shading::Raytrace])?;
    // Each variant (its tessellation may differ) against the references:
    // the global one traced on the CPU, a local one per mode. One over the
    // limit is left out with the reason, and the others run.
    // Only a tessellation override changes the geometry; copying the scene
    // for the others would double the memory this check guards.
    let mut over_the_limit = std::collections::BTreeMap::new();
    for variant in &variants {
        let varied = match (variant.segments, variant.msaa) {
            (None, None) => std::borrow::Cow::Borrowed(&scene),
            _ => std::borrow::Cow::Owned(variant.apply(&scene)?),
        };
        let modes = [variant.shading];
        let references = [variant.shading, Shading::Raytrace];
        if let Err(e) = memory.check(&name, &varied, &modes, &references) {
            over_the_limit.insert(variant.to_string(), Failure::from(e));
        }
    }
    // None fits: the run is refused, as a render over the limit is.
    if over_the_limit.len() == variants.len() {
        let first = over_the_limit.remove(&variants[0].to_string());
        return Err(first.expect("every variant is over the limit"));
    }
    let over_the_limit = over_the_limit
        .into_iter()
        .map(|(name, failure)| (name, failure.message))
        .collect();
    let context = GpuContext::new(options)?;
    // The list chosen for the scene keeps the sample counts this device
    // renders; a count asked for by name is the device's to refuse.
    let variants: Vec<Variant> = if chosen_for_the_scene {
        let info = &context.info;
        variants
            .into_iter()
            .filter(|v| {
                v.msaa
                    .is_none_or(|m| shadelab::gpu::raster::renders_samples(info, m))
            })
            .collect()
    } else {
        variants
    };
    let progress = super::progress::Progress::new("compare", 0);
    let compare_options = CompareOptions {
        runs: args.runs,
        shard: args.shard,
        reference: reference_of(args),
        metric: metric_of(args),
        budget: args.budget,
        skip: over_the_limit,
    };
    let report = run(
        &context,
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

/// Refuses a variant given twice (by its canonical name, or by the file its
/// image would be written to).
fn refuse_repeats(variants: &[Variant]) -> Result<(), Failure> {
    for (k, v) in variants.iter().enumerate() {
        let (name, stem) = (
            v.to_string(),
            shadelab::compare::report::file_stem(&v.to_string()),
        );
        if let Some(earlier) = variants[..k].iter().find(|e| {
            e.to_string() == name || shadelab::compare::report::file_stem(&e.to_string()) == stem
        }) {
            return Err(Failure::usage(format!(
                "--variants names {name} twice (as {earlier} and {v}); give each variant once"
            )));
        }
    }
    Ok(())
}

fn merge_folders(args: &CompareArgs) -> Result<Report, Failure> {
    let mut shards = Vec::new();
    for dir in &args.merge {
        let path = dir.join("report.json");
        let text = std::fs::read_to_string(&path)
            .map_err(|e| Failure::usage(format!("cannot read {}: {e}", path.display())))?;
        let report: Report = serde_json::from_str(&text).map_err(|e| {
            Failure::usage(format!("{} is not a shadelab report: {e}", path.display()))
        })?;
        shards.push((dir, report));
    }
    // Merge (which checks that the shards belong together) before copying
    // anything, so a refused merge leaves --out as it was.
    let merged = merge(shards.iter().map(|(_, r)| r.clone()).collect())
        .map_err(|e| Failure::usage(format!("cannot merge: {e}")))?;
    let mut copies = Vec::new();
    for (dir, report) in &shards {
        let mut files = vec![report.reference_image.clone()];
        if !report.local_reference_image.is_empty() {
            files.push(report.local_reference_image.clone());
        }
        for v in &report.variants {
            files.push(v.image.clone());
            files.push(v.heatmap.clone());
        }
        for file in files {
            // A report names files inside its own folder: a bare file name.
            let mut parts = Path::new(&file).components();
            if !matches!(
                (parts.next(), parts.next()),
                (Some(Component::Normal(_)), None)
            ) {
                return Err(Failure::usage(format!(
                    "{}: image `{file}` is not a file name in the shard's folder",
                    dir.join("report.json").display()
                )));
            }
            copies.push((dir.join(&file), args.out.join(&file)));
        }
    }
    for (from, to) in copies {
        if from != to {
            std::fs::copy(&from, &to)
                .map_err(|e| Failure::usage(format!("cannot copy {}: {e}", from.display())))?;
        }
    }
    Ok(merged)
}

fn print_table(report: &Report, dir: &Path) {
    println!(
        "{} at {}x{} on {}, median of {} run{}",
        report.scene,
        report.width,
        report.height,
        report.device_and_driver(),
        report.runs,
        if report.runs == 1 { "" } else { "s" },
    );
    println!("global reference (model_*): {}", report.reference);
    println!("local reference (local_*):  {}", report.local_reference);
    println!(
        "pareto front and budget: {} against the {}",
        report.plot_metric.name(),
        report.plot_reference.describe()
    );
    println!(
        "{:<40} {:>9} {:>9} {:>9} {:>11} {:>11} {:>10} {:>11} {:>7}",
        "variant",
        "gpu_ms",
        "frame_ms",
        "image_ms",
        "impl_rmse",
        "model_rmse",
        "model_flip",
        "local_rmse",
        "pareto"
    );
    for v in &report.variants {
        let local = v
            .local_error
            .map(|e| format!("{:.2e}", e.rmse))
            .unwrap_or_else(|| "-".into());
        println!(
            "{:<40} {:>9.1} {:>9.1} {:>9.1} {:>11.2e} {:>11.2e} {:>10.4} {:>11} {:>7}",
            v.name,
            v.timing.gpu_ms,
            v.timing.frame_ms,
            v.timing.image_ms,
            v.implementation_error.rmse,
            v.model_error.rmse,
            v.model_error.flip_mean,
            local,
            if v.pareto { "*" } else { "" }
        );
    }
    for v in &report.not_run {
        println!("{:<40} not run: {}", v.name, v.reason);
    }
    if let Some(budget) = &report.budget {
        println!("{}", budget_line(report, budget));
    }
    println!("report: {}", dir.join("report.json").display());
}

/// What `--budget` found, in one line.
fn budget_line(report: &Report, budget: &shadelab::compare::report::Budget) -> String {
    let what = format!(
        "{} <= {} against the {}",
        report.plot_metric.name(),
        budget.max_error,
        report.plot_reference.describe()
    );
    match budget
        .fastest
        .as_ref()
        .and_then(|name| report.variants.iter().find(|v| &v.name == name))
    {
        Some(v) => format!(
            "budget: the fastest variant with {what}: {} ({:.1} ms, error {:.3e})",
            v.name,
            v.timing.gpu_ms,
            report.error_of(v)
        ),
        None => format!("budget: no variant has {what}"),
    }
}
