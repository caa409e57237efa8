//! The one place that warns about options a run ignores: a flag that no
//! case, or only some of the cases, of a command uses (a ray-tracing flag
//! with raster modes, `--msaa` with the ray tracer, `--traversal` on the
//! CPU reference). Every command lists the flags it was given and the
//! modes and backends it runs, and this says once, in one form, what each
//! flag changes nothing in.

use shadelab::shading::Shading;

/// Where a command's images are made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Backends {
    /// The GPU alone (render's default, golden, compare, bench, warm).
    Gpu,
    /// The CPU reference alone (`render --backend cpu`).
    Cpu,
    /// Both, each case on the one it is compared with or chosen for
    /// (`check`; `render --backend auto`).
    Both,
}

/// Which cases use a flag, where the run's scenes gather caustics or not.
fn used_by(flag: &str, shading: Shading, cpu: bool, caustics: bool) -> bool {
    match flag {
        // The photon map's settings, which only `--caustics N` (or a
        // scene's `render.caustics`) turns on.
        "--caustic-passes" | "--caustic-radius" => shading == Shading::Raytrace && caustics,
        "--msaa" => shading.raster_mode().is_some(),
        // The CPU reference has one way of finding hits.
        "--traversal" => shading == Shading::Raytrace && !cpu,
        "--photons" => shading == Shading::Forward,
        // `bench --cpu`: the CPU twin of either tracer.
        "--cpu" => matches!(shading, Shading::Raytrace | Shading::Forward),
        // Forward tracing's paths are bounded by both as the eye's are.
        "--depth" | "--bounces" => matches!(shading, Shading::Raytrace | Shading::Forward),
        _ => shading == Shading::Raytrace,
    }
}

/// Why a flag changes nothing in the cases that ignore it: said of one
/// flag, and of several.
fn why(flag: &str, cpu_alone: bool, caustics: bool) -> (&'static str, &'static str) {
    match flag {
        "--caustic-passes" | "--caustic-radius" if !caustics => (
            "it sets the photon map's caustics, which only --caustics N or a scene's render.caustics turns on",
            "they set the photon map's caustics, which only --caustics N or a scene's render.caustics turns on",
        ),
        "--msaa" => (
            "it is for the raster modes; the ray tracer's anti-aliasing is --samples",
            "they are for the raster modes; the ray tracer's anti-aliasing is --samples",
        ),
        "--traversal" if cpu_alone => (
            "it chooses the GPU ray tracer's engine; the CPU reference has one",
            "they choose the GPU ray tracer's engine; the CPU reference has one",
        ),
        "--traversal" => (
            "it chooses the GPU ray tracer's engine",
            "they choose the GPU ray tracer's engine",
        ),
        "--photons" => (
            "only forward ray tracing uses it",
            "only forward ray tracing uses them",
        ),
        "--cpu" => (
            "it times the ray tracers' CPU twins",
            "they time the ray tracers' CPU twins",
        ),
        _ => (
            "only the ray tracer uses it",
            "only the ray tracer uses them",
        ),
    }
}

/// What a run renders, as far as the flags it ignores go: its modes, where,
/// and whether any of its scenes gathers caustics (after the flags).
#[derive(Debug, Clone, Copy)]
pub struct Run<'a> {
    pub modes: &'a [Shading],
    pub backends: Backends,
    pub caustics: bool,
}

/// The warnings for `given` (flags on the command line) over `run`: one
/// line for the flags that the same cases ignore for the same reason,
/// naming those cases (every mode it runs, or the ones that ignore them).
pub fn warnings(given: &[&str], run: Run) -> Vec<String> {
    let Run {
        modes,
        backends,
        caustics,
    } = run;
    // (the modes that ignore them, why) -> the flags.
    type Ignoring = (Vec<Shading>, (&'static str, &'static str));
    let mut groups: Vec<(Ignoring, Vec<&str>)> = Vec::new();
    for &flag in given {
        // A case ignores a flag where no backend it runs on uses it.
        let ignoring: Vec<Shading> = modes
            .iter()
            .copied()
            .filter(|&m| match backends {
                Backends::Gpu => !used_by(flag, m, false, caustics),
                Backends::Cpu => !used_by(flag, m, true, caustics),
                Backends::Both => {
                    !used_by(flag, m, false, caustics) && !used_by(flag, m, true, caustics)
                }
            })
            .collect();
        if ignoring.is_empty() {
            continue;
        }
        let key = (ignoring, why(flag, backends == Backends::Cpu, caustics));
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, flags)) => flags.push(flag),
            None => groups.push((key, vec![flag])),
        }
    }
    groups
        .into_iter()
        .map(|((ignoring, why), flags)| {
            let names: Vec<String> = ignoring.iter().map(|m| m.to_string()).collect();
            let it = if flags.len() == 1 { "it" } else { "them" };
            let who = if ignoring.len() == modes.len() {
                let on = if backends == Backends::Cpu {
                    " on the CPU reference"
                } else {
                    ""
                };
                format!("--shading {}{on} ignores {it}", names.join(","))
            } else {
                format!("the {} images ignore {it}", names.join(", "))
            };
            let why = if flags.len() == 1 { why.0 } else { why.1 };
            format!("shadelab: warning: {}: {who} ({why})", flags.join(", "))
        })
        .collect()
}

/// Prints [`warnings`] on stderr.
pub fn warn(given: &[&str], run: Run) {
    for line in warnings(given, run) {
        eprintln!("{line}");
    }
}

/// The flags of `SceneFlags` (and check's own of the same names) given, by
/// name: the ones a mode or a backend may ignore (`--lighting` is refused
/// where it cannot run, not ignored).
pub fn scene_flags_given(
    traversal: &super::args::TraversalArg,
    msaa: &super::args::MsaaArg,
    depth: &super::args::DepthArg,
) -> Vec<&'static str> {
    [
        ("--depth", depth.depth.is_some()),
        ("--bounces", depth.bounces.is_some()),
        ("--photons", depth.photons.is_some()),
        ("--caustics", depth.caustics.is_some()),
        ("--caustic-passes", depth.caustic_passes.is_some()),
        ("--caustic-radius", depth.caustic_radius.is_some()),
        ("--traversal", traversal.traversal.is_some()),
        ("--msaa", msaa.msaa.is_some()),
    ]
    .into_iter()
    .filter_map(|(flag, given)| given.then_some(flag))
    .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(modes: &[Shading], backends: Backends) -> Run<'_> {
        Run {
            modes,
            backends,
            caustics: false,
        }
    }

    /// `--caustic-passes` and `--caustic-radius` set a photon map that
    /// nothing turned on (issue 55: they were ignored without a word);
    /// with caustics on, the ray tracer uses them.
    #[test]
    fn the_photon_maps_settings_without_caustics_are_ignored() {
        let given = ["--caustic-passes", "--caustic-radius"];
        let modes = [Shading::Raytrace];
        assert_eq!(
            warnings(&given, run(&modes, Backends::Gpu)),
            ["shadelab: warning: --caustic-passes, --caustic-radius: --shading raytrace ignores them (they set the photon map's caustics, which only --caustics N or a scene's render.caustics turns on)"]
        );
        let on = Run {
            caustics: true,
            ..run(&modes, Backends::Both)
        };
        assert!(warnings(&given, on).is_empty());
    }

    const ALL: [Shading; 4] = [
        Shading::Flat,
        Shading::Gouraud,
        Shading::Phong,
        Shading::Raytrace,
    ];

    #[test]
    fn a_flag_some_modes_ignore_is_named_with_them() {
        let lines = warnings(&["--msaa"], run(&ALL, Backends::Gpu));
        assert_eq!(
            lines,
            ["shadelab: warning: --msaa: the raytrace images ignore it (it is for the raster modes; the ray tracer's anti-aliasing is --samples)"]
        );
        let lines = warnings(
            &["--depth"],
            run(&[Shading::Flat, Shading::Phong], Backends::Gpu),
        );
        assert_eq!(
            lines,
            ["shadelab: warning: --depth: --shading flat,phong ignores it (only the ray tracer uses it)"]
        );
        let lines = warnings(
            &["--depth", "--samples", "--msaa"],
            run(&[Shading::Phong], Backends::Gpu),
        );
        assert_eq!(
            lines,
            ["shadelab: warning: --depth, --samples: --shading phong ignores them (only the ray tracer uses them)"]
        );
        // Used by every case: nothing to say.
        assert!(warnings(
            &["--depth", "--traversal"],
            run(&[Shading::Raytrace], Backends::Gpu)
        )
        .is_empty());
        assert!(warnings(&["--msaa"], run(&[Shading::Flat], Backends::Both)).is_empty());
    }

    #[test]
    fn the_cpu_reference_ignores_the_engine() {
        let lines = warnings(&["--traversal"], run(&[Shading::Raytrace], Backends::Cpu));
        assert_eq!(
            lines,
            ["shadelab: warning: --traversal: --shading raytrace on the CPU reference ignores it (it chooses the GPU ray tracer's engine; the CPU reference has one)"]
        );
        // check renders on both: the GPU side uses it.
        assert!(warnings(&["--traversal"], run(&[Shading::Raytrace], Backends::Both)).is_empty());
    }
}
