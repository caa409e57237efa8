//! Arguments several subcommands share, with the range checks the scene
//! loader applies to the same settings in a file. Checked here rather than
//! by clap so that a bad value gets the one-line `shadelab: error:` of every
//! other bad input.

use clap::Args;
use shadelab::diff::Preset;
use shadelab::scene::{
    check_caustic_radius, watchdog_limit, LightingHook, Scene, Traversal, MAX_DEPTH, MAX_RESOLUTION,
};
use shadelab::shading::Shading;

use super::failure::Failure;

/// `--preset` of `diff` and `golden`: the limits to start from, named by
/// what they compare ([`Preset`], whose limits they are).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PresetArg {
    /// A GPU render against a reference renderer's image of the same
    /// scene: `Thresholds::default()`.
    GpuVsReference,
    /// A render against a stored render of the same renderer and driver,
    /// which repeats bit for bit: no pixel off by more than 0.01, a bit
    /// over the largest one 8-bit sRGB step (0.0089, at the top of the
    /// range), so a last-bit change that tips a pixel over one step
    /// passes and anything of two steps fails.
    StoredReference,
}

impl PresetArg {
    pub fn preset(self) -> Preset {
        match self {
            PresetArg::GpuVsReference => Preset::GpuVsReference,
            PresetArg::StoredReference => Preset::StoredReference,
        }
    }
}

/// The flags that override a scene's settings in every command that renders
/// it whole (render, bench, warm, golden), applied in this order.
#[derive(Args, Clone, Debug)]
pub struct SceneFlags {
    #[command(flatten)]
    pub lighting: LightingArg,
    #[command(flatten)]
    pub traversal: TraversalArg,
    #[command(flatten)]
    pub msaa: MsaaArg,
    #[command(flatten)]
    pub depth: DepthArg,
}

impl SceneFlags {
    /// Sets them on `scene`: the hook read, the names and counts parsed.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), Failure> {
        self.lighting.apply(scene)?;
        self.traversal.apply(scene)?;
        self.msaa.apply(scene)?;
        self.depth.apply(scene)
    }
}

/// `--width` and `--height`, overriding the scene's `[image]` size.
#[derive(Args, Clone)]
pub struct ImageSize {
    /// Image width in pixels (overrides the scene's [image] width).
    // Signed, so that `--width -5` is a range error like `--width 0`, not
    // the parser's advice to write `-- -5` (which makes -5 a scene path).
    #[arg(long, allow_negative_numbers = true)]
    pub width: Option<i64>,
    /// Image height in pixels (overrides the scene's [image] height).
    #[arg(long, allow_negative_numbers = true)]
    pub height: Option<i64>,
}

impl ImageSize {
    /// Refuses a size the scene loader would refuse.
    pub fn check(&self) -> Result<(), Failure> {
        for (flag, value) in [("--width", self.width), ("--height", self.height)] {
            if let Some(v) = value.filter(|&v| !(1..=MAX_RESOLUTION).contains(&v)) {
                return Err(Failure::usage(format!(
                    "{flag} {v} is out of range; expected 1 to {MAX_RESOLUTION} pixels"
                )));
            }
        }
        Ok(())
    }

    /// Checks the size, then sets it on `scene`.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), Failure> {
        self.check()?;
        // In range (checked): 1 to 16384 fits a u32.
        let pixels = |v: Option<i64>, old: u32| v.map_or(old, |v| v as u32);
        scene.image.width = pixels(self.width, scene.image.width);
        scene.image.height = pixels(self.height, scene.image.height);
        Ok(())
    }
}

/// `--lighting FILE`: the user's lighting hook, compiled into the GPU
/// modes in place of the built-in formula.
#[derive(Args, Clone, Debug)]
pub struct LightingArg {
    /// GLSL file defining `vec3 shade_light(vec3 N, vec3 V, vec3 L, float d,
    /// vec3 intensity, Surface m, float k)`, one light's contribution, used
    /// by every GPU mode instead of the built-in formula (see docs/lighting-hooks.md).
    /// The CPU reference keeps the built-in formula.
    #[arg(long, value_name = "FILE")]
    pub lighting: Option<std::path::PathBuf>,
    // With the hook: the watchdog is there for shader code that never ends.
    #[command(flatten)]
    pub watchdog: WatchdogArg,
}

impl LightingArg {
    /// Reads the hook's file into `scene`, and sets the watchdog.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), Failure> {
        if let Some(path) = &self.lighting {
            scene.lighting_hook = Some(std::sync::Arc::new(LightingHook::load(path)?));
        }
        self.watchdog.apply(scene)
    }
}

/// `--watchdog SECONDS`: how long one GPU submission may run, overriding
/// the scene's `render.watchdog`.
#[derive(Args, Clone, Debug, Default)]
pub struct WatchdogArg {
    /// The longest one GPU submission may run, 0 (no limit) to 86400
    /// seconds: past it the command stops with exit status 3, naming the
    /// likely cause (the --lighting hook), and writes nothing (overrides
    /// the scene's render.watchdog; default 120).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub watchdog: Option<f64>,
}

impl WatchdogArg {
    /// Sets the limit on `scene`, refusing one out of range.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), Failure> {
        if let Some(seconds) = self.watchdog {
            scene.render.watchdog =
                watchdog_limit(seconds).map_err(|e| Failure::usage(format!("--watchdog {e}")))?;
        }
        Ok(())
    }
}

/// `--device` and `--max-memory`: the machine a command renders on. Taken
/// before the subcommand (`shadelab --device 1 render`) or after it
/// (`shadelab render --device 1`); only the commands that render list them.
#[derive(Args, Clone, Default)]
pub struct MachineArgs {
    /// Vulkan device: an index or part of a name as `shadelab info` lists them
    /// (default: lavapipe). Also read from SHADELAB_DEVICE.
    #[arg(long, value_name = "NAME|INDEX")]
    pub device: Option<String>,
    /// The most memory a render may plan to take, such as 512M or 4G
    /// (binary units). A scene whose estimate is over it is refused before
    /// anything large is allocated. Also read from SHADELAB_MAX_MEMORY;
    /// default: 3/4 of the machine's memory (or of its control group's).
    #[arg(long, value_name = "SIZE")]
    pub max_memory: Option<String>,
    /// No progress on stderr (a bar on a terminal, else a line every few
    /// seconds; SHADELAB_PROGRESS_SECONDS sets how many).
    #[arg(long, short)]
    pub quiet: bool,
}

impl MachineArgs {
    /// These, where given, else `outer`'s (the flags before the subcommand).
    pub fn or(&self, outer: &MachineArgs) -> MachineArgs {
        MachineArgs {
            device: self.device.clone().or_else(|| outer.device.clone()),
            max_memory: self.max_memory.clone().or_else(|| outer.max_memory.clone()),
            quiet: self.quiet || outer.quiet,
        }
    }
}

/// `--shading a,b,...`: the modes a command runs over its scenes.
#[derive(Args)]
pub struct ModeList {
    /// Shading modes, comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "flat,gouraud,phong,raytrace"
    )]
    shading: Vec<Shading>,
}

impl ModeList {
    /// The modes asked for, each once, in the order first given:
    /// `--shading phong,phong` is one run of Phong, not two.
    pub fn modes(&self) -> Vec<Shading> {
        let mut modes = Vec::new();
        for &shading in &self.shading {
            if !modes.contains(&shading) {
                modes.push(shading);
            }
        }
        modes
    }
}

/// `--msaa`: the raster modes' samples per pixel, overriding the scene's
/// `render.msaa`.
#[derive(Args, Clone, Debug, Default)]
pub struct MsaaArg {
    /// The raster modes' samples per pixel, N or N,per-sample (shade every
    /// sample); the counts the device renders are in `shadelab info`.
    /// Overrides the scene's render.msaa [default: 1].
    #[arg(long, value_name = "N[,per-sample]")]
    pub msaa: Option<String>,
}

impl MsaaArg {
    /// Sets the samples on `scene`; text that is not a count is a usage
    /// error (the device's counts are checked where it renders).
    pub fn apply(&self, scene: &mut Scene) -> Result<(), Failure> {
        if let Some(text) = &self.msaa {
            scene.render.msaa = text
                .parse()
                .map_err(|e: String| Failure::usage(format!("--msaa {e}")))?;
        }
        Ok(())
    }
}

/// `--depth`, `--bounces` and `--photons`: how far the ray tracers go,
/// overriding the scene's.
#[derive(Args, Clone, Debug, Default)]
pub struct DepthArg {
    /// Ray tracing: maximum recursion depth (overrides the scene's
    /// render.depth).
    #[arg(long)]
    pub depth: Option<i64>,
    /// Ray tracing: diffuse bounces, secondary illumination (overrides the
    /// scene's render.bounces; 0, the default, is the Whitted tracer).
    #[arg(long)]
    pub bounces: Option<i64>,
    /// Forward ray tracing (--shading forward): photons traced from the
    /// lights, 1 to 4294967295 (overrides the scene's render.photons;
    /// default 4194304). The noise falls as one over their square root.
    #[arg(long, allow_negative_numbers = true)]
    pub photons: Option<i64>,
    /// Ray tracing: caustics from a photon map, N photons from the
    /// lights each pass, gathered where the eye's paths land through
    /// mirrors and glass and added to the image (overrides the scene's
    /// render.caustics; 0, the default, is none).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub caustics: Option<i64>,
    /// Ray tracing with --caustics: the photon map's passes, 1 to 1048576
    /// (overrides render.caustic_passes; default 16). Its gathering
    /// radius shrinks pass by pass.
    #[arg(long, value_name = "P", allow_negative_numbers = true)]
    pub caustic_passes: Option<i64>,
    /// Ray tracing with --caustics: the first gathering radius, in pixel
    /// footprints where the eye's path lands (overrides
    /// render.caustic_radius; default 2).
    #[arg(long, value_name = "R", allow_negative_numbers = true)]
    pub caustic_radius: Option<f64>,
}

impl DepthArg {
    /// Sets the depth and the bounces on `scene`, refusing either out of
    /// range, or a depth asked for below the bounces (the scene's rule:
    /// `RenderSettings::settle_depth`).
    pub fn apply(&self, scene: &mut Scene) -> Result<(), Failure> {
        if let Some(d) = self.depth {
            scene.render.depth = check_depth(d)?;
            scene.render.depth_given = true;
        }
        if let Some(b) = self.bounces {
            scene.render.bounces = u32::try_from(b)
                .ok()
                .filter(|&b| b <= MAX_DEPTH)
                .ok_or_else(|| {
                    Failure::usage(format!(
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
            Failure::usage(format!(
                "{bounces_from} needs a depth of {bounces} or more (each bounce is a level of the ray tree, which the depth bounds), and {depth_from}; give --depth {bounces} or more, or leave the depth out (it then follows the bounces)"
            ))
        })?;
        if let Some(p) = self.photons {
            scene.render.photons = check_photons(p)?;
        }
        self.apply_caustics(&mut scene.render.caustics)
    }

    /// `--caustics`, `--caustic-passes` and `--caustic-radius`, each in
    /// its range, all the passes' photons numbered in 32 bits.
    fn apply_caustics(
        &self,
        caustics: &mut shadelab::scene::CausticSettings,
    ) -> Result<(), Failure> {
        if let Some(n) = self.caustics {
            caustics.photons_per_pass = u32::try_from(n).map_err(|_| {
                Failure::usage(format!(
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
                    Failure::usage(format!(
                        "--caustic-passes {p} is out of range; expected 1 to 1048576"
                    ))
                })?;
        }
        if let Some(r) = self.caustic_radius {
            caustics.initial_radius = check_caustic_radius(r)
                .map_err(|e| Failure::usage(format!("--caustic-radius {e}")))?;
        }
        if caustics.total_photons().is_none() {
            return Err(Failure::usage(format!(
                "--caustics {} times {} passes is past 4294967295 photons (photons are numbered in 32 bits); take fewer passes or photons per pass",
                caustics.photons_per_pass, caustics.passes
            )));
        }
        Ok(())
    }
}

/// `--photons`: 1 to 2^32 - 1 (a photon's number is 32 bits).
pub fn check_photons(photons: i64) -> Result<u32, Failure> {
    u32::try_from(photons)
        .ok()
        .filter(|&p| p > 0)
        .ok_or_else(|| {
            Failure::usage(format!(
                "--photons {photons} is out of range; expected 1 to {} (photons are numbered in 32 bits; for more, add up shards)",
                u32::MAX
            ))
        })
}

/// `--depth`: the ray tracer's maximum depth, 0 to `MAX_DEPTH`.
pub fn check_depth(depth: i64) -> Result<u32, Failure> {
    u32::try_from(depth)
        .ok()
        .filter(|&d| d <= MAX_DEPTH)
        .ok_or_else(|| {
            Failure::usage(format!(
                "--depth {depth} is out of range; expected 0 to {MAX_DEPTH}"
            ))
        })
}

/// `--runs`: timed runs, 1 to 1000.
pub fn check_runs(runs: i64) -> Result<usize, Failure> {
    usize::try_from(runs)
        .ok()
        .filter(|r| (1..=1000).contains(r))
        .ok_or_else(|| Failure::usage(format!("--runs {runs} is out of range; expected 1 to 1000")))
}

/// `--traversal`: the GPU ray tracer's engine, overriding the scene's
/// `render.traversal`.
#[derive(Args, Clone, Debug, Default)]
pub struct TraversalArg {
    /// The GPU ray tracer's engine: `bvh` (the compute shader's own BVH
    /// walk), `query` (VK_KHR_ray_query through an acceleration structure
    /// the driver builds) or `auto` (chosen per device: the compute BVH on
    /// lavapipe; see docs/raytracing.md). Overrides the scene's
    /// render.traversal.
    #[arg(long, value_name = "ENGINE")]
    pub traversal: Option<String>,
}

impl TraversalArg {
    /// Sets the engine on `scene`; an unknown name is a usage error.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), Failure> {
        if let Some(name) = &self.traversal {
            scene.render.traversal = name
                .parse::<Traversal>()
                .map_err(|e| Failure::usage(format!("--traversal: {e}")))?;
        }
        Ok(())
    }
}
