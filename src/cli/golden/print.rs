//! `golden`'s lines on the terminal for each case as it is judged.

use std::path::Path;

use shadelab::golden::{Judged, Status};
use shadelab::metrics::format_figure;

use crate::cli::common::batch::CaseView;

/// The case's lines on the terminal.
pub(super) fn print_case(view: &CaseView, judged: &Judged, out: &Path) {
    let label = format!("{}/{}", view.name, view.shading);
    let word = judged.status.word();
    let reference = judged
        .reference
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_default();
    match judged.status {
        Status::Pass => {
            let figures = judged
                .comparison
                .as_ref()
                .map(|c| format!("max_abs {}", format_figure(c.stats.max_abs)))
                .unwrap_or_default();
            println!("{word:<8} {label}  {reference}  {figures}");
        }
        Status::Created if judged.failures.is_empty() => {
            println!("{word:<8} {label}  {reference} (from this render)")
        }
        Status::Created => println!(
            "{word:<8} {label}  {reference} (from this render; the shared one was: {})",
            judged.failures.join("; ")
        ),
        Status::Updated => println!(
            "{word:<8} {label}  {reference} (was: {})",
            judged.failures.join("; ")
        ),
        Status::Error => println!(
            "{word:<8} {label}  {}",
            judged.error.as_ref().map_or("", |e| e.message.as_str())
        ),
        Status::Fail | Status::Missing => {
            println!("{word:<8} {label}  {reference}");
            for f in &judged.failures {
                println!("         {f}");
            }
            if let Some(hint) = &judged.hint {
                println!("         {hint}");
            }
            if !judged.written.is_empty() {
                let names: Vec<String> = judged
                    .written
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect();
                println!(
                    "         see {} and {}",
                    names.join(", "),
                    out.join("report.html").display()
                );
            }
        }
    }
}
