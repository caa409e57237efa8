//! Whether a comparison passes: the limits on its figures, a verdict per
//! figure, and the figures written for people.

use serde::Serialize;

use super::comparison::Comparison;

/// The limits a comparison must stay within. A figure passes when it is at
/// or below its limit; NaN never passes.
///
/// The defaults are for a GPU render against a reference of the same scene:
///
/// - `flip_mean` 0.02: the mean perceptual difference wgpu's image tests
///   allow. Differences in the last bits of shading and a few edge pixels stay
///   well below it; a wrong highlight or a missing light does not.
/// - `p99_abs` 0.05: 99% of pixels within 5% of full intensity, so up to 1%
///   of pixels (silhouettes, where rasterisers disagree about coverage) may
///   differ by anything.
/// - `max_abs` 1.0: any single pixel may differ by up to full scale (an edge
///   pixel that one side covers and the other does not), but not more: this
///   catches NaN, infinity and values blown far past 1 in an EXR.
///
/// `shadelab check` (the GPU against the CPU reference) will set its own
/// thresholds, measured on the reference scenes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Thresholds {
    pub flip_mean: f64,
    pub max_abs: f64,
    pub p99_abs: f64,
    /// Limit on the RMSE over every channel; none by default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rmse: Option<f64>,
    /// The lowest PSNR (dB) that passes; none by default. Identical images
    /// (infinite PSNR) pass any; a non-finite difference (NaN) fails.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub psnr: Option<f64>,
    /// Limit on the share of pixels whose error exceeds the per-pixel
    /// threshold (`ErrorStats::fraction_over`: pixelmatch's measure); none
    /// by default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fraction_over: Option<f64>,
    /// The same as a number of pixels; none by default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub count_over: Option<f64>,
}

impl Default for Thresholds {
    fn default() -> Self {
        Self {
            flip_mean: 0.02,
            max_abs: 1.0,
            p99_abs: 0.05,
            rmse: None,
            psnr: None,
            fraction_over: None,
            count_over: None,
        }
    }
}

/// One thresholded figure: its name (as in JSON), value, limit and verdict.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    pub figure: &'static str,
    pub value: f64,
    pub limit: f64,
    pub pass: bool,
}

impl Verdict {
    /// The value for people: dB for `psnr`, a whole number for
    /// `count_over`, else `format_figure`.
    pub fn formatted_value(&self) -> String {
        match self.figure {
            "psnr" => format_psnr(self.value),
            "count_over" => format!("{:.0}", self.value),
            _ => format_figure(self.value),
        }
    }
}

impl Thresholds {
    /// Each thresholded figure of `comparison` with its verdict.
    pub fn verdicts(&self, comparison: &Comparison) -> Vec<Verdict> {
        let verdict = |figure, value: f64, limit: f64| Verdict {
            figure,
            value,
            limit,
            pass: value <= limit,
        };
        let mut all = vec![
            verdict("flip_mean", comparison.flip.mean, self.flip_mean),
            verdict("max_abs", comparison.stats.max_abs, self.max_abs),
            verdict("p99_abs", comparison.stats.p99_abs, self.p99_abs),
        ];
        if let Some(limit) = self.rmse {
            all.push(verdict("rmse", comparison.stats.rmse, limit));
        }
        if let Some(limit) = self.fraction_over {
            all.push(verdict(
                "fraction_over",
                comparison.stats.fraction_over,
                limit,
            ));
        }
        if let Some(limit) = self.count_over {
            let stats = &comparison.stats;
            let count = (stats.fraction_over * stats.pixels as f64).round();
            all.push(verdict("count_over", count, limit));
        }
        if let Some(limit) = self.psnr {
            // A floor, not a ceiling: NaN and -inf (a non-finite
            // difference) fail it, +inf (identical images) passes.
            let value = comparison.stats.psnr;
            all.push(Verdict {
                figure: "psnr",
                value,
                limit,
                pass: value >= limit,
            });
        }
        all
    }

    /// One line per failed threshold, naming the figure, its value and the
    /// limit; empty when the comparison passes.
    pub fn check(&self, comparison: &Comparison) -> Vec<String> {
        self.verdicts(comparison)
            .iter()
            .filter(|v| !v.pass)
            .map(|v| {
                let verb = if v.figure == "psnr" {
                    "is under"
                } else {
                    "exceeds"
                };
                let value = v.formatted_value();
                format!("{} {value} {verb} the limit {}", v.figure, v.limit)
            })
            .collect()
    }
}

/// A PSNR for people: dB with two decimals; `inf` for identical pixels;
/// `-inf (non-finite difference)` where a NaN or infinity on one side made
/// the error infinite, which is no match at all, not a perfect one.
pub fn format_psnr(psnr: f64) -> String {
    if psnr.is_finite() {
        format!("{psnr:.2}")
    } else if psnr == f64::INFINITY {
        "inf".to_string()
    } else {
        "-inf (non-finite difference)".to_string()
    }
}

/// A figure for people: six decimals, or three significant digits in
/// scientific notation when that would hide a small non-zero value.
pub fn format_figure(v: f64) -> String {
    if v != 0.0 && v.is_finite() && v.abs() < 1e-4 {
        format!("{v:.2e}")
    } else {
        format!("{v:.6}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linear_image::LinearImage;
    use crate::metrics::comparison::compare;
    use crate::metrics::flip::FlipStats;

    #[test]
    fn figures_switch_to_scientific_notation_below_1e_4_only_when_non_zero() {
        // cargo-mutants found these unpinned: zero, the boundary itself,
        // and a value below it.
        assert_eq!(format_figure(0.0), "0.000000");
        assert_eq!(format_figure(1e-4), "0.000100");
        assert_eq!(format_figure(5e-5), "5.00e-5");
        assert_eq!(format_figure(-5e-5), "-5.00e-5");
        assert_eq!(format_figure(0.25), "0.250000");
        assert_eq!(format_figure(f64::NAN), "NaN");
    }

    #[test]
    fn check_names_each_failed_figure() {
        let expected = LinearImage::new(16, 16, [0.0; 3]);
        let mut actual = expected.clone();
        actual.set(5, 5, [0.5; 3]);
        let c = compare(&expected, &actual, None).unwrap();
        // One pixel of 256 is under 1%: p99 is 0, max is 0.5.
        let strict = Thresholds {
            flip_mean: 1.0,
            max_abs: 0.25,
            p99_abs: 0.0,
            ..Thresholds::default()
        };
        let failed = strict.check(&c);
        assert_eq!(failed.len(), 1, "{failed:?}");
        assert!(failed[0].starts_with("max_abs 0.5"), "{}", failed[0]);
        assert!(failed[0].ends_with("limit 0.25"), "{}", failed[0]);
        let nan = Comparison {
            flip: FlipStats {
                mean: f64::NAN,
                ..c.flip.clone()
            },
            ..c
        };
        assert!(strict.check(&nan)[0].starts_with("flip_mean NaN"));
    }
}
