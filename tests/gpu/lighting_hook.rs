//! The lighting hook (`--lighting FILE`): compiled into all four GPU modes,
//! used by each, and refused with exit status 2 and a message that names
//! the file when it does not compile or does not define the hook.

use crate::common;

use std::path::PathBuf;
use std::sync::Arc;

use common::cli::shadelab;
use common::*;
use glam::DVec3;
use shadelab::scene::{tessellate, LightingHook, Object, Scene, Shape};
use shadelab::shading::Shading;
use shadelab::LinearImage;

const MODES: [Shading; 4] = [
    Shading::Flat,
    Shading::Gouraud,
    Shading::Phong,
    Shading::Raytrace,
];

fn example(name: &str) -> Arc<LightingHook> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("examples/lighting")
        .join(name);
    Arc::new(LightingHook::load(&path).unwrap())
}

/// A glossy sphere lit from the side: the specular highlight, where the
/// hooks below differ, covers many pixels.
fn glossy_sphere() -> Scene {
    let mut s = scene(96, 96, 30.0);
    s.materials[0].ks = 0.8;
    s.materials[0].p = 8.0;
    s.objects.push(Object {
        shape: Shape::Sphere {
            center: DVec3::ZERO,
            radius: 2.0,
            segments: 24,
        },
        material: 0,
    });
    s
}

fn max_difference(a: &LinearImage, b: &LinearImage) -> f32 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
        .fold(0.0, f32::max)
}

#[test]
fn the_lectures_formula_as_a_hook_renders_as_the_built_in_one_in_every_mode() {
    let context = gpu();
    let built_in = glossy_sphere();
    let mut hooked = glossy_sphere();
    hooked.lighting_hook = Some(example("phong.glsl"));
    for mode in MODES {
        let a = render(&context, &built_in, mode);
        let b = render(&context, &hooked, mode);
        // The same source text compiled again: only the compiler's freedom
        // to contract a*b+c differently could separate them, a few ulps of
        // values near 1.
        let diff = max_difference(&a, &b);
        assert!(diff <= 1e-5, "{mode}: the hook differs by {diff}");
    }
    // The same sphere as a mesh big enough for the ray tracer's 4-wide
    // walk, a module of its own that the hook is compiled into too (its
    // defines kept: the binary walk on wide nodes would lose the sphere).
    let mut built_in = glossy_sphere();
    built_in.objects[0].shape = Shape::Mesh(tessellate(&built_in.objects[0].shape));
    let rt = shadelab::rt_scene::RtScene::new(&built_in);
    let kinds = shadelab::gpu::raytrace::bvh::BvhKinds::of(&rt);
    assert!(shadelab::gpu::raytrace::bvh::gpu_bvh(&rt, kinds)
        .unwrap()
        .wide
        .is_some());
    let mut hooked = built_in.clone();
    hooked.lighting_hook = Some(example("phong.glsl"));
    let a = render(&context, &built_in, Shading::Raytrace);
    let b = render(&context, &hooked, Shading::Raytrace);
    let diff = max_difference(&a, &b);
    assert!(diff <= 1e-5, "the wide walk: the hook differs by {diff}");
    let lit = a.pixels.iter().filter(|p| p[0] > 0.1).count();
    assert!(
        lit > a.pixels.len() / 10,
        "the mesh must fill the view: {lit} lit pixels"
    );
}

#[test]
fn a_blinn_phong_hook_changes_every_mode() {
    let context = gpu();
    let built_in = glossy_sphere();
    let mut hooked = glossy_sphere();
    hooked.lighting_hook = Some(example("blinn-phong.glsl"));
    for mode in MODES {
        let a = render(&context, &built_in, mode);
        let b = render(&context, &hooked, mode);
        // With p = 8 the half-vector highlight is far wider than Phong's:
        // a whole step of intensity on some pixel, not rounding.
        let diff = max_difference(&a, &b);
        assert!(diff > 0.05, "{mode}: the hook changed nothing ({diff})");
    }
}

/// Writes `hook` to a fresh folder and renders the default scene with it;
/// returns the run and whether the output exists.
fn render_with_hook(hook: &str, shading: &str) -> (common::cli::Run, bool) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("hook.glsl"), hook).unwrap();
    let run = shadelab(
        dir.path(),
        &[
            "render",
            "--shading",
            shading,
            "--lighting",
            "hook.glsl",
            "--width",
            "32",
            "--height",
            "24",
            "--out",
            "out.png",
        ],
    );
    let written = dir.path().join("out.png").exists();
    (run, written)
}

#[test]
fn a_hook_with_a_syntax_error_is_refused_naming_its_file_and_line() {
    let hook = "// line 1\nvec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) {\n    return intensity * ;\n}\n";
    for shading in ["phong", "raytrace"] {
        let (run, written) = render_with_hook(hook, shading);
        assert_eq!(run.code, 2, "{shading}: {}", run.stderr);
        assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
        assert!(run.stderr.contains("hook.glsl:3"), "{}", run.stderr);
        assert!(!written, "{shading}: an image was written");
    }
}

#[test]
fn a_hook_with_the_wrong_signature_is_refused_naming_the_expected_one() {
    let hook = "vec3 shade_light(vec3 N, vec3 L) {\n    return vec3(dot(N, L));\n}\n";
    let (run, written) = render_with_hook(hook, "gouraud");
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr.contains(
            "vec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k)"
        ),
        "{}",
        run.stderr
    );
    assert!(!written);
}

#[test]
fn a_hook_that_declares_its_own_binding_is_refused() {
    let hook = "layout(std430, set = 0, binding = 7) readonly buffer Extra { vec4 extra[]; };\nvec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) {\n    return extra[0].rgb;\n}\n";
    let (run, written) = render_with_hook(hook, "phong");
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("binding 7"), "{}", run.stderr);
    assert!(!written);
}

#[test]
fn a_compiled_hook_is_cached_and_a_damaged_cache_entry_is_compiled_again() {
    let dir = tempfile::tempdir().unwrap();
    let hook = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/lighting/blinn-phong.glsl"
    );
    let render = |out: &str| {
        let run = shadelab(
            dir.path(),
            &[
                "render",
                "--lighting",
                hook,
                "--width",
                "32",
                "--height",
                "24",
                "--out",
                out,
            ],
        );
        assert_eq!(run.code, 0, "{}", run.stderr);
        std::fs::read(dir.path().join(out)).unwrap()
    };
    let first = render("a.png");
    let cached: Vec<PathBuf> = std::fs::read_dir(dir.path().join("cache/hooks"))
        .expect("a cache folder")
        .map(|e| e.unwrap().path())
        .collect();
    // Phong's fragment stage is the one stage of the mode with the formula.
    assert_eq!(cached.len(), 1, "{cached:?}");
    assert_eq!(render("b.png"), first, "from the cache, the same image");
    std::fs::write(&cached[0], b"not a module").unwrap();
    assert_eq!(render("c.png"), first, "a damaged entry is a miss");
    assert!(
        std::fs::read(&cached[0]).unwrap().len() > 100,
        "and is written anew"
    );
}

#[test]
fn a_missing_hook_file_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let run = shadelab(
        dir.path(),
        &["render", "--lighting", "nowhere.glsl", "--out", "out.png"],
    );
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("nowhere.glsl"), "{}", run.stderr);
    assert!(!dir.path().join("out.png").exists());
}

#[test]
fn bench_names_the_hook_it_timed() {
    let dir = tempfile::tempdir().unwrap();
    let hook = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/lighting/schlick-pow.glsl"
    );
    let args = [
        "bench",
        "--lighting",
        hook,
        "--shading",
        "phong",
        "--runs",
        "1",
        "--width",
        "32",
        "--height",
        "24",
    ];
    let text = shadelab(dir.path(), &args);
    assert_eq!(text.code, 0, "{}", text.stderr);
    assert!(
        text.stdout.contains(&format!("lighting hook: {hook}")),
        "{}",
        text.stdout
    );
    let mut with_json = args.to_vec();
    with_json.push("--json");
    let run = shadelab(dir.path(), &with_json);
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert_eq!(json["lighting"], hook);
    let mut built_in = with_json.clone();
    built_in.drain(1..3);
    let run = shadelab(dir.path(), &built_in);
    let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
    assert!(json["lighting"].is_null(), "{json}");
}

fn mean(image: &LinearImage) -> f64 {
    let sum: f64 = image
        .pixels
        .iter()
        .map(|p| f64::from(p[0] + p[1] + p[2]))
        .sum();
    sum / image.pixels.len() as f64
}

#[test]
fn an_unnormalised_normal_darkens_phong_and_leaves_gouraud_alone() {
    let context = gpu();
    let mut coarse = glossy_sphere();
    if let Shape::Sphere { segments, .. } = &mut coarse.objects[0].shape {
        *segments = 8;
    }
    let mut hooked = coarse.clone();
    hooked.lighting_hook = Some(example("unnormalised-normal.glsl"));
    let (a, b) = (
        render(&context, &coarse, Shading::Phong),
        render(&context, &hooked, Shading::Phong),
    );
    // Interpolated normals are shorter than 1 inside each triangle: the
    // diffuse term falls with their length (by up to 1 - cos 22.5 deg,
    // 8 %, at 8 segments), so Phong darkens.
    assert!(max_difference(&a, &b) > 0.02, "{}", max_difference(&a, &b));
    assert!(mean(&b) < mean(&a), "{} vs {}", mean(&b), mean(&a));
    // Gouraud shades at the vertices, whose normals are unit already.
    let (c, d) = (
        render(&context, &coarse, Shading::Gouraud),
        render(&context, &hooked, Shading::Gouraud),
    );
    assert!(max_difference(&c, &d) <= 1e-5, "{}", max_difference(&c, &d));
}

/// A hook that returns NaN (issue 30: `sqrt(-1.0 - d)`) is never a quiet
/// success: `render` writes the image (to see where) and exits 1 naming the
/// count, in every mode and for PNG (whose 8-bit target would have turned
/// NaN into a colour) as for EXR; `compare` warns about the variant.
#[test]
fn a_hook_that_returns_nan_fails_the_render_and_is_counted() {
    let dir = tempfile::tempdir().unwrap();
    let hook = dir.path().join("nan.glsl");
    std::fs::write(
        &hook,
        "vec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) {\n    return intensity * sqrt(-1.0 - d);\n}\n",
    )
    .unwrap();
    let hook = hook.to_str().unwrap();
    for (shading, out) in [
        ("phong", "p.png"),
        ("gouraud", "g.exr"),
        ("raytrace", "r.png"),
    ] {
        let run = common::cli::shadelab(
            dir.path(),
            &[
                "render",
                "--width",
                "32",
                "--height",
                "24",
                "--shading",
                shading,
                "--lighting",
                hook,
                "-o",
                out,
                "--json",
            ],
        );
        assert_eq!(run.code, 1, "{shading}: {}", run.stderr);
        assert!(
            run.stderr
                .contains("pixels are not finite (NaN or infinity)"),
            "{}",
            run.stderr
        );
        assert!(
            run.stderr.contains("the lighting hook returned them"),
            "{}",
            run.stderr
        );
        let json: serde_json::Value = serde_json::from_str(run.stdout.trim()).unwrap();
        let n = json["non_finite_pixels"].as_u64().unwrap();
        assert!(n > 0 && n <= 32 * 24, "{shading}: {n}");
        assert!(dir.path().join(out).is_file());
    }
    let fine = common::cli::shadelab(
        dir.path(),
        &[
            "render", "--width", "32", "--height", "24", "-o", "ok.png", "--json",
        ],
    );
    assert_eq!(fine.code, 0, "{}", fine.stderr);
    let json: serde_json::Value = serde_json::from_str(fine.stdout.trim()).unwrap();
    assert_eq!(json["non_finite_pixels"], 0);
    let variants = format!("phong:lighting={hook};phong");
    let cmp = common::cli::shadelab(
        dir.path(),
        &[
            "compare",
            "--width",
            "32",
            "--height",
            "24",
            "--runs",
            "1",
            "--variants",
            &variants,
            "--out",
            "c",
        ],
    );
    assert!(
        cmp.stderr.contains("pixels are not finite"),
        "{}",
        cmp.stderr
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("c/report.json")).unwrap())
            .unwrap();
    assert!(report["variants"][0]["non_finite_pixels"].as_u64().unwrap() > 0);
    assert_eq!(report["variants"][1]["non_finite_pixels"], 0);
}

/// The endless loop, summing so that no compiler drops it.
const ENDLESS: &str = "vec3 shade_light(vec3 N, vec3 V, vec3 L, float d, vec3 intensity, Surface m, float k) {\n    float sum = 0.0;\n    for (int i = 0; i >= 0; i++) { sum += d; }\n    return intensity * sum;\n}\n";

/// A hook that never returns cannot be interrupted on the device: the
/// watchdog gives its submission up at `--watchdog`, and the command ends
/// with one line that names the hook, exit status 3 and no image, in a
/// single render and in a run of cases (check), where nothing else can run
/// on the stuck device.
#[test]
fn an_endless_hook_is_stopped_by_the_watchdog_with_exit_3_and_no_image() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("endless.glsl"), ENDLESS).unwrap();
    let size = ["--width", "24", "--height", "16"];
    for (command, out) in [("render", "e.png"), ("check", "checked")] {
        let mut args = vec![command, "--lighting", "endless.glsl", "--watchdog", "2"];
        args.extend(size);
        match command {
            "render" => args.extend(["-o", out]),
            _ => args.extend(["--shading", "phong,gouraud", "--out", out]),
        }
        let started = std::time::Instant::now();
        let run = common::cli::shadelab_within(d, &args, std::time::Duration::from_secs(90))
            .unwrap_or_else(|| panic!("{args:?} still ran after 90 s: no watchdog"));
        let took = started.elapsed().as_secs_f64();
        assert_eq!(run.code, 3, "{args:?}: {}", run.stderr);
        let lines: Vec<&str> = run
            .stderr
            .lines()
            .filter(|l| l.starts_with("shadelab: error"))
            .collect();
        assert_eq!(lines.len(), 1, "{}", run.stderr);
        assert!(
            lines[0].contains("watchdog's 2 s") && lines[0].contains("lighting hook endless.glsl"),
            "{}",
            run.stderr
        );
        // Pipelines are built before the first submission; the rest is
        // the limit itself.
        assert!(took < 60.0, "{args:?} took {took:.1} s");
        if command == "render" {
            assert!(!d.join(out).exists(), "an image was written");
        }
    }
}

/// The watchdog changes nothing in a render that ends: the limit off (0)
/// or the default gives the same image, and a limit out of range is one
/// line, exit 2.
#[test]
fn the_watchdog_leaves_a_render_that_ends_alone() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let hook = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/lighting/phong.glsl");
    let hook = hook.to_str().unwrap();
    let base = [
        "render",
        "--lighting",
        hook,
        "--shading",
        "raytrace",
        "--width",
        "32",
        "--height",
        "24",
    ];
    let mut images = Vec::new();
    for (watchdog, out) in [(None, "default.png"), (Some("0"), "off.png")] {
        let mut args = base.to_vec();
        if let Some(seconds) = watchdog {
            args.extend(["--watchdog", seconds]);
        }
        args.extend(["-o", out]);
        let run = shadelab(d, &args);
        assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
        images.push(shadelab::output::read_image(&d.join(out)).unwrap());
    }
    assert_eq!(images[0].pixels, images[1].pixels);
    assert!(mean(&images[0]) > 0.01, "a lit image");
    for bad in ["-1", "1e9", "nan"] {
        let args = ["render", "--watchdog", bad, "-o", "bad.png"];
        let run = shadelab(d, &args);
        common::cli::assert_one_line_refusal(&run, &args, "--watchdog");
    }
}
