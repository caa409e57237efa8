//! What a user waits for: the phases of a whole `render` command as
//! `--json` reports them, and the caches that make a second run warm
//! (shadelab's cache folder, with Mesa's shader cache inside it).

use crate::common;

use std::path::Path;
use std::process::Command;

use common::cli::shadelab;

const PHASES: [&str; 9] = [
    "scene_ms",
    "device_ms",
    "prepare_ms",
    "pipeline_ms",
    "upload_ms",
    "codegen_ms",
    "render_ms",
    "readback_ms",
    "encode_ms",
];

fn phases(dir: &Path, args: &[&str]) -> serde_json::Map<String, serde_json::Value> {
    let mut all = vec!["render", "--width", "64", "--height", "48", "--json"];
    all.extend_from_slice(args);
    let run = shadelab(dir, &all);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    json["phases_ms"].as_object().expect("phases_ms").clone()
}

/// Each phase is a part of the wall clock, timed one after another: none is
/// negative and together they fit inside it (a phase counted twice, or one
/// timed from the wrong start, would overflow it). Only the GPU has a
/// device and a pipeline; only the ray tracer's first use is told apart.
#[test]
fn render_json_gives_the_phases_of_the_whole_command() {
    let dir = tempfile::tempdir().unwrap();
    for (args, absent) in [
        (&["--shading", "raytrace", "-o", "r.png"][..], &[][..]),
        (
            &["--shading", "phong", "-o", "p.png"][..],
            &["codegen_ms"][..],
        ),
        (
            &["--shading", "raytrace", "--backend", "cpu", "-o", "c.png"][..],
            &[
                "device_ms",
                "prepare_ms",
                "pipeline_ms",
                "upload_ms",
                "codegen_ms",
                "readback_ms",
            ][..],
        ),
    ] {
        let p = phases(dir.path(), args);
        let wall = p["wall_ms"].as_f64().expect("wall_ms");
        let mut sum = 0.0;
        for name in PHASES {
            match p[name].as_f64() {
                Some(ms) => {
                    assert!(!absent.contains(&name), "{args:?}: {name} = {ms}");
                    assert!(ms >= 0.0, "{args:?}: {name} = {ms}");
                    sum += ms;
                }
                None => assert!(absent.contains(&name), "{args:?}: no {name}"),
            }
        }
        assert!(
            sum <= wall,
            "{args:?}: the phases add up to {sum} > wall {wall}"
        );
        assert!(p["render_ms"].as_f64().unwrap() > 0.0, "{args:?}");
    }
}

/// Runs `render` with shadelab's cache folder in `cache` and Mesa's cache
/// left to shadelab (no `MESA_SHADER_CACHE_DIR`), plus `env`.
fn render_with_cache(dir: &Path, cache: &Path, env: &[(&str, &str)]) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_shadelab"));
    command
        .args(["render", "--width", "32", "--height", "24", "-o", "x.png"])
        .current_dir(dir)
        .env("SHADELAB_VALIDATION", "1")
        .env("SHADELAB_CACHE_DIR", cache)
        .env_remove("MESA_SHADER_CACHE_DIR")
        .env_remove("MESA_SHADER_CACHE_DISABLE")
        .envs(env.iter().copied());
    let out = command.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn mesa_folders(cache: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(cache)
        .map(|entries| {
            entries
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with("mesa-"))
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

/// Mesa's shader cache lives in shadelab's cache folder, one folder a CI
/// job can keep, and a code generator configuration of its own gets a
/// folder of its own: a cache built for 256-bit vectors is never handed to
/// a run at 128 bits (where a foreign cache crashed lavapipe). A command
/// that opens no GPU leaves no folder; a user's own Mesa folder is kept.
#[test]
fn mesa_shader_cache_lives_in_the_cache_folder_per_configuration() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let diff = Command::new(env!("CARGO_BIN_EXE_shadelab"))
        .args(["diff", "missing-a.png", "missing-b.png"])
        .current_dir(dir.path())
        .env("SHADELAB_CACHE_DIR", &cache)
        .env_remove("MESA_SHADER_CACHE_DIR")
        .output()
        .unwrap();
    assert_eq!(diff.status.code(), Some(2));
    assert_eq!(mesa_folders(&cache), Vec::<String>::new(), "no GPU opened");

    render_with_cache(dir.path(), &cache, &[]);
    let first = mesa_folders(&cache);
    assert_eq!(first.len(), 1, "{first:?}");
    let filled = std::fs::read_dir(cache.join(&first[0])).unwrap().count();
    assert!(filled > 0, "Mesa wrote nothing into {}", first[0]);

    render_with_cache(dir.path(), &cache, &[]);
    assert_eq!(
        mesa_folders(&cache),
        first,
        "the same configuration reuses it"
    );

    render_with_cache(dir.path(), &cache, &[("LP_NATIVE_VECTOR_WIDTH", "128")]);
    let both = mesa_folders(&cache);
    assert_eq!(both.len(), 2, "{both:?}");

    let own = dir.path().join("own-mesa");
    render_with_cache(
        dir.path(),
        &cache,
        &[("MESA_SHADER_CACHE_DIR", own.to_str().unwrap())],
    );
    assert_eq!(mesa_folders(&cache), both, "the user's choice is kept");
    assert!(own.exists(), "Mesa used the user's folder");
}

fn count(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |d| d.count())
}

/// `warm` makes the modules and machine code that renders of its scenes
/// need, at any size: a full-size render after it writes no new module (the
/// one it needs was made, under the same constants), and Mesa's folder is
/// filled. With `--depth 0` the ray tracer's constants differ (no
/// reflection, no refraction), so a render at depth 0 finds its module too.
#[test]
fn warm_fills_the_caches_that_the_renders_of_its_scenes_use() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_shadelab"))
            .args(args)
            .current_dir(dir.path())
            .env("SHADELAB_VALIDATION", "1")
            .env("SHADELAB_CACHE_DIR", &cache)
            .env_remove("MESA_SHADER_CACHE_DIR")
            .env_remove("MESA_SHADER_CACHE_DISABLE")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let said = run(&["warm", "--shading", "phong,raytrace"]);
    assert!(
        said.contains("warmed 2 pipeline(s) for 1 scene(s)"),
        "{said}"
    );
    let modules = count(&cache.join("spirv"));
    assert_eq!(modules, 1, "the ray tracer's specialised module");
    let mesa = mesa_folders(&cache);
    assert_eq!(mesa.len(), 1);
    assert!(count(&cache.join(&mesa[0])) > 0);

    run(&["render", "--shading", "raytrace", "-o", "r.png"]);
    assert_eq!(
        count(&cache.join("spirv")),
        modules,
        "render made no module"
    );

    // Depth 0 is another pipeline: made by a warm that asks for it.
    run(&["warm", "--shading", "raytrace", "--depth", "0"]);
    assert_eq!(count(&cache.join("spirv")), modules + 1);
    run(&[
        "render",
        "--shading",
        "raytrace",
        "--depth",
        "0",
        "-o",
        "r0.png",
    ]);
    assert_eq!(count(&cache.join("spirv")), modules + 1);
}

fn auto(
    dir: &Path,
    env: &[(&str, &str)],
    args: &[&str],
) -> (serde_json::Value, std::process::Output) {
    let out = Command::new(env!("CARGO_BIN_EXE_shadelab"))
        .args(["render", "--backend", "auto"])
        .args(args)
        .current_dir(dir)
        .env("SHADELAB_VALIDATION", "1")
        .env("SHADELAB_CACHE_DIR", dir.join("cache"))
        .env("MESA_SHADER_CACHE_DIR", common::cli::mesa_cache())
        .envs(env.iter().copied())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let json = if args.contains(&"--json") {
        serde_json::from_str(text.trim()).unwrap()
    } else {
        serde_json::Value::Null
    };
    (json, out)
}

/// `--backend auto` says what it chose and why, in the text and the JSON.
/// A small image with an empty driver cache goes to the CPU reference: its
/// pilot estimates a few ms against the GPU's 600 ms of code generation, a
/// margin no machine's noise closes; the image is the CPU reference's.
#[test]
fn backend_auto_takes_the_cpu_for_small_work_on_a_cold_driver_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let cold = [("MESA_SHADER_CACHE_DISABLE", "true")];
    let small = ["--shading", "raytrace", "--width", "64", "--height", "48"];
    let (json, _) = auto(
        dir.path(),
        &cold,
        &[&small[..], &["-o", "a.png", "--json"]].concat(),
    );
    assert_eq!(json["backend"], "cpu");
    let choice = &json["backend_choice"];
    assert_eq!(choice["backend"], "cpu");
    assert_eq!(choice["driver_cache_filled"], false);
    assert!(
        choice["cpu_estimate_ms"].as_f64().unwrap() < choice["gpu_estimate_ms"].as_f64().unwrap()
    );
    assert_eq!(json["device"], "CPU reference (f64)");
    let (_, out) = auto(dir.path(), &cold, &[&small[..], &["-o", "b.png"]].concat());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("backend auto: cpu: estimated "), "{text}");
    // The same pixels as --backend cpu.
    let cpu = shadelab(
        dir.path(),
        &[
            &["render", "--backend", "cpu"][..],
            &small[..],
            &["-o", "c.png"],
        ]
        .concat(),
    );
    assert_eq!(cpu.code, 0, "{}", cpu.stderr);
    let a = image::open(dir.path().join("a.png")).unwrap().to_rgb8();
    let c = image::open(dir.path().join("c.png")).unwrap().to_rgb8();
    assert_eq!(a.as_raw(), c.as_raw());
}

/// What only the GPU can run goes to the GPU, without a pilot, and says why;
/// `--backend gpu` and `cpu` carry no choice.
#[test]
fn backend_auto_keeps_the_gpu_for_a_hook_and_gives_no_choice_otherwise() {
    let dir = tempfile::tempdir().unwrap();
    let hook = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/lighting/blinn-phong.glsl");
    let hook = hook.to_str().unwrap();
    let (json, _) = auto(
        dir.path(),
        &[],
        &[
            "--width",
            "32",
            "--height",
            "24",
            "--lighting",
            hook,
            "-o",
            "h.png",
            "--json",
        ],
    );
    assert_eq!(json["backend"], "gpu");
    assert!(json["backend_choice"]["why"]
        .as_str()
        .unwrap()
        .contains("lighting hook"));
    assert!(json["backend_choice"]["pilot_ms"].is_null());
    let run = shadelab(
        dir.path(),
        &[
            "render", "--width", "32", "--height", "24", "-o", "g.png", "--json",
        ],
    );
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(json["backend"], "gpu");
    assert!(json["backend_choice"].is_null());
}

/// With no Vulkan driver, `auto` renders on the CPU and says why, unless only
/// the GPU can render the scene (a hook), which stays an error (exit 3).
#[test]
fn backend_auto_without_a_gpu_falls_back_to_the_cpu_except_for_gpu_only_work() {
    let dir = tempfile::tempdir().unwrap();
    let no_driver = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_shadelab"))
            .args(["render", "--backend", "auto", "--json"])
            .args(args)
            .current_dir(dir.path())
            .env("SHADELAB_CACHE_DIR", dir.path().join("cache"))
            .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
            .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
            .output()
            .unwrap()
    };
    // 2100 x 2100 is past the 4M samples that skip the pilot: the GPU chosen.
    let out = no_driver(&[
        "--width",
        "2100",
        "--height",
        "2100",
        "--depth",
        "0",
        "--shading",
        "raytrace",
        "-o",
        "a.png",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["backend"], "cpu");
    assert!(json["backend_choice"]["why"]
        .as_str()
        .unwrap()
        .starts_with("no GPU to open"));
    assert!(String::from_utf8_lossy(&out.stderr).contains("rendering on the CPU reference"));
    assert!(dir.path().join("a.png").is_file());
    let hook = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/lighting/blinn-phong.glsl");
    let out = no_driver(&["--lighting", hook.to_str().unwrap(), "-o", "h.png"]);
    assert_eq!(
        out.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!dir.path().join("h.png").exists());
}

/// A cache folder that cannot be written (issue 30: Mesa printed "Failed to
/// create ... for shader cache" four times per run and shadelab said
/// nothing) gets one warning from shadelab and no lines from the driver;
/// the render still works.
#[test]
fn an_unwritable_cache_folder_is_one_warning_and_the_render_works() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("blocker"), b"a file").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_shadelab"))
        .args(["render", "--width", "16", "--height", "12", "-o", "x.png"])
        .current_dir(dir.path())
        .env("SHADELAB_VALIDATION", "1")
        .env("SHADELAB_CACHE_DIR", dir.path().join("blocker/cache"))
        .env_remove("MESA_SHADER_CACHE_DIR")
        .env_remove("MESA_SHADER_CACHE_DISABLE")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert_eq!(stderr.matches("cannot be written").count(), 1, "{stderr}");
    // The driver's own lines ("Failed to create ... for shader cache", or
    // "Cannot use ... for shader cache") are not there.
    assert!(!stderr.contains("for shader cache"), "{stderr}");
    assert!(dir.path().join("x.png").is_file());
}
