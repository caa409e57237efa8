//! `check`'s report of its cases as they come in: the verdict lines, the
//! JUnit cases, the JSON objects, and the exit status made from them.

use std::path::Path;

use shadelab::check::CheckOutcome;
use shadelab::junit::TestCase;
use shadelab::shading::Shading;

use crate::cli::common::failure::Failure;

/// Which case images `check` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum KeepImages {
    /// Every case's expected, actual and diff images.
    All,
    /// Only the images of cases that failed their thresholds.
    Failures,
    /// None.
    None,
}

/// The cases as they come in: the lines printed, the JUnit cases, the JSON
/// objects, and the counts the exit status is made from.
pub(super) struct CaseReport {
    json_out: bool,
    pub cases: Vec<TestCase>,
    pub json: Vec<serde_json::Value>,
    pub failed: usize,
    pub errors: usize,
    /// Errors already printed in full, with the case that printed each: a
    /// hook that does not compile fails every case with the same message,
    /// printed once.
    printed: Vec<(String, String)>,
    first_error: Option<Failure>,
}

impl CaseReport {
    pub fn new(json_out: bool) -> Self {
        Self {
            json_out,
            cases: Vec::new(),
            json: Vec::new(),
            failed: 0,
            errors: 0,
            printed: Vec::new(),
            first_error: None,
        }
    }

    pub fn outcome(&mut self, name: &str, shading: Shading, outcome: &CheckOutcome, out: &Path) {
        let verdict = if outcome.passed() { "PASS" } else { "FAIL" };
        if !outcome.passed() {
            self.failed += 1;
        }
        let summary = summary(outcome);
        if !self.json_out {
            println!("{verdict} {name}/{shading}  {summary}");
            for f in &outcome.judgement.failures {
                println!("     {f}");
            }
        }
        self.cases.push(TestCase {
            classname: name.to_string(),
            name: shading.to_string(),
            time_s: outcome.renders_ms / 1e3,
            failure: (!outcome.passed()).then(|| outcome.judgement.failures.join("\n")),
            error: None,
            output: summary,
        });
        self.json.push(serde_json::json!({
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
            "images": out.join(name).join(shading.to_string()),
        }));
    }

    /// A case that could not run: a JUnit error with its reason.
    pub fn error(&mut self, name: &str, shading: Shading, error: Failure) {
        self.errors += 1;
        if !self.json_out {
            match self.printed.iter().find(|(m, _)| *m == error.message) {
                Some((_, case)) => {
                    println!("ERROR {name}/{shading}  the same error as {case} above")
                }
                None => println!("ERROR {name}/{shading}  {}", error.message),
            }
        }
        if !self.printed.iter().any(|(m, _)| *m == error.message) {
            self.printed
                .push((error.message.clone(), format!("{name}/{shading}")));
        }
        self.cases.push(TestCase {
            classname: name.to_string(),
            name: shading.to_string(),
            time_s: 0.0,
            failure: None,
            error: Some(error.message.clone()),
            output: String::new(),
        });
        self.json.push(serde_json::json!({
            "scene": name,
            "shading": shading,
            "passed": false,
            "error": error.message,
        }));
        self.first_error.get_or_insert(error);
    }

    /// 0 when every case passed; when none could run, the first error's
    /// status (2 bad input, 3 no device); else 1.
    pub fn exit_status(self) -> Result<(), Failure> {
        let total = self.cases.len();
        match self.first_error {
            Some(error) if self.errors == total => Err(error),
            _ if self.failed + self.errors == 0 => Ok(()),
            _ => Err(Failure {
                code: 1,
                message: format!(
                    "{} of {total} cases failed their thresholds{}",
                    self.failed,
                    if self.errors > 0 {
                        format!(" and {} could not run", self.errors)
                    } else {
                        String::new()
                    }
                ),
            }),
        }
    }
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
