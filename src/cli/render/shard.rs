//! A render split over machines: `--shard I/N` traces the I-th of N runs
//! of a forward render's photons, or of each pixel's samples of a ray
//! trace with bounces, and writes its film (`FILE.film`: what made it,
//! then its fixed-point sums); `--merge` adds the films of shards 1 to N
//! into the image one render of all the photons or samples makes, bit for
//! bit (integer sums do not care in what order they are added).

use std::path::{Path, PathBuf};

use shadelab::backend_choice::Backend;
use shadelab::film_sums::{FilmSums, PhotonStats};
use shadelab::gpu::GpuOptions;
use shadelab::memory::MemoryLimit;
use shadelab::output::ImageFormat;
use shadelab::render::{Device, Plan, Portion, RenderRequest};
use shadelab::shading::Shading;

use super::stats::print_photons;
use crate::cli::common::batch::args::RenderArgs;
use crate::cli::common::batch::scene::{apply_overrides, load_scene};
use crate::cli::common::failure::Failure;
use crate::cli::common::run_digest::first_difference;
use shadelab::digest::fnv1a_hex;
use shadelab::render::described::{effective_settings, image_metadata};

/// The settings a film's header records that say where it ran or by what
/// path its files were named, not which render it is a part of: the scene
/// and the lighting hook are known by their contents (`scene_digest`,
/// `lighting_digest`), so that `../box.toml` and its absolute path are one
/// render.
const NOT_IDENTITY_KEYS: [&str; 5] = ["backend", "device", "driver", "scene", "lighting"];

/// `render --shard I/N --out FILE.film`: shard `(i, n)` of a forward
/// render's photons or a ray trace's samples, its film written with what
/// made it.
pub(super) fn run_shard(
    args: &RenderArgs,
    (i, n): (usize, usize),
    options: &GpuOptions,
    memory: &MemoryLimit,
) -> Result<(), Failure> {
    let (out, shading) = shard_output(args)?;
    let path = args.scenes.first().map(PathBuf::as_path);
    let (mut scene, stem) = load_scene(path, memory)?;
    apply_overrides(&mut scene, args, &[shading], true)?;
    let backend = if args.backend == "cpu" {
        Backend::Cpu
    } else {
        Backend::Gpu
    };
    let request = RenderRequest {
        portion: Portion::Shard(i as u32, n as u32),
        ..RenderRequest::new(shading, backend)
    };
    // The plan's refusals (a Whitted trace or caustics do not split)
    // before the output's folder or the device.
    let plan = Plan::new(&scene, &request)?;
    shadelab::output::prepare_output_path(&out)?;
    match backend {
        Backend::Cpu => memory.check(&stem, &scene, &[], &[shading])?,
        Backend::Gpu => memory.check(&stem, &scene, &[shading], &[])?,
    };
    let device = match backend {
        Backend::Gpu => Device::open(options)?,
        Backend::Cpu => Device::cpu_only(),
    };
    let context = device.gpu().filter(|_| backend == Backend::Gpu);
    let total = plan.part.total;
    let job = plan.part.clone();
    let label = format!("{shading}, shard {i} of {n}");
    let rendered = crate::cli::common::progress::counted(&label, |counter| {
        let request = RenderRequest {
            progress: Some(counter),
            ..request.clone()
        };
        shadelab::render::render(&device, &scene, &request)
    })?;
    let (device, driver) = match context {
        Some(c) => (c.info.name.clone(), Some(c.info.driver.clone())),
        None => ("CPU reference (f64)".to_string(), None),
    };
    let settings = effective_settings(
        path,
        shading,
        &scene,
        backend,
        &rendered,
        &device,
        driver.as_deref(),
    );
    let film = rendered
        .film
        .as_ref()
        .expect("a render that sums into a film");
    let header = serde_json::json!({
        "stem": stem,
        "scene_digest": scene_digest(path)?,
        "lighting_digest": scene.lighting_hook.as_ref().map(|h| fnv1a_hex(h.source.as_bytes())),
        "settings": settings,
        "shard": [i, n],
        "range": [job.range.start, job.range.end],
        "stats": film.photons,
    });
    let bytes = film.film.to_file_bytes(&header);
    shadelab::output::write_atomically(&out, &bytes)?;
    let what = if shading == Shading::Forward {
        "photons"
    } else {
        "samples"
    };
    println!(
        "wrote {} (shard {i} of {n}: {what} {} to {} of {total}, {:.1} ms on {device})",
        out.display(),
        job.range.start,
        job.range.end,
        rendered.timings.total_ms,
    );
    if let Some(photons) = &film.photons {
        print_photons(photons);
    }
    Ok(())
}

/// `--out FILE.film`, required with `--shard`, and the mode: one render,
/// forward or ray tracing (with bounces, checked once the scene is in).
fn shard_output(args: &RenderArgs) -> Result<(PathBuf, Shading), Failure> {
    let shading = match args.modes()[..] {
        [mode @ (Shading::Forward | Shading::Raytrace)]
            if args.scenes.len() <= 1 && !args.is_batch() =>
        {
            mode
        }
        _ => {
            return Err(Failure::usage(
                "--shard splits one render's photons or samples: give one scene, --shading forward (or raytrace with --bounces 1 or more) and --out FILE.film".into(),
            ))
        }
    };
    match &args.out {
        Some(out) if out.extension().is_some_and(|e| e == "film") => Ok((out.clone(), shading)),
        _ => Err(Failure::usage(
            "--shard writes a film for --merge: give --out FILE.film".into(),
        )),
    }
}

/// A digest of the scene file's bytes, so that films of two versions of a
/// file are not added together; the built-in scene is its name.
fn scene_digest(path: Option<&Path>) -> Result<String, Failure> {
    match path {
        None => Ok("built-in default scene".into()),
        Some(p) => {
            let bytes = std::fs::read(p)
                .map_err(|e| Failure::usage(format!("cannot read {}: {e}", p.display())))?;
            Ok(fnv1a_hex(&bytes))
        }
    }
}

/// One film read back, with the header that says what made it.
struct Part {
    path: PathBuf,
    header: serde_json::Value,
    film: FilmSums,
}

/// `render --merge A.film B.film ... --out IMAGE`: the shards' films added,
/// after checking they are shards 1 to N of one render, each once.
pub(super) fn run_merge(args: &RenderArgs) -> Result<(), Failure> {
    let Some(out) = &args.out else {
        return Err(Failure::usage(
            "--merge adds films into one image: give --out FILE.png or FILE.exr".into(),
        ));
    };
    ImageFormat::from_path(out)?;
    shadelab::output::prepare_output_path(out)?;
    let parts = args
        .merge
        .iter()
        .map(|path| read_part(path))
        .collect::<Result<Vec<_>, _>>()?;
    check_parts(&parts)?;
    let mut film = parts[0].film.clone();
    // Forward shards count their photons; a ray trace's have no counts.
    let mut stats: Option<PhotonStats> = None;
    for part in &parts {
        if !std::ptr::eq(part, &parts[0]) {
            film.add(&part.film).map_err(Failure::usage)?;
        }
        let s: Option<PhotonStats> = serde_json::from_value(part.header["stats"].clone())
            .map_err(|e| Failure::usage(format!("{}: its counts: {e}", part.path.display())))?;
        if let Some(s) = s {
            stats.get_or_insert_with(PhotonStats::default).add(&s);
        }
    }
    let image = film.image();
    let first = &parts[0].header;
    let devices = distinct(&parts, "device").join(", ");
    let stem = first["stem"].as_str().unwrap_or("merged");
    let metadata = image_metadata(stem, &devices, &first["settings"]);
    shadelab::output::write_image_with(&image, out, &metadata)?;
    let shading = first["settings"]["shading"].as_str().unwrap_or("unknown");
    println!(
        "wrote {} ({}x{}, {shading}, {} shards merged, rendered on {devices})",
        out.display(),
        image.width,
        image.height,
        parts.len()
    );
    if let Some(stats) = &stats {
        print_photons(stats);
    }
    Ok(())
}

fn read_part(path: &Path) -> Result<Part, Failure> {
    let bytes = std::fs::read(path)
        .map_err(|e| Failure::usage(format!("cannot read {}: {e}", path.display())))?;
    let (header, film) = FilmSums::from_file_bytes(&bytes)
        .map_err(|why| Failure::usage(format!("{}: {why}", path.display())))?;
    Ok(Part {
        path: path.to_owned(),
        header,
        film,
    })
}

/// The settings of a part that say which render it belongs to (the
/// binary's version among them: another version may trace other samples).
fn render_identity(header: &serde_json::Value) -> serde_json::Value {
    let mut settings = header["settings"].clone();
    if let Some(map) = settings.as_object_mut() {
        for key in NOT_IDENTITY_KEYS {
            map.remove(key);
        }
    }
    serde_json::json!({
        "settings": settings,
        "scene_digest": header["scene_digest"],
        "lighting_digest": header["lighting_digest"],
    })
}

/// Refuses parts of different renders, and a set that is not shards 1 to
/// N each once; warns where they ran on different machines.
fn check_parts(parts: &[Part]) -> Result<(), Failure> {
    let first = &parts[0];
    let identity = render_identity(&first.header);
    for part in &parts[1..] {
        if let Some(why) = first_difference(&identity, &render_identity(&part.header), "") {
            return Err(Failure::usage(format!(
                "{} and {} are parts of different renders ({why}): merge only the shards of one render",
                first.path.display(),
                part.path.display()
            )));
        }
    }
    let shard = |p: &Part| -> Option<(u64, u64)> {
        let s = p.header["shard"].as_array()?;
        Some((s.first()?.as_u64()?, s.get(1)?.as_u64()?))
    };
    let mut shards = Vec::new();
    for part in parts {
        let s = shard(part).ok_or_else(|| {
            Failure::usage(format!(
                "{}: its header names no shard",
                part.path.display()
            ))
        })?;
        shards.push(s);
    }
    let n = shards[0].1;
    let mut seen: Vec<u64> = shards.iter().map(|s| s.0).collect();
    seen.sort_unstable();
    let complete: Vec<u64> = (1..=n).collect();
    if shards.iter().any(|s| s.1 != n) || seen != complete {
        let have: Vec<String> = seen.iter().map(|i| format!("{i}/{n}")).collect();
        return Err(Failure::usage(format!(
            "--merge needs shards 1/{n} to {n}/{n} of one render, each once; got {}",
            have.join(", ")
        )));
    }
    for key in ["backend", "device", "driver"] {
        if distinct(parts, key).len() > 1 {
            eprintln!(
                "shadelab: warning: the shards ran on different {key}s ({}): the image is right, but not the bits one machine makes (f32 rounding differs between them)",
                distinct(parts, key).join(", ")
            );
            break;
        }
    }
    Ok(())
}

/// The distinct values of settings key `key` over the parts, in order.
fn distinct(parts: &[Part], key: &str) -> Vec<String> {
    let mut values: Vec<String> = Vec::new();
    for part in parts {
        let v = part.header["settings"][key]
            .as_str()
            .unwrap_or("unknown")
            .to_string();
        if !values.contains(&v) {
            values.push(v);
        }
    }
    values
}
