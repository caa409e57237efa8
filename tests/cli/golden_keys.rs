//! `golden`'s references keyed by what made them: the scene's path below
//! a root, so that reordered or same-named scenes keep their own
//! references; two cases that would share one refused before any work;
//! and a failure against a reference made with other settings names each
//! difference (docs/golden.md, "Which reference a case reads").

use crate::common;

use std::path::Path;

use common::cli::{shadelab, Run};

fn json(run: &Run) -> serde_json::Value {
    serde_json::from_str(&run.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}\n{}", run.stdout, run.stderr))
}

fn statuses(run: &Run) -> Vec<String> {
    json(run)["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["status"].as_str().unwrap().to_string())
        .collect()
}

/// A small scene whose sphere is `color`: two of them differ in every
/// sphere pixel, so a swapped reference fails.
fn write_scene(path: &Path, color: [f64; 3]) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    let toml = format!(
        "[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n\
         [image]\nwidth = 32\nheight = 24\n\
         [[lights]]\nposition = [2.0, 3.0, 4.0]\nintensity = 8.0\n\
         [materials.m]\ncolor = {color:?}\n\
         [[objects]]\nshape = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"m\"\n"
    );
    std::fs::write(path, toml).unwrap();
}

fn golden(dir: &Path, scenes: &[&str], extra: &[&str]) -> Run {
    let mut args = vec!["golden"];
    args.extend(scenes);
    args.extend(["--shading", "flat", "--references", "refs", "--json"]);
    args.extend(extra);
    shadelab(dir, &args)
}

/// `a/x.toml` and `b/x.toml`: references `a/x-flat.png` and `b/x-flat.png`,
/// whatever the order; reversed, every case passes and `--bless` rewrites
/// nothing. Before keys, the second was `x-2-flat.png`, and the reversed
/// run failed both cases.
#[test]
fn reordered_scenes_of_one_name_keep_their_own_references() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(&d.join("a/x.toml"), [1.0, 0.2, 0.2]);
    write_scene(&d.join("b/x.toml"), [0.2, 0.2, 1.0]);
    let made = golden(d, &["a/x.toml", "b/x.toml"], &["--create"]);
    assert_eq!(made.code, 0, "{}", made.stderr);
    assert_eq!(statuses(&made), ["created", "created"]);
    let (a, b) = (d.join("refs/a/x-flat.png"), d.join("refs/b/x-flat.png"));
    let before = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let reversed = golden(d, &["b/x.toml", "a/x.toml"], &[]);
    assert_eq!(reversed.code, 0, "{}\n{}", reversed.stdout, reversed.stderr);
    assert_eq!(statuses(&reversed), ["pass", "pass"]);
    let blessed = golden(d, &["b/x.toml", "a/x.toml"], &["--bless"]);
    assert_eq!(statuses(&blessed), ["pass", "pass"]);
    assert_eq!(
        (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap()),
        before
    );
    // A root of the user's puts its folder in the key.
    let rooted = golden(d, &["a/x.toml"], &["--root", ".", "--create"]);
    assert_eq!(rooted.code, 0, "{}", rooted.stderr);
    assert_eq!(json(&rooted)["cases"][0]["file"], "a/x-flat.png");
    let outside = golden(d, &["a/x.toml"], &["--root", "b"]);
    assert_eq!(outside.code, 2);
    assert!(
        outside.stderr.contains("is not under --root"),
        "{}",
        outside.stderr
    );
}

/// One scene given twice, or two files of one path but their extension:
/// refused with both named, before a folder is made or a case rendered.
#[test]
fn two_cases_that_would_share_a_reference_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(&d.join("a/x.toml"), [1.0, 0.2, 0.2]);
    std::fs::copy(repo("tests/data/cube.glb"), d.join("a/x.glb")).unwrap();
    for scenes in [["a/x.toml", "a/x.toml"], ["a/x.toml", "a/x.glb"]] {
        let run = golden(d, &scenes, &["--create"]);
        assert_eq!(run.code, 2, "{scenes:?}: {}", run.stderr);
        assert!(
            run.stderr.contains("would share the reference x-flat.png")
                && run.stderr.contains(scenes[1]),
            "{}",
            run.stderr
        );
        assert!(!d.join("refs").exists() && !d.join("golden-out").exists());
    }
}

fn repo(path: &str) -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// A reference made at 4 samples and another size fails a one-sample
/// render of the same scene, and the hint names both differences.
#[test]
fn a_failure_against_a_reference_made_otherwise_names_each_difference() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(&d.join("x.toml"), [1.0, 0.2, 0.2]);
    let made = golden(
        d,
        &["x.toml"],
        &["--create", "--msaa", "4", "--width", "40"],
    );
    assert_eq!(made.code, 0, "{}", made.stderr);
    let run = golden(d, &["x.toml"], &[]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    let hint = json(&run)["cases"][0]["hint"]
        .as_str()
        .unwrap_or_default()
        .to_string();
    assert!(
        hint.contains("width 40 -> 32") && hint.contains("msaa 4 -> 1"),
        "{hint}"
    );
    // The same settings pass with no hint.
    let again = golden(d, &["x.toml"], &["--msaa", "4", "--width", "40"]);
    assert_eq!(again.code, 0, "{}", again.stderr);
}
