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
    /// The whole frame: pipeline creation, uploads, work, read-back.
    pub frame_ms: f64,
    pub frame_spread_ms: f64,
    /// Shader modules and pipeline creation, median.
    pub pipeline_ms: f64,
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
    /// GPU against the scene's reference image: what the variant costs in
    /// accuracy.
    pub model_error: Errors,
    pub timing: Timing,
    /// On the Pareto front of (gpu_ms, model RMSE): no other variant is at
    /// least as fast and at least as accurate, and strictly better in one.
    pub pareto: bool,
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
    /// `Some((i, n))` for the i-th of n shards (1-based), `None` when whole.
    pub shard: Option<(usize, usize)>,
    pub variants: Vec<VariantResult>,
}

impl Report {
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
}
