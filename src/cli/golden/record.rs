//! What a `golden` run leaves and says once its cases are judged: the
//! page, the JUnit file, the JSON or the summary line, and the record
//! (`golden.json`, made by `shadelab::golden::record`) that `--merge`
//! joins shards by, all from the cases' records in the whole run's order;
//! and `--merge` itself: the shards' pictures copied, their records joined.

use std::path::{Path, PathBuf};
use std::time::Instant;

use shadelab::golden::record::{self, RunRecord, RECORD};
use shadelab::golden::report::write_run_page;
use shadelab::golden::CaseError;
use shadelab::junit;
use shadelab::output;

use super::args::GoldenArgs;
use crate::cli::common::failure::Failure;
use crate::cli::common::shards;

/// Writes the page, the JUnit file, the record and the JSON (or the
/// summary line), and gives the exit status, from the cases' records in
/// the whole run's order: a run's, or a merge of shards'.
pub(super) fn conclude(
    args: &GoldenArgs,
    run: &RunRecord,
    records: Vec<serde_json::Value>,
    first_error: Option<CaseError>,
) -> Result<(), Failure> {
    let html = args.out.join("report.html");
    write_run_page(&html, run, &records)?;
    if let Some(path) = &args.junit {
        let junit: Vec<_> = records
            .iter()
            .map(|v| junit::TestCase::from_json(&v["junit"]))
            .collect();
        let xml = junit::render("shadelab golden", &junit);
        output::write_atomically(path, xml.as_bytes())?;
    }
    record::write_record(&args.out, run, &records)?;
    if args.json {
        println!("{}", record::run_json(run, &records, &html));
    } else {
        println!(
            "golden: {}; report {}",
            record::summary(&records),
            html.display()
        );
    }
    Ok(record::verdict(&records, first_error)?)
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
    let run = record::merged_run(&shards, shadelab::gpu::ms_since(started))?;
    let first_error = record::first_error(&records);
    conclude(args, &run, records, first_error)
}
