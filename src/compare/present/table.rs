//! `report.csv`: one row per variant with every figure of the report.

use super::error::PresentError;
use crate::compare::report::{Errors, Report};

/// The header, in column order.
pub const COLUMNS: [&str; 20] = [
    "name",
    "impl_rmse",
    "impl_max_abs",
    "impl_psnr",
    "impl_flip_mean",
    "model_rmse",
    "model_max_abs",
    "model_psnr",
    "model_flip_mean",
    "local_rmse",
    "local_max_abs",
    "local_psnr",
    "local_flip_mean",
    "gpu_ms",
    "gpu_spread_ms",
    "frame_ms",
    "frame_spread_ms",
    "pipeline_ms",
    "image_ms",
    "pareto",
];

/// The CSV bytes. Numbers are written in Rust's shortest round-trip form,
/// so they parse back to the report's exact values; a PSNR of identical
/// images (`None`) is `inf`; `pareto` is `true` or `false`. The local
/// errors are empty in a report made before the local reference existed.
pub(crate) fn csv(report: &Report) -> Result<Vec<u8>, PresentError> {
    let err = |e: csv::Error| PresentError::Draw {
        what: "CSV table",
        message: e.to_string(),
    };
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(COLUMNS).map_err(err)?;
    for v in &report.variants {
        let t = &v.timing;
        let mut row = vec![v.name.clone()];
        row.extend(errors(&v.implementation_error));
        row.extend(errors(&v.model_error));
        match &v.local_error {
            Some(e) => row.extend(errors(e)),
            None => row.extend([""; 4].map(String::from)),
        }
        row.extend(
            [
                t.gpu_ms,
                t.gpu_spread_ms,
                t.frame_ms,
                t.frame_spread_ms,
                t.pipeline_ms,
                t.image_ms,
            ]
            .map(|x| x.to_string()),
        );
        row.push(v.pareto.to_string());
        w.write_record(&row).map_err(err)?;
    }
    w.into_inner().map_err(|e| PresentError::Draw {
        what: "CSV table",
        message: e.to_string(),
    })
}

fn errors(e: &Errors) -> [String; 4] {
    [
        e.rmse.to_string(),
        e.max_abs.to_string(),
        e.psnr.map_or_else(|| "inf".to_string(), |p| p.to_string()),
        e.flip_mean.to_string(),
    ]
}
