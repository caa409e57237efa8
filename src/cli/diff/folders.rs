//! `shadelab diff EXPECTED_DIR ACTUAL_DIR`: every image of the reference
//! folder against the image of the same name in the other, with the limits
//! of a single `diff`; images on one side only are reported, and fail.

use std::collections::BTreeSet;
use std::path::Path;

use shadelab::diff::{compare_files, junit_case, Judging};
use shadelab::junit::{self, TestCase};
use shadelab::metrics::format_figure;

use crate::cli::common::failure::Failure;

/// The image files (`.png`, `.exr`) directly in `dir`, by name.
fn image_names(dir: &Path) -> Result<BTreeSet<String>, Failure> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| Failure::usage(format!("cannot read the folder {}: {e}", dir.display())))?;
    let mut names = BTreeSet::new();
    for entry in entries.flatten() {
        let path = entry.path();
        let is_image = path.extension().is_some_and(|e| {
            let e = e.to_string_lossy().to_ascii_lowercase();
            e == "png" || e == "exr"
        });
        if is_image && path.is_file() {
            names.insert(entry.file_name().to_string_lossy().into_owned());
        }
    }
    Ok(names)
}

/// What one name came to.
struct Case {
    name: String,
    /// "pass", "fail", "missing" (no actual image), "extra" (no
    /// reference), or "error" (unreadable, or of another size).
    status: &'static str,
    failures: Vec<String>,
    figures: Option<serde_json::Value>,
    time_s: f64,
}

pub fn run(
    expected_dir: &Path,
    actual_dir: &Path,
    junit: Option<&Path>,
    json: bool,
    judging: &Judging,
) -> Result<(), Failure> {
    let expected = image_names(expected_dir)?;
    let actual = image_names(actual_dir)?;
    if expected.is_empty() && actual.is_empty() {
        return Err(Failure::usage(format!(
            "neither {} nor {} holds a .png or .exr image",
            expected_dir.display(),
            actual_dir.display()
        )));
    }
    let cases: Vec<Case> = expected
        .union(&actual)
        .map(|name| {
            let started = std::time::Instant::now();
            let case = judge_name(name, &expected, &actual, expected_dir, actual_dir, judging);
            Case {
                time_s: started.elapsed().as_secs_f64(),
                ..case
            }
        })
        .collect();
    let failed = cases.iter().filter(|c| c.status != "pass").count();
    if let Some(path) = junit {
        write_junit(path, &cases)?;
    }
    if json {
        let value = serde_json::json!({
            "expected": expected_dir,
            "actual": actual_dir,
            "pass": failed == 0,
            "cases": cases.iter().map(Case::json).collect::<Vec<_>>(),
            "thresholds": judging.thresholds,
            "settings": judging.settings,
            "edge_threshold": judging.edge_threshold,
        });
        println!("{value}");
    } else {
        print_cases(&cases, failed);
    }
    if failed == 0 {
        Ok(())
    } else {
        Err(Failure {
            code: 1,
            message: format!(
                "{failed} of {} images in {} differ from {} beyond the thresholds, or are on one side only",
                cases.len(),
                actual_dir.display(),
                expected_dir.display()
            ),
        })
    }
}

/// One name: its pair compared, or on which side it is missing.
fn judge_name(
    name: &str,
    expected: &BTreeSet<String>,
    actual: &BTreeSet<String>,
    expected_dir: &Path,
    actual_dir: &Path,
    judging: &Judging,
) -> Case {
    match (expected.contains(name), actual.contains(name)) {
        (true, true) => {
            match compare_files(&expected_dir.join(name), &actual_dir.join(name), judging) {
                Ok(pair) => Case {
                    name: name.to_string(),
                    status: if pair.failures.is_empty() {
                        "pass"
                    } else {
                        "fail"
                    },
                    figures: Some(serde_json::json!({
                        "verdicts": pair.verdicts,
                        "stats": pair.comparison.stats,
                        "flip_mean": pair.comparison.flip.mean,
                        "note": pair.note,
                    })),
                    failures: pair.failures,
                    time_s: 0.0,
                },
                Err(e) => Case {
                    name: name.to_string(),
                    status: "error",
                    failures: vec![e.to_string()],
                    figures: None,
                    time_s: 0.0,
                },
            }
        }
        (true, false) => Case {
            name: name.to_string(),
            status: "missing",
            failures: vec![format!("no {name} in {}", actual_dir.display())],
            figures: None,
            time_s: 0.0,
        },
        _ => Case {
            name: name.to_string(),
            status: "extra",
            failures: vec![format!("no reference {name} in {}", expected_dir.display())],
            figures: None,
            time_s: 0.0,
        },
    }
}

impl Case {
    /// The case as `--json` lists it.
    fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "name": self.name,
            "status": self.status,
            "failures": self.failures,
            "figures": self.figures,
        })
    }
}

/// One JUnit case per name.
fn write_junit(path: &Path, cases: &[Case]) -> Result<(), Failure> {
    let junit_cases: Vec<TestCase> = cases
        .iter()
        .map(|c| {
            let mut case = junit_case(&c.name, &c.failures, c.time_s);
            if matches!(c.status, "error" | "extra") {
                // Nothing could be compared: an error, not a failure.
                case.error = case.failure.take();
            }
            case
        })
        .collect();
    std::fs::write(path, junit::render("shadelab diff", &junit_cases))
        .map_err(|e| Failure::usage(format!("cannot write {}: {e}", path.display())))
}

/// A line per name, then the count that passed.
fn print_cases(cases: &[Case], failed: usize) {
    for c in cases {
        let detail = match (&c.figures, c.failures.first()) {
            (_, Some(_)) => c.failures.join("; "),
            (Some(f), None) => format!(
                "max_abs {}",
                format_figure(f["stats"]["max_abs"].as_f64().unwrap_or(f64::NAN))
            ),
            (None, None) => String::new(),
        };
        println!("{:<8} {}  {detail}", c.status.to_uppercase(), c.name);
    }
    println!("{} of {} images passed", cases.len() - failed, cases.len());
}
