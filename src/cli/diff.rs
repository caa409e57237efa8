//! `shadelab diff`: compare two image files, report every figure, and exit 1
//! when a figure is over its threshold.

use std::path::{Path, PathBuf};

use clap::Args;
use shadelab::linear_image::LinearImage;
use shadelab::metrics::{
    self, format_figure, Comparison, ErrorStats, Settings, Thresholds, Verdict,
};
use shadelab::output::{self, ImageFormat};

use super::Failure;

/// The `--edge-threshold` default: a step of 0.1 in linear intensity between
/// neighbours counts as an edge (see `metrics::edges::gradient_mask`).
pub(super) const EDGE_THRESHOLD: f64 = 0.1;

#[derive(Args)]
pub struct DiffArgs {
    /// The reference image (.png or .exr), or a folder of them.
    pub(super) expected: PathBuf,
    /// The image to check against it (.png or .exr), or a folder of them,
    /// matched to the reference folder's by name.
    pub(super) actual: PathBuf,
    /// Also write a JUnit XML report here: one case per image.
    #[arg(long, value_name = "FILE.xml")]
    pub(super) junit: Option<PathBuf>,
    /// The limits to start from, named by purpose: a GPU render against a
    /// reference renderer's (loose: rounding and edge pixels pass), or a
    /// render against a stored render of the same renderer (one 8-bit step
    /// per pixel at most). --threshold and the flags below change them.
    #[arg(long, value_enum, default_value = "gpu-vs-reference")]
    preset: Preset,
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
    pub(super) heatmap: Option<PathBuf>,
    /// Print one JSON object with every figure on stdout.
    #[arg(long)]
    pub(super) json: bool,
    // Accepted where a script passes them to every command, and unused:
    // `diff` renders nothing (hidden from its help).
    #[arg(long, hide = true, value_name = "NAME|INDEX")]
    device: Option<String>,
    #[arg(long, hide = true, value_name = "SIZE")]
    max_memory: Option<String>,
}

fn check_limit(name: &str, value: f64) -> Result<f64, Failure> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(Failure::usage(format!(
            "{name} {value} is invalid; expected a number >= 0"
        )))
    }
}

/// Limits named by what they compare (`--preset`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub(super) enum Preset {
    /// A GPU render against a reference renderer's image of the same
    /// scene: `Thresholds::default()`.
    GpuVsReference,
    /// A render against a stored render of the same renderer and driver,
    /// which repeats bit for bit: no pixel off by more than 0.01, a bit
    /// over the largest one 8-bit sRGB step (0.0089, at the top of the
    /// range), so a last-bit change that tips a pixel over one step
    /// passes and anything of two steps fails.
    StoredReference,
}

impl Preset {
    pub fn thresholds(self) -> Thresholds {
        match self {
            Preset::GpuVsReference => Thresholds::default(),
            Preset::StoredReference => Thresholds {
                max_abs: 0.01,
                p99_abs: 0.01,
                ..Thresholds::default()
            },
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Preset::GpuVsReference => "gpu-vs-reference",
            Preset::StoredReference => "stored-reference",
        }
    }
}

/// `--threshold`'s entries (`FIGURE=X,...` or a bare X for flip_mean) on
/// top of `base`.
pub(super) fn parse_thresholds(
    base: Thresholds,
    entries: &[String],
) -> Result<Thresholds, Failure> {
    let mut t = base;
    for entry in entries.iter().flat_map(|e| e.split(',')) {
        let (figure, text) = entry.split_once('=').unwrap_or(("flip_mean", entry));
        let value = text.trim().parse::<f64>().map_err(|_| {
            Failure::usage(format!(
                "--threshold {entry} is invalid; expected X or FIGURE=X with a number X"
            ))
        })?;
        if figure.trim() == "psnr" {
            // dB: any finite number is a floor (a negative one lets
            // anything but a non-finite difference pass).
            if !value.is_finite() {
                return Err(Failure::usage(format!(
                    "--threshold {entry} is invalid; expected a finite number of dB"
                )));
            }
            t.psnr = Some(value);
            continue;
        }
        let value = check_limit("--threshold", value)?;
        match figure.trim() {
            "flip_mean" => t.flip_mean = value,
            "max_abs" => t.max_abs = value,
            "p99_abs" => t.p99_abs = value,
            "rmse" => t.rmse = Some(value),
            "fraction_over" => t.fraction_over = Some(value),
            "count_over" => t.count_over = Some(value),
            other => {
                return Err(Failure::usage(format!(
                    "--threshold {entry}: unknown figure {other:?}; expected flip_mean, max_abs, p99_abs, rmse, fraction_over, count_over or psnr"
                )))
            }
        }
    }
    Ok(t)
}

/// The thresholds from the preset, `--threshold` and the per-figure flags.
fn thresholds(args: &DiffArgs) -> Result<Thresholds, Failure> {
    let mut t = parse_thresholds(args.preset.thresholds(), &args.threshold)?;
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

/// How two images are judged: the limits, the per-pixel threshold and the
/// step that marks an edge, from the command line.
pub(super) struct Judging {
    pub thresholds: Thresholds,
    pub settings: Settings,
    pub edge_threshold: f64,
}

/// One pair of images compared: every figure, each thresholded one's
/// verdict, the failed ones, and a note where the formats differ.
pub(super) struct PairOutcome {
    pub comparison: Comparison,
    pub verdicts: Vec<Verdict>,
    pub failures: Vec<String>,
    pub note: Option<String>,
}

/// Reads both images and compares them as `judging` says.
pub(super) fn compare_files(
    expected: &Path,
    actual: &Path,
    judging: &Judging,
) -> Result<PairOutcome, Failure> {
    let expected_image = output::read_image(expected)?;
    let actual_image = output::read_image(actual)?;
    let mut outcome = compare_images(&expected_image, &actual_image, judging).map_err(|e| {
        Failure::usage(format!(
            "cannot compare {} with {}: {e}",
            expected.display(),
            actual.display()
        ))
    })?;
    outcome.note = formats_differ(expected, actual);
    Ok(outcome)
}

/// Compares two images as `judging` says; the error is why they cannot
/// be compared (sizes that differ).
pub(super) fn compare_images(
    expected: &LinearImage,
    actual: &LinearImage,
    judging: &Judging,
) -> Result<PairOutcome, String> {
    let mask = metrics::gradient_mask(expected, judging.edge_threshold);
    let comparison = metrics::compare_with(expected, actual, Some(&mask), &judging.settings)
        .map_err(|e| e.to_string())?;
    Ok(PairOutcome {
        verdicts: judging.thresholds.verdicts(&comparison),
        failures: judging.thresholds.check(&comparison),
        note: None,
        comparison,
    })
}

pub fn run(args: DiffArgs) -> Result<(), Failure> {
    let judging = Judging {
        thresholds: thresholds(&args)?,
        settings: Settings {
            pixel_threshold: check_limit("--pixel-threshold", args.pixel_threshold)?,
            ..Settings::default()
        },
        edge_threshold: check_limit("--edge-threshold", args.edge_threshold)?,
    };
    if let Some(path) = &args.junit {
        output::prepare_output_path(path)?;
    }
    match (args.expected.is_dir(), args.actual.is_dir()) {
        (true, true) => return super::diff_folders::run(&args, &judging),
        (false, false) => {}
        _ => {
            return Err(Failure::usage(format!(
                "{} and {} must both be image files or both folders",
                args.expected.display(),
                args.actual.display()
            )))
        }
    }
    // Check the heat map's name before reading anything.
    if let Some(path) = &args.heatmap {
        ImageFormat::from_path(path)?;
        output::prepare_output_path(path)?;
    }
    let started = std::time::Instant::now();
    let PairOutcome {
        comparison,
        verdicts,
        failures,
        note: formats_note,
    } = compare_files(&args.expected, &args.actual, &judging)?;
    if let Some(path) = &args.heatmap {
        output::write_image(&metrics::flip_heatmap(&comparison.flip), path)?;
    }
    let (thresholds, settings, edge_threshold) = (
        &judging.thresholds,
        &judging.settings,
        judging.edge_threshold,
    );
    if let Some(path) = &args.junit {
        let case = super::diff_folders::junit_case(
            &args.actual.display().to_string(),
            &failures,
            started.elapsed().as_secs_f64(),
        );
        std::fs::write(path, shadelab::junit::render("shadelab diff", &[case]))
            .map_err(|e| Failure::usage(format!("cannot write {}: {e}", path.display())))?;
    }

    if args.json {
        let mut value = serde_json::to_value(&comparison).expect("figures serialise");
        let extra = serde_json::json!({
            "expected": args.expected,
            "actual": args.actual,
            "pass": failures.is_empty(),
            "failures": failures,
            "verdicts": verdicts,
            "preset": args.preset,
            "thresholds": thresholds,
            "settings": settings,
            "edge_threshold": edge_threshold,
            "heatmap": args.heatmap,
            "note": formats_note,
        });
        let object = value.as_object_mut().expect("a comparison is an object");
        object.extend(extra.as_object().expect("an object").clone());
        println!("{value}");
    } else {
        print_report(&args, &comparison, &verdicts, edge_threshold);
        if let Some(note) = &formats_note {
            println!("note: {note}");
        }
    }

    if failures.is_empty() {
        Ok(())
    } else {
        Err(Failure {
            code: 1,
            message: format!(
                "{} differs from {} beyond the thresholds: {}{}",
                args.actual.display(),
                args.expected.display(),
                failures.join("; "),
                formats_note
                    .as_ref()
                    .map(|n| format!(" (note: {n})"))
                    .unwrap_or_default()
            ),
        })
    }
}

/// Where one side is an EXR and the other a PNG, what that does to the
/// figures: a PNG holds 8-bit sRGB of the intensity clamped to [0, 1], an
/// EXR the linear intensity unclamped, so the same render differs wherever
/// it is over 1, and by up to half an 8-bit step elsewhere.
fn formats_differ(expected: &Path, actual: &Path) -> Option<String> {
    let format = |p: &Path| ImageFormat::from_path(p).ok();
    match (format(expected), format(actual)) {
        (Some(e), Some(a)) if e != a => Some(
            "one image is an EXR (linear, unclamped) and the other a PNG (8-bit sRGB of the intensity clamped to [0, 1]): the same render differs wherever it is over 1; compare two of one format"
                .to_string(),
        ),
        _ => None,
    }
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
