//! `compare` on small scenes: every variant with both errors and its
//! timings; implementation errors within `check`'s FLIP limit; model error
//! falling with tessellation and depth; Phong beating Gouraud beating flat;
//! shards that merge into the unsharded report.

use crate::common;

use common::*;
use glam::DVec3;
use shadelab::compare::report::{Metric, ReferenceChoice};
use shadelab::compare::run::{merge, run, CompareOptions};
use shadelab::compare::{Report, Variant};
use shadelab::scene::{Material, Object, Scene, Shape};

fn variants(list: &[&str]) -> Vec<Variant> {
    list.iter().map(|v| v.parse().unwrap()).collect()
}

/// A glossy sphere alone: no shadows or reflections, so the raster modes'
/// model error is their shading and tessellation alone.
fn glossy_sphere() -> Scene {
    let mut s = scene(96, 72, 30.0);
    s.materials[0].ks = 0.6;
    s.materials[0].p = 40.0;
    s.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::ZERO,
            radius: 2.0,
            segments: 32,
        },
        material: 0,
    });
    s
}

/// A mirror sphere beside a lit sphere: depth matters.
fn mirror_pair() -> Scene {
    let mut s = glossy_sphere();
    s.materials.push(Material {
        name: "mirror".into(),
        kr: 0.8,
        kd: 0.1,
        ..s.materials[0].clone()
    });
    s.objects[0].shape = Shape::Sphere {
        center: DVec3::new(-1.2, 0.0, 0.0),
        radius: 1.0,
        segments: 32,
    };
    s.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::new(1.2, 0.0, 0.0),
            radius: 1.0,
            segments: 32,
        },
        material: 1,
    });
    s
}

fn compare(
    scene: &Scene,
    list: &[Variant],
    shard: Option<(usize, usize)>,
) -> (Report, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let options = CompareOptions {
        runs: 1,
        shard,
        reference: ReferenceChoice::Global,
        metric: Metric::Rmse,
        budget: None,
        skip: Default::default(),
    };
    let report = run(
        &crate::common::device(&gpu()),
        scene,
        "test",
        list,
        &options,
        dir.path(),
        |_, _, _| {},
    )
    .unwrap();
    (report, dir)
}

fn rmse(report: &Report, name: &str) -> f64 {
    report
        .variants
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("{name} missing"))
        .model_error
        .rmse
}

const RASTER: [&str; 9] = [
    "flat:segments=8",
    "flat:segments=32",
    "flat:segments=128",
    "gouraud:segments=8",
    "gouraud:segments=32",
    "gouraud:segments=128",
    "phong:segments=8",
    "phong:segments=32",
    "phong:segments=128",
];

#[test]
fn raster_variants_are_measured_and_ordered_as_the_models_predict() {
    let (report, dir) = compare(&glossy_sphere(), &variants(&RASTER), None);
    assert_eq!(report.variants.len(), RASTER.len());
    for v in &report.variants {
        assert!(
            v.timing.gpu_ms > 0.0 && v.timing.frame_ms >= v.timing.gpu_ms,
            "{}: {:?}",
            v.name,
            v.timing
        );
        // check's whole-image FLIP limit: implementation errors are tiny.
        assert!(
            v.implementation_error.flip_mean <= 1e-3,
            "{}: {:?}",
            v.name,
            v.implementation_error
        );
        assert!(v.model_error.rmse.is_finite() && v.model_error.rmse > 0.0);
        assert!(dir.path().join(&v.image).is_file() && dir.path().join(&v.heatmap).is_file());
    }
    // Finer tessellation never makes the model worse; 1e-4 absorbs f32
    // noise at RMSEs of ~1e-2.
    for mode in ["flat", "gouraud", "phong"] {
        let e: Vec<f64> = [8, 32, 128]
            .iter()
            .map(|n| rmse(&report, &format!("{mode}:segments={n}")))
            .collect();
        assert!(e[0] + 1e-4 >= e[1] && e[1] + 1e-4 >= e[2], "{mode}: {e:?}");
        assert!(e[0] > e[2], "{mode}: tessellation must matter: {e:?}");
    }
    // At equal tessellation on a glossy sphere: Phong < Gouraud < flat.
    for n in [8, 32] {
        let (f, g, p) = (
            rmse(&report, &format!("flat:segments={n}")),
            rmse(&report, &format!("gouraud:segments={n}")),
            rmse(&report, &format!("phong:segments={n}")),
        );
        assert!(
            p < g && g < f,
            "segments={n}: phong {p}, gouraud {g}, flat {f}"
        );
    }
    assert!(report.variants.iter().any(|v| v.pareto));
}

#[test]
fn deeper_ray_tracing_approaches_the_reference() {
    let list = variants(&[
        "raytrace:depth=0,cutoff=0",
        "raytrace:depth=1,cutoff=0",
        "raytrace:depth=3,cutoff=0",
    ]);
    let (report, _dir) = compare(&mirror_pair(), &list, None);
    let e: Vec<f64> = report.variants.iter().map(|v| v.model_error.rmse).collect();
    assert!(e[0] >= e[1] && e[1] + 1e-4 >= e[2], "{e:?}");
    assert!(e[0] > 2.0 * e[2], "the mirror must matter: {e:?}");
    for v in &report.variants {
        assert!(
            v.implementation_error.flip_mean <= 1e-3,
            "{}: {:?}",
            v.name,
            v.implementation_error
        );
    }
}

#[test]
fn shards_merge_into_the_unsharded_report() {
    let list = variants(&RASTER[..5]);
    let scene = glossy_sphere();
    let (whole, _a) = compare(&scene, &list, None);
    let (one, _b) = compare(&scene, &list, Some((1, 2)));
    let (two, _c) = compare(&scene, &list, Some((2, 2)));
    assert_eq!(one.variants.len() + two.variants.len(), list.len());
    // Given out of order on purpose: merge sorts by shard index.
    let merged = merge(vec![two, one]).unwrap();
    assert_eq!(merged.shard, None);
    assert_eq!(merged.variants.len(), whole.variants.len());
    for (m, w) in merged.variants.iter().zip(&whole.variants) {
        // Every figure but the timings (and the Pareto flag, which rests on
        // them) is deterministic.
        assert_eq!(m.name, w.name);
        assert_eq!(m.implementation_error, w.implementation_error, "{}", m.name);
        assert_eq!(m.model_error, w.model_error, "{}", m.name);
    }
    let (lone, _d) = compare(&scene, &list, Some((1, 2)));
    assert!(
        merge(vec![lone]).is_err(),
        "one shard of two is not a whole report"
    );
}

/// The default scene at a size a test can afford.
fn small_default_scene() -> Scene {
    let mut s = shadelab::scene::default_scene();
    s.image.width = 160;
    s.image.height = 120;
    s
}

#[test]
fn the_local_error_falls_with_every_doubling_of_the_segments() {
    // On the default scene the global error of every raster variant sits
    // near 0.1 (shadows and reflections the raster modes lack); against
    // the local reference the tessellation sweep shows.
    let list = [8, 16, 32, 64, 128, 256].map(|n| format!("phong:segments={n}"));
    let names: Vec<&str> = list.iter().map(String::as_str).collect();
    let (report, _dir) = compare(&small_default_scene(), &variants(&names), None);
    let local: Vec<f64> = report
        .variants
        .iter()
        .map(|v| v.local_error.expect("a local error").rmse)
        .collect();
    for pair in local.windows(2) {
        assert!(
            pair[1] < pair[0],
            "local RMSE by segments 8..256: {local:?}"
        );
    }
    let global: Vec<f64> = report.variants.iter().map(|v| v.model_error.rmse).collect();
    assert!(
        local[5] < global[5] / 2.0,
        "the local reference must be the closer one for Phong: {local:?} vs {global:?}"
    );
}

#[test]
fn hook_variants_get_both_errors_and_differ_from_the_built_in_formula() {
    let hook = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/lighting/blinn-phong.glsl"
    );
    let list = [
        "phong".to_string(),
        format!("phong:lighting={hook}"),
        "raytrace".to_string(),
        format!("raytrace:lighting={hook}"),
    ];
    let names: Vec<&str> = list.iter().map(String::as_str).collect();
    let (report, _dir) = compare(&glossy_sphere(), &variants(&names), None);
    for v in &report.variants {
        let local = v.local_error.expect("a local error");
        assert!(
            local.rmse.is_finite() && v.model_error.rmse.is_finite(),
            "{}",
            v.name
        );
    }
    let local = |i: usize| report.variants[i].local_error.unwrap().rmse;
    // The built-in formula converges to the local reference; the
    // Blinn-Phong hook is another formula, so it is further from it.
    assert!(
        local(1) > local(0) * 2.0,
        "phong {} vs hook {}",
        local(0),
        local(1)
    );
    assert!(
        report.variants[3].model_error.rmse > report.variants[2].model_error.rmse * 2.0,
        "raytrace: {:?}",
        report
            .variants
            .iter()
            .map(|v| v.model_error.rmse)
            .collect::<Vec<_>>()
    );
}

#[test]
fn no_two_plot_labels_overlap_on_the_default_scenes_report() {
    let scene = small_default_scene();
    let mut list = shadelab::compare::default_variants(&scene);
    // And a name far wider than the list beside the plot.
    let hook = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/lighting/blinn-phong.glsl"
    );
    list.push(
        format!("phong:segments=256,lighting={hook}")
            .parse()
            .unwrap(),
    );
    let (report, _dir) = compare(&scene, &list, None);
    let boxes = shadelab::compare::present::plot::label_boxes(&report).unwrap();
    // Every point's number and every line of the list beside the plot.
    assert!(boxes.len() > report.variants.len(), "{} boxes", boxes.len());
    use shadelab::compare::present::plot::{HEIGHT, WIDTH};
    for (i, a) in boxes.iter().enumerate() {
        assert!(
            a.left >= 0 && a.top >= 0 && a.right <= WIDTH as i32 && a.bottom <= HEIGHT as i32,
            "{a:?} leaves the image"
        );
        for b in &boxes[i + 1..] {
            assert!(!a.intersects(b), "{a:?} overlaps {b:?}");
        }
    }
}
