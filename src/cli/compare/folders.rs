//! `compare`'s --out folder: an earlier comparison's files cleared before
//! a new one writes its own, and the shards' folders merged into it.

use std::path::{Component, Path, PathBuf};

use shadelab::compare::run::merge;
use shadelab::compare::Report;

use crate::cli::common::failure::Failure;
use crate::cli::common::run_digest::run_difference;

/// Whether two paths name one folder.
pub(super) fn same_folder(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Removes the files an earlier comparison wrote into `dir`: those its
/// `report.json` names and the presentation's; nothing else. Returns how
/// many went. A folder with no readable report is left as it is.
pub(super) fn clear_earlier_run(dir: &Path) -> usize {
    let Ok(text) = std::fs::read_to_string(dir.join("report.json")) else {
        return 0;
    };
    let Ok(earlier) = serde_json::from_str::<Report>(&text) else {
        return 0;
    };
    let mut files: Vec<String> = vec![earlier.reference_image, earlier.local_reference_image];
    for v in earlier.variants {
        files.push(v.image);
        files.push(v.heatmap);
    }
    files.extend(
        [
            shadelab::compare::present::CONTACT_SHEET,
            shadelab::compare::present::PLOT_PNG,
            shadelab::compare::present::PLOT_SVG,
            shadelab::compare::present::CSV,
            shadelab::compare::present::HTML,
            "report.json",
            "speed-vs-error-local.png",
            "speed-vs-error-local.svg",
        ]
        .map(String::from),
    );
    files
        .iter()
        // Names only, never paths out of the folder.
        .filter(|f| !f.is_empty() && Path::new(f).file_name() == Some(std::ffi::OsStr::new(f)))
        .filter(|f| std::fs::remove_file(dir.join(f)).is_ok())
        .count()
}

/// The reports in the shard folders `dirs` merged into one, and their
/// images copied into `out`.
pub(super) fn merge_folders(dirs: &[PathBuf], out: &Path) -> Result<Report, Failure> {
    let mut shards = Vec::new();
    for dir in dirs {
        let path = dir.join("report.json");
        let text = std::fs::read_to_string(&path)
            .map_err(|e| Failure::usage(format!("cannot read {}: {e}", path.display())))?;
        let report: Report = serde_json::from_str(&text).map_err(|e| {
            Failure::usage(format!("{} is not a shadelab report: {e}", path.display()))
        })?;
        shards.push((dir, report));
    }
    if let Some((first_dir, first)) = shards.first() {
        for (dir, report) in &shards[1..] {
            let null = serde_json::Value::Null;
            let run_of = |r: &Report| r.run.clone().unwrap_or(null.clone());
            if let Some(why) = run_difference(&run_of(first), &run_of(report)) {
                return Err(Failure::usage(format!(
                    "cannot merge: {} is of another run than {}: {why}",
                    dir.display(),
                    first_dir.display()
                )));
            }
        }
    }
    // Merge (which checks that the shards belong together) before copying
    // anything, so a refused merge leaves --out as it was.
    let merged = merge(shards.iter().map(|(_, r)| r.clone()).collect())
        .map_err(|e| Failure::usage(format!("cannot merge: {e}")))?;
    let mut copies = Vec::new();
    for (dir, report) in &shards {
        let mut files = vec![report.reference_image.clone()];
        if !report.local_reference_image.is_empty() {
            files.push(report.local_reference_image.clone());
        }
        for v in &report.variants {
            files.push(v.image.clone());
            files.push(v.heatmap.clone());
        }
        for file in files {
            // A report names files inside its own folder: a bare file name.
            let mut parts = Path::new(&file).components();
            if !matches!(
                (parts.next(), parts.next()),
                (Some(Component::Normal(_)), None)
            ) {
                return Err(Failure::usage(format!(
                    "{}: image `{file}` is not a file name in the shard's folder",
                    dir.join("report.json").display()
                )));
            }
            copies.push((dir.join(&file), out.join(&file)));
        }
    }
    for (from, to) in copies {
        if from != to {
            std::fs::copy(&from, &to)
                .map_err(|e| Failure::usage(format!("cannot copy {}: {e}", from.display())))?;
        }
    }
    Ok(merged)
}
