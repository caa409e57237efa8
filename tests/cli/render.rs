//! The `shadelab` binary as users and scripts drive it: outputs, exit
//! statuses, and one clear error line for each kind of bad input, with no
//! output file left behind.

mod common;

use std::path::{Path, PathBuf};

use common::cli::{assert_one_line_refusal, shadelab};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

const CAMERA: &str = "[camera]\nposition = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n";
const SPHERE: &str =
    "[materials.m]\ncolor = [1, 1, 1]\n[[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n";

/// Renders `scene_text` (written as scene.toml) and expects exit status 2,
/// one error line containing every word of `expect`, and no image written.
fn assert_bad_input(scene_text: &str, extra_args: &[&str], expect: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), scene_text).unwrap();
    let before = files_in(dir.path());
    let mut args = vec!["render", "scene.toml", "--out", "out.png"];
    args.extend_from_slice(extra_args);
    let run = shadelab(dir.path(), &args);
    assert_eq!(
        run.code, 2,
        "exit status for {expect:?}; stderr: {}",
        run.stderr
    );
    assert!(!run.stderr.contains("panicked"), "a panic: {}", run.stderr);
    let lines: Vec<&str> = run
        .stderr
        .lines()
        .filter(|l| !l.trim().is_empty())
        .collect();
    assert_eq!(lines.len(), 1, "one error line, got: {}", run.stderr);
    assert!(lines[0].starts_with("shadelab: error: "), "{}", lines[0]);
    for word in expect {
        assert!(
            lines[0].contains(word),
            "error should mention {word:?}: {}",
            lines[0]
        );
    }
    assert_eq!(
        files_in(dir.path()),
        before,
        "no output (or temporary) file may be left"
    );
}

#[test]
fn renders_the_default_scene_to_png_and_exr() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "render",
            "--shading",
            "gouraud",
            "--width",
            "64",
            "--height",
            "48",
            "--out",
            "a.png",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let png = shadelab::output::read_image(&dir.path().join("a.png")).unwrap();
    assert_eq!((png.width, png.height), (64, 48));
    let run = shadelab(
        dir.path(),
        &[
            "render",
            "--shading",
            "gouraud",
            "--width",
            "64",
            "--height",
            "48",
            "--out",
            "a.exr",
            "--json",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: serde_json::Value =
        serde_json::from_str(run.stdout.trim()).expect("--json prints one JSON object");
    assert_eq!(json["width"], 64);
    assert_eq!(json["shading"], "gouraud");
    // The EXR comes from the float target, the PNG from the 8-bit one.
    assert_eq!(json["color_target"], "rgba32f");
    let exr = shadelab::output::read_image(&dir.path().join("a.exr")).unwrap();
    // The PNG is the EXR clamped and sRGB-encoded, within one 8-bit step
    // (the 8-bit target's encoding may round a value between two bytes the
    // other way).
    let mut lit = 0;
    for (p, e) in png.pixels.iter().zip(&exr.pixels) {
        for c in 0..3 {
            let want = shadelab::output::linear_to_srgb8(e[c]);
            let got = shadelab::output::linear_to_srgb8(p[c]);
            assert!(got.abs_diff(want) <= 1, "{got} against {want}");
        }
        if e[0] > 0.2 {
            lit += 1;
        }
    }
    assert!(lit > 100, "the default scene should show lit objects");
}

#[test]
fn default_output_name_follows_scene_and_mode() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "render",
            "--shading",
            "flat",
            "--width",
            "32",
            "--height",
            "32",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(dir.path().join("default-flat.png").is_file());
}

#[test]
fn info_lists_the_device_in_use() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(dir.path(), &["info", "--json"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    let selected = json["selected"].as_u64().expect("a selected device") as usize;
    assert!(json["devices"][selected]["name"].is_string());
}

/// Reports name the driver and its version beside the device: `render
/// --json` and `bench --json` give what `info` lists for the device in use.
#[test]
fn render_and_bench_name_the_driver() {
    let dir = tempfile::tempdir().unwrap();
    let info = shadelab(dir.path(), &["info", "--json"]);
    let info: serde_json::Value = serde_json::from_str(info.stdout.trim()).unwrap();
    let selected = info["selected"].as_u64().unwrap() as usize;
    let driver = info["devices"][selected]["driver"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(!driver.is_empty());
    let size = ["--width", "32", "--height", "24"];
    let render = shadelab(
        dir.path(),
        &[&["render", "--out", "x.png", "--json"][..], &size].concat(),
    );
    assert_eq!(render.code, 0, "{}", render.stderr);
    let render: serde_json::Value = serde_json::from_str(render.stdout.trim()).unwrap();
    assert_eq!(render["driver"], driver.as_str());
    let bench = shadelab(
        dir.path(),
        &[
            &["bench", "--shading", "raytrace", "--runs", "1", "--json"][..],
            &size,
        ]
        .concat(),
    );
    assert_eq!(bench.code, 0, "{}", bench.stderr);
    let bench: serde_json::Value = serde_json::from_str(bench.stdout.trim()).unwrap();
    assert_eq!(bench["driver"], driver.as_str());
}

/// `bench --cpu` times the CPU reference on the same work and `bench
/// --every-feature` the uber-shader build; each ratio is the quotient of the
/// figures it is printed beside.
#[test]
fn bench_compares_with_the_cpu_and_the_uber_shader() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "bench",
            "--shading",
            "phong,raytrace",
            "--runs",
            "1",
            "--width",
            "48",
            "--height",
            "32",
            "--cpu",
            "--every-feature",
            "--json",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    let results = json["results"].as_array().unwrap();
    assert_eq!(results.len(), 2);
    for row in results {
        let gpu = row["gpu_ms"].as_f64().unwrap();
        let cpu = row["cpu_ms"].as_f64().expect("--cpu times every mode");
        assert!(gpu > 0.0 && cpu > 0.0, "{row}");
        let speedup = row["gpu_speedup_over_cpu"].as_f64().unwrap();
        assert!((speedup - cpu / gpu).abs() <= 1e-9 * speedup, "{row}");
        let traced = row["shading"] == "raytrace";
        assert_eq!(row["every_feature_gpu_ms"].is_f64(), traced, "{row}");
        if traced {
            let uber = row["every_feature_gpu_ms"].as_f64().unwrap();
            let ratio = row["every_feature_ratio"].as_f64().unwrap();
            assert!((ratio - uber / gpu).abs() <= 1e-9 * ratio, "{row}");
        }
    }
}

/// `bench` times the raster modes on the path `render --out x.png` takes,
/// into the 8-bit sRGB target, and says so in its header and each JSON
/// row; `--target exr` times the float target instead. The ray tracer
/// always writes floats.
#[test]
fn bench_names_the_colour_target_it_timed() {
    let dir = tempfile::tempdir().unwrap();
    for (target, raster) in [
        (None, "rgba8-srgb"),
        (Some("exr"), "rgba32f"),
        (Some("png"), "rgba8-srgb"),
    ] {
        let mut args = vec![
            "bench",
            "--shading",
            "flat,phong,raytrace",
            "--runs",
            "1",
            "--width",
            "32",
            "--height",
            "24",
        ];
        if let Some(t) = target {
            args.extend(["--target", t]);
        }
        let text = shadelab(dir.path(), &args);
        assert_eq!(text.code, 0, "{}", text.stderr);
        assert!(
            text.stdout
                .contains(&format!("timed into the {raster} target")),
            "{}",
            text.stdout
        );
        args.push("--json");
        let run = shadelab(dir.path(), &args);
        assert_eq!(run.code, 0, "{}", run.stderr);
        let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
        assert_eq!(json["raster_target"], raster);
        for row in json["results"].as_array().unwrap() {
            let want = if row["shading"] == "raytrace" {
                "rgba32f"
            } else {
                raster
            };
            assert_eq!(row["color_target"], want, "{row}");
        }
    }
}

#[test]
fn unknown_device_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &["--device", "no-such-gpu", "render", "--out", "x.png"],
    );
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("no-such-gpu"));
    assert!(!dir.path().join("x.png").exists());
}

#[test]
fn malformed_toml() {
    assert_bad_input(
        "[camera\nposition = [0, 0, 5]\n",
        &[],
        &["scene.toml", "line 1"],
    );
}

#[test]
fn unknown_key() {
    let text = format!("{CAMERA}colour = 1\n{SPHERE}");
    assert_bad_input(&text, &[], &["scene.toml", "line 4", "colour"]);
}

#[test]
fn missing_required_key() {
    assert_bad_input(
        "[camera]\nposition = [0.0, 0.0, 5.0]\n",
        &[],
        &["scene.toml", "look_at"],
    );
}

#[test]
fn wrong_type() {
    let text = format!("{CAMERA}fov_y = \"wide\"\n{SPHERE}");
    assert_bad_input(&text, &[], &["scene.toml", "line 4", "fov_y"]);
}

#[test]
fn non_finite_number() {
    let text = format!("{CAMERA}[lighting]\nk = nan\n{SPHERE}");
    assert_bad_input(&text, &[], &["scene.toml", "line 5", "finite"]);
    let text = format!("{CAMERA}[[lights]]\nposition = [0, inf, 0]\nintensity = 1\n{SPHERE}");
    assert_bad_input(&text, &[], &["scene.toml", "line 5", "finite"]);
}

#[test]
fn unknown_material() {
    let text = format!(
        "{CAMERA}{}",
        SPHERE.replace("material = \"m\"", "material = \"marble\"")
    );
    assert_bad_input(&text, &[], &["scene.toml", "marble"]);
}

#[test]
fn missing_mesh_file() {
    let text = format!("{CAMERA}[[objects]]\nshape = \"mesh\"\nfile = \"models/missing.glb\"\n");
    assert_bad_input(&text, &[], &["missing.glb"]);
}

#[test]
fn corrupt_glb() {
    let path = fixture("corrupt.glb");
    let text = format!(
        "{CAMERA}[[objects]]\nshape = \"mesh\"\nfile = {:?}\n",
        path.display().to_string()
    );
    assert_bad_input(&text, &[], &["corrupt.glb"]);
}

#[test]
fn nan_in_vertex_data() {
    let path = fixture("nan_position.gltf");
    let text = format!(
        "{CAMERA}[[objects]]\nshape = \"mesh\"\nfile = {:?}\n",
        path.display().to_string()
    );
    assert_bad_input(&text, &[], &["nan_position.gltf"]);
}

#[test]
fn mesh_of_only_zero_area_triangles() {
    let dir = tempfile::tempdir().unwrap();
    // Three collinear points, in a glTF written here.
    let positions: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 2., 0., 0.]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    let b64 = base64_encode(&positions);
    let gltf = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[2,0,0]}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{b64}"}}]}}"#
    );
    let mesh = dir.path().join("flat.gltf");
    std::fs::write(&mesh, gltf).unwrap();
    let text = format!(
        "{CAMERA}[[objects]]\nshape = \"mesh\"\nfile = {:?}\n",
        mesh.display().to_string()
    );
    assert_bad_input(&text, &[], &["flat.gltf"]);
}

fn base64_encode(bytes: &[u8]) -> String {
    const TABLE: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |acc, (i, b)| acc | u32::from(*b) << (16 - 8 * i));
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(TABLE[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[test]
fn absurd_resolution_in_the_file() {
    let text = format!("{CAMERA}[image]\nwidth = 0\n{SPHERE}");
    assert_bad_input(&text, &[], &["scene.toml", "width"]);
    let text = format!("{CAMERA}[image]\nheight = 100000\n{SPHERE}");
    assert_bad_input(&text, &[], &["scene.toml", "height"]);
}

#[test]
fn absurd_resolution_on_the_command_line() {
    let text = format!("{CAMERA}{SPHERE}");
    assert_bad_input(&text, &["--width", "100000"], &["--width", "100000"]);
    assert_bad_input(&text, &["--height", "0"], &["--height"]);
}

#[test]
fn unknown_output_format() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(dir.path(), &["render", "--out", "picture.jpg"]);
    assert_eq!(run.code, 2);
    assert!(
        run.stderr.contains(".png") && run.stderr.contains("picture.jpg"),
        "{}",
        run.stderr
    );
    assert!(files_in(dir.path()).is_empty());
}

#[test]
fn missing_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(dir.path(), &["render", "nowhere.toml", "--out", "x.png"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("nowhere.toml"), "{}", run.stderr);
    assert!(files_in(dir.path()).is_empty());
}

/// An output that cannot be written fails before the render, with nothing
/// left; a missing folder is created (issue 30: it rendered fully and only
/// then failed to write), as `check --junit` and `diff --heatmap` do.
#[test]
fn unwritable_output_leaves_nothing_and_a_missing_folder_is_made() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("blocker"), b"a file, not a folder").unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "render",
            "--width",
            "16",
            "--height",
            "16",
            "--out",
            "blocker/x.png",
            "--json",
        ],
    );
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("blocker/x.png"), "{}", run.stderr);
    assert!(
        run.stdout.is_empty(),
        "rendered before failing: {}",
        run.stdout
    );
    assert_eq!(files_in(dir.path()), ["blocker"]);
    let run = shadelab(
        dir.path(),
        &[
            "render",
            "--width",
            "16",
            "--height",
            "16",
            "--out",
            "new/dir/x.png",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(dir.path().join("new/dir/x.png").is_file());
    let run = shadelab(
        dir.path(),
        &[
            "diff",
            "new/dir/x.png",
            "new/dir/x.png",
            "--heatmap",
            "heat/h.png",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(dir.path().join("heat/h.png").is_file());
}

#[test]
fn usage_errors_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    assert_eq!(
        shadelab(dir.path(), &["render", "--shading", "toon"]).code,
        2
    );
    assert_eq!(shadelab(dir.path(), &["paint"]).code, 2);
    assert_eq!(shadelab(dir.path(), &["--help"]).code, 0);
}

#[test]
fn cpu_backend_renders_the_same_picture() {
    let dir = tempfile::tempdir().unwrap();
    for backend in ["gpu", "cpu"] {
        let out = format!("{backend}.png");
        let run = shadelab(
            dir.path(),
            &[
                "render",
                "--backend",
                backend,
                "--width",
                "80",
                "--height",
                "60",
                "--out",
                &out,
            ],
        );
        assert_eq!(run.code, 0, "{backend}: {}", run.stderr);
    }
    let gpu = shadelab::output::read_image(&dir.path().join("gpu.png")).unwrap();
    let cpu = shadelab::output::read_image(&dir.path().join("cpu.png")).unwrap();
    // 8-bit images of the same render: equal except where a silhouette edge
    // lands on the other side of a sample (a few percent of pixels at most),
    // and within 1 in 255 elsewhere (the GPU's PNG comes from its 8-bit sRGB
    // target, whose encoding may round a value between two bytes the other
    // way).
    let bytes = |p: &[f32; 3]| p.map(shadelab::srgb::linear_to_srgb8);
    let differing = gpu
        .pixels
        .iter()
        .zip(&cpu.pixels)
        .filter(|(g, c)| {
            let (g, c) = (bytes(g), bytes(c));
            (0..3).any(|k| g[k].abs_diff(c[k]) > 1)
        })
        .count();
    assert!(
        differing * 50 < gpu.pixels.len(),
        "{differing} of {} pixels differ",
        gpu.pixels.len()
    );
}

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

#[test]
fn compare_writes_every_report_file() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "compare",
            "--variants",
            "flat;phong:segments=16;raytrace:depth=1",
            "--runs",
            "1",
            "--width",
            "64",
            "--height",
            "48",
            "--out",
            "cmp",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    for file in [
        "report.json",
        "report.csv",
        "report.html",
        "speed-vs-error.png",
        "speed-vs-error.svg",
        "contact-sheet.png",
        "reference.png",
    ] {
        assert!(
            dir.path().join("cmp").join(file).is_file(),
            "{file} missing"
        );
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("cmp/report.json")).unwrap())
            .unwrap();
    let names: Vec<&str> = json["variants"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["flat", "phong:segments=16", "raytrace:depth=1"]);
}

#[test]
fn compare_rejects_bad_variants_and_shards() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        vec!["compare", "--variants", "flat:depth=3", "--out", "x"],
        vec!["compare", "--variants", "toon", "--out", "x"],
        vec!["compare", "--shard", "3/2", "--out", "x"],
        vec!["compare", "--shard", "0/2", "--out", "x"],
        vec!["compare", "--merge", "nowhere", "--out", "x"],
    ] {
        let run = shadelab(dir.path(), &args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    }
    // `--shard $CI_NODE_INDEX/$CI_NODE_TOTAL` with the variables unset.
    let args = ["compare", "--shard", "/", "--out", "x"];
    let run = shadelab(dir.path(), &args);
    assert_one_line_refusal(&run, &args, "variables empty");
    assert!(run.stderr.contains("--shard auto"), "{}", run.stderr);
    assert_eq!(
        shadelab(dir.path(), &["compare"]).code,
        2,
        "--out is required"
    );
}

#[test]
fn compare_shards_merge_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let common = [
        "--variants",
        "flat;gouraud;phong",
        "--runs",
        "1",
        "--width",
        "48",
        "--height",
        "36",
    ];
    for (shard, out) in [("1/2", "a"), ("2/2", "b")] {
        let mut args = vec!["compare", "--shard", shard, "--out", out];
        args.extend_from_slice(&common);
        let run = shadelab(dir.path(), &args);
        assert_eq!(run.code, 0, "{}", run.stderr);
    }
    let run = shadelab(
        dir.path(),
        &["compare", "--merge", "b", "a", "--out", "merged", "--json"],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(json["variants"].as_array().unwrap().len(), 3);
    assert!(json["shard"].is_null());
    assert!(dir.path().join("merged/report.html").is_file());
    assert!(
        dir.path().join("merged/gouraud.png").is_file(),
        "images come along"
    );

    // A report that names an image outside its folder is refused before
    // anything is copied.
    let report = dir.path().join("b/report.json");
    let text = std::fs::read_to_string(&report).unwrap();
    let tampered = text.replacen("\"phong.png\"", "\"../phong.png\"", 1);
    assert_ne!(text, tampered, "the shard names phong.png");
    std::fs::write(&report, tampered).unwrap();
    let run = shadelab(
        dir.path(),
        &["compare", "--merge", "a", "b", "--out", "evil"],
    );
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("../phong.png"), "{}", run.stderr);
    assert!(!dir.path().join("evil/flat.png").exists(), "nothing copied");

    // A shard of another variant list is of another run (once merged
    // silently into a report of neither): refused in one line that names
    // the setting.
    let mut args = vec!["compare", "--shard", "2/2", "--out", "c"];
    args.extend_from_slice(&common);
    args[6] = "flat;phong";
    let run = shadelab(dir.path(), &args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let args = ["compare", "--merge", "a", "c", "--out", "mixed"];
    let run = shadelab(dir.path(), &args);
    assert_one_line_refusal(
        &run,
        &args,
        "variants is [\"flat\",\"gouraud\",\"phong\"] against",
    );
}

/// The size, depth and run-count checks are shared by every command that
/// takes them, and the CPU reference refuses an image over the pixel cap
/// itself: before, `bench` clamped `--depth` silently and `compare` set off
/// a 268-megapixel CPU render.
#[test]
fn every_command_checks_size_depth_and_runs_alike() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 6] = [
        (&["bench", "--width", "0"], "--width 0"),
        (&["bench", "--depth", "65"], "--depth 65"),
        (&["check", "--height", "0", "--out", "c"], "--height 0"),
        (&["compare", "--out", "o", "--runs", "0"], "--runs 0"),
        (
            &[
                "compare", "--out", "o", "--width", "16384", "--height", "16384",
            ],
            "16384x16384",
        ),
        (
            &[
                "render",
                "--backend",
                "cpu",
                "--width",
                "16384",
                "--height",
                "16384",
                "--out",
                "x.png",
            ],
            "16384x16384",
        ),
    ];
    for (args, expect) in cases {
        let run = shadelab(dir.path(), args);
        common::cli::assert_one_line_refusal(&run, args, expect);
    }
    assert!(!dir.path().join("x.png").exists());
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

/// Ray-tracing options given to a raster mode change nothing and say so
/// (issue 30); given to the ray tracer, nothing is said.
#[test]
fn ray_tracing_options_on_a_raster_mode_are_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let small = ["--width", "16", "--height", "12"];
    let run = shadelab(
        dir.path(),
        &[
            &[
                "render",
                "--shading",
                "phong",
                "--depth",
                "3",
                "--samples",
                "4",
                "-o",
                "p.png",
            ][..],
            &small,
        ]
        .concat(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stderr.contains(
            "warning: --depth, --samples: --shading phong ignores them (only the ray tracer uses them)"
        ),
        "{}",
        run.stderr
    );
    let run = shadelab(
        dir.path(),
        &[
            &[
                "render",
                "--shading",
                "raytrace",
                "--depth",
                "3",
                "--samples",
                "4",
                "-o",
                "r.png",
            ][..],
            &small,
        ]
        .concat(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(!run.stderr.contains("warning"), "{}", run.stderr);
    let run = shadelab(
        dir.path(),
        &["warm", "--shading", "flat,phong", "--depth", "2"],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("--depth: --shading flat,phong ignores it"),
        "{}",
        run.stderr
    );
}

/// One reference for every variant (issue 30): by default the global one,
/// stated; a budget no variant meets is exit status 1 naming the reference
/// and the metric; a budget met names the fastest variant within it by the
/// same reference.
#[test]
fn compare_measures_every_variant_against_one_reference_and_a_missed_budget_fails() {
    let dir = tempfile::tempdir().unwrap();
    let base = [
        "compare",
        "--width",
        "32",
        "--height",
        "24",
        "--runs",
        "1",
        "--variants",
        "phong;raytrace:depth=2",
    ];
    let run = shadelab(
        dir.path(),
        &[&base[..], &["--out", "a", "--budget", "1e-9"]].concat(),
    );
    assert_eq!(run.code, 1, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains(
            "no variant has RMSE <= 0.000000001 against the global (ray-traced) reference"
        ),
        "{}",
        run.stderr
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("a/report.json")).unwrap())
            .unwrap();
    assert_eq!(report["plot_reference"], "global");
    // The variants' plotted errors are their global errors, Phong's too.
    let run = shadelab(
        dir.path(),
        &[&base[..], &["--out", "b", "--budget", "10", "--json"]].concat(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    let variants = report["variants"].as_array().unwrap();
    let fastest = variants
        .iter()
        .min_by(|a, b| {
            a["timing"]["gpu_ms"]
                .as_f64()
                .partial_cmp(&b["timing"]["gpu_ms"].as_f64())
                .unwrap()
        })
        .unwrap();
    assert_eq!(report["budget"]["fastest"], fastest["name"]);
    let run = shadelab(
        dir.path(),
        &[&base[..], &["--out", "c", "--reference", "local"]].concat(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout
            .contains("pareto front and budget: RMSE against the local reference"),
        "{}",
        run.stdout
    );
    // Both: two plots, two fronts, two budget answers, each naming its own.
    let run = shadelab(
        dir.path(),
        &[
            &base[..],
            &["--out", "d", "--reference", "both", "--budget", "10"],
        ]
        .concat(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout
            .contains("budget: the fastest variant with RMSE <= 10 against the global"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("budget: the fastest variant with RMSE <= 10 against the local"),
        "{}",
        run.stdout
    );
    let global = std::fs::read_to_string(dir.path().join("d/speed-vs-error.svg")).unwrap();
    let local = std::fs::read_to_string(dir.path().join("d/speed-vs-error-local.svg")).unwrap();
    assert!(
        global.contains("against the global (ray-traced) reference")
            && !global.contains("against the local")
    );
    assert!(local.contains("against the local reference") && !local.contains("against the global"));
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

/// A render stopped by SIGTERM while writing leaves no temporary file and
/// exits 130 (issue 30: a 4096x4096 EXR left 69 to 111 MB behind). The
/// test waits for the temporary file to appear, then signals; a run that
/// finished before it was seen is tried again.
#[test]
fn a_render_stopped_while_writing_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut caught = 0;
    for _ in 0..3 {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_shadelab"))
            .args([
                "render",
                "--shading",
                "flat",
                "--width",
                "4096",
                "--height",
                "4096",
                "-o",
                "big.exr",
            ])
            .current_dir(dir.path())
            .env("SHADELAB_CACHE_DIR", dir.path().join("cache"))
            .env("MESA_SHADER_CACHE_DIR", common::cli::mesa_cache())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let temp = dir.path().join(format!(".big.exr.{}.tmp", child.id()));
        let mut seen = false;
        while child.try_wait().unwrap().is_none() {
            if temp.exists() {
                seen = true;
                let pid = child.id().to_string();
                let _ = std::process::Command::new("kill")
                    .args(["-TERM", &pid])
                    .status();
                break;
            }
            std::thread::sleep(std::time::Duration::from_micros(200));
        }
        let status = child.wait().unwrap();
        if seen {
            caught += 1;
            assert_eq!(status.code(), Some(130));
            assert!(!temp.exists(), "the temporary file was left behind");
            // big.exr may be there: the rename can win the race with the
            // signal, and then the file is whole.
            break;
        }
        let _ = std::fs::remove_file(dir.path().join("big.exr"));
    }
    assert!(caught > 0, "never saw the temporary file being written");
}

/// `compare --out` reused by a smaller run removes the earlier run's files,
/// and only them (issue 30: the bigger run's images stayed beside the new
/// ones), saying so.
#[test]
fn compare_into_a_used_folder_removes_only_its_own_earlier_files() {
    let dir = tempfile::tempdir().unwrap();
    let base = [
        "compare", "--width", "24", "--height", "16", "--runs", "1", "--out", "cmp",
    ];
    let run = shadelab(
        dir.path(),
        &[&base[..], &["--variants", "flat;gouraud"]].concat(),
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(dir.path().join("cmp/gouraud.png").is_file());
    std::fs::write(dir.path().join("cmp/notes.txt"), b"mine").unwrap();
    let run = shadelab(dir.path(), &[&base[..], &["--variants", "flat"]].concat());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stderr.contains("files of an earlier comparison"),
        "{}",
        run.stderr
    );
    assert!(!dir.path().join("cmp/gouraud.png").exists());
    assert!(!dir.path().join("cmp/gouraud-heat.png").exists());
    assert!(dir.path().join("cmp/flat.png").is_file());
    assert!(dir.path().join("cmp/notes.txt").is_file());
}

/// A reader that closes the pipe early (`shadelab render ... | head -1`)
/// ends the command quietly, not with a panic and a backtrace.
#[test]
fn a_closed_output_pipe_is_no_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_shadelab"))
        .args([
            "render",
            "--backend",
            "cpu",
            "--width",
            "8",
            "--height",
            "8",
            "-o",
            "x.png",
        ])
        .current_dir(dir.path())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader is gone before the first line
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// The rough messages of issue 30, item 11, each in the house style: one
/// line, naming what is wrong.
#[test]
fn rough_messages_name_what_is_wrong_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let one_error_line = |run: &common::cli::Run| {
        let first = run.stderr.lines().next().unwrap_or_default().to_string();
        assert!(first.starts_with("shadelab: error: "), "{}", run.stderr);
        assert!(run.stderr.lines().count() <= 2, "{}", run.stderr);
        first
    };
    // A negative size is a range error, not advice to write `-- -5`.
    let run = shadelab(d, &["render", "--width", "-5"]);
    assert_eq!(run.code, 2);
    assert_eq!(
        one_error_line(&run),
        "shadelab: error: --width -5 is out of range; expected 1 to 16384 pixels"
    );
    // The parser's errors: one line, the suggestion kept, then the usage.
    let run = shadelab(d, &["render", "--shadin", "phong"]);
    assert_eq!(run.code, 2);
    assert!(
        one_error_line(&run).contains("'--shadin' found (a similar argument exists: '--shading')")
    );
    assert!(
        run.stderr
            .lines()
            .nth(1)
            .unwrap_or_default()
            .starts_with("usage: shadelab render"),
        "{}",
        run.stderr
    );
    // A glTF whose .bin is missing names it.
    std::fs::write(
        d.join("m.gltf"),
        r#"{"asset":{"version":"2.0"},"buffers":[{"uri":"gone.bin","byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0}"#,
    )
    .unwrap();
    let run = shadelab(d, &["render", "m.gltf", "-o", "m.png"]);
    assert_eq!(run.code, 2);
    assert!(
        one_error_line(&run).contains("buffer 0 names the file `gone.bin`, which does not exist")
    );
    // A hook with its own #version says so, not glslang's "must occur first".
    std::fs::write(
        d.join("v.glsl"),
        "#version 460\nvec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) { return intensity; }\n",
    )
    .unwrap();
    let run = shadelab(d, &["render", "--lighting", "v.glsl", "-o", "v.png"]);
    assert_eq!(run.code, 2);
    assert!(one_error_line(&run).contains("v.glsl line 1: a lighting hook has no #version line"));
    // A bad variant is named.
    let run = shadelab(d, &["compare", "--variants", "flat;phnog", "--out", "c"]);
    assert_eq!(run.code, 2);
    assert!(
        one_error_line(&run).contains("variant `phnog`: unknown shading mode"),
        "{}",
        run.stderr
    );
    // "1 timed run", not "1 timed runs".
    let run = shadelab(
        d,
        &[
            "compare",
            "--width",
            "16",
            "--height",
            "12",
            "--runs",
            "1",
            "--variants",
            "flat",
            "--out",
            "c",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let html = std::fs::read_to_string(d.join("c/report.html")).unwrap();
    assert!(
        html.contains("1 timed run per variant") && !html.contains("1 timed runs"),
        "{html}"
    );
    assert!(
        run.stdout.contains("median of 1 run\n") || run.stdout.contains("median of 1 run"),
        "{}",
        run.stdout
    );
}

/// A PNG says how it was made (issue 30): the sRGB chunk with its gAMA
/// fallback, `Software`, and render's settings, the same as `--json`'s.
#[test]
fn a_rendered_png_carries_srgb_and_the_settings_it_was_made_with() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "render",
            "--shading",
            "raytrace",
            "--width",
            "24",
            "--height",
            "16",
            "--depth",
            "2",
            "--samples",
            "4",
            "-o",
            "r.png",
            "--json",
        ],
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    let settings = &json["settings"];
    assert_eq!(
        (settings["depth"].as_u64(), settings["samples"].as_u64()),
        (Some(2), Some(4))
    );
    assert_eq!(settings["scene"], "built-in default scene");
    assert_eq!(settings["width"], 24);
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(dir.path().join("r.png")).unwrap(),
    ));
    let reader = decoder.read_info().unwrap();
    let info = reader.info();
    assert!(info.srgb.is_some(), "no sRGB chunk");
    // gAMA is there too (the decoder hides it behind sRGB): read the chunks.
    let bytes = std::fs::read(dir.path().join("r.png")).unwrap();
    let mut at = 8;
    let mut gamma = None;
    while at + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        if &bytes[at + 4..at + 8] == b"gAMA" {
            gamma = Some(u32::from_be_bytes(
                bytes[at + 8..at + 12].try_into().unwrap(),
            ));
        }
        at += 12 + len;
    }
    assert_eq!(gamma, Some(45455));
    let text = |key: &str| {
        info.uncompressed_latin1_text
            .iter()
            .find(|t| t.keyword == key)
            .map(|t| t.text.clone())
            .unwrap_or_else(|| panic!("no {key} text"))
    };
    assert!(text("Software").starts_with("shadelab "));
    assert_eq!(text("Title"), "default");
    let stored: serde_json::Value = serde_json::from_str(&text("shadelab:settings")).unwrap();
    assert_eq!(&stored, settings);
    assert!(text("Comment").contains("depth=2"), "{}", text("Comment"));
    // A raster render has no ray-tracing settings to state.
    let run = shadelab(
        dir.path(),
        &[
            "render", "--width", "24", "--height", "16", "-o", "p.png", "--json",
        ],
    );
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert!(json["settings"]["depth"].is_null() && json["settings"]["traversal"].is_null());
}

/// Where `spirv-opt` is not installed (no PATH at all here), the driver
/// specialises the ray tracer's module instead: the same image to the
/// bit, only its pipeline made slower (src/gpu/vk/specialise.rs).
#[test]
fn the_ray_tracer_renders_the_same_image_without_spirv_opt() {
    let dir = tempfile::tempdir().unwrap();
    let render = |out: &str, path: Option<&str>| {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_shadelab"));
        command
            .args([
                "render",
                "--shading",
                "raytrace",
                "--width",
                "48",
                "--height",
                "36",
            ])
            .args(["-q", "-o", out])
            .current_dir(dir.path())
            .env("SHADELAB_CACHE_DIR", dir.path().join("cache"));
        if let Some(path) = path {
            command.env("PATH", path);
        }
        let status = command.status().unwrap();
        assert!(status.success(), "{out}: {status}");
        std::fs::read(dir.path().join(out)).unwrap()
    };
    let with = render("with.exr", None);
    let spirv = dir.path().join("cache").join("spirv");
    assert!(
        std::fs::read_dir(&spirv).is_ok_and(|d| d.count() > 0),
        "spirv-opt specialised the module (package spirv-tools installed?)"
    );
    let without = render("without.exr", Some("/nonexistent"));
    assert!(with == without, "the EXRs differ");
}

/// The light inside a closed diffuse sphere (tests/common/closed_sphere.rs)
/// as a scene file, which gives no depth.
const CLOSED_SPHERE: &str =
    "[camera]\nposition = [0, 0, 0]\nlook_at = [0.3, 0.1, -1]\nfov_y = 60\n\
    [image]\nwidth = 32\nheight = 24\n\
    [lighting]\nambient = 0.2\nfalloff = \"inverse-square\"\n\
    [[lights]]\nposition = [0, 0, 0]\nintensity = 3\n\
    [materials.inside]\ncolor = [1, 1, 1]\nka = 0.5\nkd = 0.6\nks = 0.25\np = 20\n\
    [[objects]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 2\nmaterial = \"inside\"\n";

/// `--bounces N` renders N bounces (issue 55: `--bounces 10` at the default
/// depth rendered 5): the depth follows the bounces up where nobody gave
/// one, and a depth given below them is one line, exit 2, not fewer bounces.
#[test]
fn bounces_reach_their_count_and_a_depth_below_them_is_refused() {
    use common::closed_sphere::expected;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("sphere.toml"), CLOSED_SPHERE).unwrap();
    let base = [
        "render",
        "sphere.toml",
        "--shading",
        "raytrace",
        "--backend",
        "cpu",
        "--samples",
        "16",
    ];
    let mut args = base.to_vec();
    args.extend(["--bounces", "10", "-o", "ten.exr"]);
    let (mean, _) = common::cli::render_mean(d, &args, "ten.exr");
    // The 10-bounce answer, well away from the 5-bounce one (3.7% below).
    assert!(
        (mean / expected(10) - 1.0).abs() < 0.01,
        "mean {mean}, 10 bounces {}, 5 bounces {}",
        expected(10),
        expected(5)
    );
    for (flags, expect) in [
        (
            &["--bounces", "10", "--depth", "5"][..],
            "--bounces 10 needs a depth of 10 or more",
        ),
        (&["--bounces", "6", "--depth", "0"][..], "and --depth is 0"),
    ] {
        let mut args = base.to_vec();
        args.extend(flags);
        args.extend(["-o", "no.png"]);
        let run = shadelab(d, &args);
        common::cli::assert_one_line_refusal(&run, &args, expect);
        assert!(!d.join("no.png").exists());
    }
    // A scene's own depth is as binding as --depth.
    std::fs::write(
        d.join("deep.toml"),
        format!("{CLOSED_SPHERE}[render]\ndepth = 3\n"),
    )
    .unwrap();
    let args = [
        "render",
        "deep.toml",
        "--shading",
        "raytrace",
        "--bounces",
        "4",
        "-o",
        "no.png",
    ];
    let run = shadelab(d, &args);
    common::cli::assert_one_line_refusal(&run, &args, "the scene's render.depth is 3");
}

/// A bad value of a numeric flag is one line, exit 2, as `--photons -5`
/// always was (issue 55: `--bounces -1` gave clap's "unexpected argument"
/// and the usage), in every command; so is a value that is no number, and
/// an absurd caustic radius.
#[test]
fn a_bad_number_is_one_line_in_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 12] = [
        (
            &["render", "--bounces", "-1"],
            "--bounces -1 is out of range",
        ),
        (&["render", "--depth", "-1"], "--depth -1 is out of range"),
        (
            &["render", "--samples", "-1"],
            "--samples -1 is out of range",
        ),
        (&["render", "--cutoff", "-1"], "--cutoff -1"),
        (&["render", "--bounces", "abc"], "'abc' for '--bounces"),
        (&["bench", "--runs", "-1"], "--runs -1 is out of range"),
        (
            &["compare", "--out", "o", "--runs", "-2"],
            "--runs -2 is out of range",
        ),
        (
            &["check", "--flip-mean", "-1", "--out", "c"],
            "--flip-mean -1",
        ),
        (&["warm", "--bounces", "-3"], "--bounces -3 is out of range"),
        (
            &["render", "--caustic-radius", "1e30"],
            "--caustic-radius 1e30 is out of range",
        ),
        (
            &["render", "--caustic-radius", "0"],
            "--caustic-radius 0 is out of range",
        ),
        (
            &["golden", "--references", "r", "--depth", "-1"],
            "--depth -1 is out of range",
        ),
    ];
    for (args, expect) in cases {
        let mut args = args.to_vec();
        if args[0] == "render" {
            args.extend(["-o", "x.png"]);
        }
        let run = shadelab(dir.path(), &args);
        common::cli::assert_one_line_refusal(&run, &args, expect);
    }
    assert!(!dir.path().join("x.png").exists());
}

/// The photon map's settings without caustics are said to be ignored
/// (issue 55: silently), and not where caustics are on; a shard of a trace
/// with caustics is refused for its caustics, not as a Whitted trace.
#[test]
fn caustic_settings_without_caustics_warn_and_a_caustic_shard_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let small = ["--shading", "raytrace", "--width", "8", "--height", "8"];
    let warning = "--caustic-passes, --caustic-radius: --shading raytrace ignores them (they set the photon map's caustics, which only --caustics N or a scene's render.caustics turns on)";
    for (caustics, warned) in [(None, true), (Some("64"), false)] {
        let mut args = vec![
            "render",
            "--caustic-passes",
            "2",
            "--caustic-radius",
            "3",
            "-o",
            "c.png",
        ];
        args.extend(small);
        if let Some(n) = caustics {
            args.extend(["--caustics", n]);
        }
        let run = shadelab(d, &args);
        assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
        assert_eq!(
            run.stderr.contains(warning),
            warned,
            "{args:?}: {}",
            run.stderr
        );
    }
    let args = [
        "render",
        "--shading",
        "raytrace",
        "--caustics",
        "100",
        "--shard",
        "1/2",
        "--out",
        "a.film",
    ];
    let run = shadelab(d, &args);
    common::cli::assert_one_line_refusal(&run, &args, "its caustics do not split");
    assert!(!d.join("a.film").exists());
}
