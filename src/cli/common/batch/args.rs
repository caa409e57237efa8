//! `shadelab render`'s command line, which `golden` fills in too (so it is
//! shared, with the batch it describes): the scenes and modes, the
//! backend, the overrides, and where the images go.

use std::path::PathBuf;

use clap::Args;
use shadelab::shading::Shading;

use crate::cli::common::args::{ImageSize, SceneFlags};

#[derive(Args)]
pub struct RenderArgs {
    /// Scene files (.toml, .gltf or .glb); the built-in default scene if
    /// left out. More than one makes a batch (see --out-dir).
    #[arg(value_name = "SCENE")]
    pub(in crate::cli) scenes: Vec<PathBuf>,
    /// Shading mode, or modes comma-separated (a batch: each scene in each).
    #[arg(long, value_delimiter = ',', default_value = "phong")]
    pub(in crate::cli) shading: Vec<Shading>,
    /// Renderer: the Vulkan pipelines (gpu), the CPU reference (cpu), or
    /// whichever should give the image first (auto: a short CPU pilot set
    /// against the GPU's fixed costs; the choice is printed).
    #[arg(long, default_value = "gpu", value_parser = ["gpu", "cpu", "auto"])]
    pub(in crate::cli) backend: String,
    #[command(flatten)]
    pub(in crate::cli) size: ImageSize,
    #[command(flatten)]
    pub(in crate::cli) settings: SceneFlags,
    /// Ray tracing: adaptive depth cut-off on the ray weight.
    #[arg(long)]
    pub(in crate::cli) cutoff: Option<f64>,
    /// Ray tracing: samples per pixel.
    #[arg(long)]
    pub(in crate::cli) samples: Option<i64>,
    /// Ray tracing: no shadow rays.
    #[arg(long)]
    pub(in crate::cli) no_shadows: bool,
    /// Output image: .png (8-bit sRGB) or .exr (linear 32-bit float).
    /// Default: <scene name>-<mode>.png in the current folder.
    #[arg(long, short)]
    pub(in crate::cli) out: Option<PathBuf>,
    /// A batch: the folder the images go into, named by --name (created if
    /// missing). Implied (the current folder) by more than one scene or mode.
    #[arg(long, value_name = "DIR")]
    pub(in crate::cli) out_dir: Option<PathBuf>,
    /// A batch: each image's file name, from {scene} (the scene file's
    /// name without its extension) and {mode}; .png or .exr [default:
    /// {scene}-{mode}.png]. Makes a batch of even one image.
    #[arg(long, value_name = "PATTERN")]
    pub(in crate::cli) name: Option<String>,
    /// Print one JSON object describing the render on stdout (a batch: one
    /// object with a case per image).
    #[arg(long)]
    pub(in crate::cli) json: bool,
    /// Ray tracing: print the rays traced, by kind (a table, or "stats" in
    /// the --json object).
    #[arg(long)]
    pub(in crate::cli) stats: bool,
    /// Forward ray tracing, or ray tracing with --bounces on the GPU: stop
    /// tracing photons or samples after SECONDS (from the start of the
    /// render) and write the estimate of those traced.
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub(in crate::cli) time: Option<f64>,
    /// Forward ray tracing, or ray tracing with --bounces, on the GPU:
    /// stop once the render's own estimate of its RMSE (from two halves
    /// of its batches) is RMSE or less, and write the estimate of what it
    /// traced.
    #[arg(long = "error", value_name = "RMSE", allow_negative_numbers = true)]
    pub(in crate::cli) error_budget: Option<f64>,
    /// Forward ray tracing, or ray tracing with --bounces, split over
    /// machines: trace only the I-th of N runs of the photons or of each
    /// pixel's samples, and write its film to --out FILE.film for --merge.
    /// `auto` reads I and N from the CI's own variables (docs/golden.md).
    #[arg(long = "shard", value_name = "I/N", value_parser = crate::cli::common::shards::parse_shard)]
    pub(in crate::cli) render_shard: Option<(usize, usize)>,
    /// Add the films of shards 1 to N of one render (each a --shard's
    /// --out) into --out: the image one render of all the photons or
    /// samples makes, bit for bit.
    #[arg(long, num_args = 1.., value_name = "FILE.film", conflicts_with_all = ["scenes", "render_shard"])]
    pub(in crate::cli) merge: Vec<PathBuf>,
    #[command(flatten)]
    pub machine: crate::cli::common::args::MachineArgs,
    /// A batch: each scene's `{scene}` in file names, given by the caller
    /// (`golden`'s keys), in place of the file's stem made unique.
    #[arg(skip)]
    pub(in crate::cli) scene_names: Option<Vec<String>>,
    /// A batch: only the cases of shard I of N (`golden --shard`), dealt
    /// out by `{scene}/{mode}`.
    #[arg(skip)]
    pub(in crate::cli) shard: Option<(usize, usize)>,
}

impl RenderArgs {
    /// `--time` and `--error`.
    pub(in crate::cli) fn budgets(&self) -> shadelab::render::overrides::Budgets {
        shadelab::render::overrides::Budgets {
            time: self.time,
            error: self.error_budget,
        }
    }

    /// When `--time` runs out, counted from now: the render's start.
    pub(in crate::cli) fn deadline(&self) -> Option<std::time::Instant> {
        self.budgets().deadline()
    }

    /// The modes asked for, each once, in the order first given.
    pub(in crate::cli) fn modes(&self) -> Vec<Shading> {
        let mut modes = Vec::new();
        for &shading in &self.shading {
            if !modes.contains(&shading) {
                modes.push(shading);
            }
        }
        modes
    }

    /// More than one image, `--out-dir` or `--name`: a batch.
    pub(in crate::cli) fn is_batch(&self) -> bool {
        self.scenes.len() > 1
            || self.modes().len() > 1
            || self.out_dir.is_some()
            || self.name.is_some()
    }

    /// The batch's file name pattern.
    pub(in crate::cli) fn name_pattern(&self) -> &str {
        self.name.as_deref().unwrap_or("{scene}-{mode}.png")
    }
}
