//! The results of a comparison run: what `report.json` holds, what the
//! CSV, the plot, the contact sheet and the HTML page are made from, and
//! what shards are merged by. Plain data; nothing here renders or writes.

use serde::{Deserialize, Serialize};

use super::variant::Variant;

/// Error figures of one image against another (the subset of
/// `metrics::ErrorStats` and `FlipStats` a report keeps).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Errors {
    pub rmse: f64,
    pub max_abs: f64,
    /// dB; `None` for identical images (infinite).
    pub psnr: Option<f64>,
    pub flip_mean: f64,
}

/// Milliseconds: the median and the spread (slowest minus fastest) of the
/// timed runs after a warm-up.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    /// Queue submission to completion: the GPU's work.
    pub gpu_ms: f64,
    pub gpu_spread_ms: f64,
    /// The whole frame: uploads, work, read-back, and the pipeline's
    /// lookup (built once, by the warm-up, and reused).
    pub frame_ms: f64,
    pub frame_spread_ms: f64,
    /// Shader modules and pipeline creation, paid by the variant's first
    /// render.
    pub pipeline_ms: f64,
    /// Time to image: the variant's first render in the run, pipeline
    /// creation and the driver's code generation (or its cache's load)
    /// included. 0 in a report from before it was measured.
    #[serde(default)]
    pub image_ms: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VariantResult {
    /// The variant's canonical name, also its file stem (with `:`, `,` and
    /// `=` made file-safe by `file_stem`).
    pub name: String,
    pub variant: Variant,
    /// Image file (PNG) relative to the report's folder.
    pub image: String,
    /// Heat map (PNG, FLIP against the reference) relative to the folder.
    pub heatmap: String,
    /// GPU against the CPU reference of the same variant: should be tiny;
    /// large means a bug.
    pub implementation_error: Errors,
    /// GPU against the scene's (global) reference image, the ray-traced
    /// one: what the variant costs in accuracy, shadows and reflections
    /// included.
    pub model_error: Errors,
    /// GPU against the local reference: the formula per pixel on exact
    /// geometry, no shadows, reflection or refraction (what Phong shading
    /// converges to). `None` in reports written before it existed.
    #[serde(default)]
    pub local_error: Option<Errors>,
    pub timing: Timing,
    /// The GPU ray tracer's engine (`bvh` or `query`, never `auto`); `None`
    /// for the raster modes and in reports written before it existed.
    #[serde(default)]
    pub traversal: Option<crate::scene::Traversal>,
    /// Pixels of the GPU image with a NaN or infinite channel (a lighting
    /// hook gone wrong): its errors are then infinite, and the run warns.
    #[serde(default)]
    pub non_finite_pixels: usize,
    /// On the Pareto front of (gpu_ms, plotted RMSE, `Report::error_of`):
    /// no other variant is at least as fast and at least as accurate, and
    /// strictly better in one.
    pub pareto: bool,
}

/// Which reference a variant's plotted error (and the front and the
/// budget) is against: one for every variant, so that their errors can be
/// set side by side.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ReferenceChoice {
    /// The ray-traced reference: the scene as it should look, shadows and
    /// reflections in. The default. Reports written before issue 30 may
    /// say `auto` (the raster modes against the local reference and ray
    /// tracing against the global one, on one front): read as global.
    #[default]
    #[serde(alias = "auto")]
    Global,
    Local,
}

impl ReferenceChoice {
    /// `auto` is read as the default, `global` (it mixed the two before).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "auto" | "global" => Some(Self::Global),
            "local" => Some(Self::Local),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Local => "local",
            Self::Global => "global",
        }
    }

    /// The reference in a sentence's words ("against the ...").
    pub fn describe(self) -> &'static str {
        match self {
            Self::Local => "local reference",
            Self::Global => "global (ray-traced) reference",
        }
    }
}

/// Which error figure the plot and the budget use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Metric {
    #[default]
    Rmse,
    Flip,
}

impl Metric {
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "rmse" => Some(Self::Rmse),
            "flip" => Some(Self::Flip),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Rmse => "RMSE",
            Self::Flip => "mean FLIP",
        }
    }

    pub fn of(self, e: &Errors) -> f64 {
        match self {
            Self::Rmse => e.rmse,
            Self::Flip => e.flip_mean,
        }
    }
}

/// `compare --budget E`: the fastest variant whose error is at most `E`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Budget {
    pub max_error: f64,
    /// The fastest variant within the budget (by `gpu_ms`), or `None` when
    /// none is.
    pub fastest: Option<String>,
}

impl VariantResult {
    /// The errors against `reference`: the same reference for every
    /// variant, whatever its mode (a report without local errors has the
    /// global ones only).
    pub fn errors_against(&self, reference: ReferenceChoice) -> &Errors {
        match (reference, &self.local_error) {
            (ReferenceChoice::Local, Some(local)) => local,
            _ => &self.model_error,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Report {
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub device: String,
    /// The device's driver and its version (`shadelab info`); empty in
    /// reports written before it was recorded.
    #[serde(default)]
    pub driver: String,
    /// Timed runs per variant (after one warm-up).
    pub runs: usize,
    /// How the reference image was made.
    pub reference: String,
    pub reference_image: String,
    /// How the local reference image was made, and its file; empty in
    /// reports written before it existed.
    #[serde(default)]
    pub local_reference: String,
    #[serde(default)]
    pub local_reference_image: String,
    /// The reference and the figure the plot, the Pareto front and the
    /// budget use.
    #[serde(default)]
    pub plot_reference: ReferenceChoice,
    #[serde(default)]
    pub plot_metric: Metric,
    /// `Some((i, n))` for the i-th of n shards (1-based), `None` when whole.
    pub shard: Option<(usize, usize)>,
    pub variants: Vec<VariantResult>,
    /// Present when `--budget` was given.
    #[serde(default)]
    pub budget: Option<Budget>,
    /// The variants asked for that did not run (over the memory limit, or
    /// failed), each with why; empty in reports written before.
    #[serde(default)]
    pub not_run: Vec<NotRun>,
    /// A shard's: what the whole run is (its scene's contents, the full
    /// variant list, the settings) and their digest, for `--merge` to
    /// refuse shards of different runs; absent from a whole run's report.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<serde_json::Value>,
}

/// A variant the run left out, and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NotRun {
    /// Its canonical name, as a result's.
    pub name: String,
    pub variant: Variant,
    pub reason: String,
}

impl Report {
    /// A variant's plotted error: the chosen figure against the chosen
    /// reference.
    pub fn error_of(&self, v: &VariantResult) -> f64 {
        self.plot_metric.of(v.errors_against(self.plot_reference))
    }

    /// The fastest variant (by `gpu_ms`) whose plotted error is at most
    /// `max_error`; `None` when none is. Of two equally fast, the first.
    pub fn fastest_within(&self, max_error: f64) -> Option<&VariantResult> {
        self.variants
            .iter()
            .filter(|v| self.error_of(v) <= max_error)
            .fold(None, |best: Option<&VariantResult>, v| match best {
                Some(b) if b.timing.gpu_ms <= v.timing.gpu_ms => Some(b),
                _ => Some(v),
            })
    }

    /// The device, with its driver and version where recorded.
    pub fn device_and_driver(&self) -> String {
        if self.driver.is_empty() {
            self.device.clone()
        } else {
            format!("{} ({})", self.device, self.driver)
        }
    }
}

/// A file name for a variant: `raytrace:depth=3,cutoff=0.01` becomes
/// `raytrace_depth-3_cutoff-0.01`.
pub fn file_stem(name: &str) -> String {
    name.chars()
        .map(|c| match c {
            ':' | ',' => '_',
            '=' => '-',
            c if c.is_ascii_alphanumeric() || c == '.' || c == '-' || c == '_' => c,
            _ => '_',
        })
        .collect()
}

/// Marks the Pareto front of (time, error) among `points`: index i is on it
/// when no j has time_j <= time_i and error_j <= error_i with one of them
/// strictly smaller. Ties in both keep every tied point.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(t, e)| {
            !points
                .iter()
                .any(|&(t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_of_a_constructed_table() {
        // time, error
        let points = [
            (1.0, 10.0), // fastest: on the front
            (2.0, 5.0),  // on the front
            (3.0, 6.0),  // dominated by (2, 5)
            (4.0, 1.0),  // most accurate: on the front
            (4.0, 1.0),  // an exact tie with the previous: both stay
            (5.0, 1.0),  // as accurate but slower: dominated
            (2.0, 7.0),  // dominated by (2, 5): same time, worse error
        ];
        assert_eq!(
            pareto_front(&points),
            [true, true, false, true, true, false, false]
        );
    }

    #[test]
    fn file_stems_are_safe() {
        assert_eq!(
            file_stem("raytrace:depth=3,cutoff=0.01"),
            "raytrace_depth-3_cutoff-0.01"
        );
        assert_eq!(file_stem("flat"), "flat");
    }

    fn result(name: &str, gpu_ms: f64, global: f64, local: Option<f64>) -> VariantResult {
        let errors = |rmse: f64| Errors {
            rmse,
            max_abs: rmse * 4.0,
            psnr: None,
            flip_mean: rmse / 2.0,
        };
        VariantResult {
            name: name.into(),
            variant: name.parse().unwrap(),
            image: String::new(),
            heatmap: String::new(),
            implementation_error: errors(0.0),
            model_error: errors(global),
            local_error: local.map(errors),
            timing: Timing {
                gpu_ms,
                gpu_spread_ms: 0.0,
                frame_ms: gpu_ms,
                frame_spread_ms: 0.0,
                pipeline_ms: 0.0,
                image_ms: 0.0,
            },
            traversal: None,
            non_finite_pixels: 0,
            pareto: false,
        }
    }

    fn hand_made() -> Report {
        Report {
            scene: "s".into(),
            width: 1,
            height: 1,
            device: String::new(),
            driver: String::new(),
            runs: 1,
            reference: String::new(),
            reference_image: String::new(),
            local_reference: String::new(),
            local_reference_image: String::new(),
            plot_reference: ReferenceChoice::Global,
            plot_metric: Metric::Rmse,
            shard: None,
            variants: vec![
                result("flat", 1.0, 0.30, Some(0.20)),
                result("gouraud", 2.0, 0.12, Some(0.05)),
                result("phong", 3.0, 0.11, Some(0.01)),
                result("raytrace", 9.0, 0.02, Some(0.15)),
            ],
            budget: None,
            not_run: Vec::new(),
            run: None,
        }
    }

    #[test]
    fn the_budget_picks_the_fastest_variant_within_it_by_the_chosen_reference() {
        let mut r = hand_made();
        // The default, global, for every mode: issue 30's case, where the
        // ray tracer (0.02) is the one within 0.02 and Phong's small local
        // error (0.01) must not count, since Phong misses the shadows.
        let pick = |r: &Report, e: f64| r.fastest_within(e).map(|v| v.name.clone());
        assert_eq!(pick(&r, 0.02).as_deref(), Some("raytrace"));
        assert_eq!(pick(&r, 0.25).as_deref(), Some("gouraud"));
        assert_eq!(pick(&r, 0.115).as_deref(), Some("phong"));
        assert_eq!(pick(&r, 0.005), None);
        r.plot_reference = ReferenceChoice::Local;
        assert_eq!(pick(&r, 0.02).as_deref(), Some("phong"));
        assert_eq!(pick(&r, 0.16).as_deref(), Some("gouraud"));
        r.plot_metric = Metric::Flip;
        // FLIP here is half the RMSE: 0.1 local FLIP for flat.
        assert_eq!(pick(&r, 0.1).as_deref(), Some("flat"));
    }

    #[test]
    fn reports_without_a_local_error_measure_against_the_global_one() {
        let v = result("phong", 1.0, 0.3, None);
        assert_eq!(v.errors_against(ReferenceChoice::Global).rmse, 0.3);
        assert_eq!(v.errors_against(ReferenceChoice::Local).rmse, 0.3);
        let text = serde_json::to_string(&hand_made()).unwrap();
        let without: Report = serde_json::from_str(
            &text
                .replace(",\"budget\":null", "")
                .replace("\"plot_reference\":\"global\",", ""),
        )
        .unwrap();
        assert_eq!(without.plot_reference, ReferenceChoice::Global);
        // A report of the mixed `auto` of before reads as global.
        let auto: Report = serde_json::from_str(&text.replace(
            "\"plot_reference\":\"global\"",
            "\"plot_reference\":\"auto\"",
        ))
        .unwrap();
        assert_eq!(auto.plot_reference, ReferenceChoice::Global);
        assert_eq!(
            ReferenceChoice::from_name("auto"),
            Some(ReferenceChoice::Global)
        );
    }
}
