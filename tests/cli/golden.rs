//! `shadelab golden`: a scene suite with a user's lighting hook against
//! stored references. Missing references fail until made; repeated renders
//! pass; a deliberate change fails with a report and is accepted with one
//! flag; each shader change of issue 33's list is caught by the default
//! limits; a driver's own references are found before the shared ones.

use crate::common;

use std::path::{Path, PathBuf};

use common::cli::{shadelab, shadelab_with, Run};

fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path)
}

fn json(run: &Run) -> serde_json::Value {
    serde_json::from_str(&run.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}\n{}", run.stdout, run.stderr))
}

fn statuses(report: &serde_json::Value) -> Vec<String> {
    report["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["status"].as_str().unwrap().to_string())
        .collect()
}

/// The cases of a report with `status`, as `scene/mode`.
fn cases_with(report: &serde_json::Value, status: &str) -> Vec<String> {
    report["cases"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["status"] == status)
        .map(|c| {
            format!(
                "{}/{}",
                c["scene"].as_str().unwrap(),
                c["shading"].as_str().unwrap()
            )
        })
        .collect()
}

/// The lecture's formula as a hook, with `edit` applied to its text.
fn hook(dir: &Path, name: &str, edit: (&str, &str)) -> String {
    let text = std::fs::read_to_string(repo("examples/lighting/phong.glsl")).unwrap();
    assert!(text.contains(edit.0), "the hook has no {:?}", edit.0);
    std::fs::write(dir.join(name), text.replace(edit.0, edit.1)).unwrap();
    name.to_string()
}

const SPECULAR: &str = "reflected += vec3(m.ks * s);";
const EXPONENT: &str = "pow(r_dot_v, m.p)";

/// `golden` over two scenes of `assets/` in three modes, small.
fn suite(dir: &Path, hook: &str, extra: &[&str]) -> Run {
    let (spheres, whitted) = (
        repo("assets/spheres.toml").display().to_string(),
        repo("assets/whitted.toml").display().to_string(),
    );
    let mut args = vec![
        "golden",
        &spheres,
        &whitted,
        "--shading",
        "flat,phong,raytrace",
        "--references",
        "refs",
        "--lighting",
        hook,
        "--width",
        "96",
        "--height",
        "72",
        "--json",
    ];
    args.extend_from_slice(extra);
    shadelab(dir, &args)
}

#[test]
fn a_suite_with_a_users_hook_is_made_repeated_broken_and_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let same = hook(d, "mine.glsl", (SPECULAR, SPECULAR));
    let brighter = hook(
        d,
        "brighter.glsl",
        (SPECULAR, "reflected += vec3(1.03 * m.ks * s);"),
    );

    // No references yet: every case fails as missing, and says how to make it.
    let run = suite(d, &same, &[]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert_eq!(statuses(&json(&run)), vec!["missing"; 6]);
    assert!(run.stderr.contains("--bless"), "{}", run.stderr);
    assert!(d.join("golden-out/spheres-phong-actual.png").is_file());

    let run = suite(d, &same, &["--create"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(statuses(&json(&run)), vec!["created"; 6]);
    let made = std::fs::read(d.join("refs/whitted-raytrace.png")).unwrap();
    // The reference says what made it: the device and driver are in it.
    let settings = shadelab::output::png_text(&made, "shadelab:settings").unwrap();
    let settings: serde_json::Value = serde_json::from_str(&settings).unwrap();
    assert_eq!(settings["shading"], "raytrace");
    assert!(settings["driver"].as_str().is_some_and(|d| !d.is_empty()));
    assert!(settings["lighting"]
        .as_str()
        .is_some_and(|h| h.ends_with("mine.glsl")));

    // Repeated: every case exactly equal, and the stale pictures gone.
    let run = suite(d, &same, &[]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report = json(&run);
    assert_eq!(statuses(&report), vec!["pass"; 6]);
    for case in report["cases"].as_array().unwrap() {
        assert_eq!(case["figures"]["stats"]["max_abs"], 0.0, "{case}");
    }
    assert!(!d.join("golden-out/spheres-phong-actual.png").exists());

    // A deliberate change: the specular term 3% brighter fails wherever a
    // highlight shows, with the pictures and a report to read.
    let junit = d.join("golden.xml");
    let junit_arg = junit.display().to_string();
    let run = suite(d, &brighter, &["--junit", &junit_arg]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    let report = json(&run);
    let failed = cases_with(&report, "fail");
    assert!(
        failed.contains(&"spheres/phong".to_string())
            && failed.contains(&"whitted/raytrace".to_string()),
        "{failed:?}"
    );
    assert!(
        run.stderr.contains("run again with --bless"),
        "{}",
        run.stderr
    );
    for picture in ["actual", "diff", "error"] {
        let path = d.join(format!("golden-out/spheres-phong-{picture}.png"));
        assert!(path.is_file(), "{} is missing", path.display());
    }
    let html = std::fs::read_to_string(d.join("golden-out/report.html")).unwrap();
    assert!(html.contains("spheres/phong: FAIL"), "report.html");
    assert!(html.contains("max_abs") && html.contains("exceeds the limit 0.01"));
    // The reference, the render, FLIP and the scaled error, per failure.
    assert_eq!(
        html.matches("data:image/png;base64,").count(),
        4 * failed.len()
    );
    let xml = std::fs::read_to_string(&junit).unwrap();
    assert!(
        xml.contains(&format!("failures=\"{}\"", failed.len())),
        "{xml}"
    );

    // Accepted with one flag: the changed references rewritten and named.
    let before = std::fs::read(d.join("refs/spheres-phong.png")).unwrap();
    let run = suite(d, &brighter, &["--bless"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report = json(&run);
    let updated = cases_with(&report, "updated");
    assert_eq!(updated, failed, "bless rewrites exactly the failed cases");
    assert_ne!(
        std::fs::read(d.join("refs/spheres-phong.png")).unwrap(),
        before
    );
    assert_eq!(suite(d, &brighter, &[]).code, 0);
    // And the old look is now the change.
    assert_eq!(suite(d, &same, &[]).code, 1);
}

/// A scene (the built-in default scene where "default") at 320 x 240 in
/// one mode against `refs/{scene}.png`, or `--references` in `extra`.
fn default_case(dir: &Path, scene: &str, mode: &str, extra: &[&str]) -> Run {
    let mut args = vec!["golden"];
    if scene != "default" {
        args.push(scene);
    }
    if !extra.contains(&"--references") {
        args.extend_from_slice(&["--references", "refs"]);
    }
    args.extend_from_slice(&[
        "--shading",
        mode,
        "--name",
        "{scene}.png",
        "--width",
        "320",
        "--height",
        "240",
        "--json",
    ]);
    args.extend_from_slice(extra);
    shadelab(dir, &args)
}

#[test]
fn every_listed_shader_change_fails_the_default_limits_and_a_repeat_passes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene_text = std::fs::read_to_string(repo("src/scene/default.toml")).unwrap();
    std::fs::write(d.join("default.toml"), &scene_text).unwrap();
    let key_light = "position  = [4.0, 6.0, 5.0]";
    assert!(scene_text.contains(key_light));
    let moved = scene_text.replace(key_light, "position  = [4.04, 6.06, 5.05]");
    std::fs::create_dir(d.join("moved")).unwrap();
    std::fs::write(d.join("moved/default.toml"), moved).unwrap();
    let same = hook(d, "same.glsl", (SPECULAR, SPECULAR));
    let ks = hook(
        d,
        "ks.glsl",
        (SPECULAR, "reflected += vec3(1.03 * m.ks * s);"),
    );
    let p = hook(d, "p.glsl", (EXPONENT, "pow(r_dot_v, 0.9 * m.p)"));

    let mut changes = 0;
    for mode in ["phong", "raytrace"] {
        let name = format!("refs-{mode}");
        let refs = ["--references", &name];
        let run = |scene: &str, hook: &str, extra: &[&str]| {
            let mut all = vec!["--lighting", hook];
            all.extend_from_slice(&refs);
            all.extend_from_slice(extra);
            default_case(d, scene, mode, &all)
        };
        let created = run("default.toml", &same, &["--create"]);
        assert_eq!(created.code, 0, "{}", created.stderr);
        // Repeated renders pass, exactly.
        for _ in 0..2 {
            let again = run("default.toml", &same, &[]);
            assert_eq!(again.code, 0, "{mode}: {}", again.stderr);
            assert_eq!(json(&again)["cases"][0]["figures"]["stats"]["max_abs"], 0.0);
        }
        for (what, scene, hook) in [
            ("specular ks +3%", "default.toml", &ks),
            ("glossiness p x 0.9", "default.toml", &p),
            ("the key light moved by 1%", "moved/default.toml", &same),
        ] {
            let changed = run(scene, hook, &[]);
            assert_eq!(
                changed.code, 1,
                "{what} ({mode}) passed: {}",
                changed.stdout
            );
            assert_eq!(statuses(&json(&changed)), ["fail"], "{what} ({mode})");
            changes += 1;
        }
    }
    // Gouraud against Phong's reference of the same scene.
    let gouraud = default_case(
        d,
        "default.toml",
        "gouraud",
        &["--references", "refs-phong", "--lighting", &same],
    );
    assert_eq!(gouraud.code, 1, "{}", gouraud.stdout);
    assert_eq!(statuses(&json(&gouraud)), ["fail"]);
    assert_eq!(changes + 1, 7);
}

#[test]
fn a_drivers_own_reference_is_found_first_and_made_with_per_driver() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let same = hook(d, "same.glsl", (SPECULAR, SPECULAR));
    let ks = hook(
        d,
        "ks.glsl",
        (SPECULAR, "reflected += vec3(1.05 * m.ks * s);"),
    );
    let case = |hook: &str, extra: &[&str]| {
        let mut args = vec!["--lighting", hook];
        args.extend_from_slice(extra);
        default_case(d, "default", "phong", &args)
    };
    assert_eq!(case(&same, &["--create"]).code, 0);
    let shared = std::fs::read(d.join("refs/default.png")).unwrap();
    // This "driver" renders the brighter look: its own reference, made
    // beside the shared one, which stays as it was.
    let run = case(&ks, &["--key", "driver-b", "--per-driver", "--bless"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report = json(&run);
    assert_eq!(statuses(&report), ["created"]);
    assert_eq!(report["cases"][0]["reference_kind"], "driver");
    assert!(d.join("refs/driver-b/default.png").is_file());
    assert_eq!(std::fs::read(d.join("refs/default.png")).unwrap(), shared);
    // Its own first; another driver falls back to the shared one.
    let own = case(&ks, &["--key", "driver-b"]);
    assert_eq!(own.code, 0, "{}", own.stdout);
    assert_eq!(json(&own)["cases"][0]["reference_kind"], "driver");
    let other = case(&ks, &["--key", "driver-c"]);
    assert_eq!(other.code, 1);
    assert_eq!(json(&other)["cases"][0]["reference_kind"], "shared");
    // The default key names this device's driver, and is printed.
    let plain = case(&same, &[]);
    assert_eq!(plain.code, 0);
    let key = json(&plain)["key"].as_str().unwrap().to_string();
    assert!(!key.is_empty() && !key.contains(['/', ' ']), "{key}");
}

/// A reference made on another driver that fails says so, and how to keep
/// one per driver.
#[test]
fn a_failure_against_another_drivers_reference_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    assert_eq!(default_case(d, "default", "flat", &["--create"]).code, 0);
    let path = d.join("refs/default.png");
    let mut image = shadelab::output::read_image(&path).unwrap();
    image.pixels[0] = [1.0, 0.0, 1.0];
    let settings = serde_json::json!({"device": "Another GPU", "driver": "Other 1.0"});
    let metadata =
        shadelab::output::ImageMetadata::software().with("shadelab:settings", settings.to_string());
    let bytes = shadelab::output::encode_with(&image, &path, &metadata).unwrap();
    std::fs::write(&path, bytes).unwrap();
    let run = default_case(d, "default", "flat", &[]);
    assert_eq!(run.code, 1);
    let hint = json(&run)["cases"][0]["hint"].as_str().unwrap().to_string();
    assert!(
        hint.contains("made on Another GPU (Other 1.0)") && hint.contains("--per-driver"),
        "{hint}"
    );
}

#[test]
fn bad_references_and_flags_get_one_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("file"), "x").unwrap();
    let run = shadelab(d, &["golden", "--references", "file"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("is not a folder"), "{}", run.stderr);
    let run = shadelab(d, &["golden", "--references", "refs", "--key", "../up"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("--key"), "{}", run.stderr);
    let run = shadelab(
        d,
        &["golden", "--references", "refs", "--threshold", "max_abs=x"],
    );
    assert_eq!(run.code, 2);
    // A bad file name pattern or size is refused before any folder is made.
    for bad in [["--name", "{scene}-{shading}.png"], ["--width", "0"]] {
        let mut args = vec!["golden", "--references", "refs"];
        args.extend(bad);
        let run = shadelab(d, &args);
        assert_eq!(run.code, 2, "{bad:?}: {}", run.stderr);
    }
    assert!(!d.join("refs").exists() && !d.join("golden-out").exists());
    // A corrupt reference is an error of its case (every case: exit 2),
    // and --bless replaces it.
    std::fs::create_dir(d.join("refs")).unwrap();
    std::fs::write(d.join("refs/default.png"), "not a png").unwrap();
    let run = default_case(d, "default", "flat", &[]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert_eq!(statuses(&json(&run)), ["error"]);
    assert!(run.stderr.contains("cannot be read"), "{}", run.stderr);
    assert_eq!(default_case(d, "default", "flat", &["--bless"]).code, 0);
    assert_eq!(default_case(d, "default", "flat", &[]).code, 0);
}

/// `SHADELAB_BLESS=1` is `--bless`, for CI systems that set variables more
/// easily than flags.
#[test]
fn the_bless_variable_accepts_as_the_flag_does() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let run = shadelab_with(
        d,
        &[
            "golden",
            "--shading",
            "gouraud",
            "--references",
            "refs",
            "--width",
            "64",
            "--height",
            "48",
        ],
        &[("SHADELAB_BLESS", "1")],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("CREATED"), "{}", run.stdout);
    assert!(d.join("refs/default-gouraud.png").is_file());
}
