//! `shadelab check`: every scene in every mode, GPU against the CPU
//! reference; images for CI to keep, a verdict line per case, optionally a
//! JUnit report; exit status 1 when any case fails.

use std::path::{Path, PathBuf};

use clap::Args;
use shadelab::check::{check, scaled, CheckOutcome, CheckThresholds};
use shadelab::gpu::{GpuContext, GpuOptions};
use shadelab::junit::{self, TestCase};
use shadelab::memory::MemoryLimit;
use shadelab::metrics::heatmap::flip_heatmap;
use shadelab::output::{write_atomically, write_image};
use shadelab::shading::Shading;

use super::args::{ImageSize, LightingArg, TraversalArg};
use super::render::load_scene;
use super::Failure;

#[derive(Args)]
pub struct CheckArgs {
    /// Scene files; the built-in default scene if none.
    scenes: Vec<PathBuf>,
    /// Modes to check, comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "flat,gouraud,phong,raytrace"
    )]
    shading: Vec<Shading>,
    /// Folder for <scene>/<mode>-{expected,actual,diff}.png.
    #[arg(long, default_value = "check-out")]
    out: PathBuf,
    /// Also write a JUnit XML report here.
    #[arg(long)]
    junit: Option<PathBuf>,
    /// Print one JSON object with every figure on stdout.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    size: ImageSize,
    #[command(flatten)]
    lighting: LightingArg,
    #[command(flatten)]
    traversal: TraversalArg,
    /// Largest error allowed at an interior pixel [default: 1e-3, and 5e-3
    /// for raytrace].
    #[arg(long)]
    interior_max_abs: Option<f64>,
    /// Largest share (0-1) of the image allowed to be edge pixels that differ
    /// by more than 0.01 [default: 5e-4, and 5e-3 for raytrace].
    #[arg(long)]
    edge_fraction: Option<f64>,
    /// Largest mean FLIP allowed over the image [default: 1e-3, and 5e-3 for
    /// raytrace].
    #[arg(long)]
    flip_mean: Option<f64>,
}

fn io_failure(path: &Path, e: impl std::fmt::Display) -> Failure {
    Failure::usage(format!("cannot write {}: {e}", path.display()))
}

pub fn run(args: CheckArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    let limits_for = |shading: Shading| {
        let defaults = CheckThresholds::for_shading(shading);
        CheckThresholds {
            interior_max_abs: args.interior_max_abs.unwrap_or(defaults.interior_max_abs),
            edge_fraction: args.edge_fraction.unwrap_or(defaults.edge_fraction),
            flip_mean: args.flip_mean.unwrap_or(defaults.flip_mean),
            ..defaults
        }
    };
    for (name, v) in [
        ("--interior-max-abs", args.interior_max_abs.unwrap_or(0.0)),
        ("--edge-fraction", args.edge_fraction.unwrap_or(0.0)),
        ("--flip-mean", args.flip_mean.unwrap_or(0.0)),
    ] {
        if !v.is_finite() || v < 0.0 {
            return Err(Failure::usage(format!(
                "{name} {v} is invalid; expected a number >= 0"
            )));
        }
    }
    // Check and load everything first: bad input stops the run before any
    // rendering.
    args.size.check()?;
    let mut scenes = Vec::new();
    let paths: Vec<Option<&Path>> = if args.scenes.is_empty() {
        vec![None]
    } else {
        args.scenes.iter().map(|p| Some(p.as_path())).collect()
    };
    for path in paths {
        let (mut scene, stem) = load_scene(path, memory)?;
        args.size.apply(&mut scene)?;
        args.lighting.apply(&mut scene)?;
        args.traversal.apply(&mut scene)?;
        memory.check(&stem, &scene, &args.shading, &args.shading)?;
        let mut name = stem;
        if scenes.iter().any(|(_, n): &(_, String)| *n == name) {
            name = format!("{name}-{}", scenes.len() + 1);
        }
        scenes.push((scene, name));
    }
    let context = GpuContext::new(options)?;
    let mut cases = Vec::new();
    let mut reports = Vec::new();
    let mut failed = 0;
    // A case that cannot be checked at all (the device refuses the scene,
    // say) fails on its own; the others still run and the report is still
    // written. The run then exits with that error's status.
    let mut first_error: Option<Failure> = None;
    for (scene, name) in &scenes {
        let folder = args.out.join(name);
        std::fs::create_dir_all(&folder).map_err(|e| io_failure(&folder, e))?;
        for &shading in &args.shading {
            let outcome = match check(&context, scene, scene, shading, &limits_for(shading)) {
                Ok(outcome) => outcome,
                Err(e) => {
                    let error = Failure::from(e);
                    if !args.json {
                        println!("ERROR {name}/{shading}  {}", error.message);
                    }
                    failed += 1;
                    cases.push(TestCase {
                        classname: name.clone(),
                        name: shading.to_string(),
                        time_s: 0.0,
                        failure: Some(format!("could not be checked: {}", error.message)),
                        output: String::new(),
                    });
                    reports.push(serde_json::json!({
                        "scene": name,
                        "shading": shading,
                        "passed": false,
                        "error": error.message,
                    }));
                    first_error.get_or_insert(error);
                    continue;
                }
            };
            write_images(&folder, &outcome)?;
            let verdict = if outcome.passed() { "PASS" } else { "FAIL" };
            if !outcome.passed() {
                failed += 1;
            }
            let summary = summary(&outcome);
            if !args.json {
                println!("{verdict} {name}/{shading}  {summary}");
                for f in &outcome.judgement.failures {
                    println!("     {f}");
                }
            }
            cases.push(TestCase {
                classname: name.clone(),
                name: shading.to_string(),
                time_s: outcome.renders_ms / 1e3,
                failure: (!outcome.passed()).then(|| outcome.judgement.failures.join("\n")),
                output: summary,
            });
            reports.push(serde_json::json!({
                "scene": name,
                "shading": shading,
                "passed": outcome.passed(),
                "failures": outcome.judgement.failures,
                "interior": outcome.judgement.interior,
                "edges": outcome.judgement.edges,
                "edge_share": outcome.judgement.edge_share,
                "flip_mean": outcome.judgement.flip.mean,
                "flip_p99": outcome.judgement.flip.p99,
                "scale": outcome.judgement.scale,
                "gpu_ms": outcome.gpu_ms,
                "traversal": outcome.traversal.map(|t| t.name()),
                "cpu_ms": outcome.cpu_ms,
                "renders_ms": outcome.renders_ms,
                "images": folder.join(shading.to_string()),
            }));
        }
    }
    if let Some(path) = &args.junit {
        let xml = junit::render("shadelab check", &cases);
        write_atomically(path, xml.as_bytes())?;
    }
    if args.json {
        let value = serde_json::json!({
            "thresholds": {
                "raster": limits_for(Shading::Phong),
                "raytrace": limits_for(Shading::Raytrace),
            },
            "cases": reports,
            "failed": failed,
        });
        println!("{value}");
    } else {
        println!(
            "{} of {} cases passed; images in {}",
            cases.len() - failed,
            cases.len(),
            args.out.display()
        );
    }
    if let Some(error) = first_error {
        return Err(error);
    }
    if failed > 0 {
        return Err(Failure {
            code: 1,
            message: format!("{failed} of {} cases failed their thresholds", cases.len()),
        });
    }
    Ok(())
}

fn summary(o: &CheckOutcome) -> String {
    let unit = if o.judgement.scale == 1.0 {
        String::new()
    } else {
        format!(
            "  (errors relative to the brightest value, {:.1e})",
            o.judgement.scale
        )
    };
    let engine = o
        .traversal
        .map(|t| format!(", traversal {}", t.name()))
        .unwrap_or_default();
    format!(
        "interior max {:.1e}  differing edge pixels {:.4}%  FLIP mean {:.1e}  (GPU {:.0} ms{engine}, CPU {:.0} ms, side by side){unit}",
        o.judgement.interior.max_abs,
        o.judgement.edge_share * 100.0,
        o.judgement.flip.mean,
        o.gpu_ms,
        o.cpu_ms
    )
}

/// The images as compared: in units of `o.judgement.scale`, so that a scene lit at
/// 1e30 is not written all white.
fn write_images(folder: &Path, o: &CheckOutcome) -> Result<(), Failure> {
    let mode = o.shading.to_string();
    let expected = scaled(&o.expected, o.judgement.scale);
    let actual = scaled(&o.actual, o.judgement.scale);
    // Three encodings, each on one thread: side by side.
    let heat = || {
        write_image(
            &flip_heatmap(&o.judgement.flip),
            &folder.join(format!("{mode}-diff.png")),
        )
    };
    let ((e, a), h) = rayon::join(
        || {
            rayon::join(
                || write_image(&expected, &folder.join(format!("{mode}-expected.png"))),
                || write_image(&actual, &folder.join(format!("{mode}-actual.png"))),
            )
        },
        heat,
    );
    e?;
    a?;
    h?;
    Ok(())
}
