//! The backward tracer with diffuse bounces sums its samples in fixed
//! point (`film_sums`, `shaders/include/rt_sample_sums.glsl`), so a render
//! split into runs of each pixel's samples adds up to the whole render bit
//! for bit: batches on one device, shards on many (`render --shard`,
//! `--merge`), on the GPU and on its CPU twin. The batches also give
//! progress, a time budget (`--time`) and a refusal, after the first
//! batch, of a render that would take hours.

use common::cli::{assert_one_line_refusal, render_mean, shadelab, shadelab_with};
use shadelab::backend_choice::Backend;
use shadelab::film_sums::FilmSums;
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::render::{render, Device, FilmRender, Portion, RenderRequest};
use shadelab::scene::Scene;
use shadelab::shading::Shading;

use crate::common;

const BOX: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/diffuse-box.toml");

fn diffuse_box(width: u32, height: u32, samples: u32) -> Scene {
    let mut scene = shadelab::scene::load(std::path::Path::new(BOX)).unwrap();
    scene.image.width = width;
    scene.image.height = height;
    scene.render.samples = samples;
    scene
}

/// The film of samples `range` of `scene`'s pixels, on the GPU where
/// `context` is given, else on the CPU twin.
fn film_of(
    context: Option<&std::sync::Arc<GpuContext>>,
    scene: &Scene,
    range: (u32, u32),
) -> FilmSums {
    let backend = if context.is_some() {
        Backend::Gpu
    } else {
        Backend::Cpu
    };
    let request = RenderRequest {
        portion: Portion::Range(range.0..range.1),
        ..RenderRequest::new(Shading::Raytrace, backend)
    };
    let device = Device::from(context.cloned());
    let rendered = render(&device, scene, &request).unwrap();
    let FilmRender { film, traced, .. } = rendered.film.expect("bounces sum into a film");
    assert_eq!(traced, u64::from(range.1 - range.0));
    film
}

/// Samples 0..3, 3..4 and 4..11 of 11 add up to the film of all 11, sum
/// for sum, on the GPU and on the twin; and the whole render's image is
/// that film's. A shader that summed in floats, or keyed a sample's random
/// numbers by its place in the part rather than in the pixel, fails here
/// (the parts' sums would differ in their last bits, or the paths would).
#[test]
fn parts_of_the_samples_add_up_to_the_whole_render_bit_for_bit() {
    let context = GpuContext::new(&GpuOptions::default()).unwrap();
    let scene = diffuse_box(40, 30, 11);
    for on in [Some(&context), None] {
        let whole = film_of(on, &scene, (0, 11));
        let mut added = film_of(on, &scene, (4, 11));
        for range in [(0, 3), (3, 4)] {
            added.add(&film_of(on, &scene, range)).unwrap();
        }
        let where_ = if on.is_some() { "GPU" } else { "CPU twin" };
        assert!(
            added == whole,
            "{where_}: the parts' sums differ from the whole's"
        );
        if on.is_some() {
            let image = crate::common::render_gpu(&context, &scene, Shading::Raytrace).unwrap();
            assert_eq!(image.image.pixels, whole.image().pixels);
        }
    }
}

/// `render --shard I/N --out FILE.film` three times and `--merge` make the
/// EXR one render makes, byte for byte, on the GPU and on the CPU twin; a
/// Whitted trace (no bounces), whose mean is summed in floats, is refused
/// in one line.
#[test]
fn sample_shards_merge_into_the_unsharded_image() {
    let dir = tempfile::tempdir().unwrap();
    let common = [
        "--shading",
        "raytrace",
        "--samples",
        "10",
        "--width",
        "48",
        "--height",
        "36",
    ];
    for backend in ["gpu", "cpu"] {
        let render = |extra: &[&str]| {
            let mut args = vec!["render", BOX, "--backend", backend];
            args.extend_from_slice(&common);
            args.extend_from_slice(extra);
            let run = shadelab(dir.path(), &args);
            assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
            run
        };
        for i in 1..=3 {
            render(&[
                "--shard",
                &format!("{i}/3"),
                "--out",
                &format!("{backend}{i}.film"),
            ]);
        }
        render(&["--out", &format!("{backend}-whole.exr")]);
        let merged = format!("{backend}-merged.exr");
        let films = [2, 3, 1].map(|i| format!("{backend}{i}.film"));
        let mut merge = vec!["render", "--merge"];
        merge.extend(films.iter().map(String::as_str));
        merge.extend(["--out", &merged]);
        let run = shadelab(dir.path(), &merge);
        assert_eq!(run.code, 0, "{}", run.stderr);
        assert!(
            run.stdout.contains("raytrace, 3 shards merged"),
            "{}",
            run.stdout
        );
        let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
        assert!(
            read(&merged) == read(&format!("{backend}-whole.exr")),
            "{backend}: merged and whole images differ"
        );
    }
    let glass = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/rt-glass.toml");
    let whitted = [
        "render",
        glass,
        "--shading",
        "raytrace",
        "--shard",
        "1/2",
        "--out",
        "w.film",
    ];
    let run = shadelab(dir.path(), &whitted);
    assert_one_line_refusal(&run, &whitted, "--bounces 1 or more");
    assert!(!dir.path().join("w.film").exists());
}

/// `--time` stops a ray trace with bounces between batches of samples and
/// writes the estimate of the samples traced: its mean is the full
/// render's within 3% (each pixel's mean of at least a few samples; the
/// image's mean over 19200 pixels is within 0.5% of the truth, where an
/// unscaled image would be darker by the share untraced, over 90% here).
/// The CPU reference traces every sample, so `--time` with it is refused.
#[test]
fn a_time_budget_stops_a_ray_trace_at_the_estimate_of_its_samples() {
    let dir = tempfile::tempdir().unwrap();
    let size = ["--width", "160", "--height", "120", "--shading", "raytrace"];
    let mean_of = |extra: &[&str], out: &str| {
        let mut args = vec!["render", BOX, "--out", out];
        args.extend_from_slice(&size);
        args.extend_from_slice(extra);
        render_mean(dir.path(), &args, out)
    };
    let (full, _) = mean_of(&["--samples", "32"], "full.exr");
    let (budget, stderr) = mean_of(&["--samples", "1024", "--time", "0.3"], "budget.exr");
    assert!(stderr.contains("stopped after"), "{stderr}");
    assert!(stderr.contains("samples per pixel"), "{stderr}");
    assert!(
        ((budget - full) / full).abs() < 0.03,
        "{budget} against {full}"
    );
    let cpu = [
        "render",
        BOX,
        "--shading",
        "raytrace",
        "--backend",
        "cpu",
        "--time",
        "1",
    ];
    assert_one_line_refusal(&shadelab(dir.path(), &cpu), &cpu, "leave out --backend");
    let whitted = ["render", "--shading", "raytrace", "--time", "1"];
    assert_one_line_refusal(
        &shadelab(dir.path(), &whitted),
        &whitted,
        "--bounces 1 or more",
    );
}

/// A render whose first batch says it would run past the limit is refused
/// in one line with the figure, exit 2, and writes nothing: here the limit
/// is lowered to a second (`SHADELAB_LONGEST_RENDER_S`) so that the test
/// is quick on any machine, for a ray trace with bounces and a forward
/// render. Progress is counted in samples per pixel.
#[test]
fn a_render_projected_past_the_limit_is_refused_with_the_figure() {
    let dir = tempfile::tempdir().unwrap();
    let env = [
        ("SHADELAB_LONGEST_RENDER_S", "1"),
        ("SHADELAB_PROGRESS_SECONDS", "0"),
    ];
    let size = ["--width", "320", "--height", "240"];
    let cases: [&[&str]; 2] = [
        &["--shading", "raytrace", "--samples", "1024"],
        &["--shading", "forward", "--photons", "4000000000"],
    ];
    for case in cases {
        let mut args = vec!["render", BOX, "--out", "long.exr"];
        args.extend_from_slice(&size);
        args.extend_from_slice(case);
        let run = shadelab_with(dir.path(), &args, &env);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        let last = run.stderr.lines().last().unwrap_or_default();
        assert!(last.contains("would take about"), "{}", run.stderr);
        assert!(last.contains("--time SECONDS"), "{}", run.stderr);
        assert!(!dir.path().join("long.exr").exists());
        if case[1] == "raytrace" {
            assert!(run.stderr.contains("samples per pixel:"), "{}", run.stderr);
        }
    }
}

/// Films name what they are a part of by content: a shard of `../box.toml`
/// and one of the same file by its absolute path merge. Films that cannot
/// be added are refused in one line, exit 2, and nothing is written: one
/// with 4 bytes of its sums overwritten (named, as damaged), and a shard
/// of another sample count (the setting named, with both values).
#[test]
fn films_merge_by_scene_content_and_a_damaged_or_foreign_one_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    std::fs::copy(BOX, dir.path().join("box.toml")).unwrap();
    let absolute = dir.path().join("box.toml");
    let absolute = absolute.to_str().unwrap();
    let shard = |scene: &str, i: u32, samples: &str, out: &str| {
        let args = [
            "render",
            scene,
            "--backend",
            "cpu",
            "--shading",
            "raytrace",
            "--samples",
            samples,
            "--width",
            "16",
            "--height",
            "12",
            "--shard",
            &format!("{i}/2"),
            "--out",
            out,
        ];
        let run = shadelab(&sub, &args);
        assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
    };
    shard("../box.toml", 1, "6", "1.film");
    shard(absolute, 2, "6", "2.film");
    shard(absolute, 2, "8", "2-of-8.film");
    let merge = |films: &[&'static str]| {
        let mut args = vec!["render", "--merge"];
        args.extend_from_slice(films);
        args.extend(["--out", "merged.exr"]);
        (shadelab(&sub, &args), args)
    };
    let (run, _) = merge(&["1.film", "2.film"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    std::fs::remove_file(sub.join("merged.exr")).unwrap();

    let (run, args) = merge(&["1.film", "2-of-8.film"]);
    assert_one_line_refusal(&run, &args, "settings.samples is 6 against 8");
    assert!(run.stderr.contains("2-of-8.film"), "{}", run.stderr);

    let mut bytes = std::fs::read(sub.join("2.film")).unwrap();
    let at = bytes.len() - 8 * 40;
    bytes[at..at + 4].copy_from_slice(&[0xde, 0xad, 0xbe, 0xef]);
    std::fs::write(sub.join("damaged.film"), &bytes).unwrap();
    let (run, args) = merge(&["1.film", "damaged.film"]);
    assert_one_line_refusal(&run, &args, "damaged.film: its sums are damaged");
    assert!(!sub.join("merged.exr").exists());
}

/// Under `--error` each batch is traced a stream at a time (the even
/// samples, then the odd, two dispatches that step by 2), so that the
/// budget reads each stream's part of the film apart. The film it stops
/// with is the film of the same samples traced in one run, sum for sum: a
/// shader that stepped by 1 in a stream's dispatch, or a host that dealt a
/// stream's first sample wrongly, traces samples twice or not at all and
/// fails here. (The run of one step is the one the CPU twin is held to.)
#[test]
fn an_error_budget_traces_a_stream_at_a_time_and_sums_the_same_samples() {
    let context = GpuContext::new(&GpuOptions::default()).unwrap();
    let scene = diffuse_box(40, 30, 1024);
    let request = RenderRequest {
        error: Some(0.2),
        ..RenderRequest::gpu(Shading::Raytrace)
    };
    let budgeted = render(&common::device(&context), &scene, &request)
        .unwrap()
        .film
        .expect("bounces sum into a film");
    let traced = budgeted.traced as u32;
    // Batches of 16 under this budget: more than one, so that both streams
    // of several batches were traced, and far from all 1024.
    assert!((32..512).contains(&traced), "stopped at {traced}");
    assert!(budgeted.estimated_rmse.is_some_and(|e| e <= 0.2));
    assert!(
        budgeted.film == film_of(Some(&context), &scene, (0, traced)),
        "the budgeted film differs from samples 0..{traced} traced at once"
    );
}
