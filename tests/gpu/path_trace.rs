//! Secondary illumination (`render.bounces`, docs/lighting-model.md,
//! "Secondary illumination") held to an answer worked out by hand, on the
//! GPU and on the CPU twin, and the twins to each other: the closed
//! sphere of `common::closed_sphere`, whose every pixel is a series in
//! the albedo.

use crate::common;

use common::closed_sphere::{closed_sphere, expected, AMBIENT, KA};
use shadelab::scene::Scene;
use shadelab::shading::Shading;
use shadelab::LinearImage;

fn worst_relative_error(image: &LinearImage, want: f64) -> f64 {
    image
        .pixels
        .iter()
        .flat_map(|p| p.iter())
        .map(|&v| (f64::from(v) - want).abs() / want)
        .fold(0.0, f64::max)
}

fn cpu(scene: &Scene) -> LinearImage {
    crate::common::render_cpu(scene, Shading::Raytrace)
        .unwrap_or_else(|e| panic!("{e}"))
        .0
        .image
}

/// Every pixel, on both twins (the GPU with each engine it has), for 1 to
/// 3 bounces (no roulette yet): the
/// f64 twin within 1e-6 (its image is stored in f32, 6e-8 relative), the
/// GPU's f32 within 1e-5 (a few roundings of a handful of terms).
#[test]
fn a_light_inside_a_closed_sphere_matches_the_series() {
    let context = common::gpu();
    for bounces in 1..=3 {
        let scene = closed_sphere(bounces);
        let want = expected(bounces);
        let on_cpu = worst_relative_error(&cpu(&scene), want);
        assert!(
            on_cpu < 1e-6,
            "{bounces} bounces, CPU: {on_cpu:e} off {want}"
        );
        for engine in common::engines(&context) {
            let scene = common::with_engine(&scene, engine);
            let gpu = common::render(&context, &scene, Shading::Raytrace);
            let on_gpu = worst_relative_error(&gpu, want);
            assert!(
                on_gpu < 1e-5,
                "{bounces} bounces, GPU ({engine:?}): {on_gpu:e} off {want}"
            );
        }
    }
}

/// Past three bounces Russian roulette ends paths at random and divides
/// the survivors' weights by their chance: each pixel is no longer the
/// series, but its expectation is. The mean over the image's pixels is held
/// to 5 standard errors, measured from the pixels themselves; the pixels
/// must differ (the roulette ran) and the twins trace the same paths, so
/// their images agree pixel by pixel up to f32 rounding.
#[test]
fn russian_roulette_keeps_the_expectation() {
    let mut scene = closed_sphere(8);
    scene.image.width = 64;
    scene.image.height = 64;
    let want = expected(8);
    let image = cpu(&scene);
    let values: Vec<f64> = image.pixels.iter().map(|p| f64::from(p[0])).collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let standard_error = (variance / n).sqrt();
    assert!(variance > 0.0, "no pixel differs: the roulette never ran");
    assert!(
        (mean - want).abs() < 5.0 * standard_error,
        "mean {mean} against {want}, standard error {standard_error}"
    );
    let gpu = common::render(&common::gpu(), &scene, Shading::Raytrace);
    let worst = common::worst_difference(&image, &gpu);
    assert!(worst < 1e-4 * want, "GPU and CPU differ by {worst}");
}

/// Without bounces the tracer is Whitted's, ambient term and all: the
/// same sphere shows `ka Ia` more than the path tracer's first term, on
/// both twins.
#[test]
fn without_bounces_the_ambient_term_stays() {
    let scene = closed_sphere(0);
    let want = expected(0) + KA * AMBIENT;
    assert!(worst_relative_error(&cpu(&scene), want) < 1e-6);
    let gpu = common::render(&common::gpu(), &scene, Shading::Raytrace);
    assert!(worst_relative_error(&gpu, want) < 1e-5);
}

/// `--bounces` out of range is one line and exit status 2; in range it renders, and the
/// JSON says how many bounces made the image.
#[test]
fn the_command_line_takes_bounces_and_refuses_what_it_cannot_trace() {
    let dir = tempfile::tempdir().unwrap();
    let refusals: [(&[&str], &str); 2] = [
        (
            &[
                "render",
                "--shading",
                "raytrace",
                "--bounces",
                "65",
                "--out",
                "a.png",
            ],
            "--bounces 65 is out of range",
        ),
        (
            &["compare", "--variants", "raytrace:bounces=-1", "--out", "c"],
            "bounces=-1 is invalid",
        ),
    ];
    for (args, expect) in refusals {
        let run = common::cli::shadelab(dir.path(), args);
        common::cli::assert_one_line_refusal(&run, args, expect);
        assert!(!dir.path().join("a.png").exists());
    }
    let run = common::cli::shadelab(
        dir.path(),
        &[
            "render",
            "--shading",
            "raytrace",
            "--bounces",
            "2",
            "--width",
            "32",
            "--height",
            "24",
            "--out",
            "d.png",
            "--json",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(json["settings"]["bounces"], 2, "{}", run.stdout);
}
