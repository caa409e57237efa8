//! Shader-variant comparison runs: the same scene in many variants, each
//! timed and measured against the CPU reference of the same variant and
//! against the scene's reference image, laid out as data for reports.

pub mod present;
pub mod report;
pub mod run;
pub mod variant;

pub use report::{pareto_front, Errors, Report, Timing, VariantResult};
pub use variant::{default_variants, Variant};
