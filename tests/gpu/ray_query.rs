//! The ray tracer's two engines (`--traversal bvh|query|auto`): each one
//! asked for is the one used, `auto` follows its rule, and the ray-query
//! engine holds `check`'s ray-tracing limits against the CPU twin on every
//! scene in `assets/` (the hard cases: tests/gpu/hard_cases.rs). On a device
//! without ray queries (Mesa 22.3's lavapipe) the query engine's tests say
//! so on stderr and check only that it is refused with a reason.

use crate::common;

use std::path::PathBuf;

use crate::common::render_gpu;
use common::cli::shadelab;
use common::*;
use shadelab::check::{check, CheckThresholds};
use shadelab::gpu::raytrace::engine_for;
use shadelab::scene::{self, Traversal};
use shadelab::shading::Shading;

#[test]
fn each_engine_asked_for_is_the_engine_used() {
    let context = gpu();
    let mut small = scene::default_scene();
    (small.image.width, small.image.height) = (64, 48);
    for engine in engines(&context) {
        let r = render_gpu(&context, &with_engine(&small, engine), Shading::Raytrace).unwrap();
        assert_eq!(r.traversal, Some(engine));
    }
    // `auto` is the device's rule, the same every time; on lavapipe (a CPU
    // device) the compute BVH, the faster engine there.
    let auto = engine_for(Traversal::Auto, &context.info).unwrap();
    for _ in 0..2 {
        let r = render_gpu(
            &context,
            &with_engine(&small, Traversal::Auto),
            Shading::Raytrace,
        );
        assert_eq!(r.unwrap().traversal, Some(auto));
    }
    if context.info.is_lavapipe {
        assert_eq!(auto, Traversal::Bvh);
    }
    // The raster modes trace nothing and name no engine.
    let r = render_gpu(&context, &small, Shading::Phong).unwrap();
    assert_eq!(r.traversal, None);
}

#[test]
fn the_query_engine_holds_checks_limits_on_every_asset() {
    let context = gpu();
    if !engines(&context).contains(&Traversal::Query) {
        // `engines` said why on stderr.
        let refused = engine_for(Traversal::Query, &context.info).unwrap_err();
        assert!(refused.to_string().contains("lacks"), "{refused}");
        return;
    }
    let scenes = asset_scenes();
    assert!(scenes.len() >= 6, "assets/ lost scenes: {}", scenes.len());
    let limits = CheckThresholds::for_shading(Shading::Raytrace);
    for (name, scene) in scenes {
        let s = with_engine(&scene, Traversal::Query);
        let o = check(
            &crate::common::device(&context),
            &s,
            &s,
            Shading::Raytrace,
            &limits,
        )
        .unwrap();
        assert_eq!(o.traversal, Some(Traversal::Query));
        assert!(o.passed(), "{name}: {:?}", o.judgement.failures);
    }
}

/// Each mesh is a bottom level of its own, its corners found by its first
/// record (`build` in src/gpu/raytrace/accel.rs); the assets have one mesh each, where every
/// mesh starts at record 0. Three copies of rt-mesh's cube, side by side:
/// a second or third mesh read from the wrong records would be drawn as
/// another cube's faces, or none, and miss `check`'s limits.
#[test]
fn the_query_engine_finds_every_mesh_of_a_scene_with_several() {
    let context = gpu();
    if !engines(&context).contains(&Traversal::Query) {
        return; // `engines` said why on stderr
    }
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/rt-mesh.toml");
    let mut scene = scene::load(&path).unwrap();
    let cube = scene
        .objects
        .iter()
        .find(|o| matches!(o.shape, scene::Shape::Mesh(_)))
        .unwrap()
        .clone();
    for shift in [-1.6, 1.6] {
        let mut copy = cube.clone();
        if let scene::Shape::Mesh(mesh) = &mut copy.shape {
            for p in &mut mesh.positions {
                p.z += shift;
            }
        }
        scene.objects.push(copy);
    }
    let s = with_engine(&scene, Traversal::Query);
    let limits = CheckThresholds::for_shading(Shading::Raytrace);
    let o = check(
        &crate::common::device(&context),
        &s,
        &s,
        Shading::Raytrace,
        &limits,
    )
    .unwrap();
    assert_eq!(o.traversal, Some(Traversal::Query));
    assert!(o.passed(), "{:?}", o.judgement.failures);
}

#[test]
fn the_command_line_names_the_engine_and_refuses_an_unknown_one() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "render",
            "--shading",
            "raytrace",
            "--traversal",
            "bvh",
            "--width",
            "32",
            "--height",
            "24",
            "--out",
            "a.png",
            "--json",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(json["traversal"], "bvh");

    let run = shadelab(
        dir.path(),
        &["render", "--traversal", "rtx", "--out", "b.png"],
    );
    assert_eq!(run.code, 2);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(
        run.stderr.contains("expected auto, bvh or query"),
        "{}",
        run.stderr
    );
    assert!(!dir.path().join("b.png").exists());

    // A raster render has no engine to name.
    let run = shadelab(
        dir.path(),
        &[
            "render", "--width", "32", "--height", "24", "--out", "c.png", "--json",
        ],
    );
    let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert!(json["traversal"].is_null());
}

/// A lighting hook runs on the compute BVH only (naga checks a hook's
/// module and cannot read ray queries): asked for with `query`, one line
/// and exit status 2, nothing written; with `bvh` it renders.
#[test]
fn a_lighting_hook_with_the_query_engine_is_refused_in_one_line() {
    let context = gpu();
    if !engines(&context).contains(&Traversal::Query) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let hook = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/lighting/phong.glsl");
    let hook = hook.to_str().unwrap();
    let args = |engine: &'static str, out: &'static str| {
        [
            "render",
            "--shading",
            "raytrace",
            "--lighting",
            hook,
            "--traversal",
            engine,
            "--width",
            "32",
            "--height",
            "24",
            "--out",
            out,
        ]
    };
    let run = shadelab(dir.path(), &args("query", "q.png"));
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(run.stderr.contains("--traversal bvh"), "{}", run.stderr);
    assert!(!dir.path().join("q.png").exists());
    let run = shadelab(dir.path(), &args("bvh", "b.png"));
    assert_eq!(run.code, 0, "{}", run.stderr);
}
