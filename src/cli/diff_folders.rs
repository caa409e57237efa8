//! `shadelab diff EXPECTED_DIR ACTUAL_DIR`: every image of the reference
//! folder against the image of the same name in the other, with the limits
//! of a single `diff`; images on one side only are reported, and fail.

use std::collections::BTreeSet;
use std::path::Path;

use shadelab::junit::{self, TestCase};
use shadelab::metrics::format_figure;

use super::diff::{compare_files, DiffArgs, Judging};
use super::Failure;

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

/// A JUnit case for one image: failed with `failures`, passed without.
pub(super) fn junit_case(name: &str, failures: &[String], time_s: f64) -> TestCase {
    TestCase {
        classname: "shadelab diff".to_string(),
        name: name.to_string(),
        time_s,
        failure: (!failures.is_empty()).then(|| failures.join("\n")),
        error: None,
        output: String::new(),
    }
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

pub fn run(args: &DiffArgs, judging: &Judging) -> Result<(), Failure> {
    if args.heatmap.is_some() {
        return Err(Failure::usage(
            "--heatmap names one image; with two folders, compare the image pair that failed on its own to get its heat map".to_string(),
        ));
    }
    let expected = image_names(&args.expected)?;
    let actual = image_names(&args.actual)?;
    if expected.is_empty() && actual.is_empty() {
        return Err(Failure::usage(format!(
            "neither {} nor {} holds a .png or .exr image",
            args.expected.display(),
            args.actual.display()
        )));
    }
    let mut cases = Vec::new();
    for name in expected.union(&actual) {
        let started = std::time::Instant::now();
        let case = match (expected.contains(name), actual.contains(name)) {
            (true, true) => {
                match compare_files(&args.expected.join(name), &args.actual.join(name), judging) {
                    Ok(pair) => Case {
                        name: name.clone(),
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
                        name: name.clone(),
                        status: "error",
                        failures: vec![e.message],
                        figures: None,
                        time_s: 0.0,
                    },
                }
            }
            (true, false) => Case {
                name: name.clone(),
                status: "missing",
                failures: vec![format!("no {name} in {}", args.actual.display())],
                figures: None,
                time_s: 0.0,
            },
            _ => Case {
                name: name.clone(),
                status: "extra",
                failures: vec![format!(
                    "no reference {name} in {}",
                    args.expected.display()
                )],
                figures: None,
                time_s: 0.0,
            },
        };
        cases.push(Case {
            time_s: started.elapsed().as_secs_f64(),
            ..case
        });
    }
    let failed = cases.iter().filter(|c| c.status != "pass").count();
    if let Some(path) = &args.junit {
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
            .map_err(|e| Failure::usage(format!("cannot write {}: {e}", path.display())))?;
    }
    if args.json {
        let list: Vec<serde_json::Value> = cases
            .iter()
            .map(|c| {
                serde_json::json!({
                    "name": c.name,
                    "status": c.status,
                    "failures": c.failures,
                    "figures": c.figures,
                })
            })
            .collect();
        let value = serde_json::json!({
            "expected": args.expected,
            "actual": args.actual,
            "pass": failed == 0,
            "cases": list,
            "thresholds": judging.thresholds,
            "settings": judging.settings,
            "edge_threshold": judging.edge_threshold,
        });
        println!("{value}");
    } else {
        for c in &cases {
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
    if failed == 0 {
        Ok(())
    } else {
        Err(Failure {
            code: 1,
            message: format!(
                "{failed} of {} images in {} differ from {} beyond the thresholds, or are on one side only",
                cases.len(),
                args.actual.display(),
                args.expected.display()
            ),
        })
    }
}
