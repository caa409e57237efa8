//! What a `golden` case came to: its status, the reference it was judged
//! against, the figures and the pictures a person looks at. The judging
//! makes these, the reports and the record read them.

use std::path::PathBuf;

use crate::metrics::{Comparison, Verdict};

/// Why a case could not be judged, and the exit status it gives a run
/// whose every case is such an error.
#[derive(Debug, Clone)]
pub struct CaseError {
    pub code: u8,
    pub message: String,
}

impl From<crate::Error> for CaseError {
    fn from(e: crate::Error) -> Self {
        CaseError {
            code: e.exit_code() as u8,
            message: e.to_string(),
        }
    }
}

/// What a case came to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Within the limits of its reference.
    Pass,
    /// Over them (or of another size).
    Fail,
    /// No reference, and none made.
    Missing,
    /// No reference: made from this render (`--create`, `--bless`).
    Created,
    /// Over its limits, and rewritten from this render (`--bless`).
    Updated,
    /// Not rendered, or its reference unreadable.
    Error,
}

impl Status {
    pub fn word(self) -> &'static str {
        match self {
            Status::Pass => "PASS",
            Status::Fail => "FAIL",
            Status::Missing => "MISSING",
            Status::Created => "CREATED",
            Status::Updated => "UPDATED",
            Status::Error => "ERROR",
        }
    }
}

/// One case judged against its reference.
pub struct Judged {
    pub status: Status,
    /// The reference compared with, or written.
    pub reference: Option<PathBuf>,
    /// `driver` (DIR/KEY/NAME) or `shared` (DIR/NAME).
    pub reference_kind: Option<&'static str>,
    pub failures: Vec<String>,
    pub verdicts: Vec<Verdict>,
    pub comparison: Option<Comparison>,
    /// Said with the failure: the reference was made on another driver.
    pub hint: Option<String>,
    pub error: Option<CaseError>,
    /// The images a person looks at, as PNG bytes: expected, actual and
    /// heat map, for the cases that did not pass (and the blessed ones).
    pub pictures: Option<Pictures>,
    /// Files written into `--out` for this case.
    pub written: Vec<PathBuf>,
    pub time_s: f64,
}

pub struct Pictures {
    pub expected: Option<Vec<u8>>,
    pub actual: Vec<u8>,
    pub heatmap: Option<Vec<u8>>,
    /// The per-pixel error scaled so that its largest is white, and that
    /// largest error.
    pub error: Option<(Vec<u8>, f64)>,
    pub width: u32,
    pub height: u32,
}

impl Judged {
    /// `status`, against `reference` (with its kind), nothing else yet.
    pub fn new(status: Status, reference: Option<(PathBuf, &'static str)>) -> Self {
        let (reference, reference_kind) = reference.unzip();
        Judged {
            status,
            reference,
            reference_kind,
            failures: Vec::new(),
            verdicts: Vec::new(),
            comparison: None,
            hint: None,
            error: None,
            pictures: None,
            written: Vec::new(),
            time_s: 0.0,
        }
    }

    pub fn error(error: CaseError, time_s: f64) -> Self {
        Judged {
            error: Some(error),
            time_s,
            ..Judged::new(Status::Error, None)
        }
    }
}

/// What a golden case's image records of what made it, beside the
/// render's settings (`render::described::effective_settings`): the case's
/// key, and the lighting hook's source by its digest (a hook whose text
/// changed made another image under the same file name).
pub fn mark_settings(settings: &mut serde_json::Value, key: &str, hook_source: Option<&str>) {
    settings["golden_scene"] = key.into();
    if let Some(source) = hook_source {
        settings["lighting_fnv1a"] = crate::digest::fnv1a_hex(source.as_bytes()).into();
    }
}
