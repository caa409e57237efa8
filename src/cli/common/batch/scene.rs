//! A scene as a render takes it: loaded (within the memory limit), the
//! command line's overrides applied and checked, and a warning for the
//! flags no mode in play uses.

use std::path::Path;

use shadelab::memory::MemoryLimit;
use shadelab::render::Technique;
use shadelab::scene::{self, Scene};
use shadelab::shading::Shading;

use super::args::RenderArgs;
use crate::cli::common::failure::Failure;
use crate::cli::common::ignored::{self, Backends};

/// Loads `path` (the default scene when `None`), refusing a glTF file whose
/// geometry alone would exceed `memory`, and returns it with its name.
pub fn load_scene(path: Option<&Path>, memory: &MemoryLimit) -> Result<(Scene, String), Failure> {
    match path {
        None => Ok((scene::default_scene(), "default".to_string())),
        Some(p) => {
            let scene = scene::load_within(p, &memory.load_limits())?;
            let stem = p
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scene".into());
            Ok((scene, stem))
        }
    }
}

/// Applies the command-line overrides to the scene, checking their ranges as
/// the scene loader checks the file's; warns once (`warn`) of ray-tracing
/// flags that no mode in `modes` uses.
pub(in crate::cli) fn apply_overrides(
    scene: &mut Scene,
    args: &RenderArgs,
    modes: &[Shading],
    warn: bool,
) -> Result<(), Failure> {
    args.size.apply(scene)?;
    if args.settings.lighting.lighting.is_some() && args.backend == "cpu" {
        return Err(Failure::usage(
            "--lighting is for the GPU backend; the CPU reference always evaluates the built-in formula".to_string(),
        ));
    }
    args.settings.apply(scene)?;
    if let Some(c) = args.cutoff {
        if !c.is_finite() || c < 0.0 {
            return Err(Failure::usage(format!(
                "--cutoff {c} is invalid; expected a number >= 0"
            )));
        }
        scene.render.cutoff = c;
    }
    if let Some(s) = args.samples {
        scene.render.samples = u32::try_from(s)
            .ok()
            .filter(|s| (1..=1024).contains(s))
            .ok_or_else(|| {
                Failure::usage(format!("--samples {s} is out of range; expected 1 to 1024"))
            })?;
    }
    if args.no_shadows {
        scene.render.shadows = false;
    }
    check_budgets(args, scene)?;
    // Said once the flags are known to be valid: a bad one is the answer.
    if warn {
        let backends = match args.backend.as_str() {
            "cpu" => Backends::Cpu,
            "auto" => Backends::Both,
            _ => Backends::Gpu,
        };
        let ignoring = ignored::Run {
            modes,
            backends,
            caustics: scene.render.caustics.on(),
        };
        ignored::warn(&options_given(args), ignoring);
    }
    Ok(())
}

/// `--time SECONDS` and `--error RMSE`: numbers above 0, for one render
/// that sums into a film (forward, or ray tracing with bounces: a batch,
/// a shard or another mode has no use for them) or a ray trace with
/// caustics (`--time` alone: the photon map is biased), on the GPU (the
/// CPU reference's ray tracer traces every sample; its forward tracer
/// keeps a time budget but cannot judge its error).
fn check_budgets(args: &RenderArgs, scene: &Scene) -> Result<(), Failure> {
    for (flag, value, unit) in [
        ("--time", args.time, "a number of seconds"),
        ("--error", args.error_budget, "an RMSE"),
    ] {
        let Some(v) = value else {
            continue;
        };
        if !(v.is_finite() && v > 0.0) {
            return Err(Failure::usage(format!(
                "{flag} {v} is invalid; expected {unit} above 0"
            )));
        }
        let one = match args.modes()[..] {
            [mode] if !args.is_batch() && args.render_shard.is_none() => Some(mode),
            _ => None,
        };
        let caustics = one == Some(Shading::Raytrace) && scene.render.caustics.on();
        if caustics && flag == "--error" {
            return Err(Failure::usage(
                "--error estimates an unbiased render's error from two halves of its batches, and the photon map's caustics are biased (their radius shrinks pass by pass): stop them with --time or --caustic-passes".into(),
            ));
        }
        let budgeted = caustics || one.is_some_and(|m| Technique::of(scene, m).sums_in_film());
        if !budgeted {
            return Err(Failure::usage(format!(
                "{flag} stops one render (--shading forward, or raytrace with --bounces 1 or more or with --caustics; one scene, no --shard) at a budget"
            )));
        }
        let needs_gpu = one == Some(Shading::Raytrace) || flag == "--error";
        if needs_gpu && args.backend != "gpu" {
            return Err(Failure::usage(format!(
                "{flag} stops a render between its GPU batches, and the CPU reference traces them all: leave out --backend"
            )));
        }
    }
    Ok(())
}

/// The options on the command line that a mode or a backend may ignore,
/// by flag: those every command shares and render's own.
fn options_given(args: &RenderArgs) -> Vec<&'static str> {
    let s = &args.settings;
    let mut given = ignored::scene_flags_given(&s.traversal, &s.msaa, &s.depth);
    for (flag, present) in [
        ("--cutoff", args.cutoff.is_some()),
        ("--samples", args.samples.is_some()),
        ("--no-shadows", args.no_shadows),
    ] {
        if present {
            given.push(flag);
        }
    }
    given
}
