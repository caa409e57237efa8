//! `shadelab golden`: each scene in each mode rendered (the lighting hook in
//! play) and compared with its stored reference image, with limits for a
//! render against a stored render of the same renderer. Missing references
//! fail unless `--create` makes them; `--bless` accepts the renders that
//! changed. References are kept per driver where one needs its own, found
//! before the shared ones.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use shadelab::gpu::GpuOptions;
use shadelab::linear_image::LinearImage;
use shadelab::memory::MemoryLimit;
use shadelab::metrics::{self, Comparison, Settings, Thresholds, Verdict};
use shadelab::output::{self, ImageFormat, ImageMetadata};

use super::args::{ImageSize, ModeList, SceneFlags};
use super::diff::{compare_images, parse_thresholds, Judging, Preset, EDGE_THRESHOLD};
use super::golden_keys;
use super::golden_record::{conclude, merge, RunRecord};
use super::golden_report::{
    case_figure_html, case_json, case_row_html, junit_cases, junit_json, print_case, ReportCase,
};
use super::render::{image_metadata, RenderArgs};
use super::render_batch::{file_name, non_finite_failure, Batch, CaseView, Made};
use super::shards;
use super::Failure;

#[derive(Args)]
pub struct GoldenArgs {
    /// Scene files (.toml, .gltf or .glb); the built-in default scene if none.
    scenes: Vec<PathBuf>,
    #[command(flatten)]
    modes: ModeList,
    /// The folder of stored references: DIR/KEY/NAME (this driver's, looked
    /// for first), then DIR/NAME (shared by every driver).
    #[arg(long, value_name = "DIR", required_unless_present = "merge")]
    references: Option<PathBuf>,
    /// Each reference's file name, from {scene} (the scene file's path
    /// below --root, without its extension: its name alone where every
    /// scene is in one folder) and {mode}; .png or .exr.
    #[arg(long, value_name = "PATTERN", default_value = "{scene}-{mode}.png")]
    name: String,
    /// Run only the cases of shard I of N (1 <= I <= N): cases are dealt out
    /// by their scene's path and mode, so a case stays on its shard when
    /// others are added. Each shard's --out holds its record for --merge.
    #[arg(long, value_name = "I/N", value_parser = shards::parse_shard)]
    shard: Option<(usize, usize)>,
    /// Join the records of these shard folders (each a shard's --out) into
    /// one report in --out: report.html, golden.json, --junit and --json,
    /// as the whole run writes them.
    #[arg(long, num_args = 1.., value_name = "DIR", conflicts_with_all = ["scenes", "shard", "create", "bless"])]
    pub(super) merge: Vec<PathBuf>,
    /// The folder the scenes' paths in reference names are taken from
    /// [default: the deepest folder that holds every scene].
    #[arg(long, value_name = "DIR")]
    root: Option<PathBuf>,
    /// Make the references that are missing from this run's renders (else a
    /// missing reference fails its case).
    #[arg(long)]
    create: bool,
    /// Accept this run's renders: rewrite every reference that is over its
    /// limits (or cannot be compared), make the missing ones, and list each.
    /// Also SHADELAB_BLESS=1.
    #[arg(long, visible_alias = "update")]
    bless: bool,
    /// Write the references that --create or --bless make into this
    /// driver's folder (DIR/KEY/), leaving the shared ones as they are.
    #[arg(long)]
    per_driver: bool,
    /// This driver's folder of references [default: made from the device
    /// and driver names, printed by every run].
    #[arg(long, value_name = "KEY")]
    key: Option<String>,
    /// The limits to start from: stored-reference (no pixel off by more
    /// than 0.01, one 8-bit step) or gpu-vs-reference (diff's defaults).
    #[arg(long, value_enum, default_value = "stored-reference")]
    preset: Preset,
    /// Thresholds on top of the preset, as diff's: `FIGURE=X[,FIGURE=X...]`
    /// for flip_mean, max_abs, p99_abs, rmse, fraction_over, count_over or
    /// psnr (a floor, dB).
    #[arg(long, value_name = "[FIGURE=]X,...")]
    threshold: Vec<String>,
    /// Folder for report.html and, for each case that did not pass, its
    /// NAME-actual and NAME-diff images.
    #[arg(long, value_name = "DIR", default_value = "golden-out")]
    pub(super) out: PathBuf,
    /// Also write a JUnit XML report here.
    #[arg(long, value_name = "FILE.xml")]
    pub(super) junit: Option<PathBuf>,
    /// Print one JSON object with every case on stdout.
    #[arg(long)]
    pub(super) json: bool,
    #[command(flatten)]
    size: ImageSize,
    #[command(flatten)]
    settings: SceneFlags,
    #[command(flatten)]
    pub machine: super::args::MachineArgs,
}

/// What a case came to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum Status {
    /// Within the limits of its reference.
    Pass,
    /// Over them (or of another size).
    Fail,
    /// No reference, and none made.
    Missing,
    /// No reference: made from this render (`--create`, `--bless`).
    Created,
    /// Over its limits, and rewritten from this render (`--bless`).
    Updated,
    /// Not rendered, or its reference unreadable.
    Error,
}

impl Status {
    pub(super) fn word(self) -> &'static str {
        match self {
            Status::Pass => "PASS",
            Status::Fail => "FAIL",
            Status::Missing => "MISSING",
            Status::Created => "CREATED",
            Status::Updated => "UPDATED",
            Status::Error => "ERROR",
        }
    }
}

/// One case judged against its reference.
pub(super) struct Judged {
    pub status: Status,
    /// The reference compared with, or written.
    pub reference: Option<PathBuf>,
    /// `driver` (DIR/KEY/NAME) or `shared` (DIR/NAME).
    pub reference_kind: Option<&'static str>,
    pub failures: Vec<String>,
    pub verdicts: Vec<Verdict>,
    pub comparison: Option<Comparison>,
    /// Said with the failure: the reference was made on another driver.
    pub hint: Option<String>,
    pub error: Option<Failure>,
    /// The images a person looks at, as PNG bytes: expected, actual and
    /// heat map, for the cases that did not pass (and the blessed ones).
    pub pictures: Option<Pictures>,
    /// Files written into `--out` for this case.
    pub written: Vec<PathBuf>,
    pub time_s: f64,
}

pub(super) struct Pictures {
    pub expected: Option<Vec<u8>>,
    pub actual: Vec<u8>,
    pub heatmap: Option<Vec<u8>>,
    /// The per-pixel error scaled so that its largest is white, and that
    /// largest error.
    pub error: Option<(Vec<u8>, f64)>,
    pub width: u32,
    pub height: u32,
}

impl Judged {
    /// `status`, against `reference` (with its kind), nothing else yet.
    fn new(status: Status, reference: Option<(PathBuf, &'static str)>) -> Self {
        let (reference, reference_kind) = reference.unzip();
        Judged {
            status,
            reference,
            reference_kind,
            failures: Vec::new(),
            verdicts: Vec::new(),
            comparison: None,
            hint: None,
            error: None,
            pictures: None,
            written: Vec::new(),
            time_s: 0.0,
        }
    }

    fn error(failure: Failure, time_s: f64) -> Self {
        Judged {
            error: Some(failure),
            time_s,
            ..Judged::new(Status::Error, None)
        }
    }
}

/// The folder name for a device's references: the device and driver
/// names, lower case, each run of characters other than a-z, 0-9 and `.`
/// made one `-` (`llvmpipe-llvm-15.0.6-256-bits-mesa-25.0.7-...`): the
/// vector width and the Mesa version, which change the image, are in it.
pub(super) fn driver_key(device: &str, driver: &str) -> String {
    let mut key = String::new();
    for c in format!("{device} {driver}").to_lowercase().chars() {
        if c.is_ascii_alphanumeric() || c == '.' {
            key.push(c);
        } else if !key.ends_with('-') {
            key.push('-');
        }
    }
    key.trim_matches('-').to_string()
}

/// Where a case's reference is: this driver's, then the shared one.
fn find_reference(references: &Path, key: &str, file: &str) -> Option<(PathBuf, &'static str)> {
    let own = references.join(key).join(file);
    let shared = references.join(file);
    if own.is_file() {
        Some((own, "driver"))
    } else if shared.is_file() {
        Some((shared, "shared"))
    } else {
        None
    }
}

/// `NAME-actual.png` for `NAME.png`, in NAME's folder (`hard/x-phong.png`
/// gives `hard/x-phong-actual.png`).
fn beside(file: &str, what: &str, ext: &str) -> String {
    let path = Path::new(file);
    let stem = path
        .file_stem()
        .map_or_else(|| file.to_string(), |s| s.to_string_lossy().into_owned());
    let name = format!("{stem}-{what}.{ext}");
    match path.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(folder) => folder.join(name).to_string_lossy().into_owned(),
        None => name,
    }
}

fn png_of(image: &LinearImage) -> Result<Vec<u8>, Failure> {
    Ok(output::encode_with(
        image,
        Path::new("picture.png"),
        &ImageMetadata::software(),
    )?)
}

/// What made a reference: the `shadelab:settings` of a PNG that `render`
/// or `golden` wrote.
fn made_with(reference_bytes: &[u8]) -> Option<serde_json::Value> {
    let text = output::png_text(reference_bytes, "shadelab:settings")?;
    serde_json::from_str(&text).ok()
}

/// Where the reference was made, from its settings: `device (driver)`.
fn made_on(settings: &serde_json::Value) -> Option<String> {
    let device = settings["device"].as_str()?;
    let driver = settings["driver"].as_str().unwrap_or("no driver");
    Some(format!("{device} ({driver})"))
}

struct Plan<'a> {
    args: &'a GoldenArgs,
    judging: Judging,
    bless: bool,
    key: String,
}

impl Plan<'_> {
    /// The path a made or blessed reference goes to.
    fn target(&self, file: &str, found: Option<&Path>) -> PathBuf {
        match (self.args.per_driver, found) {
            (false, Some(found)) => found.to_path_buf(),
            (false, None) => self.args.references().join(file),
            (true, _) => self.args.references().join(&self.key).join(file),
        }
    }

    /// Compares case `view`'s render with its reference; writes what a
    /// person needs to see a failure, and the references made or blessed.
    fn judge(&self, view: &CaseView, made: Result<Made, Failure>, started: Instant) -> Judged {
        let time = || started.elapsed().as_secs_f64();
        // A case's pictures from an earlier run would be read as this
        // run's: they go, and come back only if this case fails.
        let file = view.file_name;
        for stale in [
            beside(file, "actual", "png"),
            beside(file, "actual", "exr"),
            beside(file, "diff", "png"),
            beside(file, "error", "png"),
        ] {
            let _ = std::fs::remove_file(self.args.out.join(stale));
        }
        let mut made = match made {
            Ok(made) => made,
            Err(failure) => return Judged::error(failure, time()),
        };
        // What made the reference, as it will say: its key and the hook's
        // source, beside render's settings.
        made.settings["golden_scene"] = view.name.into();
        if let Some(source) = &made.hook_source {
            made.settings["lighting_fnv1a"] = golden_keys::fnv1a_hex(source).into();
        }
        made.metadata = image_metadata(view.name, &made.device, &made.settings);
        // An image with NaN is never a reference, nor blessed into one.
        if let Some(failure) = non_finite_failure(&made) {
            return Judged::error(failure, time());
        }
        match self.judge_made(view, &made) {
            Ok(mut judged) => {
                // The render's time too: JUnit's time is the case's.
                judged.time_s = time() + made.rendered.timings.total_ms / 1e3;
                judged
            }
            Err(failure) => Judged::error(failure, time()),
        }
    }

    fn judge_made(&self, view: &CaseView, made: &Made) -> Result<Judged, Failure> {
        let file = view.file_name;
        let format = ImageFormat::from_path(Path::new(file))?;
        // The render as its reference file would hold it: compared after
        // the same encoding, so that a repeated render is exactly equal.
        let bytes = output::encode_with(&made.rendered.image, Path::new(file), &made.metadata)?;
        let actual = output::decode_image(&bytes, format)
            .map_err(|e| Failure::usage(format!("cannot decode the render of {file}: {e}")))?;
        let found = find_reference(self.args.references(), &self.key, file);
        let mut judged = Judged::new(Status::Pass, found.clone());
        let Some((reference_path, _)) = &found else {
            if self.args.create || self.bless {
                let target = self.target(file, None);
                write_reference(&target, &bytes)?;
                judged.status = Status::Created;
                judged.reference = Some(target);
                judged.reference_kind = Some(if self.args.per_driver {
                    "driver"
                } else {
                    "shared"
                });
            } else {
                judged.status = Status::Missing;
                judged.failures.push(format!(
                    "no reference {} (nor {}); run with --create to make it from this render",
                    self.args.references().join(file).display(),
                    self.args.references().join(&self.key).join(file).display()
                ));
                judged.pictures = Some(self.keep_pictures(
                    file,
                    format,
                    &bytes,
                    &actual,
                    None,
                    None,
                    &mut judged.written,
                )?);
            }
            return Ok(judged);
        };
        let reference_bytes = std::fs::read(reference_path).map_err(|e| {
            Failure::usage(format!(
                "cannot read the reference {}: {e}",
                reference_path.display()
            ))
        })?;
        let expected = output::decode_image(&reference_bytes, format);
        let compared = match &expected {
            Ok(expected) => compare_images(expected, &actual, &self.judging).map_err(|e| {
                format!(
                    "{} cannot be compared with the render: {e}",
                    reference_path.display()
                )
            }),
            Err(e) => Err(format!(
                "the reference {} cannot be read: {e}",
                reference_path.display()
            )),
        };
        let over = match &compared {
            Ok(pair) => !pair.failures.is_empty(),
            Err(_) => true,
        };
        if let Ok(pair) = &compared {
            judged.verdicts = pair.verdicts.clone();
            judged.failures = pair.failures.clone();
            judged.comparison = Some(pair.comparison.clone());
        }
        if !over {
            return Ok(judged);
        }
        if let Err(why) = &compared {
            judged.failures.push(why.clone());
        }
        let reference_settings = made_with(&reference_bytes);
        let mut hints = Vec::new();
        if let Some(settings) = &reference_settings {
            let differences = golden_keys::settings_differences(settings, &made.settings);
            if !differences.is_empty() {
                hints.push(format!(
                    "the reference was made with other settings ({}): run with the reference's, or accept this render with --bless",
                    differences.join(", ")
                ));
            }
        }
        if let Some(there) = reference_settings.as_ref().and_then(made_on) {
            let here = format!(
                "{} ({})",
                made.device,
                made.driver.as_deref().unwrap_or("no driver")
            );
            if there != here {
                hints.push(format!(
                    "the reference was made on {there}, this render on {here}: where a driver's images differ, keep references per driver (--per-driver --bless)"
                ));
            }
        }
        if !hints.is_empty() {
            judged.hint = Some(hints.join("; "));
        }
        let heat = judged
            .comparison
            .as_ref()
            .map(|c| metrics::flip_heatmap(&c.flip));
        let expected_png = match &expected {
            Ok(_) if format == ImageFormat::Png => Some(reference_bytes.clone()),
            Ok(image) => Some(png_of(image)?),
            Err(_) => None,
        };
        let same_size = |e: &LinearImage| e.width == actual.width && e.height == actual.height;
        let expected_image = expected.as_ref().ok().filter(|e| same_size(e));
        judged.pictures = Some(self.keep_pictures(
            file,
            format,
            &bytes,
            &actual,
            expected_png.map(|png| (png, expected_image)),
            heat.as_ref(),
            &mut judged.written,
        )?);
        if self.bless {
            let target = self.target(file, Some(reference_path));
            write_reference(&target, &bytes)?;
            // A driver's own reference made beside a shared one is new; any
            // other is the old one rewritten.
            judged.status = if target == *reference_path {
                Status::Updated
            } else {
                Status::Created
            };
            judged.reference = Some(target);
            if self.args.per_driver {
                judged.reference_kind = Some("driver");
            }
        } else if expected.is_err() {
            judged.status = Status::Error;
            judged.error = Some(Failure::usage(judged.failures.join("; ")));
        } else {
            judged.status = Status::Fail;
        }
        Ok(judged)
    }

    /// Writes the render (`NAME-actual.EXT`), the FLIP heat map
    /// (`NAME-diff.png`) and the scaled error (`NAME-error.png`) into
    /// `--out`, and returns the pictures for the report. `expected` is the
    /// reference as a PNG, and as an image where it is the render's size.
    #[allow(clippy::too_many_arguments)]
    fn keep_pictures(
        &self,
        file: &str,
        format: ImageFormat,
        actual_bytes: &[u8],
        actual: &LinearImage,
        expected: Option<(Vec<u8>, Option<&LinearImage>)>,
        heat: Option<&LinearImage>,
        written: &mut Vec<PathBuf>,
    ) -> Result<Pictures, Failure> {
        let mut keep = |what: &str, image: &LinearImage| -> Result<Vec<u8>, Failure> {
            let path = self.args.out.join(beside(file, what, "png"));
            let bytes = png_of(image)?;
            output::write_atomically(&path, &bytes)?;
            written.push(path);
            Ok(bytes)
        };
        let ext = match format {
            ImageFormat::Png => "png",
            ImageFormat::Exr => "exr",
        };
        let heatmap = heat.map(|heat| keep("diff", heat)).transpose()?;
        let (expected_png, expected_image) = expected.map_or((None, None), |(p, i)| (Some(p), i));
        let error = match expected_image {
            Some(reference) => {
                let (image, scale) = metrics::scaled_error_heatmap(reference, actual);
                Some((keep("error", &image)?, scale))
            }
            None => None,
        };
        let actual_path = self.args.out.join(beside(file, "actual", ext));
        output::write_atomically(&actual_path, actual_bytes)?;
        written.insert(0, actual_path);
        let actual_png = match format {
            ImageFormat::Png => actual_bytes.to_vec(),
            ImageFormat::Exr => png_of(actual)?,
        };
        Ok(Pictures {
            expected: expected_png,
            actual: actual_png,
            heatmap,
            error,
            width: actual.width,
            height: actual.height,
        })
    }
}

fn write_reference(path: &Path, bytes: &[u8]) -> Result<(), Failure> {
    output::prepare_output_path(path)?;
    Ok(output::write_atomically(path, bytes)?)
}

/// `SHADELAB_BLESS` set to anything but empty, 0 or false.
fn bless_from_env() -> bool {
    std::env::var("SHADELAB_BLESS")
        .map(|v| !matches!(v.trim(), "" | "0" | "false"))
        .unwrap_or(false)
}

impl GoldenArgs {
    /// `--references`, which clap requires unless merging.
    fn references(&self) -> &Path {
        self.references.as_deref().unwrap_or(Path::new("."))
    }
}

pub fn run(args: GoldenArgs, options: &GpuOptions, memory: &MemoryLimit) -> Result<(), Failure> {
    if !args.merge.is_empty() {
        return merge(&args);
    }
    let started = Instant::now();
    let thresholds: Thresholds = parse_thresholds(args.preset.thresholds(), &args.threshold)?;
    let judging = Judging {
        thresholds,
        settings: Settings::default(),
        edge_threshold: EDGE_THRESHOLD,
    };
    if let Some(key) = &args.key {
        let clean = !key.is_empty() && key != "." && key != ".." && !key.contains(['/', '\\']);
        if !clean {
            return Err(Failure::usage(format!(
                "--key {key:?} must be a folder name (no path)"
            )));
        }
    }
    if args.references().exists() && !args.references().is_dir() {
        return Err(Failure::usage(format!(
            "--references {} is not a folder",
            args.references().display()
        )));
    }
    let bless = args.bless || bless_from_env();
    let render_args = RenderArgs {
        scenes: args.scenes.clone(),
        shading: args.modes.modes(),
        backend: "gpu".to_string(),
        size: args.size.clone(),
        settings: args.settings.clone(),
        cutoff: None,
        samples: None,
        no_shadows: false,
        out: None,
        out_dir: None,
        name: Some(args.name.clone()),
        json: args.json,
        stats: false,
        machine: args.machine.clone(),
        scene_names: Some(golden_keys::scene_keys(&args.scenes, args.root.as_deref())?),
        shard: args.shard,
    };
    Batch::check_flags(&render_args)?;
    refuse_shared_references(&render_args)?;
    output::prepare_output_folder(&args.out)?;
    if let Some(path) = &args.junit {
        output::prepare_output_path(path)?;
    }
    let batch = Batch::plan(&render_args, options, memory)?;
    let (device, driver) = batch.context().map_or_else(
        || ("no device".to_string(), String::new()),
        |c| (c.info.name.clone(), c.info.driver.clone()),
    );
    let key = args
        .key
        .clone()
        .unwrap_or_else(|| driver_key(&device, &driver));
    let plan = Plan {
        args: &args,
        judging,
        bless,
        key,
    };
    if !args.json {
        println!(
            "references {} (this driver's: {}); limits {}",
            args.references().display(),
            args.references().join(&plan.key).display(),
            describe_limits(args.preset, &plan.judging.thresholds)
        );
    }
    let mut cases: Vec<(usize, ReportCase)> = Vec::new();
    let handle =
        |view: &CaseView, made: Result<Made, Failure>| plan.judge(view, made, Instant::now());
    let report = |view: &CaseView, judged: Judged| {
        if !args.json {
            print_case(view, &judged, &args.out);
        }
        cases.push((
            view.order,
            ReportCase {
                scene: view.name.to_string(),
                shading: view.shading,
                file: view.file_name.to_string(),
                judged,
            },
        ));
        Ok(())
    };
    batch.run("golden", &render_args, handle, report)?;

    let limits = describe_limits(args.preset, &plan.judging.thresholds);
    let junit = junit_cases(&cases.iter().map(|(_, c)| c).collect::<Vec<_>>());
    let records: Vec<serde_json::Value> = cases
        .iter()
        .zip(&junit)
        .map(|((order, c), t)| {
            let mut v = case_json(c);
            v["order"] = (*order).into();
            v["junit"] = junit_json(t);
            v["html_row"] = case_row_html(c).into();
            v["html_figure"] = case_figure_html(c).into();
            v
        })
        .collect();
    let run = RunRecord {
        shard: args.shard,
        references: args.references().to_path_buf(),
        key: plan.key.clone(),
        device,
        driver,
        preset: args.preset,
        thresholds: serde_json::to_value(plan.judging.thresholds).unwrap_or_default(),
        limits,
        bless,
        wall_ms: shadelab::gpu::ms_since(started),
    };
    let first_error = cases.iter().find_map(|(_, c)| c.judged.error.clone());
    conclude(&args, &run, records, first_error)
}

/// Refuses, before any work, two cases that would read and write one
/// reference (two scenes whose paths differ only in their extension, one
/// scene given twice, a `--name` that leaves the mode out).
fn refuse_shared_references(args: &RenderArgs) -> Result<(), Failure> {
    let names = args.scene_names.as_deref().unwrap_or_default();
    let mut cases = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let scene = args.scenes.get(k).map_or_else(
            || "the default scene".to_string(),
            |p| p.display().to_string(),
        );
        for shading in args.modes() {
            let file = file_name(args.name_pattern(), name, shading);
            cases.push((file, format!("{scene} ({shading})")));
        }
    }
    match golden_keys::first_clash(&cases) {
        Some((file, first, second)) => Err(Failure::usage(format!(
            "{first} and {second} would share the reference {file}; give each scene its own path below --root (or its own file name)"
        ))),
        None => Ok(()),
    }
}

/// The limits for people: the preset's name, then each limit.
fn describe_limits(preset: Preset, t: &Thresholds) -> String {
    let mut parts = vec![
        format!("max_abs {}", t.max_abs),
        format!("p99_abs {}", t.p99_abs),
        format!("flip_mean {}", t.flip_mean),
    ];
    for (name, value) in [
        ("rmse", t.rmse),
        ("fraction_over", t.fraction_over),
        ("count_over", t.count_over),
    ] {
        if let Some(v) = value {
            parts.push(format!("{name} {v}"));
        }
    }
    if let Some(psnr) = t.psnr {
        parts.push(format!("psnr >= {psnr} dB"));
    }
    format!("{} ({})", preset.name(), parts.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_driver_key_is_a_folder_name_holding_the_vector_width_and_the_version() {
        let key = driver_key(
            "llvmpipe (LLVM 15.0.6, 256 bits)",
            "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)",
        );
        assert_eq!(
            key,
            "llvmpipe-llvm-15.0.6-256-bits-mesa-25.0.7-2-bpo12-1-llvm-15.0.6"
        );
        assert_ne!(
            key,
            driver_key(
                "llvmpipe (LLVM 15.0.6, 128 bits)",
                "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"
            )
        );
        assert_eq!(driver_key("A/B", ".."), "a-b-..");
    }

    #[test]
    fn the_drivers_own_reference_is_found_before_the_shared_one() {
        let dir = tempfile::tempdir().unwrap();
        let refs = dir.path();
        assert_eq!(find_reference(refs, "k", "a.png"), None);
        std::fs::write(refs.join("a.png"), b"x").unwrap();
        assert_eq!(
            find_reference(refs, "k", "a.png"),
            Some((refs.join("a.png"), "shared"))
        );
        std::fs::create_dir(refs.join("k")).unwrap();
        std::fs::write(refs.join("k/a.png"), b"x").unwrap();
        assert_eq!(
            find_reference(refs, "k", "a.png"),
            Some((refs.join("k/a.png"), "driver"))
        );
        assert_eq!(
            find_reference(refs, "other", "a.png"),
            Some((refs.join("a.png"), "shared"))
        );
    }
}
