//! Arguments several subcommands share, with the range checks the scene
//! loader applies to the same settings in a file. Checked here rather than
//! by clap so that a bad value gets the one-line `shadelab: error:` of every
//! other bad input.

use clap::Args;
use shadelab::diff::Preset;
use shadelab::render::overrides::{self, Overrides};
use shadelab::scene::{LightingHook, Scene};
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
        let mut o = Overrides::default();
        self.fill(&mut o)?;
        Ok(o.apply(scene)?)
    }

    /// Writes them into `o` (the hook's file read).
    pub fn fill(&self, o: &mut Overrides) -> Result<(), Failure> {
        self.lighting.fill(o)?;
        self.traversal.fill(o);
        self.msaa.fill(o);
        self.depth.fill(o);
        Ok(())
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
        Ok(overrides::check_size(self.width, self.height)?)
    }

    /// Checks the size, then sets it on `scene`.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), Failure> {
        let mut o = Overrides::default();
        self.fill(&mut o);
        Ok(o.apply_size(scene)?)
    }

    /// Writes them into `o`.
    pub fn fill(&self, o: &mut Overrides) {
        o.width = self.width;
        o.height = self.height;
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
        let mut o = Overrides::default();
        self.fill(&mut o)?;
        Ok(o.apply(scene)?)
    }

    /// Reads the hook's file into `o`, with the watchdog.
    pub fn fill(&self, o: &mut Overrides) -> Result<(), Failure> {
        if let Some(path) = &self.lighting {
            o.lighting = Some(std::sync::Arc::new(LightingHook::load(path)?));
        }
        self.watchdog.fill(o);
        Ok(())
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
        let mut o = Overrides::default();
        self.fill(&mut o);
        Ok(o.apply(scene)?)
    }

    /// Writes it into `o`.
    pub fn fill(&self, o: &mut Overrides) {
        o.watchdog = self.watchdog;
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
        let mut o = Overrides::default();
        self.fill(&mut o);
        Ok(o.apply(scene)?)
    }

    /// Writes it into `o`.
    pub fn fill(&self, o: &mut Overrides) {
        o.msaa = self.msaa.clone();
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
    /// Sets the depth, bounces, photons and caustics on `scene`, each in
    /// its range (`Overrides::apply`).
    pub fn apply(&self, scene: &mut Scene) -> Result<(), Failure> {
        let mut o = Overrides::default();
        self.fill(&mut o);
        Ok(o.apply(scene)?)
    }

    /// Writes them into `o`.
    pub fn fill(&self, o: &mut Overrides) {
        o.depth = self.depth;
        o.bounces = self.bounces;
        o.photons = self.photons;
        o.caustics = self.caustics;
        o.caustic_passes = self.caustic_passes;
        o.caustic_radius = self.caustic_radius;
    }
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
        let mut o = Overrides::default();
        self.fill(&mut o);
        Ok(o.apply(scene)?)
    }

    /// Writes it into `o`.
    pub fn fill(&self, o: &mut Overrides) {
        o.traversal = self.traversal.clone();
    }
}
