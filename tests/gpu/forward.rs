//! Forward ray tracing on the GPU (`shaders/forward.comp.glsl`) held to
//! its f64 twin photon by photon, to the closed sphere's exact answer, and
//! to its promise of the same bits on every run, thread count and split of
//! the photons; and the command line's refusals.

use common::cli::{assert_one_line_refusal, render_mean, shadelab, shadelab_with};
use common::closed_sphere::{closed_sphere, expected};
use shadelab::film_sums::RenderPart;
use shadelab::gpu::raytrace::forward;
use shadelab::scene::Scene;
use shadelab::work_counter::WorkCounter;

use crate::common;

fn diffuse_box(width: u32, height: u32) -> Scene {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/diffuse-box.toml");
    let mut scene = shadelab::scene::load(std::path::Path::new(path)).unwrap();
    scene.image.width = width;
    scene.image.height = height;
    scene
}

/// The GPU and the twin trace the same photons (the same hash, the same
/// light shares, the same events), so their images differ only where f32
/// rounding sends a photon another way: a splat in the neighbouring pixel,
/// a bounce in another direction. On the diffuse box (2 bounces, 2^20
/// photons, 80 x 60) the counts are equal, the images' means agree to
/// 1e-6 (measured 4e-9, f32 splats against f64), and 99% of the pixels to
/// 1e-3 relative (measured: 6 of 4800 apart). A wrong splat factor, a
/// light picked differently or an event chosen by another number moves
/// the mean by far more than 1e-6.
#[test]
fn the_gpu_traces_the_twins_photons() {
    let context = common::gpu();
    let mut scene = diffuse_box(80, 60);
    scene.render.photons = 1 << 20;
    let job = RenderPart::all(scene.render.photons);
    let gpu = forward::render(&context, &scene, &job, &WorkCounter::default()).unwrap();
    let cpu = crate::common::forward_cpu(&scene, scene.render.photons).unwrap();
    assert_eq!(gpu.stats.emitted, cpu.stats.emitted);
    let (g, c) = (gpu.film.image(), cpu.image());
    let mean = |i: &shadelab::LinearImage| {
        i.pixels
            .iter()
            .map(|p| f64::from(p[0] + p[1] + p[2]))
            .sum::<f64>()
            / i.pixels.len() as f64
    };
    let (mg, mc) = (mean(&g), mean(&c));
    eprintln!(
        "means: gpu {mg}, twin {mc}; stats gpu {:?} twin {:?}",
        gpu.stats, cpu.stats
    );
    assert!(((mg - mc) / mc).abs() < 1e-6, "means {mg} and {mc}");
    let apart = g
        .pixels
        .iter()
        .zip(&c.pixels)
        .filter(|(a, b)| (0..3).any(|k| (a[k] - b[k]).abs() > 1e-3 * b[k].abs().max(1e-3)))
        .count();
    eprintln!("{apart} of {} pixels apart", g.pixels.len());
    assert!(apart * 100 <= g.pixels.len(), "{apart} pixels apart");
    // The counts differ only by the photons rounding sent elsewhere.
    let close = |a: u64, b: u64| a.abs_diff(b) * 1000 <= b;
    assert!(
        close(gpu.stats.seen, cpu.stats.seen),
        "{:?} {:?}",
        gpu.stats,
        cpu.stats
    );
    assert!(close(gpu.stats.splats, cpu.stats.splats));
}

/// In the closed sphere every pixel's expectation is the series (see
/// `common::closed_sphere`): the GPU's image mean lies within 5 standard
/// errors of it, with and without bounces.
#[test]
fn gpu_photons_in_a_closed_sphere_converge_to_the_series() {
    let context = common::gpu();
    for bounces in [0, 2] {
        let want = expected(bounces);
        let scene = closed_sphere(bounces);
        let job = RenderPart::all(1 << 20);
        let out = forward::render(&context, &scene, &job, &WorkCounter::default()).unwrap();
        let values: Vec<f64> = out
            .film
            .image()
            .pixels
            .iter()
            .map(|p| f64::from(p[0]))
            .collect();
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let error = (var / n).sqrt();
        eprintln!("{bounces} bounces: mean {mean}, want {want}, error {error}");
        assert!(
            (mean - want).abs() < 5.0 * error,
            "{bounces} bounces: {mean} against {want}"
        );
    }
}

/// The film's sums are integers: the same bits on a repeat, and a render
/// split into four parts of its photons (as shards are) adds up to the
/// whole one, bit for bit; the twin's too, at 1 thread and at 2.
#[test]
fn films_are_the_same_bits_however_the_photons_are_split() {
    let context = common::gpu();
    let mut scene = diffuse_box(40, 30);
    scene.render.photons = 300_001;
    let total = scene.render.photons;
    let counter = WorkCounter::default();
    let whole = forward::render(&context, &scene, &RenderPart::all(total), &counter).unwrap();
    let again = forward::render(&context, &scene, &RenderPart::all(total), &counter).unwrap();
    assert_eq!(whole.film, again.film, "a repeat");
    let cuts = [0, 1, 77_777, 200_000, total];
    let mut sum = shadelab::film_sums::FilmSums::zero(40, 30);
    for part in cuts.windows(2) {
        let job = RenderPart {
            total,
            range: part[0]..part[1],
            deadline: None,
            error: None,
            cancel: None,
        };
        let out = forward::render(&context, &scene, &job, &counter).unwrap();
        sum.add(&out.film).unwrap();
    }
    assert_eq!(sum, whole.film, "four parts added");
    let twin_at = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| crate::common::forward_cpu(&scene, total).unwrap().film)
    };
    assert_eq!(twin_at(1), twin_at(2), "the twin at 1 and 2 threads");
}

/// lavapipe at 1 thread and at 2 writes the same image, bit for bit: the
/// forward tracer's (integer sums) and the backward tracer's with bounces
/// (each pixel's paths are its own, keyed by pixel and sample).
#[test]
fn the_image_is_the_same_at_any_lavapipe_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    for (mode, count, amount) in [
        ("forward", "--photons", "200000"),
        ("raytrace", "--samples", "8"),
    ] {
        let mut images = Vec::new();
        for threads in ["1", "2"] {
            let out = format!("box-{mode}-{threads}.exr");
            let args = [
                "render",
                concat!(env!("CARGO_MANIFEST_DIR"), "/assets/diffuse-box.toml"),
                "--shading",
                mode,
                count,
                amount,
                "--bounces",
                "2",
                "--width",
                "64",
                "--height",
                "48",
                "--out",
                &out,
            ];
            let run = shadelab_with(dir.path(), &args, &[("LP_NUM_THREADS", threads)]);
            assert_eq!(run.code, 0, "{}", run.stderr);
            images.push(std::fs::read(dir.path().join(&out)).unwrap());
        }
        assert!(images[0] == images[1], "{mode}: the images differ");
    }
}

/// What forward tracing cannot do is said in one line, exit 2; what it
/// cannot see (a mirror and glass, in the default scene) is a warning.
#[test]
fn bad_forward_input_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let dark = dir.path().join("dark.toml");
    std::fs::write(
        &dark,
        "[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, -1]\n\n[materials.m]\ncolor = [1, 1, 1]\n\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, -3]\nradius = 1\nmaterial = \"m\"\n",
    )
    .unwrap();
    let dark = dark.display().to_string();
    let hook = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/lighting/phong.glsl").to_string();
    let cases: [(&[&str], &str); 5] = [
        (
            &["render", "--shading", "forward", "--photons", "0"],
            "--photons 0 is out of range",
        ),
        (
            &["render", "--shading", "forward", "--photons", "5000000000"],
            "numbered in 32 bits",
        ),
        (
            &["render", &dark, "--shading", "forward"],
            "the scene has no light",
        ),
        (
            &["render", &dark, "--shading", "forward", "--backend", "cpu"],
            "the scene has no light",
        ),
        (
            &["render", "--shading", "forward", "--lighting", &hook],
            "a lighting hook replaces",
        ),
    ];
    for (args, expect) in cases {
        let run = shadelab(dir.path(), args);
        assert_one_line_refusal(&run, args, expect);
    }
    let args = [
        "render",
        "--shading",
        "forward",
        "--photons",
        "20000",
        "--width",
        "64",
        "--height",
        "48",
    ];
    let run = shadelab(dir.path(), &args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stderr.contains("cannot see through mirrors or glass")
            && run.stderr.contains("4 (mirror), 5 (glass)"),
        "{}",
        run.stderr
    );
    // A batch says it too, per scene that has them.
    let batch = [
        "render",
        "--shading",
        "phong,forward",
        "--photons",
        "20000",
        "--width",
        "64",
        "--height",
        "48",
        "--out-dir",
        "batch",
    ];
    let run = shadelab(dir.path(), &batch);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("default: forward ray tracing cannot see through mirrors or glass"),
        "{}",
        run.stderr
    );
}

/// `render --shard I/N` four times and `--merge` make the image one render
/// makes, byte for byte, whatever order the films come in; an incomplete
/// set or films of another render are refused in one line.
#[test]
fn four_shards_merge_into_the_unsharded_image() {
    let dir = tempfile::tempdir().unwrap();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/diffuse-box.toml");
    let common = [
        "--shading",
        "forward",
        "--photons",
        "100003",
        "--width",
        "48",
        "--height",
        "36",
    ];
    let render = |extra: &[&str]| {
        let mut args = vec!["render", scene];
        args.extend_from_slice(&common);
        args.extend_from_slice(extra);
        let run = shadelab(dir.path(), &args);
        assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
    };
    for i in 1..=4 {
        render(&["--shard", &format!("{i}/4"), "--out", &format!("p{i}.film")]);
    }
    render(&["--out", "whole.exr"]);
    let merge = [
        "render",
        "--merge",
        "p3.film",
        "p1.film",
        "p4.film",
        "p2.film",
        "--out",
        "merged.exr",
    ];
    let run = shadelab(dir.path(), &merge);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout.contains("photons: 100003 emitted"),
        "{}",
        run.stdout
    );
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert!(
        read("merged.exr") == read("whole.exr"),
        "merged and whole images differ"
    );

    let incomplete = ["render", "--merge", "p1.film", "p2.film", "--out", "x.exr"];
    assert_one_line_refusal(
        &shadelab(dir.path(), &incomplete),
        &incomplete,
        "shards 1/4 to 4/4",
    );
    let twice = [
        "render", "--merge", "p1.film", "p1.film", "p3.film", "p4.film", "--out", "x.exr",
    ];
    assert_one_line_refusal(&shadelab(dir.path(), &twice), &twice, "each once");
    render(&["--bounces", "1", "--shard", "2/4", "--out", "other.film"]);
    let mixed = [
        "render",
        "--merge",
        "p1.film",
        "other.film",
        "p3.film",
        "p4.film",
        "--out",
        "x.exr",
    ];
    assert_one_line_refusal(&shadelab(dir.path(), &mixed), &mixed, "different renders");
    let not_film = ["render", "--merge", "whole.exr", "--out", "x.exr"];
    assert_one_line_refusal(
        &shadelab(dir.path(), &not_film),
        &not_film,
        "not a shadelab film",
    );
    assert!(
        !dir.path().join("x.exr").exists(),
        "no image from a refused merge"
    );
}

/// `compare` puts samples and photons on one front against a reference
/// of 1024 samples a pixel, made once and kept in the cache folder: each
/// 4x the samples or photons roughly halves the error against it (0.5
/// promised; 0.3 to 0.7 allows a 40 x 30 image's noise), Whitted misses
/// the secondary light, and a second run reads the kept reference (shown
/// by blackening the kept file: the second report's reference is black).
#[test]
fn compare_measures_samples_and_photons_against_a_kept_reference() {
    let dir = tempfile::tempdir().unwrap();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/diffuse-box.toml");
    let variants = "raytrace:bounces=2,samples=4;raytrace:bounces=2,samples=16;forward:bounces=2,photons=16384;forward:bounces=2,photons=65536;raytrace:bounces=0";
    let run_compare = |out: &str| {
        let args = [
            "compare",
            scene,
            "--width",
            "40",
            "--height",
            "30",
            "--runs",
            "1",
            "--variants",
            variants,
            "--out",
            out,
            "-q",
        ];
        let run = shadelab(dir.path(), &args);
        assert_eq!(run.code, 0, "{}", run.stderr);
        let text = std::fs::read_to_string(dir.path().join(out).join("report.json")).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()
    };
    let report = run_compare("first");
    assert!(
        report["reference"]
            .as_str()
            .unwrap()
            .contains("1024 samples"),
        "{}",
        report["reference"]
    );
    let rmse = |name: &str| {
        report["variants"]
            .as_array()
            .unwrap()
            .iter()
            .find(|v| v["name"] == name)
            .unwrap_or_else(|| panic!("{name}"))["model_error"]["rmse"]
            .as_f64()
            .unwrap()
    };
    let samples = rmse("raytrace:samples=16,bounces=2") / rmse("raytrace:samples=4,bounces=2");
    let photons = rmse("forward:bounces=2,photons=65536") / rmse("forward:bounces=2,photons=16384");
    eprintln!("4x samples: {samples:.3} of the error; 4x photons: {photons:.3}");
    for ratio in [samples, photons] {
        assert!((0.3..0.7).contains(&ratio), "{ratio}");
    }
    assert!(rmse("raytrace:bounces=0") > 2.0 * rmse("forward:bounces=2,photons=65536"));

    let kept: Vec<_> = std::fs::read_dir(dir.path().join("cache/references"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(kept.len(), 1, "{kept:?}");
    let black = shadelab::LinearImage::new(40, 30, [0.0; 3]);
    shadelab::output::write_image(&black, &kept[0]).unwrap();
    run_compare("second");
    let second = shadelab::output::read_image(&dir.path().join("second/reference.png")).unwrap();
    assert!(
        second.pixels.iter().flatten().all(|&v| v == 0.0),
        "the kept reference was read"
    );
}

/// `--time` stops tracing at its budget and scales the image to the
/// photons traced: its mean is the full render's (measured within 0.5%;
/// 3% allows the noise of the few photons a short budget traces on the
/// CPU), where an unscaled image would be darker by the share of photons
/// left untraced (here over 99%). On both backends; a bad budget is
/// refused.
#[test]
fn a_time_budget_gives_the_estimate_of_the_photons_traced() {
    let dir = tempfile::tempdir().unwrap();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/diffuse-box.toml");
    let size = ["--width", "40", "--height", "30"];
    let mean_of = |extra: &[&str], out: &str| {
        let mut args = vec!["render", scene, "--shading", "forward", "--out", out];
        args.extend_from_slice(&size);
        args.extend_from_slice(extra);
        render_mean(dir.path(), &args, out)
    };
    let (full, _) = mean_of(&["--photons", "2000000"], "full.exr");
    for backend in ["gpu", "cpu"] {
        let args = [
            "--photons",
            "4000000000",
            "--time",
            "0.5",
            "--backend",
            backend,
        ];
        let (budget, stderr) = mean_of(&args, &format!("budget-{backend}.exr"));
        assert!(stderr.contains("stopped after"), "{stderr}");
        eprintln!("{backend}: full {full}, budget {budget}");
        assert!(
            ((budget - full) / full).abs() < 0.03,
            "{backend}: {budget} against {full}"
        );
    }
    let bad = ["render", "--shading", "forward", "--time", "0"];
    assert_one_line_refusal(&shadelab(dir.path(), &bad), &bad, "--time 0 is invalid");
    let other = ["render", "--shading", "raytrace", "--time", "1"];
    assert_one_line_refusal(&shadelab(dir.path(), &other), &other, "--bounces 1 or more");
}
