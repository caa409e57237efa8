//! The ray tracer's module specialised (and inlined) before the driver
//! sees it (`gpu::specialise`) against the driver specialising it, pixel for pixel.
//!
//! A binary of its own, not a module of `tests/gpu/`: it points the cache
//! folder (`SHADELAB_CACHE_DIR`, which the library reads at every lookup)
//! at an empty folder of its own with `std::env::set_var`. In a process
//! shared with other tests that would race their threads' reads of the
//! environment, and their specialised modules would land in its folder
//! and in its count.

mod common;

use common::*;
use shadelab::gpu::raytrace;

/// Specialising the module before the driver (`gpu::specialise`: the
/// constants' values written in, the code they rule out removed) changes
/// no pixel against the driver specialising it: on the default scene
/// (reflection, refraction, listed objects and materials), a mesh big
/// enough for the 4-wide walk, the same with Blinn-Phong as a
/// lighting hook, and spheres alone with no shadows and no specular term.
/// Only dead code goes, and calls and locals are resolved (`Lowering`:
/// the binary walk's module inlined, the 4-wide walk's also in SSA form),
/// so the arithmetic is the same to the bit; a value written in wrongly (a
/// boolean inverted, a count off) changes the image.
#[test]
fn specialising_before_the_driver_changes_no_pixel() {
    // A cache folder of its own, or a module cached by an earlier run would
    // stand in for the code under test. The only test in this binary, so
    // no other thread reads the environment while it is set.
    let cache = tempfile::tempdir().unwrap();
    std::env::set_var("SHADELAB_CACHE_DIR", cache.path());
    use raytrace::TraceOptions;
    use shadelab::scene::LightingHook;
    let context = gpu();
    let mut default = shadelab::scene::default_scene();
    default.image.width = 96;
    default.image.height = 72;
    let mesh = mesh_sphere_scene();
    let mut hooked = mesh_sphere_scene();
    let hook = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/lighting/blinn-phong.glsl"
    );
    hooked.lighting_hook = Some(
        LightingHook::load(std::path::Path::new(hook))
            .unwrap()
            .into(),
    );
    let mut plain = plain_sphere_scene();
    plain.render.shadows = false;
    for (name, s) in [
        ("default", default),
        ("mesh", mesh),
        ("hook", hooked),
        ("plain", plain),
    ] {
        let trace = |driver_specialises| {
            let options = TraceOptions {
                driver_specialises,
                ..TraceOptions::default()
            };
            crate::common::trace_gpu(&context, &s, options)
                .unwrap_or_else(|e| panic!("{name}: {e}"))
                .image
        };
        let (ours, drivers) = (trace(false), trace(true));
        let differing = ours
            .pixels
            .iter()
            .zip(&drivers.pixels)
            .filter(|(a, b)| a.map(f32::to_bits) != b.map(f32::to_bits))
            .count();
        assert_eq!(differing, 0, "{name}: pixels that differ");
        // Traced again on a device of its own (the first keeps its
        // pipeline), the module comes from the cache folder: the same image.
        let from_cache = crate::common::trace_gpu(&gpu(), &s, raytrace::TraceOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .image;
        assert_eq!(from_cache.pixels, ours.pixels, "{name}: from the cache");
    }
    // Also what makes the comparison above mean something: had `spirv-opt`
    // not run, both sides would have been the driver's.
    let cached = std::fs::read_dir(cache.path().join("spirv"))
        .expect("specialised modules in the cache: is spirv-opt (package spirv-tools) installed?")
        .count();
    assert_eq!(cached, 4, "one specialised module per scene in the cache");
}
