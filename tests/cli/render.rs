//! The `shadelab` binary's renders as users and scripts drive them: the
//! images and their names, the device and driver named (`info`, `bench`),
//! the settings a written image carries, the ray tracer's options and
//! bounces, and a render stopped or piped that leaves nothing half-made.

use crate::common;
use crate::common::cli::shadelab;

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
