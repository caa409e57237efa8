//! `shadelab warm`: fills the caches for a set of scenes without rendering
//! them at size, so that the renders after it (a CI job's, or the user's)
//! start warm: the specialised modules and lavapipe's machine code of every
//! pipeline those scenes need, in the cache folder (`cache`).
//!
//! The code a pipeline gets does not depend on the image's size, so each
//! scene is rendered at a few pixels: the cost is the pipelines alone.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use shadelab::gpu::GpuOptions;
use shadelab::memory::MemoryLimit;
use shadelab::render::{render, Device, RenderRequest};

use crate::cli::common::args::{ModeList, SceneFlags};
use crate::cli::common::batch::scene::load_scene;
use crate::cli::common::failure::Failure;

/// The size each scene is rendered at: the pipelines are the same at any.
const WARM_SIZE: u32 = 16;

#[derive(Args)]
pub struct WarmArgs {
    /// Scene files; the built-in default scene if none.
    scenes: Vec<PathBuf>,
    #[command(flatten)]
    modes: ModeList,
    #[command(flatten)]
    settings: SceneFlags,
    #[command(flatten)]
    pub machine: crate::cli::common::args::MachineArgs,
}

pub fn run(args: WarmArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    let modes = args.modes.modes();
    let started = Instant::now();
    let paths: Vec<Option<PathBuf>> = if args.scenes.is_empty() {
        vec![None]
    } else {
        args.scenes.iter().cloned().map(Some).collect()
    };
    let mut scenes = Vec::new();
    for path in &paths {
        let (mut scene, name) = load_scene(path.as_deref(), memory)?;
        scene.image.width = WARM_SIZE;
        scene.image.height = WARM_SIZE;
        args.settings.apply(&mut scene)?;
        // The photon map's pipeline is the same at any count: one pass
        // of a few photons builds it.
        let caustics = &mut scene.render.caustics;
        if caustics.on() {
            caustics.passes = 1;
            caustics.photons_per_pass = caustics.photons_per_pass.min(1024);
        }
        memory.check(&name, &scene, &modes, &[])?;
        scenes.push((scene, name));
    }
    // Said once the flags are known to be valid: a bad one is the answer.
    let s = &args.settings;
    let ignoring = crate::cli::common::ignored::Run {
        modes: &modes,
        backends: crate::cli::common::ignored::Backends::Gpu,
        caustics: scenes.iter().any(|(scene, _)| scene.render.caustics.on()),
    };
    crate::cli::common::ignored::warn(
        &crate::cli::common::ignored::scene_flags_given(&s.traversal, &s.msaa, &s.depth),
        ignoring,
    );
    let device = Device::open(options)?;
    for (scene, _) in &scenes {
        for &shading in &modes {
            render(&device, scene, &RenderRequest::gpu(shading))?;
        }
    }
    let folder = shadelab::cache::folder()
        .map(|f| f.display().to_string())
        .unwrap_or_else(|| "none (set SHADELAB_CACHE_DIR)".into());
    let mesa = if std::env::var_os("MESA_SHADER_CACHE_DISABLE").is_some() {
        "off (MESA_SHADER_CACHE_DISABLE is set): the machine code is not kept".to_string()
    } else {
        std::env::var_os("MESA_SHADER_CACHE_DIR").map_or_else(
            || "Mesa's default folder".to_string(),
            |d| PathBuf::from(d).display().to_string(),
        )
    };
    println!(
        "warmed {} pipeline(s) for {} scene(s) in {:.1} s",
        device.require_gpu()?.pipelines_kept(),
        scenes.len(),
        started.elapsed().as_secs_f64()
    );
    println!("cache folder: {folder}");
    println!("Mesa's shader cache: {mesa}");
    Ok(())
}
