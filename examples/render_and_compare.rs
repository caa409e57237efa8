//! Renders a scene on the GPU and with the CPU reference, and prints how far
//! apart the two images are: the library's whole path in one page.
//!
//! ```text
//! cargo run --release --example render_and_compare [SCENE] [MODE]
//! ```
//!
//! SCENE is a `.toml`, `.gltf` or `.glb` file (default: the built-in scene);
//! MODE is flat, gouraud, phong (default) or raytrace. Errors are in linear
//! intensity, where 1.0 is full white and one 8-bit step is about 0.004.

use std::error::Error;
use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use shadelab::gpu::GpuOptions;
use shadelab::metrics::{self, format_figure, ErrorStats};
use shadelab::render::{render, Device, RenderRequest};
use shadelab::shading::Shading;

const USAGE: &str = "usage: render_and_compare [SCENE] [flat|gouraud|phong|raytrace]";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    // Printed here rather than returned: an `Err` returned from `main` is
    // shown with `Debug`, the error's fields instead of its sentence.
    match run(&args, &mut std::io::stdout().lock()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Everything `main` does, writing the report to `out` so that a test can
/// read it (`tests/gpu/example_render_and_compare.rs`).
pub fn run(args: &[String], out: &mut impl Write) -> Result<(), Box<dyn Error>> {
    if args.len() > 2 {
        return Err(USAGE.into());
    }
    // The mode first: a typo should not cost a scene load and a render.
    let shading: Shading = match args.get(1) {
        Some(mode) => mode.parse()?,
        None => Shading::Phong,
    };
    let (scene, name) = match args.first() {
        Some(path) => (shadelab::scene::load(Path::new(path))?, path.as_str()),
        None => (shadelab::scene::default_scene(), "the built-in scene"),
    };
    for warning in &scene.warnings {
        eprintln!("warning: {warning}");
    }

    // The device keeps its pipelines between renders; the CPU reference
    // needs none, and comes with any device.
    let device = Device::open(&GpuOptions::from_env())?;
    let gpu = render(&device, &scene, &RenderRequest::gpu(shading))?;
    let cpu = render(&device, &scene, &RenderRequest::cpu(shading))?;
    let coverage = cpu
        .coverage
        .as_ref()
        .ok_or("the CPU reference knows its pixels")?;

    // The CPU image is the expected one. `near_edge` marks the pixels whose
    // sample lies so close to an edge that two correct renderers may cover
    // it differently: their error says little about shading, so it is
    // reported apart from the interior's.
    let c = metrics::compare(&cpu.image, &gpu.image, Some(&coverage.near_edge))?;

    let (width, height) = (scene.image.width, scene.image.height);
    writeln!(out, "scene       {name}, {width}x{height}, {shading}")?;
    writeln!(
        out,
        "time        GPU {:.1} ms, CPU reference {:.1} ms",
        gpu.timings.total_ms, cpu.timings.total_ms
    )?;
    print_stats(out, "all", &c.stats)?;
    if let Some(interior) = &c.interior {
        print_stats(out, "interior", interior)?;
    }
    if let Some(silhouette) = &c.silhouette {
        print_stats(out, "silhouette", silhouette)?;
    }
    writeln!(out, "flip_mean   {}", format_figure(c.flip.mean))?;
    Ok(())
}

/// One line of figures over a set of pixels.
fn print_stats(out: &mut impl Write, pixels: &str, s: &ErrorStats) -> std::io::Result<()> {
    writeln!(
        out,
        "{pixels:<11} max_abs {}  p99_abs {}  rmse {}  ({} pixels)",
        format_figure(s.max_abs),
        format_figure(s.p99_abs),
        format_figure(s.rmse),
        s.pixels
    )
}
