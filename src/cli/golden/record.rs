//! What a `golden` run leaves and says once its cases are judged: the
//! page, the JUnit file, the JSON and the record (`golden.json`) that
//! `--merge` joins shards by, all made from the cases' records in the
//! whole run's order, so that a run and a merge of its shards write the
//! same; and `--merge` itself.

use std::path::{Path, PathBuf};
use std::time::Instant;

use shadelab::junit;
use shadelab::output;

use super::args::GoldenArgs;
use super::report::{write_page, PageHead};
use crate::cli::common::failure::Failure;
use crate::cli::common::shards;
use shadelab::diff::Preset;
use shadelab::golden::Status;

/// What a golden run (or a shard of one) was, beside its cases: the
/// record's head in `golden.json`, and the page's.
pub(super) struct RunRecord {
    pub(super) shard: Option<(usize, usize)>,
    /// The whole run's settings and their digest (`common/run_digest.rs`).
    pub(super) identity: serde_json::Value,
    pub(super) references: PathBuf,
    /// The driver's folder of references; `None` for a shard that had no
    /// case to open a device for.
    pub(super) key: Option<String>,
    pub(super) device: String,
    pub(super) driver: String,
    pub(super) preset: Preset,
    pub(super) thresholds: serde_json::Value,
    pub(super) limits: String,
    pub(super) bless: bool,
    pub(super) wall_ms: f64,
}

/// The file a golden run leaves in `--out` for `--merge`: every case, with
/// its JUnit case and its rows of the page.
const RECORD: &str = "golden.json";

/// Writes the page, the JUnit file, the record and the JSON (or the
/// summary line), and gives the exit status, from the cases' records in
/// the whole run's order: a run's, or a merge of shards'.
pub(super) fn conclude(
    args: &GoldenArgs,
    run: &RunRecord,
    records: Vec<serde_json::Value>,
    first_error: Option<Failure>,
) -> Result<(), Failure> {
    let count = |s: Status| count(&records, s);
    let html = args.out.join("report.html");
    write_report_page(&html, run, &records)?;
    if let Some(path) = &args.junit {
        let junit: Vec<_> = records
            .iter()
            .map(|v| junit::TestCase::from_json(&v["junit"]))
            .collect();
        let xml = junit::render("shadelab golden", &junit);
        output::write_atomically(path, xml.as_bytes())?;
    }
    write_record(&args.out, run, &records)?;
    let total = records.len();
    let summary = format!(
        "{} passed, {} failed, {} missing, {} created, {} updated, {} errors of {total} cases",
        count(Status::Pass),
        count(Status::Fail),
        count(Status::Missing),
        count(Status::Created),
        count(Status::Updated),
        count(Status::Error),
    );
    if args.json {
        print_json(run, &records, &html);
    } else {
        println!("golden: {summary}; report {}", html.display());
    }
    exit_status(&records, &summary, first_error)
}

/// How many of the cases' records have status `s`.
fn count(records: &[serde_json::Value], s: Status) -> usize {
    let status_of = |v: &serde_json::Value| v["status"].as_str().unwrap_or("error").to_string();
    let word = s.word().to_lowercase();
    records.iter().filter(|v| status_of(v) == word).count()
}

/// `report.html` from the cases' rows and figures.
fn write_report_page(
    html: &Path,
    run: &RunRecord,
    records: &[serde_json::Value],
) -> Result<(), Failure> {
    let rows: Vec<String> = records
        .iter()
        .map(|v| v["html_row"].as_str().unwrap_or_default().to_string())
        .collect();
    let figures: Vec<String> = records
        .iter()
        .filter_map(|v| v["html_figure"].as_str().map(str::to_string))
        .collect();
    let head = PageHead {
        references: &run.references,
        key: run.key.as_deref().unwrap_or_default(),
        device: &run.device,
        driver: &run.driver,
        limits: &run.limits,
    };
    write_page(html, &head, count(records, Status::Pass), &rows, &figures)
}

/// `golden.json` in `out`: the run's head and every case's record.
fn write_record(out: &Path, run: &RunRecord, records: &[serde_json::Value]) -> Result<(), Failure> {
    // What run the cases are of, for `--merge` to check that shards
    // belong together (`run`); the driver's key apart, as an empty shard
    // has none.
    let record = serde_json::json!({
        "shard": run.shard.map(|(i, n)| [i, n]),
        "run": run.identity,
        "references": run.references,
        "key": run.key,
        "thresholds": run.thresholds,
        "device": run.device,
        "driver": run.driver,
        "limits": run.limits,
        "preset": run.preset,
        "cases": records,
    });
    Ok(output::write_atomically(
        &out.join(RECORD),
        record.to_string().as_bytes(),
    )?)
}

/// `--json`: the run and its cases, without the record's own fields.
fn print_json(run: &RunRecord, records: &[serde_json::Value], html: &Path) {
    let count = |s: Status| count(records, s);
    let cases: Vec<serde_json::Value> = records
        .iter()
        .map(|v| {
            let mut v = v.clone();
            if let Some(o) = v.as_object_mut() {
                for internal in ["order", "junit", "html_row", "html_figure"] {
                    o.remove(internal);
                }
            }
            v
        })
        .collect();
    let value = serde_json::json!({
        "references": run.references,
        "key": run.key,
        "device": run.device,
        "driver": run.driver,
        "preset": run.preset,
        "thresholds": run.thresholds,
        "bless": run.bless,
        "shard": run.shard.map(|(i, n)| format!("{i}/{n}")),
        "cases": cases,
        "passed": count(Status::Pass),
        "failed": count(Status::Fail),
        "missing": count(Status::Missing),
        "created": count(Status::Created),
        "updated": count(Status::Updated),
        "errors": count(Status::Error),
        "report": html,
        "wall_ms": run.wall_ms,
    });
    println!("{value}");
}

/// Success where every case passed or was made; else the first error's
/// status where every case is an error, else 1.
fn exit_status(
    records: &[serde_json::Value],
    summary: &str,
    first_error: Option<Failure>,
) -> Result<(), Failure> {
    let count = |s: Status| count(records, s);
    let total = records.len();
    let ok = count(Status::Pass) + count(Status::Created) + count(Status::Updated);
    let not_ok = total - ok;
    if not_ok == 0 {
        return Ok(());
    }
    // Every case an error (no device, no scene): that error's status.
    if count(Status::Error) == total {
        if let Some(error) = first_error {
            return Err(error);
        }
    }
    let hint = if count(Status::Fail) + count(Status::Missing) > 0 {
        "; to accept these renders as the references, run again with --bless"
    } else {
        ""
    };
    Err(Failure {
        code: 1,
        message: format!("{not_ok} of {total} cases did not pass ({summary}){hint}"),
    })
}

/// `--merge DIR...`: the shards' records joined into one report in
/// `--out`, as the whole run would have written it; their pictures copied
/// beside it.
pub(super) fn merge(args: &GoldenArgs) -> Result<(), Failure> {
    let started = Instant::now();
    output::prepare_output_folder(&args.out)?;
    if let Some(path) = &args.junit {
        output::prepare_output_path(path)?;
    }
    let mut shards = shards::read_shards(&args.merge, RECORD)?;
    for (dir, shard) in &mut shards {
        for case in shard["cases"].as_array_mut().into_iter().flatten() {
            for written in case["written"].as_array_mut().into_iter().flatten() {
                let Some(path) = written.as_str().map(PathBuf::from) else {
                    continue;
                };
                // Recorded as the shard wrote it: under its --out.
                let name = path
                    .strip_prefix(&*dir)
                    .ok()
                    .or_else(|| path.file_name().map(Path::new))
                    .unwrap_or(&path);
                shards::copy_into(dir, &args.out, name)?;
                // The merged record names the copy, as a whole run names
                // its own files under its --out.
                *written = args.out.join(name).to_string_lossy().into_owned().into();
            }
        }
    }
    let records = shards::merged_cases(&shards);
    let first = &shards[0].1;
    // The device and key of a shard that ran cases: an empty one has none.
    let ran = one_driver_key(&shards)?.unwrap_or(first);
    let text = |k: &str| ran[k].as_str().unwrap_or_default().to_string();
    let run = RunRecord {
        shard: None,
        identity: first["run"].clone(),
        references: PathBuf::from(first["references"].as_str().unwrap_or_default()),
        key: ran["key"].as_str().map(str::to_string),
        device: text("device"),
        driver: text("driver"),
        preset: serde_json::from_value(first["preset"].clone()).unwrap_or(Preset::StoredReference),
        thresholds: first["thresholds"].clone(),
        limits: text("limits"),
        bless: false,
        wall_ms: shadelab::gpu::ms_since(started),
    };
    let first_error = records
        .iter()
        .find_map(|v| v["error"].as_str().map(|m| Failure::usage(m.to_string())));
    conclude(args, &run, records, first_error)
}

/// The record of the first shard that has a driver's key, after checking
/// that every shard that has one has the same: shards judged against
/// different drivers' references are not one run.
fn one_driver_key(
    shards: &[(PathBuf, serde_json::Value)],
) -> Result<Option<&serde_json::Value>, Failure> {
    let mut keyed = shards.iter().filter(|(_, r)| r["key"].is_string());
    let Some((first_dir, first)) = keyed.next() else {
        return Ok(None);
    };
    for (dir, record) in keyed {
        if record["key"] != first["key"] {
            return Err(Failure::usage(format!(
                "{} is of another run than {}: its driver's key is {} against {} (shards of one run render on one driver, or give --key)",
                dir.display(),
                first_dir.display(),
                record["key"],
                first["key"]
            )));
        }
    }
    Ok(Some(first))
}
