//! The HTML report of a study folder (placeholder until the report lands).

pub mod stats;

use std::path::{Path, PathBuf};

/// Why the report could not be made.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct ReportError(pub String);

/// Writes `DIR/report/index.html` from `DIR/results.json`; returns the page's path.
pub fn write_report(dir: &Path) -> Result<PathBuf, ReportError> {
    Err(ReportError(format!("the report of {} is not written yet", dir.display())))
}
