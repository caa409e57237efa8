//! The Rust library's own time for a loop of renders: the default scene
//! with its first light moved around a circle, each frame's scene made
//! from a table (as the Python package's `Scene.from_dict` makes it) and
//! rendered through one kept device. `python/bench/loop_bench.py` times the
//! same loop from Python and as separate `shadelab render` commands
//! against this one.
//!
//! ```text
//! cargo run --release --example render_loop -- FRAMES WIDTH HEIGHT [table|light]
//! ```
//!
//! `table` (the default) makes each frame's scene from the table with the
//! light moved; `light` reads the scene once and moves its light
//! (`Scene::with_light`, the package's `Scene.with_light`).
//!
//! Prints one JSON object: the frames, the loop's wall and CPU
//! milliseconds, and the mean of the last frame's pixels (so the work
//! cannot be skipped).

use std::error::Error;
use std::path::Path;
use std::time::Instant;

use shadelab::gpu::GpuOptions;
use shadelab::render::overrides::Overrides;
use shadelab::render::{render, Device, RenderRequest};
use shadelab::scene::{toml::from_table, DEFAULT_SCENE_TOML};
use shadelab::shading::Shading;

/// The CPU time this process has taken, every thread's (the driver's
/// included), in milliseconds: less bent than the wall clock by what else
/// a shared machine runs.
fn cpu_ms() -> f64 {
    // SAFETY: getrusage(2) fills the zeroed struct it is given.
    let usage = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_SELF, &mut usage);
        usage
    };
    let ms = |t: libc::timeval| t.tv_sec as f64 * 1e3 + t.tv_usec as f64 / 1e3;
    ms(usage.ru_utime) + ms(usage.ru_stime)
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let numbers: Vec<u32> = args
        .iter()
        .take(3)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let (&[frames, width, height], way) = (&numbers[..], args.get(3).map(String::as_str)) else {
        return Err("usage: render_loop FRAMES WIDTH HEIGHT [table|light]".into());
    };
    let by_light = match way {
        None | Some("table") => false,
        Some("light") => true,
        Some(other) => return Err(format!("{other}: expected table or light").into()),
    };
    let device = Device::open(&GpuOptions::from_env())?;
    let mut table: toml::Table = DEFAULT_SCENE_TOML.parse()?;
    // The pipeline built (or loaded from the cache) before the clock
    // starts, as the Python loop's device has it.
    render(
        &device,
        &from_table(&table, Path::new("."))?,
        &RenderRequest::gpu(Shading::Phong),
    )?;
    let started = Instant::now();
    let cpu_started = cpu_ms();
    let mut mean = 0.0;
    let size = Overrides {
        width: Some(i64::from(width)),
        height: Some(i64::from(height)),
        ..Overrides::default()
    };
    let base = from_table(&table, Path::new("."))?;
    for frame in 0..frames {
        let angle = std::f64::consts::TAU * f64::from(frame) / f64::from(frames);
        let position = [5.0 * angle.cos(), 5.0, 5.0 * angle.sin()];
        if by_light {
            // The scene read once, its light moved (`Scene::with_light`).
            let mut scene = base.with_light(0, Some(position), None)?;
            size.apply(&mut scene)?;
            let rendered = render(&device, &scene, &RenderRequest::gpu(Shading::Phong))?;
            let pixels = &rendered.image.pixels;
            mean = pixels.iter().map(|p| f64::from(p[0])).sum::<f64>() / pixels.len() as f64;
            continue;
        }
        let light = table["lights"][0]
            .as_table()
            .ok_or("the scene has a light")?;
        let mut light = light.clone();
        light.insert(
            "position".into(),
            toml::Value::Array(position.iter().map(|&v| toml::Value::Float(v)).collect()),
        );
        if let Some(toml::Value::Array(lights)) = table.get_mut("lights") {
            lights[0] = toml::Value::Table(light);
        }
        let mut scene = from_table(&table, Path::new("."))?;
        size.apply(&mut scene)?;
        let rendered = render(&device, &scene, &RenderRequest::gpu(Shading::Phong))?;
        let pixels = &rendered.image.pixels;
        mean = pixels.iter().map(|p| f64::from(p[0])).sum::<f64>() / pixels.len() as f64;
    }
    let ms = started.elapsed().as_secs_f64() * 1e3;
    let cpu = cpu_ms() - cpu_started;
    println!("{{\"frames\": {frames}, \"wall_ms\": {ms}, \"cpu_ms\": {cpu}, \"mean\": {mean}}}");
    Ok(())
}
