//! One clear error line for each kind of bad input, exit status 2, and no
//! output file left behind: scene files, meshes, numbers, sizes and the
//! arguments of every command.

use std::path::{Path, PathBuf};

use crate::common;
use crate::common::cli::shadelab;

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
