//! A `golden` run's record once its cases are judged: the head that says
//! what the run was, the file (`golden.json`) that `--merge` joins shards
//! by, the counts and the run's verdict, all from the cases' records in
//! the whole run's order, so that a run and a merge of its shards come to
//! the same; and a merge's head from its shards' records.

use std::path::{Path, PathBuf};

use crate::diff::Preset;
use crate::output;
use crate::Error;

use super::case::{CaseError, Status};

/// What a golden run (or a shard of one) was, beside its cases: the
/// record's head in `golden.json`, and the page's.
pub struct RunRecord {
    pub shard: Option<(usize, usize)>,
    /// The whole run's settings and their digest (the CLI's run digest).
    pub identity: serde_json::Value,
    pub references: PathBuf,
    /// The driver's folder of references; `None` for a shard that had no
    /// case to open a device for.
    pub key: Option<String>,
    pub device: String,
    pub driver: String,
    pub preset: Preset,
    pub thresholds: serde_json::Value,
    pub limits: String,
    pub bless: bool,
    pub wall_ms: f64,
}

/// The file a golden run leaves in its output folder for `--merge`: every
/// case, with its JUnit case and its rows of the page.
pub const RECORD: &str = "golden.json";

/// How many of the cases' records have status `s`.
pub fn count(records: &[serde_json::Value], s: Status) -> usize {
    let status_of = |v: &serde_json::Value| v["status"].as_str().unwrap_or("error").to_string();
    let word = s.word().to_lowercase();
    records.iter().filter(|v| status_of(v) == word).count()
}

/// The counts of every status, as the run's last line says them.
pub fn summary(records: &[serde_json::Value]) -> String {
    let count = |s: Status| count(records, s);
    format!(
        "{} passed, {} failed, {} missing, {} created, {} updated, {} errors of {} cases",
        count(Status::Pass),
        count(Status::Fail),
        count(Status::Missing),
        count(Status::Created),
        count(Status::Updated),
        count(Status::Error),
        records.len()
    )
}

/// `golden.json` in `out`: the run's head and every case's record.
pub fn write_record(
    out: &Path,
    run: &RunRecord,
    records: &[serde_json::Value],
) -> Result<(), Error> {
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

/// The run and its cases as `--json` gives them, without the record's own
/// fields; `html` is the report page.
pub fn run_json(run: &RunRecord, records: &[serde_json::Value], html: &Path) -> serde_json::Value {
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
    serde_json::json!({
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
    })
}

/// The run's verdict: passed where every case passed or was made; else
/// the first error (with its exit status) where every case is an error,
/// else a failure (exit status 1) that counts the cases.
pub fn verdict(
    records: &[serde_json::Value],
    first_error: Option<CaseError>,
) -> Result<(), CaseError> {
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
    Err(CaseError {
        code: 1,
        message: format!(
            "{not_ok} of {total} cases did not pass ({}){hint}",
            summary(records)
        ),
    })
}

/// The head of a merge of shards' records (each `(folder, record)`): the
/// first shard's run, and the device and key of a shard that ran cases,
/// after checking that every shard with a driver's key has the same.
pub fn merged_run(
    shards: &[(PathBuf, serde_json::Value)],
    wall_ms: f64,
) -> Result<RunRecord, Error> {
    let first = &shards[0].1;
    // The device and key of a shard that ran cases: an empty one has none.
    let ran = one_driver_key(shards)?.unwrap_or(first);
    let text = |k: &str| ran[k].as_str().unwrap_or_default().to_string();
    Ok(RunRecord {
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
        wall_ms,
    })
}

/// The first case of the records that is an error (its message; bad
/// input, as a record keeps no exit status).
pub fn first_error(records: &[serde_json::Value]) -> Option<CaseError> {
    records.iter().find_map(|v| {
        v["error"].as_str().map(|m| CaseError {
            code: 2,
            message: m.to_string(),
        })
    })
}

/// The record of the first shard that has a driver's key, after checking
/// that every shard that has one has the same: shards judged against
/// different drivers' references are not one run.
fn one_driver_key(
    shards: &[(PathBuf, serde_json::Value)],
) -> Result<Option<&serde_json::Value>, Error> {
    let mut keyed = shards.iter().filter(|(_, r)| r["key"].is_string());
    let Some((first_dir, first)) = keyed.next() else {
        return Ok(None);
    };
    for (dir, record) in keyed {
        if record["key"] != first["key"] {
            return Err(Error::Usage(format!(
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
