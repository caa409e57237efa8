//! `render` with many scenes and modes: one image per case, named by the
//! pattern, each the same as `render` makes of that case alone; one device
//! whose pipelines the cases share; a failed case reported while the
//! others are written.

use crate::common;

use std::path::{Path, PathBuf};

use common::cli::shadelab;

fn asset(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name)
        .display()
        .to_string()
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    names.sort();
    names
}

/// Small and quick: the raster modes and the ray tracer at 64 x 48.
const SIZE: [&str; 4] = ["--width", "64", "--height", "48"];

#[test]
fn every_scene_in_every_mode_each_as_render_makes_it_alone() {
    let dir = tempfile::tempdir().unwrap();
    let (spheres, whitted) = (asset("spheres.toml"), asset("whitted.toml"));
    let mut args = vec![
        "render",
        &spheres,
        &whitted,
        "--shading",
        "flat,phong,raytrace",
        "--out-dir",
        "batch",
        "--json",
    ];
    args.extend(SIZE);
    let run = shadelab(dir.path(), &args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(report["rendered"], 6);
    assert_eq!(report["failed"], 0);
    let expected_names: Vec<String> = ["spheres", "whitted"]
        .iter()
        .flat_map(|s| ["flat", "phong", "raytrace"].map(|m| format!("{s}-{m}.png")))
        .collect();
    let mut sorted = expected_names.clone();
    sorted.sort();
    assert_eq!(names_in(&dir.path().join("batch")), sorted);
    // The cases in the order given: scenes, then modes within each.
    let outputs: Vec<String> = report["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            assert_eq!(c["status"], "ok", "{c}");
            Path::new(c["output"].as_str().unwrap())
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    assert_eq!(outputs, expected_names);
    // Byte for byte what one `render` writes, metadata and all: the batch
    // changes where the work runs, not the image.
    for (scene, mode) in [(&whitted, "raytrace"), (&spheres, "flat")] {
        let mut alone = vec![
            "render",
            scene.as_str(),
            "--shading",
            mode,
            "-o",
            "alone.png",
        ];
        alone.extend(SIZE);
        let single = shadelab(dir.path(), &alone);
        assert_eq!(single.code, 0, "{}", single.stderr);
        let stem = Path::new(scene).file_stem().unwrap().to_string_lossy();
        let batch = std::fs::read(dir.path().join(format!("batch/{stem}-{mode}.png"))).unwrap();
        assert!(
            batch == std::fs::read(dir.path().join("alone.png")).unwrap(),
            "{stem}-{mode}.png differs from the single render"
        );
    }
}

/// Two copies of one scene in two modes: four cases, two pipelines. Each
/// case on a device of its own (or none kept) would say otherwise.
#[test]
fn the_cases_share_one_device_and_its_pipelines() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(asset("spheres.toml")).unwrap();
    std::fs::write(dir.path().join("a.toml"), &text).unwrap();
    std::fs::write(dir.path().join("b.toml"), &text).unwrap();
    let mut args = vec![
        "render",
        "a.toml",
        "b.toml",
        "--shading",
        "phong,raytrace",
        "--out-dir",
        "out",
        "--name",
        "{mode}/../{scene}.png",
    ];
    // A pattern with a folder in it is refused before anything runs, as
    // is a bad size: no folder is made.
    let refused = shadelab(dir.path(), &args);
    assert_eq!(refused.code, 2, "{}", refused.stderr);
    assert!(refused.stderr.contains("not a path"), "{}", refused.stderr);
    let mut bad_size = args.clone();
    bad_size[8] = "{scene}.png";
    bad_size.extend(["--width", "0"]);
    assert_eq!(shadelab(dir.path(), &bad_size).code, 2);
    assert!(!dir.path().join("out").exists());
    args[8] = "{scene}_{mode}.exr";
    args.push("--json");
    args.extend(SIZE);
    let run = shadelab(dir.path(), &args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(report["pipelines_built"], 2, "{report}");
    assert_eq!(
        names_in(&dir.path().join("out")),
        [
            "a_phong.exr",
            "a_raytrace.exr",
            "b_phong.exr",
            "b_raytrace.exr"
        ]
    );
    let a = shadelab::output::read_image(&dir.path().join("out/a_raytrace.exr")).unwrap();
    let b = shadelab::output::read_image(&dir.path().join("out/b_raytrace.exr")).unwrap();
    assert_eq!(a.pixels, b.pixels);
}

#[test]
fn a_failed_case_is_reported_and_the_others_are_written() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("broken.toml"), "[camera\n").unwrap();
    let spheres = asset("spheres.toml");
    let mut args = vec![
        "render",
        "broken.toml",
        &spheres,
        "--shading",
        "gouraud,phong",
        "--out-dir",
        "out",
    ];
    args.extend(SIZE);
    let run = shadelab(dir.path(), &args);
    // The first failed case's status: a scene that does not parse is bad
    // input (2), as for one image.
    assert_eq!(run.code, 2, "{}\n{}", run.stdout, run.stderr);
    assert_eq!(
        names_in(&dir.path().join("out")),
        ["spheres-gouraud.png", "spheres-phong.png"]
    );
    for case in ["broken/gouraud", "broken/phong"] {
        assert!(
            run.stderr.contains(&format!("shadelab: error: {case}: ")),
            "{}",
            run.stderr
        );
    }
    assert!(
        run.stdout.contains("rendered 2 of 4 images into out") && run.stdout.contains("2 failed"),
        "{}",
        run.stdout
    );
    args.push("--json");
    let run = shadelab(dir.path(), &args);
    assert_eq!(run.code, 2);
    let report: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    let statuses: Vec<&str> = report["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["status"].as_str().unwrap())
        .collect();
    assert_eq!(statuses, ["failed", "failed", "ok", "ok"]);
    assert!(report["cases"][0]["error"]
        .as_str()
        .is_some_and(|e| e.contains("broken.toml")));
}

#[test]
fn one_output_file_for_a_batch_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &["render", "--shading", "flat,phong", "--out", "x.png"],
    );
    assert_eq!(run.code, 2);
    assert!(
        run.stderr.contains("--out x.png names one image") && run.stderr.contains("--out-dir"),
        "{}",
        run.stderr
    );
    let run = shadelab(
        dir.path(),
        &["render", "--shading", "flat,phong", "--name", "{scene}.png"],
    );
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("needs {mode}"), "{}", run.stderr);
    assert_eq!(names_in(dir.path()), Vec::<String>::new());
    // `--name` alone makes a batch of one, in the current folder.
    let mut args = vec!["render", "--shading", "flat", "--name", "one-{mode}.png"];
    args.extend(SIZE);
    let run = shadelab(dir.path(), &args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout.contains("rendered 1 of 1 images"),
        "{}",
        run.stdout
    );
    assert!(dir.path().join("one-flat.png").is_file());
}
