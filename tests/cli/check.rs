//! `shadelab check` from the command line: its images and JUnit report,
//! exit 1 over a threshold, bad input refused before rendering, and each
//! case it can run is run, the others reported once as JUnit errors.

use std::path::Path;

use crate::common::cli::shadelab;

#[test]
fn check_passes_and_writes_images_and_junit() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "check",
            "--width",
            "96",
            "--height",
            "72",
            "--junit",
            "report.xml",
        ],
    );
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert_eq!(
        run.stdout
            .lines()
            .filter(|l| l.starts_with("PASS default/"))
            .count(),
        4,
        "{}",
        run.stdout
    );
    for mode in ["flat", "gouraud", "phong", "raytrace"] {
        for kind in ["expected", "actual", "diff"] {
            let path = dir
                .path()
                .join(format!("check-out/default/{mode}-{kind}.png"));
            let image = shadelab::output::read_image(&path).unwrap();
            assert_eq!((image.width, image.height), (96, 72));
        }
    }
    let xml = std::fs::read_to_string(dir.path().join("report.xml")).unwrap();
    assert!(xml.contains("tests=\"4\" failures=\"0\""), "{xml}");
}

#[test]
fn check_over_threshold_exits_1_with_a_junit_failure() {
    let dir = tempfile::tempdir().unwrap();
    // No GPU matches an f64 reference to 1e-12: every mode must fail.
    let run = shadelab(
        dir.path(),
        &[
            "check",
            "--shading",
            "phong",
            "--width",
            "64",
            "--height",
            "48",
            "--interior-max-abs",
            "1e-12",
            "--junit",
            "r.xml",
            "--json",
        ],
    );
    assert_eq!(run.code, 1, "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(json["failed"], 1);
    assert!(json["cases"][0]["failures"][0]
        .as_str()
        .unwrap()
        .contains("interior max error"));
    let xml = std::fs::read_to_string(dir.path().join("r.xml")).unwrap();
    assert!(
        xml.contains("failures=\"1\"") && xml.contains("<failure message=\"interior max error"),
        "{xml}"
    );
    assert!(run.stderr.contains("1 of 1 cases failed"), "{}", run.stderr);
}

#[test]
fn check_rejects_bad_input_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(dir.path(), &["check", "missing.toml"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("missing.toml"));
    assert!(!dir.path().join("check-out").exists());
    let run = shadelab(dir.path(), &["check", "--flip-mean", "-1"]);
    assert_eq!(run.code, 2);
}

/// A case that cannot be checked fails as a case: the JUnit report is still
/// written, with the reason, and the exit status is the error's.
#[test]
fn check_reports_a_case_it_cannot_run() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "check",
            "--shading",
            "flat,phong",
            "--width",
            "10000",
            "--height",
            "10000",
            "--out",
            "o",
            "--junit",
            "j.xml",
        ],
    );
    assert_eq!(run.code, 2, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        run.stdout.matches("ERROR default/").count(),
        2,
        "{}",
        run.stdout
    );
    let xml = std::fs::read_to_string(dir.path().join("j.xml")).expect("the JUnit report");
    // A case that cannot run is a JUnit error, not a failure (issue 30).
    let errors = xml
        .matches("<error message=\"a 10000x10000 image exceeds")
        .count();
    assert_eq!(errors, 2, "{xml}");
    assert!(xml.contains("failures=\"0\" errors=\"2\""), "{xml}");
}

/// `check` in a CI job (issue 30): a scene that does not load, or is missing,
/// is a JUnit `<error>` with its reason and the other cases still run; a
/// repeated mode runs once; `--images failures` writes no image of a case
/// that passed; exit 1 when some case could not run, 2 when none could.
#[test]
fn check_runs_every_case_it_can_and_reports_the_others_as_junit_errors() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("typo.toml"),
        "[camera]\nposition = [0, 0, 5]\n",
    )
    .unwrap();
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/spheres.toml");
    let small = [
        "--width",
        "32",
        "--height",
        "24",
        "--shading",
        "phong,phong",
    ];
    let run = shadelab(
        dir.path(),
        &[
            &[
                "check",
                assets.to_str().unwrap(),
                "typo.toml",
                "missing.toml",
            ][..],
            &small,
            &["--junit", "junit-out/report.xml", "--images", "failures"],
        ]
        .concat(),
    );
    assert_eq!(run.code, 1, "{}\n{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("PASS spheres/phong"), "{}", run.stdout);
    assert!(
        run.stdout.contains("ERROR typo/phong  typo.toml line 1"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout.contains("ERROR missing/phong  missing.toml"),
        "{}",
        run.stdout
    );
    assert!(
        run.stderr
            .contains("0 of 3 cases failed their thresholds and 2 could not run"),
        "{}",
        run.stderr
    );
    // The JUnit folder is created; one case per scene (phong once).
    let xml = std::fs::read_to_string(dir.path().join("junit-out/report.xml")).unwrap();
    assert!(
        xml.contains("tests=\"3\" failures=\"0\" errors=\"2\""),
        "{xml}"
    );
    assert!(
        xml.contains("<error message=\"typo.toml line 1, column 1: missing required key"),
        "{xml}"
    );
    assert!(
        !dir.path().join("check-out/spheres").exists(),
        "a passing case's images were written"
    );
    // Nothing could run: exit 2, the JUnit file still written.
    let run = shadelab(
        dir.path(),
        &[
            "check",
            "typo.toml",
            "--shading",
            "flat",
            "--junit",
            "none.xml",
        ],
    );
    assert_eq!(run.code, 2, "{}", run.stderr);
    let xml = std::fs::read_to_string(dir.path().join("none.xml")).unwrap();
    assert!(
        xml.contains("tests=\"1\" failures=\"0\" errors=\"1\""),
        "{xml}"
    );
}

/// With no Vulkan driver every case is a JUnit error saying so, exit 3, with
/// an install hint; a hook that does not compile is printed once.
#[test]
fn check_without_a_driver_or_with_a_broken_hook_says_so_once() {
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_shadelab"))
        .args([
            "check",
            "--width",
            "16",
            "--height",
            "12",
            "--shading",
            "flat,phong",
            "--junit",
            "j.xml",
        ])
        .current_dir(dir.path())
        .env("SHADELAB_CACHE_DIR", dir.path().join("cache"))
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("apt-get install mesa-vulkan-drivers"),
        "{stderr}"
    );
    let xml = std::fs::read_to_string(dir.path().join("j.xml")).unwrap();
    assert!(
        xml.contains("tests=\"2\" failures=\"0\" errors=\"2\""),
        "{xml}"
    );
    std::fs::write(
        dir.path().join("bad.glsl"),
        "vec3 shade_light(vec3 N) { return undeclared; }\n",
    )
    .unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "check",
            "--width",
            "16",
            "--height",
            "12",
            "--shading",
            "flat,phong",
            "--lighting",
            "bad.glsl",
            "--junit",
            "h.xml",
        ],
    );
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert_eq!(
        run.stdout.matches("does not compile").count(),
        1,
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("ERROR default/phong  the same error as default/flat above"),
        "{}",
        run.stdout
    );
    let xml = std::fs::read_to_string(dir.path().join("h.xml")).unwrap();
    assert!(xml.contains("errors=\"2\""), "{xml}");
}
