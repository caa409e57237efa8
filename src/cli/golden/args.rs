//! `shadelab golden`'s command line: the scenes and modes, where the
//! references are and how they are named, the limits, and what to write.

use std::path::{Path, PathBuf};

use clap::Args;

use crate::cli::common::args::PresetArg;
use crate::cli::common::args::{ImageSize, ModeList, SceneFlags};
use crate::cli::common::shards;

#[derive(Args)]
pub struct GoldenArgs {
    /// Scene files (.toml, .gltf or .glb); the built-in default scene if none.
    pub(super) scenes: Vec<PathBuf>,
    #[command(flatten)]
    pub(super) modes: ModeList,
    /// The folder of stored references: DIR/KEY/NAME (this driver's, looked
    /// for first), then DIR/NAME (shared by every driver).
    #[arg(long, value_name = "DIR", required_unless_present = "merge")]
    pub(super) references: Option<PathBuf>,
    /// Each reference's file name, from {scene} (the scene file's path
    /// below --root, without its extension: its name alone where every
    /// scene is in one folder) and {mode}; .png or .exr.
    #[arg(long, value_name = "PATTERN", default_value = "{scene}-{mode}.png")]
    pub(super) name: String,
    /// Run only the cases of shard I of N (1 <= I <= N): cases are dealt out
    /// by their scene's path and mode, so a case stays on its shard when
    /// others are added. Each shard's --out holds its record for --merge.
    /// `auto` reads I and N from the CI's own variables (docs/golden.md).
    #[arg(long, value_name = "I/N", value_parser = shards::parse_shard)]
    pub(super) shard: Option<(usize, usize)>,
    /// Join the records of these shard folders (each a shard's --out) into
    /// one report in --out: report.html, golden.json, --junit and --json,
    /// as the whole run writes them.
    #[arg(long, num_args = 1.., value_name = "DIR", conflicts_with_all = ["scenes", "shard", "create", "bless"])]
    pub(super) merge: Vec<PathBuf>,
    /// The folder the scenes' paths in reference names are taken from
    /// [default: the deepest folder that holds every scene].
    #[arg(long, value_name = "DIR")]
    pub(super) root: Option<PathBuf>,
    /// Make the references that are missing from this run's renders (else a
    /// missing reference fails its case).
    #[arg(long)]
    pub(super) create: bool,
    /// Accept this run's renders: rewrite every reference that is over its
    /// limits (or cannot be compared), make the missing ones, and list each.
    /// Also SHADELAB_BLESS=1.
    #[arg(long, visible_alias = "update")]
    pub(super) bless: bool,
    /// Write the references that --create or --bless make into this
    /// driver's folder (DIR/KEY/), leaving the shared ones as they are.
    #[arg(long)]
    pub(super) per_driver: bool,
    /// This driver's folder of references [default: made from the device
    /// and driver names, printed by every run].
    #[arg(long, value_name = "KEY")]
    pub(super) key: Option<String>,
    /// The limits to start from: stored-reference (no pixel off by more
    /// than 0.01, one 8-bit step) or gpu-vs-reference (diff's defaults).
    #[arg(long, value_enum, default_value = "stored-reference")]
    pub(super) preset: PresetArg,
    /// Thresholds on top of the preset, as diff's: `FIGURE=X[,FIGURE=X...]`
    /// for flip_mean, max_abs, p99_abs, rmse, fraction_over, count_over or
    /// psnr (a floor, dB).
    #[arg(long, value_name = "[FIGURE=]X,...")]
    pub(super) threshold: Vec<String>,
    /// Folder for report.html and, for each case that did not pass, its
    /// NAME-actual and NAME-diff images.
    #[arg(long, value_name = "DIR", default_value = "golden-out")]
    pub(super) out: PathBuf,
    /// Also write a JUnit XML report here.
    #[arg(long, value_name = "FILE.xml")]
    pub(super) junit: Option<PathBuf>,
    /// Print one JSON object with every case on stdout.
    #[arg(long)]
    pub(super) json: bool,
    #[command(flatten)]
    pub(super) size: ImageSize,
    #[command(flatten)]
    pub(super) settings: SceneFlags,
    #[command(flatten)]
    pub machine: crate::cli::common::args::MachineArgs,
}

impl GoldenArgs {
    /// `--references`, which clap requires unless merging.
    pub(super) fn references(&self) -> &Path {
        self.references.as_deref().unwrap_or(Path::new("."))
    }
}
