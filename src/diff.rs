//! Two images judged against limits, as `shadelab diff` judges a pair and
//! `shadelab golden` each render against its reference: the limits named
//! by purpose (presets), threshold entries (`FIGURE=X`), the step that
//! marks an edge, and the figures and verdicts of one pair.

use std::path::Path;

use crate::junit::TestCase;
use crate::linear_image::LinearImage;
use crate::metrics::{self, Comparison, Settings, Thresholds, Verdict};
use crate::output::{self, ImageFormat};
use crate::Error;

/// The default edge step (`diff --edge-threshold`): a step of 0.1 in linear intensity between
/// neighbours counts as an edge (see `metrics::edges::gradient_mask`).
pub const EDGE_THRESHOLD: f64 = 0.1;

/// `value` as a limit named `name` (a flag, in the message): a finite
/// number >= 0.
pub fn check_limit(name: &str, value: f64) -> Result<f64, Error> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(Error::Usage(format!(
            "{name} {value} is invalid; expected a number >= 0"
        )))
    }
}

/// Limits named by what they compare (the commands' `--preset`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
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

/// Threshold entries, as `--threshold` takes them (`FIGURE=X,...` or a
/// bare X for flip_mean), on top of `base`.
pub fn parse_thresholds(base: Thresholds, entries: &[String]) -> Result<Thresholds, Error> {
    let mut t = base;
    for entry in entries.iter().flat_map(|e| e.split(',')) {
        let (figure, text) = entry.split_once('=').unwrap_or(("flip_mean", entry));
        let value = text.trim().parse::<f64>().map_err(|_| {
            Error::Usage(format!(
                "--threshold {entry} is invalid; expected X or FIGURE=X with a number X"
            ))
        })?;
        if figure.trim() == "psnr" {
            // dB: any finite number is a floor (a negative one lets
            // anything but a non-finite difference pass).
            if !value.is_finite() {
                return Err(Error::Usage(format!(
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
                return Err(Error::Usage(format!(
                    "--threshold {entry}: unknown figure {other:?}; expected flip_mean, max_abs, p99_abs, rmse, fraction_over, count_over or psnr"
                )))
            }
        }
    }
    Ok(t)
}

/// How two images are judged: the limits, the per-pixel threshold and the
/// step that marks an edge.
#[derive(Debug, Clone)]
pub struct Judging {
    pub thresholds: Thresholds,
    pub settings: Settings,
    pub edge_threshold: f64,
}

impl Judging {
    /// `thresholds`, with the default per-pixel threshold and edge step
    /// (as `golden` judges).
    pub fn new(thresholds: Thresholds) -> Self {
        Judging {
            thresholds,
            settings: Settings::default(),
            edge_threshold: EDGE_THRESHOLD,
        }
    }
}

/// One pair of images compared: every figure, each thresholded one's
/// verdict, the failed ones, and a note where the formats differ.
pub struct PairOutcome {
    pub comparison: Comparison,
    pub verdicts: Vec<Verdict>,
    pub failures: Vec<String>,
    pub note: Option<String>,
}

/// Reads both images and compares them as `judging` says.
pub fn compare_files(
    expected: &Path,
    actual: &Path,
    judging: &Judging,
) -> Result<PairOutcome, Error> {
    let expected_image = output::read_image(expected)?;
    let actual_image = output::read_image(actual)?;
    let mut outcome = compare_images(&expected_image, &actual_image, judging).map_err(|e| {
        Error::Usage(format!(
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
pub fn compare_images(
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

/// A JUnit case for one image: failed with `failures`, passed without.
pub fn junit_case(name: &str, failures: &[String], time_s: f64) -> TestCase {
    TestCase {
        classname: "shadelab diff".to_string(),
        name: name.to_string(),
        time_s,
        failure: (!failures.is_empty()).then(|| failures.join("\n")),
        error: None,
        output: String::new(),
    }
}
