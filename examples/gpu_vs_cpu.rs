//! The threshold-tuning tool: the measurements behind `check`'s limits
//! (`shadelab::check::CheckThresholds`), not an introduction to the library
//! (for that, see `examples/render_and_compare.rs`).
//!
//! Prints GPU-vs-CPU error figures for a scene (default: the built-in one)
//! in every raster mode: interior pixels (3x3 neighbourhood on one object)
//! and silhouette pixels separately.

use shadelab::render::{render, Device, RenderRequest};
use shadelab::shading::Shading;

fn main() {
    let scene = match std::env::args().nth(1) {
        Some(p) => shadelab::scene::load(std::path::Path::new(&p)).expect("scene loads"),
        None => shadelab::scene::default_scene(),
    };
    let device = Device::open(&shadelab::gpu::GpuOptions::from_env()).unwrap();
    for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
        let gpu = render(&device, &scene, &RenderRequest::gpu(shading)).unwrap();
        let cpu = render(&device, &scene, &RenderRequest::cpu(shading)).unwrap();
        let ids = cpu
            .coverage
            .as_ref()
            .expect("the CPU reference knows its pixels")
            .surface_ids
            .clone();
        let (w, h) = (scene.image.width as usize, scene.image.height as usize);
        let mut interior = (0.0f64, 0usize, 0.0f64);
        let mut edge = (0.0f64, 0usize, 0.0f64);
        let (mut over_1e2, mut over_1e1) = (0usize, 0usize);
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                let err = (0..3)
                    .map(|c| (gpu.image.pixels[i][c] as f64 - cpu.image.pixels[i][c] as f64).abs())
                    .fold(0.0, f64::max);
                let same = (y > 0 && y + 1 < h && x > 0 && x + 1 < w)
                    && (0..9).all(|k| ids[(y + k / 3 - 1) * w + x + k % 3 - 1] == ids[i]);
                if !same && err > 0.01 {
                    over_1e2 += 1;
                }
                if !same && err > 0.1 {
                    over_1e1 += 1;
                }
                let bucket = if same { &mut interior } else { &mut edge };
                bucket.0 = bucket.0.max(err);
                bucket.1 += 1;
                bucket.2 += err;
            }
        }
        println!(
            "{shading:8} interior: max {:.2e} mean {:.2e} ({} px)   edges: max {:.2e} mean {:.2e} ({} px, {} over 0.01, {} over 0.1)   cpu {:.0} ms",
            interior.0, interior.2 / interior.1 as f64, interior.1, edge.0, edge.2 / edge.1.max(1) as f64, edge.1, over_1e2, over_1e1, cpu.timings.total_ms
        );
    }
}
