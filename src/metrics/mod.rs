//! Comparing two images: error statistics, FLIP, heat maps and silhouette
//! masks, and the thresholds a comparison passes or fails.
//!
//! Works on `LinearImage` values only. Nothing here reads or writes a file,
//! knows about Vulkan, prints or exits: `src/diff.rs` reads the files and
//! judges a pair against limits, and `shadelab diff` (`src/cli/diff/`)
//! prints it. One job per file:
//!
//! - `stats.rs`: pixel-wise figures (max, mean, RMSE, PSNR, 99th percentile)
//! - `flip.rs`: NVIDIA's FLIP through the `nv-flip` crate
//! - `heatmap.rs`: the FLIP map as a magma-coloured image
//! - `edges.rs`: silhouette masks, from object ids or from image gradients
//! - `comparison.rs`: every figure of one comparison, whole and masked
//! - `thresholds.rs`: the limits a comparison passes or fails, and the
//!   figures for people

pub mod comparison;
pub mod edges;
pub mod flip;
pub mod heatmap;
pub mod stats;
pub mod thresholds;

pub use comparison::{compare, compare_with, Comparison, MetricsError, Settings};
pub use edges::gradient_mask;
pub use flip::{flip, FlipStats};
pub use heatmap::{flip_heatmap, scaled_error_heatmap};
pub use stats::ErrorStats;
pub use thresholds::{format_figure, format_psnr, Thresholds, Verdict};
