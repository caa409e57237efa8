//! `compare`'s report on the terminal: a row per variant, the variants
//! not run and why, and what `--budget` found.

use std::path::Path;

use shadelab::compare::report::Budget;
use shadelab::compare::Report;

/// The report as a table, with the references and what the front and
/// the budget measure against.
pub(super) fn print_table(report: &Report, dir: &Path) {
    println!(
        "{} at {}x{} on {}, median of {} run{}",
        report.scene,
        report.width,
        report.height,
        report.device_and_driver(),
        report.runs,
        if report.runs == 1 { "" } else { "s" },
    );
    println!("global reference (model_*): {}", report.reference);
    println!("local reference (local_*):  {}", report.local_reference);
    println!(
        "pareto front and budget: {} against the {}",
        report.plot_metric.name(),
        report.plot_reference.describe()
    );
    println!(
        "{:<40} {:>9} {:>9} {:>9} {:>11} {:>11} {:>10} {:>11} {:>7}",
        "variant",
        "gpu_ms",
        "frame_ms",
        "image_ms",
        "impl_rmse",
        "model_rmse",
        "model_flip",
        "local_rmse",
        "pareto"
    );
    for v in &report.variants {
        let local = v
            .local_error
            .map(|e| format!("{:.2e}", e.rmse))
            .unwrap_or_else(|| "-".into());
        println!(
            "{:<40} {:>9.1} {:>9.1} {:>9.1} {:>11.2e} {:>11.2e} {:>10.4} {:>11} {:>7}",
            v.name,
            v.timing.gpu_ms,
            v.timing.frame_ms,
            v.timing.image_ms,
            v.implementation_error.rmse,
            v.model_error.rmse,
            v.model_error.flip_mean,
            local,
            if v.pareto { "*" } else { "" }
        );
    }
    for v in &report.not_run {
        println!("{:<40} not run: {}", v.name, v.reason);
    }
    if let Some(budget) = &report.budget {
        println!("{}", budget_line(report, budget));
    }
    println!("report: {}", dir.join("report.json").display());
}

/// What `--budget` found, in one line.
pub(super) fn budget_line(report: &Report, budget: &Budget) -> String {
    let what = format!(
        "{} <= {} against the {}",
        report.plot_metric.name(),
        budget.max_error,
        report.plot_reference.describe()
    );
    match budget
        .fastest
        .as_ref()
        .and_then(|name| report.variants.iter().find(|v| &v.name == name))
    {
        Some(v) => format!(
            "budget: the fastest variant with {what}: {} ({:.1} ms, error {:.3e})",
            v.name,
            v.timing.gpu_ms,
            report.error_of(v)
        ),
        None => format!("budget: no variant has {what}"),
    }
}
