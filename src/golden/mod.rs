//! Image regression tests (`shadelab golden`) without the command line:
//! each render judged against its stored reference (this driver's, then the
//! shared one), references made or accepted, and what names them.
//!
//! `keys` names the references (a scene's key, a driver's folder),
//! `judge` judges one case's render into a `case` outcome, `record` keeps
//! a run's cases (`golden.json`), counts them into the run's verdict and
//! joins shards' records, `report` makes each case's record (JSON, JUnit,
//! the page's rows) and the page. Rendering the cases and printing them
//! are the caller's.

pub mod case;
pub mod judge;
pub mod keys;
pub mod record;
pub mod report;

pub use case::{mark_settings, CaseError, Judged, Pictures, Status};
pub use judge::{clear_pictures, CaseRender, JudgeOptions};
pub use record::RunRecord;
