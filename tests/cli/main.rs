//! The `shadelab` binary end to end, as users and scripts drive it: each
//! test runs the command in a folder of its own (`common::cli::shadelab`,
//! its environment passed to the child, never set in this process) and
//! reads its outputs, exit status and error lines.

#[path = "../common/mod.rs"]
mod common;

mod bad_input;
mod cache_config;
mod check;
mod compare;
mod compare_not_run;
mod diff;
mod diff_thresholds;
mod error_budget;
mod fuzz_regressions;
mod golden;
mod golden_keys;
mod memory_limit;
mod progress;
mod render;
mod render_batch;
mod shards;
mod time_to_image;
