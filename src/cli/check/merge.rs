//! `check --merge DIR...`: the records the shards of a `check` left in
//! their folders, joined into the report of the whole run.

use std::path::{Path, PathBuf};

use shadelab::junit;
use shadelab::output::write_atomically;

use crate::cli::common::failure::Failure;

/// The record a shard of `check` leaves in its --out for `--merge`.
pub(super) const RECORD: &str = "check.json";

/// `--merge DIR...`: the shards' records joined in the whole run's order,
/// their images copied into --out, and the JUnit file, the record and the
/// summary written as the whole run writes them.
pub(super) fn merge(
    dirs: &[PathBuf],
    out: &Path,
    junit: Option<&Path>,
    json: bool,
) -> Result<(), Failure> {
    if let Some(path) = junit {
        shadelab::output::prepare_output_path(path)?;
    }
    let shards = crate::cli::common::shards::read_shards(dirs, RECORD)?;
    shadelab::output::prepare_output_folder(out)?;
    let cases = crate::cli::common::shards::merged_cases(&shards);
    copy_images(&shards, out)?;
    if let Some(path) = junit {
        let junit: Vec<_> = cases
            .iter()
            .map(|v| shadelab::junit::TestCase::from_json(&v["junit"]))
            .collect();
        write_atomically(path, junit::render("shadelab check", &junit).as_bytes())?;
    }
    let failed = cases
        .iter()
        .filter(|v| v["passed"] == false && v.get("error").is_none())
        .count();
    let errors = cases.iter().filter(|v| v.get("error").is_some()).count();
    let record =
        serde_json::json!({"shard": null, "run": shards[0].1["run"], "out": out, "cases": cases});
    write_atomically(&out.join(RECORD), record.to_string().as_bytes())?;
    if json {
        let value = serde_json::json!({"cases": cases, "failed": failed, "errors": errors});
        println!("{value}");
    } else {
        println!(
            "{} of {} cases passed{}; merged from {} shards into {}",
            cases.len() - failed - errors,
            cases.len(),
            if errors > 0 {
                format!(", {errors} could not run")
            } else {
                String::new()
            },
            shards.len(),
            out.display()
        );
    }
    verdict(cases.len(), failed, errors)
}

/// Each shard's kept images (`OUT/scene/mode-{expected,actual,diff}.png`)
/// copied to the same place under `out`.
fn copy_images(shards: &[(PathBuf, serde_json::Value)], out: &Path) -> Result<(), Failure> {
    for (dir, shard) in shards {
        let shard_out = shard["out"].as_str().map(PathBuf::from);
        for case in shard["cases"].as_array().into_iter().flatten() {
            let Some(images) = case["images"].as_str().map(Path::new) else {
                continue;
            };
            // `OUT/scene/mode`: its three images, where they were kept.
            let relative = shard_out
                .as_deref()
                .and_then(|o| images.strip_prefix(o).ok())
                .unwrap_or(images);
            for what in ["expected", "actual", "diff"] {
                let name = relative.with_file_name(format!(
                    "{}-{what}.png",
                    relative
                        .file_name()
                        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
                ));
                if dir.join(&name).is_file() {
                    crate::cli::common::shards::copy_into(dir, out, &name)?;
                }
            }
        }
    }
    Ok(())
}

/// 0 when every case passed, else 1 with how many did not.
fn verdict(cases: usize, failed: usize, errors: usize) -> Result<(), Failure> {
    if failed + errors == 0 {
        return Ok(());
    }
    Err(Failure {
        code: 1,
        message: format!(
            "{failed} of {cases} cases failed their thresholds{}",
            if errors > 0 {
                format!(" and {errors} could not run")
            } else {
                String::new()
            }
        ),
    })
}
