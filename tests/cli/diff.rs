//! `shadelab diff` as scripts drive it, and FLIP against NVIDIA's reference
//! implementation. No GPU: every image is built here or read from
//! tests/data/flip/.

use crate::common;

use std::path::{Path, PathBuf};

use common::cli::{shadelab, Run};

use shadelab::output::{read_image, write_image};
use shadelab::LinearImage;

fn flip_data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/flip")
        .join(name)
}

fn json(run: &Run) -> serde_json::Value {
    serde_json::from_str(run.stdout.trim()).expect("--json prints one JSON object")
}

/// Exit status 2 and exactly one `shadelab: error:` line holding each of
/// `words`.
fn assert_bad_input(run: &Run, words: &[&str]) {
    assert_eq!(run.code, 2, "stderr: {}", run.stderr);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().filter(|l| !l.is_empty()).collect();
    assert_eq!(lines.len(), 1, "one error line, got: {}", run.stderr);
    assert!(lines[0].starts_with("shadelab: error: "), "{}", lines[0]);
    for word in words {
        assert!(lines[0].contains(word), "{word:?} in: {}", lines[0]);
    }
}

/// 4x2 of 0.25 grey, and the same with two pixels changed by amounts exact
/// in binary (so EXR holds them exactly).
fn known_pair() -> (LinearImage, LinearImage) {
    let expected = LinearImage::new(4, 2, [0.25; 3]);
    let mut actual = expected.clone();
    actual.set(0, 0, [0.75, 0.25, 0.25]); // +0.5 red
    actual.set(3, 1, [0.25, 0.125, 0.5]); // -0.125 green, +0.25 blue
    (expected, actual)
}

fn write_pair(dir: &Path, expected: &LinearImage, actual: &LinearImage, ext: &str) {
    write_image(expected, &dir.join(format!("expected.{ext}"))).unwrap();
    write_image(actual, &dir.join(format!("actual.{ext}"))).unwrap();
}

#[test]
fn identical_images_have_zero_error_and_exit_0() {
    let dir = tempfile::tempdir().unwrap();
    let mut image = LinearImage::new(20, 10, [0.1, 0.5, 0.9]);
    image.set(4, 4, [3.0, 0.0, 0.0]);
    write_pair(dir.path(), &image, &image, "exr");
    let run = shadelab(dir.path(), &["diff", "expected.exr", "actual.exr"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.is_empty(), "{}", run.stderr);
    assert_eq!(run.stdout.matches("PASS").count(), 3, "{}", run.stdout);
    assert!(!run.stdout.contains("FAIL"));

    let run = shadelab(
        dir.path(),
        &["diff", "expected.exr", "actual.exr", "--json"],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let j = json(&run);
    assert_eq!(j["pass"], true);
    for figure in ["max_abs", "mean_abs", "rmse", "p99_abs", "fraction_over"] {
        assert_eq!(j["stats"][figure], 0.0, "{figure}");
    }
    assert!(j["stats"]["psnr"].is_null(), "infinite PSNR is null");
    assert_eq!(j["flip"]["mean"], 0.0);
}

#[test]
fn known_difference_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let (expected, actual) = known_pair();
    write_pair(dir.path(), &expected, &actual, "exr");
    // Loose limits: this test is about the figures, not the verdict.
    let run = shadelab(
        dir.path(),
        &[
            "diff",
            "expected.exr",
            "actual.exr",
            "--json",
            "--flip-mean",
            "1",
            "--p99-abs",
            "1",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let stats = &json(&run)["stats"];
    let get = |k: &str| stats[k].as_f64().unwrap();
    // Channel differences 0.5, 0.125, 0.25 over 8 pixels x 3 channels:
    // MSE = (0.25 + 0.015625 + 0.0625) / 24 = 0.013671875.
    let mse: f64 = 0.328_125 / 24.0;
    assert!((get("rmse") - mse.sqrt()).abs() < 1e-6, "{}", get("rmse"));
    assert!((get("rmse") - 0.116_926_79).abs() < 1e-6);
    assert!((get("max_abs") - 0.5).abs() < 1e-6);
    // Pixel errors (max over channels): 0.5, 0.25 and six zeros.
    assert!((get("mean_abs") - 0.75 / 8.0).abs() < 1e-6);
    assert!((get("psnr") - 18.641_719).abs() < 1e-5, "{}", get("psnr"));
    assert_eq!(get("fraction_over"), 0.25, "2 of 8 pixels over 0.01");
    assert_eq!(stats["pixels"], 8);
}

#[test]
fn png_and_exr_mix() {
    // A PNG decodes to linear, so it compares with the EXR of the same
    // 8-bit values at zero error.
    let dir = tempfile::tempdir().unwrap();
    let mut image = LinearImage::new(8, 8, [0.0; 3]);
    for y in 0..8 {
        for x in 0..8 {
            image.set(x, y, [x as f32 / 7.0, y as f32 / 7.0, 0.5]);
        }
    }
    write_image(&image, &dir.path().join("a.png")).unwrap();
    let decoded = read_image(&dir.path().join("a.png")).unwrap();
    // Decoded to linear, not left in sRGB: within half an 8-bit sRGB step
    // of what was written, at most 0.0045 in linear (next to white). Left
    // in sRGB, the 0.5 channel alone would be 0.24 off.
    let worst = common::worst_difference(&image, &decoded);
    assert!(worst < 0.0046, "PNG round trip off by {worst}");
    write_image(&decoded, &dir.path().join("a.exr")).unwrap();
    let run = shadelab(dir.path(), &["diff", "a.png", "a.exr", "--json"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(json(&run)["stats"]["max_abs"], 0.0);
}

#[test]
fn mismatched_sizes_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&LinearImage::new(4, 3, [0.0; 3]), &dir.path().join("a.png")).unwrap();
    write_image(&LinearImage::new(3, 4, [0.0; 3]), &dir.path().join("b.exr")).unwrap();
    let run = shadelab(dir.path(), &["diff", "a.png", "b.exr"]);
    assert_bad_input(&run, &["a.png", "b.exr", "4x3", "3x4"]);
    assert!(run.stdout.is_empty());
}

#[test]
fn unreadable_input_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&LinearImage::new(4, 4, [0.0; 3]), &dir.path().join("a.png")).unwrap();
    std::fs::write(
        dir.path().join("corrupt.png"),
        b"\x89PNG\r\n\x1a\nnot really",
    )
    .unwrap();
    std::fs::write(dir.path().join("picture.jpg"), b"").unwrap();

    let run = shadelab(dir.path(), &["diff", "a.png", "missing.png"]);
    assert_bad_input(&run, &["missing.png"]);
    let run = shadelab(dir.path(), &["diff", "corrupt.png", "a.png"]);
    assert_bad_input(&run, &["corrupt.png"]);
    let run = shadelab(dir.path(), &["diff", "a.png", "picture.jpg"]);
    assert_bad_input(&run, &["picture.jpg", ".png or .exr"]);
    assert_eq!(shadelab(dir.path(), &["diff", "a.png"]).code, 2);
}

#[test]
fn bad_thresholds_and_heat_map_names_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let image = LinearImage::new(4, 4, [0.0; 3]);
    write_pair(dir.path(), &image, &image, "png");
    let pair = ["diff", "expected.png", "actual.png"];
    let with = |extra: &[&str]| {
        let mut args = pair.to_vec();
        args.extend_from_slice(extra);
        shadelab(dir.path(), &args)
    };
    assert_bad_input(&with(&["--flip-mean", "-1"]), &["--flip-mean"]);
    assert_bad_input(&with(&["--threshold", "ssim=3"]), &["ssim"]);
    assert_bad_input(&with(&["--threshold", "psnr=inf"]), &["psnr=inf"]);
    assert_bad_input(&with(&["--threshold", "max_abs=x"]), &["max_abs=x"]);
    assert_bad_input(&with(&["--heatmap", "heat.jpg"]), &["heat.jpg"]);
    std::fs::write(dir.path().join("blocker"), b"a file").unwrap();
    assert_bad_input(&with(&["--heatmap", "blocker/h.png"]), &["h.png"]);
    assert!(!dir.path().join("heat.jpg").exists());
}

#[test]
fn over_threshold_exits_1_naming_the_figure() {
    let dir = tempfile::tempdir().unwrap();
    let (expected, actual) = known_pair();
    write_pair(dir.path(), &expected, &actual, "exr");
    let pair = ["diff", "expected.exr", "actual.exr"];
    let with = |extra: &[&str]| {
        let mut args = pair.to_vec();
        args.extend_from_slice(extra);
        shadelab(dir.path(), &args)
    };

    // Only max_abs (0.5) is over its limit.
    let run = with(&["--max-abs", "0.4", "--flip-mean", "1", "--p99-abs", "1"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    assert!(
        lines[0].contains("max_abs 0.500000 exceeds the limit 0.4"),
        "{}",
        lines[0]
    );
    assert!(!lines[0].contains("flip_mean") && !lines[0].contains("p99_abs"));
    let table_row = run
        .stdout
        .lines()
        .find(|l| l.starts_with("max_abs") && l.contains("0.4"))
        .expect("a table row for max_abs");
    assert!(table_row.ends_with("FAIL"), "{table_row}");

    // The same through --threshold FIGURE=X; a bare X is flip_mean.
    let run = with(&[
        "--threshold",
        "max_abs=0.4",
        "--threshold",
        "1",
        "--p99-abs",
        "1",
    ]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("max_abs"), "{}", run.stderr);
    assert!(!run.stderr.contains("flip_mean"), "{}", run.stderr);
    // The per-figure flag wins over --threshold.
    let run = with(&[
        "--threshold",
        "max_abs=0.4",
        "--max-abs",
        "0.5",
        "--threshold",
        "1",
        "--p99-abs",
        "1",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);

    // Defaults: p99_abs (0.5 > 0.05) and flip_mean fail, max_abs passes.
    let run = with(&["--json"]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("p99_abs") && run.stderr.contains("flip_mean"));
    let j = json(&run);
    assert_eq!(j["pass"], false);
    let failures: Vec<&str> = j["failures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert_eq!(failures.len(), 2, "{failures:?}");
    assert!(failures[0].starts_with("flip_mean") && failures[1].starts_with("p99_abs"));
    // Every figure is there.
    for part in ["stats", "interior", "silhouette"] {
        for figure in [
            "max_abs",
            "mean_abs",
            "rmse",
            "psnr",
            "fraction_over",
            "p99_abs",
            "pixels",
            "non_finite",
        ] {
            // An empty part (this pair has no edges) has an infinite PSNR.
            let value = &j[part][figure];
            assert!(
                value.is_number() || (figure == "psnr" && value.is_null()),
                "{part}.{figure}: {j}"
            );
        }
    }
    for figure in ["mean", "median", "p99", "max", "pixels_per_degree"] {
        assert!(j["flip"][figure].is_number(), "flip.{figure}");
    }
    assert_eq!(j["thresholds"]["flip_mean"], 0.02);
    assert_eq!(j["thresholds"]["max_abs"], 1.0);
    assert_eq!(j["thresholds"]["p99_abs"], 0.05);
    assert_eq!(
        (j["width"].as_u64(), j["height"].as_u64()),
        (Some(4), Some(2))
    );
}

#[test]
fn gradient_mask_splits_interior_and_silhouette() {
    // 10x10 black with a white 4x4 square at x, y in 3..=6: the step marks
    // the square's 12 border pixels and the 16 pixels just outside it.
    let dir = tempfile::tempdir().unwrap();
    let mut expected = LinearImage::new(10, 10, [0.0; 3]);
    for y in 3..=6 {
        for x in 3..=6 {
            expected.set(x, y, [1.0; 3]);
        }
    }
    // The actual image misses the square's top-left corner pixel (an edge
    // difference) and is off by 0.02 at an interior pixel far away.
    let mut actual = expected.clone();
    actual.set(3, 3, [0.0; 3]);
    actual.set(0, 9, [0.02, 0.0, 0.0]);
    write_pair(dir.path(), &expected, &actual, "exr");
    let run = shadelab(
        dir.path(),
        &["diff", "expected.exr", "actual.exr", "--json"],
    );
    let j = json(&run);
    assert_eq!(j["silhouette"]["pixels"], 28);
    assert_eq!(j["interior"]["pixels"], 72);
    assert_eq!(j["silhouette"]["max_abs"], 1.0);
    let interior_max = j["interior"]["max_abs"].as_f64().unwrap();
    assert!((interior_max - 0.02).abs() < 1e-6, "{interior_max}");
}

/// The mean FLIP that NVIDIA's reference implementation reports for
/// tests/data/flip/{reference,test}.png (made by make_pair.py):
///
/// ```text
/// $ flip -r reference.png -t test.png -ppd 67      # flip-evaluator 1.7 (FLIP v1.7), PyPI
///      Mean: 0.228790
///      Max: 0.966368
/// ```
///
/// and `flip_evaluator.evaluate(..., "LDR", parameters={"ppd": 67.0})[1]`
/// = 0.22878988087177277, the unrounded mean.
const REFERENCE_FLIP_MEAN: f64 = 0.228_789_880_871_772_77;
const REFERENCE_FLIP_MAX: f64 = 0.966_368;

/// `nv-flip` builds NVIDIA's C++ FLIP, an older copy than 1.7's but the same
/// LDR algorithm in f32. What may differ is only rounding: the order of the
/// mean's sum (we add in f64; FLIP pools in its own histogram code) and the
/// compiler's use of fused multiply-add. Measured: 2.1e-8. The tolerance,
/// 1e-5, is 500 times that and still 2000 times finer than the default
/// threshold 0.02, so it cannot hide a difference that changes a verdict.
#[test]
fn flip_matches_nvidias_reference() {
    let expected = read_image(&flip_data("reference.png")).unwrap();
    let actual = read_image(&flip_data("test.png")).unwrap();
    let f = shadelab::metrics::flip(&expected, &actual, 67.0);
    assert!(
        (f.mean - REFERENCE_FLIP_MEAN).abs() < 1e-5,
        "ours {} against the reference's {REFERENCE_FLIP_MEAN}",
        f.mean
    );
    // The reference prints the maximum to 6 decimals.
    assert!((f.max - REFERENCE_FLIP_MAX).abs() <= 5e-7, "{}", f.max);

    // The CLI reports the same, and its heat map is the reference's magma
    // error map (`flip ... -d DIR`, saved as reference-flip-magma.png)
    // pixel for pixel.
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "diff",
            flip_data("reference.png").to_str().unwrap(),
            flip_data("test.png").to_str().unwrap(),
            "--json",
            "--heatmap",
            "heat.png",
        ],
    );
    assert_eq!(run.code, 1, "this pair is over the default thresholds");
    let mean = json(&run)["flip"]["mean"].as_f64().unwrap();
    assert!((mean - REFERENCE_FLIP_MEAN).abs() < 1e-5, "{mean}");
    let ours = read_image(&dir.path().join("heat.png")).unwrap();
    let theirs = read_image(&flip_data("reference-flip-magma.png")).unwrap();
    assert_eq!((ours.width, ours.height), (48, 32));
    assert!(ours == theirs, "the heat map differs from the reference's");
}

/// A 16-bit PNG is read at 16 bits (issue 30): 32768/65535 against 128/255
/// differ by 1.9e-3 in sRGB, 2.7e-4 ... 6e-4 in linear intensity; read as 8
/// bits they were the same byte and `diff` reported max_abs 0.
#[test]
fn a_sixteen_bit_png_is_read_at_full_precision() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    image::ImageBuffer::<image::Rgb<u16>, _>::from_pixel(4, 4, image::Rgb([32768u16; 3]))
        .save(d.join("sixteen.png"))
        .unwrap();
    image::RgbImage::from_pixel(4, 4, image::Rgb([128u8; 3]))
        .save(d.join("eight.png"))
        .unwrap();
    let run = common::cli::shadelab(d, &["diff", "eight.png", "sixteen.png", "--json"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    let max_abs = json["stats"]["max_abs"].as_f64().unwrap();
    // The exact linear values: sRGB decode of 128/255 and 32768/65535.
    let decode = |s: f64| ((s + 0.055) / 1.055).powf(2.4);
    let want = (decode(32768.0 / 65535.0) - decode(128.0 / 255.0)).abs();
    assert!((max_abs - want).abs() < 1e-6, "{max_abs} against {want}");
    assert!(max_abs > 1e-4);
}

/// An EXR against a PNG of the same render fails on the PNG's clamp; the
/// failure says why (issue 30), and a diff of one format says nothing.
#[test]
fn an_exr_against_a_png_says_the_formats_differ() {
    let dir = tempfile::tempdir().unwrap();
    let mut bright = LinearImage::new(4, 4, [0.5; 3]);
    bright.set(1, 1, [3.0, 3.0, 3.0]);
    write_image(&bright, &dir.path().join("r.exr")).unwrap();
    write_image(&bright, &dir.path().join("r.png")).unwrap();
    let run = shadelab(dir.path(), &["diff", "r.exr", "r.png"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("one image is an EXR (linear, unclamped) and the other a PNG"),
        "{}",
        run.stderr
    );
    assert!(
        run.stdout.contains("note: one image is an EXR"),
        "{}",
        run.stdout
    );
    let same = shadelab(dir.path(), &["diff", "r.exr", "r.exr"]);
    assert_eq!(same.code, 0);
    assert!(!same.stdout.contains("note:"), "{}", same.stdout);
}

/// The share and the count of pixels over the per-pixel threshold
/// (pixelmatch's gate), off by default: the known pair has 2 of its 8
/// pixels off by more than 0.01 (by 0.5 and 0.25), so a limit of 1 pixel
/// or 20% fails and 2 pixels or 25% passes; with `--pixel-threshold 0.3`
/// one pixel is over.
#[test]
fn the_share_and_count_of_pixels_over_a_threshold_can_be_gated() {
    let dir = tempfile::tempdir().unwrap();
    let (expected, actual) = known_pair();
    write_pair(dir.path(), &expected, &actual, "exr");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "diff",
            "expected.exr",
            "actual.exr",
            "--flip-mean",
            "1",
            "--p99-abs",
            "1",
        ];
        args.extend_from_slice(extra);
        shadelab(dir.path(), &args)
    };
    // Off by default: no row for either.
    let plain = run(&[]);
    assert_eq!(plain.code, 0, "{}", plain.stderr);
    assert!(!plain.stdout.contains("count_over"), "{}", plain.stdout);
    let failed = run(&["--threshold", "count_over=1"]);
    assert_eq!(failed.code, 1, "{}", failed.stderr);
    assert!(
        failed.stderr.contains("count_over 2 exceeds the limit 1"),
        "{}",
        failed.stderr
    );
    assert_eq!(run(&["--threshold", "count_over=2"]).code, 0);
    let failed = run(&["--threshold", "fraction_over=0.2"]);
    assert_eq!(failed.code, 1, "{}", failed.stderr);
    assert!(
        failed
            .stderr
            .contains("fraction_over 0.250000 exceeds the limit 0.2"),
        "{}",
        failed.stderr
    );
    assert_eq!(
        run(&["--threshold", "fraction_over=0.25,count_over=2"]).code,
        0
    );
    let one = run(&[
        "--threshold",
        "count_over=0",
        "--pixel-threshold",
        "0.3",
        "--json",
    ]);
    assert_eq!(one.code, 1, "{}", one.stderr);
    let j = json(&one);
    assert_eq!(j["thresholds"]["count_over"], 0.0);
    let verdicts = j["verdicts"].as_array().unwrap();
    let count = verdicts
        .iter()
        .find(|v| v["figure"] == "count_over")
        .unwrap();
    assert_eq!(count["value"], 1.0);
    assert_eq!(run(&["--threshold", "count_over=-1"]).code, 2);
}

/// `reference/` and `run/` in `dir`: an image the same on both sides, one
/// changed, one on each side only, and a file that is no image; returns
/// the two folders and the unchanged image.
fn two_folders(dir: &Path) -> (PathBuf, PathBuf, LinearImage) {
    let (expected, actual) = known_pair();
    let (reference, run_dir) = (dir.join("reference"), dir.join("run"));
    std::fs::create_dir_all(&reference).unwrap();
    std::fs::create_dir_all(&run_dir).unwrap();
    for (name, r, a) in [
        ("same.exr", &expected, &expected),
        ("changed.exr", &expected, &actual),
    ] {
        write_image(r, &reference.join(name)).unwrap();
        write_image(a, &run_dir.join(name)).unwrap();
    }
    write_image(&expected, &reference.join("gone.exr")).unwrap();
    write_image(&expected, &run_dir.join("new.exr")).unwrap();
    std::fs::write(run_dir.join("notes.txt"), "not an image").unwrap();
    (reference, run_dir, expected)
}

/// Two folders: images matched by name, each judged with the limits of a
/// single diff; one on one side only fails too (missing) or cannot be
/// judged (extra: an error in JUnit). Exit 1 when any does not pass.
#[test]
fn two_folders_are_compared_image_by_image_with_junit() {
    let dir = tempfile::tempdir().unwrap();
    let (reference, run_dir, expected) = two_folders(dir.path());
    let run = shadelab(
        dir.path(),
        &[
            "diff",
            "reference",
            "run",
            "--junit",
            "report.xml",
            "--json",
        ],
    );
    assert_eq!(run.code, 1, "{}", run.stderr);
    let j = json(&run);
    assert_eq!(j["pass"], false);
    let status = |name: &str| {
        j["cases"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["name"] == name)
            .map(|c| c["status"].as_str().unwrap().to_string())
    };
    assert_eq!(status("same.exr").as_deref(), Some("pass"));
    assert_eq!(status("changed.exr").as_deref(), Some("fail"));
    assert_eq!(status("gone.exr").as_deref(), Some("missing"));
    assert_eq!(status("new.exr").as_deref(), Some("extra"));
    assert_eq!(status("notes.txt"), None);
    let xml = std::fs::read_to_string(dir.path().join("report.xml")).unwrap();
    assert!(
        xml.contains("tests=\"4\" failures=\"2\" errors=\"1\""),
        "{xml}"
    );
    // The same limits as a single diff: loose enough, everything present
    // and within them passes.
    std::fs::remove_file(reference.join("gone.exr")).unwrap();
    std::fs::remove_file(run_dir.join("new.exr")).unwrap();
    let loose = || {
        let limits = ["--max-abs", "1", "--p99-abs", "1", "--flip-mean", "1"];
        let mut args = vec!["diff", "reference", "run"];
        args.extend(limits);
        shadelab(dir.path(), &args)
    };
    let run = loose();
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout.contains("2 of 2 images passed"),
        "{}",
        run.stdout
    );
    // An image on one side only fails the folder, with every pair passing.
    for (side, name) in [(&reference, "gone.exr"), (&run_dir, "new.exr")] {
        write_image(&expected, &side.join(name)).unwrap();
        let run = loose();
        assert_eq!(run.code, 1, "{name}: {}", run.stdout);
        assert!(
            run.stdout.contains("2 of 3 images passed"),
            "{}",
            run.stdout
        );
        std::fs::remove_file(side.join(name)).unwrap();
    }
    // One pair with --junit: one case, failed.
    let one = shadelab(
        dir.path(),
        &[
            "diff",
            "reference/changed.exr",
            "run/changed.exr",
            "--junit",
            "one.xml",
        ],
    );
    assert_eq!(one.code, 1, "{}", one.stderr);
    let xml = std::fs::read_to_string(dir.path().join("one.xml")).unwrap();
    assert!(xml.contains("tests=\"1\" failures=\"1\""), "{xml}");
    // A folder against a file, a heat map for a folder, empty folders.
    let mixed = shadelab(dir.path(), &["diff", "reference", "run/same.exr"]);
    assert_eq!(mixed.code, 2, "{}", mixed.stderr);
    let heat = shadelab(
        dir.path(),
        &["diff", "reference", "run", "--heatmap", "h.png"],
    );
    assert_eq!(heat.code, 2, "{}", heat.stderr);
    std::fs::create_dir_all(dir.path().join("e1")).unwrap();
    std::fs::create_dir_all(dir.path().join("e2")).unwrap();
    assert_eq!(shadelab(dir.path(), &["diff", "e1", "e2"]).code, 2);
}

/// The presets by purpose: one pixel of 400 off by 0.02 (two 8-bit steps
/// at mid grey) is within the GPU-against-reference limits (the 99th
/// percentile ignores it, max_abs allows an edge pixel anything) and over
/// the stored-reference ones (no pixel off by more than 0.01); a flag on
/// top of the preset wins.
#[test]
fn the_stored_reference_preset_fails_what_the_default_lets_through() {
    let dir = tempfile::tempdir().unwrap();
    let expected = LinearImage::new(20, 20, [0.25; 3]);
    let mut actual = expected.clone();
    actual.set(7, 9, [0.27, 0.25, 0.25]);
    write_pair(dir.path(), &expected, &actual, "exr");
    let run = |extra: &[&str]| {
        let mut args = vec!["diff", "expected.exr", "actual.exr", "--json"];
        args.extend_from_slice(extra);
        shadelab(dir.path(), &args)
    };
    let loose = run(&[]);
    assert_eq!(loose.code, 0, "{}", loose.stderr);
    assert_eq!(json(&loose)["preset"], "gpu-vs-reference");
    let tight = run(&["--preset", "stored-reference"]);
    assert_eq!(tight.code, 1, "{}", tight.stdout);
    let j = json(&tight);
    assert_eq!(j["preset"], "stored-reference");
    assert_eq!(j["thresholds"]["max_abs"], 0.01);
    assert!(
        tight
            .stderr
            .contains("max_abs 0.020000 exceeds the limit 0.01"),
        "{}",
        tight.stderr
    );
    let eased = run(&["--preset", "stored-reference", "--max-abs", "0.03"]);
    assert_eq!(eased.code, 0, "{}", eased.stderr);
    assert_eq!(run(&["--preset", "exact"]).code, 2);
}
