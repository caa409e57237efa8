//! A device keeps the pipelines it has built (`check`, `compare` and
//! `bench` render the same variant many times), and a render reuses one
//! only when everything that went into it is the same: the mode, the
//! scene's constants, the colour target, the engine and the lighting hook.

use crate::common;

use std::path::Path;

use common::*;
use shadelab::gpu::raster::{self, ColorTarget};
use shadelab::scene::{default_scene, LightingHook, Scene};
use shadelab::shading::RasterMode;

fn small() -> Scene {
    let mut s = default_scene();
    s.image.width = 48;
    s.image.height = 36;
    s
}

fn with_hook(mut s: Scene, file: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/lighting")
        .join(file);
    s.lighting_hook = Some(LightingHook::load(&path).unwrap().into());
    s
}

#[test]
fn a_pipeline_is_reused_only_where_everything_that_built_it_matches() {
    let context = gpu();
    let kept = || context.pipelines_kept();
    let trace = |s: &Scene| crate::common::trace_gpu_counting(&context, s, false).unwrap();
    let draw = |s: &Scene, mode, target| raster::render(&context, s, mode, target).unwrap();

    let scene = small();
    let first = trace(&scene);
    assert_eq!(kept(), 1);
    let again = trace(&scene);
    assert_eq!(kept(), 1, "the same scene reuses its pipeline");
    assert_eq!(again.image.pixels, first.image.pixels);

    // Another hook is another module: never the built-in formula's pipeline.
    let hooked = trace(&with_hook(small(), "blinn-phong.glsl"));
    assert_eq!(kept(), 2);
    assert_ne!(
        hooked.image.pixels, first.image.pixels,
        "the hook is in use"
    );

    // Other constants: a scene without shadows.
    let mut shadowless = small();
    shadowless.render.shadows = false;
    let plain = trace(&shadowless);
    assert_eq!(kept(), 3);
    assert_ne!(plain.image.pixels, first.image.pixels);

    // Counting rays is a constant of its own.
    crate::common::trace_gpu_counting(&context, &scene, true).unwrap();
    assert_eq!(kept(), 4);

    // The raster modes: one pipeline per mode and target.
    let phong = draw(&scene, RasterMode::Phong, ColorTarget::Float32);
    assert_eq!(kept(), 5);
    draw(&scene, RasterMode::Phong, ColorTarget::Srgb8);
    assert_eq!(kept(), 6);
    draw(&scene, RasterMode::Flat, ColorTarget::Float32);
    assert_eq!(kept(), 7);
    let phong_again = draw(&scene, RasterMode::Phong, ColorTarget::Float32);
    assert_eq!(kept(), 7);
    assert_eq!(phong_again.image.pixels, phong.image.pixels);
    let hooked_phong = draw(
        &with_hook(small(), "blinn-phong.glsl"),
        RasterMode::Phong,
        ColorTarget::Float32,
    );
    assert_eq!(kept(), 8);
    assert_ne!(hooked_phong.image.pixels, phong.image.pixels);
}
