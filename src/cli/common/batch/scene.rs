//! A scene as a render takes it: loaded (within the memory limit), the
//! command line's overrides applied and checked, and a warning for the
//! flags no mode in play uses.

use std::path::Path;

use shadelab::backend_choice::Backend;
use shadelab::memory::MemoryLimit;
use shadelab::render::overrides::{self, Overrides};
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
    let backend = match args.backend.as_str() {
        "cpu" => Backend::Cpu,
        _ => Backend::Gpu,
    };
    overrides::refuse_hook_on_cpu(args.settings.lighting.lighting.is_some(), backend)?;
    let mut o = Overrides::default();
    args.size.fill(&mut o);
    args.settings.fill(&mut o)?;
    o.cutoff = args.cutoff;
    o.samples = args.samples;
    o.no_shadows = args.no_shadows;
    o.apply(scene)?;
    let one = match args.modes()[..] {
        [mode] if !args.is_batch() && args.render_shard.is_none() => Some(mode),
        _ => None,
    };
    args.budgets().check(scene, one, args.backend == "gpu")?;
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
