//! Progress where stderr is not a terminal (a CI log): lines saying what is
//! done and what is left, for the CPU reference's phases and for the cases
//! of `check` and `golden` (`compare`'s: tests/cli/compare_not_run.rs). With
//! `SHADELAB_PROGRESS_SECONDS=0` a line comes at every step the poller
//! sees, so a short run shows some.

use crate::common;

use common::cli::shadelab_with;

const EVERY_STEP: [(&str, &str); 1] = [("SHADELAB_PROGRESS_SECONDS", "0")];

/// A sphere of 512 segments (261k triangles): long enough on the CPU
/// reference for its phases to be seen counting.
fn sphere_scene(dir: &std::path::Path) {
    std::fs::write(
        dir.join("sphere.toml"),
        "[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n\
         [image]\nwidth = 320\nheight = 240\n\
         [[lights]]\nposition = [2.0, 3.0, 4.0]\nintensity = 8.0\n\
         [materials.m]\ncolor = [0.8, 0.3, 0.3]\n\
         [[objects]]\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nsegments = 512\nmaterial = \"m\"\n",
    )
    .unwrap();
}

#[test]
fn the_cpu_reference_counts_its_triangles_then_its_rows() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    sphere_scene(d);
    let args = [
        "render",
        "sphere.toml",
        "--backend",
        "cpu",
        "--shading",
        "flat",
        "-o",
        "s.png",
    ];
    let run = shadelab_with(d, &args, &EVERY_STEP);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let total = "of 261120 done";
    assert!(
        run.stderr.lines().any(|l| l
            .starts_with("shadelab: flat on the CPU reference, triangles set up: ")
            && l.contains(total)),
        "{}",
        run.stderr
    );
    assert!(
        run.stderr
            .contains("flat on the CPU reference, bands of rows: "),
        "{}",
        run.stderr
    );
    let quiet = shadelab_with(d, &[&args[..], &["--quiet"]].concat(), &EVERY_STEP);
    assert_eq!(quiet.code, 0);
    assert!(!quiet.stderr.contains("CPU reference,"), "{}", quiet.stderr);
}

#[test]
fn check_and_golden_say_how_many_cases_are_done() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let small = ["--shading", "flat,phong", "--width", "32", "--height", "24"];
    let check = shadelab_with(
        d,
        &[&["check", "--out", "c"][..], &small].concat(),
        &EVERY_STEP,
    );
    assert_eq!(check.code, 0, "{}", check.stderr);
    // The first case named as it starts, the end said; the steps between
    // may pass unseen where the two cases end together.
    assert!(
        check
            .stderr
            .contains("shadelab: check: 0 of 2 done, running default flat")
            && check.stderr.contains("shadelab: check: 2 of 2 done"),
        "{}",
        check.stderr
    );
    let golden = shadelab_with(
        d,
        &[&["golden", "--references", "r", "--create"][..], &small].concat(),
        &EVERY_STEP,
    );
    assert_eq!(golden.code, 0, "{}", golden.stderr);
    assert!(
        golden
            .stderr
            .contains("shadelab: golden: 0 of 2 done, running default-flat.png")
            && golden.stderr.contains("shadelab: golden: 2 of 2 done"),
        "{}",
        golden.stderr
    );
}

/// `check` says where the running case's CPU reference is, within the case.
#[test]
fn check_says_where_a_cases_cpu_reference_is() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    sphere_scene(d);
    let args = [
        "check",
        "sphere.toml",
        "--shading",
        "flat",
        "--out",
        "c",
        "--images",
        "none",
    ];
    let run = shadelab_with(d, &args, &EVERY_STEP);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stderr.contains(
            "shadelab: check: 0 of 1 done, running sphere flat (its CPU reference: triangles set up "
        ),
        "{}",
        run.stderr
    );
}
