//! `shadelab diff`: compare two image files, report every figure, and exit 1
//! when a figure is over its threshold.

mod folders;

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use shadelab::diff::{
    check_limit, compare_files, junit_case, parse_thresholds, Judging, PairOutcome, EDGE_THRESHOLD,
};
use shadelab::metrics::{
    self, format_figure, Comparison, ErrorStats, Settings, Thresholds, Verdict,
};
use shadelab::output::{self, ImageFormat};

use crate::cli::common::args::PresetArg;
use crate::cli::common::failure::Failure;

#[derive(Args)]
pub struct DiffArgs {
    /// The reference image (.png or .exr), or a folder of them.
    expected: PathBuf,
    /// The image to check against it (.png or .exr), or a folder of them,
    /// matched to the reference folder's by name.
    actual: PathBuf,
    /// Also write a JUnit XML report here: one case per image.
    #[arg(long, value_name = "FILE.xml")]
    junit: Option<PathBuf>,
    /// The limits to start from, named by purpose: a GPU render against a
    /// reference renderer's (loose: rounding and edge pixels pass), or a
    /// render against a stored render of the same renderer (one 8-bit step
    /// per pixel at most). --threshold and the flags below change them.
    #[arg(long, value_enum, default_value = "gpu-vs-reference")]
    preset: PresetArg,
    /// Thresholds: `FIGURE=X[,FIGURE=X...]` for flip_mean, max_abs,
    /// p99_abs, rmse, fraction_over, count_over (ceilings) or psnr (a
    /// floor, dB), or a bare X for flip_mean. May be repeated; the flags
    /// below win over it.
    #[arg(long, value_name = "[FIGURE=]X,...")]
    threshold: Vec<String>,
    /// Limit on the mean FLIP error [default: 0.02].
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    flip_mean: Option<f64>,
    /// Limit on the largest per-pixel error (max over channels, linear) [default: 1.0].
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    max_abs: Option<f64>,
    /// Limit on the 99th percentile of the per-pixel error [default: 0.05].
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    p99_abs: Option<f64>,
    /// The per-pixel error that `fraction_over` counts pixels above.
    #[arg(long, value_name = "X", allow_negative_numbers = true, default_value_t = Settings::default().pixel_threshold)]
    pixel_threshold: f64,
    /// The step between neighbouring pixels of EXPECTED that marks an edge,
    /// splitting the figures into interior and silhouette pixels.
    #[arg(long, value_name = "X", allow_negative_numbers = true, default_value_t = EDGE_THRESHOLD)]
    edge_threshold: f64,
    /// Write the FLIP error map, magma-coloured, to this image (.png or .exr).
    #[arg(long, value_name = "FILE.png")]
    heatmap: Option<PathBuf>,
    /// Print one JSON object with every figure on stdout.
    #[arg(long)]
    json: bool,
    // Accepted where a script passes them to every command, and unused:
    // `diff` renders nothing (hidden from its help).
    #[arg(long, hide = true, value_name = "NAME|INDEX")]
    device: Option<String>,
    #[arg(long, hide = true, value_name = "SIZE")]
    max_memory: Option<String>,
}

/// The thresholds from the preset, `--threshold` and the per-figure flags.
fn thresholds(args: &DiffArgs) -> Result<Thresholds, Failure> {
    let mut t = parse_thresholds(args.preset.preset().thresholds(), &args.threshold)?;
    if let Some(v) = args.flip_mean {
        t.flip_mean = check_limit("--flip-mean", v)?;
    }
    if let Some(v) = args.max_abs {
        t.max_abs = check_limit("--max-abs", v)?;
    }
    if let Some(v) = args.p99_abs {
        t.p99_abs = check_limit("--p99-abs", v)?;
    }
    Ok(t)
}

pub fn run(args: DiffArgs) -> Result<(), Failure> {
    let judging = judging(&args)?;
    if let Some(path) = &args.junit {
        output::prepare_output_path(path)?;
    }
    match (args.expected.is_dir(), args.actual.is_dir()) {
        (true, true) => {
            if args.heatmap.is_some() {
                return Err(Failure::usage(
                    "--heatmap names one image; with two folders, compare the image pair that failed on its own to get its heat map".to_string(),
                ));
            }
            folders::run(
                &args.expected,
                &args.actual,
                args.junit.as_deref(),
                args.json,
                &judging,
            )
        }
        (false, false) => run_pair(&args, &judging),
        _ => Err(Failure::usage(format!(
            "{} and {} must both be image files or both folders",
            args.expected.display(),
            args.actual.display()
        ))),
    }
}

/// How the images are judged, from the command line.
fn judging(args: &DiffArgs) -> Result<Judging, Failure> {
    Ok(Judging {
        thresholds: thresholds(args)?,
        settings: Settings {
            pixel_threshold: check_limit("--pixel-threshold", args.pixel_threshold)?,
            ..Settings::default()
        },
        edge_threshold: check_limit("--edge-threshold", args.edge_threshold)?,
    })
}

/// Two image files: judged, the heat map and the JUnit case written, the
/// figures reported, and the verdict.
fn run_pair(args: &DiffArgs, judging: &Judging) -> Result<(), Failure> {
    // Check the heat map's name before reading anything.
    if let Some(path) = &args.heatmap {
        ImageFormat::from_path(path)?;
        output::prepare_output_path(path)?;
    }
    let started = Instant::now();
    let pair = compare_files(&args.expected, &args.actual, judging)?;
    if let Some(path) = &args.heatmap {
        output::write_image(&metrics::flip_heatmap(&pair.comparison.flip), path)?;
    }
    if let Some(path) = &args.junit {
        let case = junit_case(
            &args.actual.display().to_string(),
            &pair.failures,
            started.elapsed().as_secs_f64(),
        );
        std::fs::write(path, shadelab::junit::render("shadelab diff", &[case]))
            .map_err(|e| Failure::usage(format!("cannot write {}: {e}", path.display())))?;
    }
    if args.json {
        println!("{}", pair_json(args, judging, &pair));
    } else {
        print_report(
            args,
            &pair.comparison,
            &pair.verdicts,
            judging.edge_threshold,
        );
        if let Some(note) = &pair.note {
            println!("note: {note}");
        }
    }
    verdict(args, &pair)
}

/// `--json`: every figure of the comparison, and what it was judged by.
fn pair_json(args: &DiffArgs, judging: &Judging, pair: &PairOutcome) -> serde_json::Value {
    let mut value = serde_json::to_value(&pair.comparison).expect("figures serialise");
    let extra = serde_json::json!({
        "expected": args.expected,
        "actual": args.actual,
        "pass": pair.failures.is_empty(),
        "failures": pair.failures,
        "verdicts": pair.verdicts,
        "preset": args.preset.preset(),
        "thresholds": judging.thresholds,
        "settings": judging.settings,
        "edge_threshold": judging.edge_threshold,
        "heatmap": args.heatmap,
        "note": pair.note,
    });
    let object = value.as_object_mut().expect("a comparison is an object");
    object.extend(extra.as_object().expect("an object").clone());
    value
}

/// Exit status 1, with every failed figure, when any is over its limit.
fn verdict(args: &DiffArgs, pair: &PairOutcome) -> Result<(), Failure> {
    if pair.failures.is_empty() {
        return Ok(());
    }
    Err(Failure {
        code: 1,
        message: format!(
            "{} differs from {} beyond the thresholds: {}{}",
            args.actual.display(),
            args.expected.display(),
            pair.failures.join("; "),
            pair.note
                .as_ref()
                .map(|n| format!(" (note: {n})"))
                .unwrap_or_default()
        ),
    })
}

fn print_report(args: &DiffArgs, c: &Comparison, verdicts: &[Verdict], edge_threshold: f64) {
    let show = |p: &Path| p.display().to_string();
    println!("expected  {}", show(&args.expected));
    println!("actual    {}", show(&args.actual));
    println!(
        "size      {}x{}; silhouette = pixels of expected at a step > {edge_threshold} to a neighbour",
        c.width, c.height
    );
    if let Some(path) = &args.heatmap {
        println!("heat map  {}", show(path));
    }
    println!();
    println!("{:<12} {:>12} {:>10}  result", "figure", "value", "limit");
    for v in verdicts {
        println!(
            "{:<12} {:>12} {:>10}  {}",
            v.figure,
            v.formatted_value(),
            v.limit,
            if v.pass { "PASS" } else { "FAIL" }
        );
    }
    println!();
    let columns = [Some(&c.stats), c.interior.as_ref(), c.silhouette.as_ref()];
    println!(
        "{:<14} {:>12} {:>12} {:>12}",
        "figure", "all", "interior", "silhouette"
    );
    let row = |name: &str, f: &dyn Fn(&ErrorStats) -> String| {
        let cell = |i: usize| columns[i].map_or_else(|| "-".to_string(), f);
        println!(
            "{:<14} {:>12} {:>12} {:>12}",
            name,
            cell(0),
            cell(1),
            cell(2)
        );
    };
    row("pixels", &|s| s.pixels.to_string());
    row("max_abs", &|s| format_figure(s.max_abs));
    row("p99_abs", &|s| format_figure(s.p99_abs));
    row("mean_abs", &|s| format_figure(s.mean_abs));
    row("rmse", &|s| format_figure(s.rmse));
    row("psnr (dB)", &|s| metrics::format_psnr(s.psnr));
    row(&format!("over {}", c.stats.pixel_threshold), &|s| {
        format_figure(s.fraction_over)
    });
    if c.stats.non_finite > 0 {
        row("non-finite", &|s| s.non_finite.to_string());
    }
    println!();
    println!(
        "FLIP (LDR, {} pixels per degree): mean {}, median {}, p99 {}, max {}",
        c.flip.pixels_per_degree,
        format_figure(c.flip.mean),
        format_figure(c.flip.median),
        format_figure(c.flip.p99),
        format_figure(c.flip.max)
    );
}
