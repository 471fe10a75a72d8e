//! The HTML report of a study folder: `DIR/report/index.html` with its figures beside it
//! (SVG charts, PNG trajectory maps), relative links only and no scripts, so it opens from
//! the file system. [`summary`] computes the numbers, [`stats`] their intervals, [`figures`]
//! draws the charts, [`trajectories`] the maps and [`html`] writes the page.

pub mod example;
pub mod figures;
pub mod html;
pub mod stats;
pub mod summary;
pub mod trajectories;

use crate::results::{read_results, ExperimentRecord, ResultsError};
use crate::spec::TrajectorySpec;
use std::path::{Path, PathBuf};

/// Why the report could not be made; each names the file at fault.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// `results.json` or `experiment.json` could not be read.
    #[error("reading the study: {0}")]
    Results(#[from] ResultsError),
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A file is not what it should be.
    #[error("{}: {message}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A figure could not be drawn.
    #[error("drawing {}: {message}", path.display())]
    Figure {
        /// The figure's file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A trajectory's map could not be read.
    #[error("reading a trajectory's map: {0}")]
    Map(#[from] xhab_nav::map_server::MapError),
    /// A trajectory picture could not be written.
    #[error(transparent)]
    Picture(#[from] xhab_bridge::map_picture::PictureError),
}

/// Writes `DIR/report/index.html` from `DIR/results.json` (and `DIR/experiment.json`, for the
/// configurations' order and which trajectories to draw); returns the page's path.
pub fn write_report(dir: &Path) -> Result<PathBuf, ReportError> {
    let results = read_results(dir)?;
    let mut notes = Vec::new();
    let (order, spec) = if ExperimentRecord::path(dir).exists() {
        let record = ExperimentRecord::read(dir)?;
        (record.spec.configurations.iter().map(|c| c.label()).collect(), record.spec.trajectories)
    } else {
        notes.push("experiment.json is missing: configurations appear in run order, and trajectories are the default 2 lowest-SPL episodes per run.".to_string());
        (Vec::new(), TrajectorySpec::default())
    };
    let out = dir.join("report");
    // Pictures of an earlier report would linger beside the new ones.
    let old = out.join("trajectories");
    if old.exists() {
        std::fs::remove_dir_all(&old).map_err(|source| ReportError::Io { path: old.clone(), source })?;
    }
    std::fs::create_dir_all(&out).map_err(|source| ReportError::Io { path: out.clone(), source })?;
    if results.runs.is_empty() {
        notes.push("The study has no runs.".to_string());
    }
    let summary = summary::Summary::new(&results, &order);
    let figures = figures::write_all(&out, &summary)?;
    let runs = trajectories::draw(dir, &out, &results, &spec)?;
    let page = html::page(&html::Page { results: &results, summary: &summary, figures: &figures, runs: &runs, trajectories: &spec, notes: &notes });
    let path = out.join("index.html");
    std::fs::write(&path, page).map_err(|source| ReportError::Io { path: path.clone(), source })?;
    Ok(path)
}

#[cfg(test)]
mod tests;
