//! The settings a caller sets over a scene's own (`render --width`,
//! `--samples`, ...; the Python package's keyword arguments), each checked
//! against the range the scene loader holds the file's value to. One
//! place, so that a command line and a Python call refuse the same values
//! with the same sentence; the messages name the flags, as `docs/cli.md`
//! lists them.

use std::sync::Arc;

use crate::backend_choice::Backend;
use crate::error::Error;
use crate::render::Technique;
use crate::scene::{
    check_caustic_radius, watchdog_limit, CausticSettings, LightingHook, Scene, Traversal,
    MAX_DEPTH, MAX_RESOLUTION,
};
use crate::shading::Shading;

/// What a caller overrides of a scene; `None` (and `false`) keeps the
/// scene's own. Applied in field order by [`Overrides::apply`].
#[derive(Debug, Clone, Default)]
pub struct Overrides {
    /// `--width` and `--height`, 1 to `MAX_RESOLUTION` pixels.
    pub width: Option<i64>,
    pub height: Option<i64>,
    /// `--lighting`: the user's GLSL for one light's contribution.
    pub lighting: Option<Arc<LightingHook>>,
    /// `--watchdog`: seconds one GPU submission may run.
    pub watchdog: Option<f64>,
    /// `--traversal`: `bvh`, `query` or `auto`.
    pub traversal: Option<String>,
    /// `--msaa`: `N` or `N,per-sample`.
    pub msaa: Option<String>,
    pub depth: Option<i64>,
    pub bounces: Option<i64>,
    pub photons: Option<i64>,
    pub caustics: Option<i64>,
    pub caustic_passes: Option<i64>,
    pub caustic_radius: Option<f64>,
    pub cutoff: Option<f64>,
    pub samples: Option<i64>,
    /// `--no-shadows`.
    pub no_shadows: bool,
}

fn usage(message: String) -> Error {
    Error::Usage(message)
}

impl Overrides {
    /// Sets every override on `scene`, refusing the first out of range.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), Error> {
        self.apply_size(scene)?;
        if let Some(hook) = &self.lighting {
            scene.lighting_hook = Some(hook.clone());
        }
        if let Some(seconds) = self.watchdog {
            scene.render.watchdog =
                watchdog_limit(seconds).map_err(|e| usage(format!("--watchdog {e}")))?;
        }
        if let Some(name) = &self.traversal {
            scene.render.traversal = name
                .parse::<Traversal>()
                .map_err(|e| usage(format!("--traversal: {e}")))?;
        }
        if let Some(text) = &self.msaa {
            scene.render.msaa = text
                .parse()
                .map_err(|e: String| usage(format!("--msaa {e}")))?;
        }
        self.apply_depth(scene)?;
        if let Some(p) = self.photons {
            scene.render.photons = check_photons(p)?;
        }
        self.apply_caustics(&mut scene.render.caustics)?;
        self.apply_ray_settings(scene)
    }

    /// `--width` and `--height` alone (the commands that size a scene
    /// but take no other override).
    pub fn apply_size(&self, scene: &mut Scene) -> Result<(), Error> {
        check_size(self.width, self.height)?;
        // In range (checked): 1 to 16384 fits a u32.
        let pixels = |v: Option<i64>, old: u32| v.map_or(old, |v| v as u32);
        scene.image.width = pixels(self.width, scene.image.width);
        scene.image.height = pixels(self.height, scene.image.height);
        Ok(())
    }

    /// The depth and the bounces, each in range, and a depth asked for
    /// below the bounces refused (the scene's rule:
    /// `RenderSettings::settle_depth`).
    fn apply_depth(&self, scene: &mut Scene) -> Result<(), Error> {
        if let Some(d) = self.depth {
            scene.render.depth = check_depth(d)?;
            scene.render.depth_given = true;
        }
        if let Some(b) = self.bounces {
            scene.render.bounces = u32::try_from(b)
                .ok()
                .filter(|&b| b <= MAX_DEPTH)
                .ok_or_else(|| {
                    usage(format!(
                        "--bounces {b} is out of range; expected 0 to {MAX_DEPTH} (a bounce is a level of the ray tree, which --depth bounds)"
                    ))
                })?;
        }
        scene.render.settle_depth().map_err(|(depth, bounces)| {
            let bounces_from = match self.bounces {
                Some(_) => format!("--bounces {bounces}"),
                None => format!("the scene's render.bounces = {bounces}"),
            };
            let depth_from = match self.depth {
                Some(_) => format!("--depth is {depth}"),
                None => format!("the scene's render.depth is {depth}"),
            };
            usage(format!(
                "{bounces_from} needs a depth of {bounces} or more (each bounce is a level of the ray tree, which the depth bounds), and {depth_from}; give --depth {bounces} or more, or leave the depth out (it then follows the bounces)"
            ))
        })
    }

    /// `--caustics`, `--caustic-passes` and `--caustic-radius`, each in
    /// its range, all the passes' photons numbered in 32 bits.
    fn apply_caustics(&self, caustics: &mut CausticSettings) -> Result<(), Error> {
        if let Some(n) = self.caustics {
            caustics.photons_per_pass = u32::try_from(n).map_err(|_| {
                usage(format!(
                    "--caustics {n} is out of range; expected 0 to {} photons per pass",
                    u32::MAX
                ))
            })?;
        }
        if let Some(p) = self.caustic_passes {
            caustics.passes = u32::try_from(p)
                .ok()
                .filter(|p| (1..=1 << 20).contains(p))
                .ok_or_else(|| {
                    usage(format!(
                        "--caustic-passes {p} is out of range; expected 1 to 1048576"
                    ))
                })?;
        }
        if let Some(r) = self.caustic_radius {
            caustics.initial_radius =
                check_caustic_radius(r).map_err(|e| usage(format!("--caustic-radius {e}")))?;
        }
        if caustics.total_photons().is_none() {
            return Err(usage(format!(
                "--caustics {} times {} passes is past 4294967295 photons (photons are numbered in 32 bits); take fewer passes or photons per pass",
                caustics.photons_per_pass, caustics.passes
            )));
        }
        Ok(())
    }

    /// `--cutoff`, `--samples` and `--no-shadows`.
    fn apply_ray_settings(&self, scene: &mut Scene) -> Result<(), Error> {
        if let Some(c) = self.cutoff {
            if !c.is_finite() || c < 0.0 {
                return Err(usage(format!(
                    "--cutoff {c} is invalid; expected a number >= 0"
                )));
            }
            scene.render.cutoff = c;
        }
        if let Some(s) = self.samples {
            scene.render.samples = u32::try_from(s)
                .ok()
                .filter(|s| (1..=1024).contains(s))
                .ok_or_else(|| {
                    usage(format!("--samples {s} is out of range; expected 1 to 1024"))
                })?;
        }
        if self.no_shadows {
            scene.render.shadows = false;
        }
        Ok(())
    }
}

/// `--width` and `--height`: 1 to `MAX_RESOLUTION`, as the scene loader
/// holds `[image]` to.
pub fn check_size(width: Option<i64>, height: Option<i64>) -> Result<(), Error> {
    for (flag, value) in [("--width", width), ("--height", height)] {
        if let Some(v) = value.filter(|&v| !(1..=MAX_RESOLUTION).contains(&v)) {
            return Err(usage(format!(
                "{flag} {v} is out of range; expected 1 to {MAX_RESOLUTION} pixels"
            )));
        }
    }
    Ok(())
}

/// `--photons`: 1 to 2^32 - 1 (a photon's number is 32 bits).
pub fn check_photons(photons: i64) -> Result<u32, Error> {
    u32::try_from(photons)
        .ok()
        .filter(|&p| p > 0)
        .ok_or_else(|| {
            usage(format!(
                "--photons {photons} is out of range; expected 1 to {} (photons are numbered in 32 bits; for more, add up shards)",
                u32::MAX
            ))
        })
}

/// `--depth`: the ray tracer's maximum depth, 0 to `MAX_DEPTH`.
pub fn check_depth(depth: i64) -> Result<u32, Error> {
    u32::try_from(depth)
        .ok()
        .filter(|&d| d <= MAX_DEPTH)
        .ok_or_else(|| {
            usage(format!(
                "--depth {depth} is out of range; expected 0 to {MAX_DEPTH}"
            ))
        })
}

/// A lighting hook asked of the CPU reference, which always evaluates
/// the built-in formula.
pub fn refuse_hook_on_cpu(hook: bool, backend: Backend) -> Result<(), Error> {
    if hook && backend == Backend::Cpu {
        return Err(usage(
            "--lighting is for the GPU backend; the CPU reference always evaluates the built-in formula".to_string(),
        ));
    }
    Ok(())
}

/// The budgets of one render: `--time SECONDS` and `--error RMSE`.
#[derive(Debug, Clone, Copy, Default)]
pub struct Budgets {
    pub time: Option<f64>,
    pub error: Option<f64>,
}

impl Budgets {
    /// Numbers above 0, for one render (`one`: the mode where there is a
    /// single image, no batch and no shard) that sums into a film
    /// (forward, or ray tracing with bounces) or a ray trace with caustics
    /// (`--time` alone: the photon map is biased), on the GPU (the CPU
    /// reference's ray tracer traces every sample; its forward tracer
    /// keeps a time budget but cannot judge its error). `gpu_only`: the
    /// backend is the GPU's alone (not `cpu`, not `auto`).
    pub fn check(&self, scene: &Scene, one: Option<Shading>, gpu_only: bool) -> Result<(), Error> {
        for (flag, value, unit) in [
            ("--time", self.time, "a number of seconds"),
            ("--error", self.error, "an RMSE"),
        ] {
            let Some(v) = value else {
                continue;
            };
            if !(v.is_finite() && v > 0.0) {
                return Err(usage(format!(
                    "{flag} {v} is invalid; expected {unit} above 0"
                )));
            }
            let caustics = one == Some(Shading::Raytrace) && scene.render.caustics.on();
            if caustics && flag == "--error" {
                return Err(usage(
                    "--error estimates an unbiased render's error from two halves of its batches, and the photon map's caustics are biased (their radius shrinks pass by pass): stop them with --time or --caustic-passes".into(),
                ));
            }
            let budgeted = caustics || one.is_some_and(|m| Technique::of(scene, m).sums_in_film());
            if !budgeted {
                return Err(usage(format!(
                    "{flag} stops one render (--shading forward, or raytrace with --bounces 1 or more or with --caustics; one scene, no --shard) at a budget"
                )));
            }
            let needs_gpu = one == Some(Shading::Raytrace) || flag == "--error";
            if needs_gpu && !gpu_only {
                return Err(usage(format!(
                    "{flag} stops a render between its GPU batches, and the CPU reference traces them all: leave out --backend"
                )));
            }
        }
        Ok(())
    }

    /// When `--time` runs out, counted from now: the render's start.
    pub fn deadline(&self) -> Option<std::time::Instant> {
        self.time
            .map(|s| std::time::Instant::now() + std::time::Duration::from_secs_f64(s))
    }
}
