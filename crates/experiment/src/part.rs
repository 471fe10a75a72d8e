//! A finished part of a run (some or all of its episodes): the file a run or shard leaves in
//! `DIR/parts/RUN/FIRST-END.json`. Its presence is what resume and merge go by.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use xhab_bridge::report::BenchReport;

/// Episodes `first..end` of run `run`: their report and trajectories.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Part {
    /// The run's id.
    pub run: String,
    /// First episode (index into the run's episodes).
    pub first: usize,
    /// One past the last.
    pub end: usize,
    /// The bench report of these episodes (`xhab bench --out`'s document).
    pub report: BenchReport,
    /// Each reported episode's index in the episode set, parallel to `report.episodes`.
    pub indices: Vec<usize>,
    /// Each invalid episode's index, parallel to `report.invalid.reasons`.
    pub invalid_indices: Vec<usize>,
    /// The top-down path of each reported episode.
    pub trajectories: Vec<Trajectory>,
}

/// An episode's path over its floor's map (world frame, m).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trajectory {
    /// The episode's id.
    pub episode_id: String,
    /// Its index in the episode set.
    pub index: usize,
    /// The floor's map (map_server YAML), relative to the experiment's folder.
    pub map: String,
    /// The robot's positions, one per step (m).
    pub path: Vec<[f64; 2]>,
    /// The shortest path the metrics measure (m).
    pub shortest_path: Vec<[f64; 2]>,
    /// Start position (m).
    pub start: [f64; 2],
    /// Goal positions (m).
    pub goals: Vec<[f64; 2]>,
}

/// Why a part could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum PartError {
    /// Reading or writing failed.
    #[error("{path}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The file is not a part.
    #[error("{path}: not a part of an xhab experiment: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

impl Part {
    /// Where a run's part lives under the experiment folder `dir`.
    pub fn path(dir: &Path, run: &str, first: usize, end: usize) -> PathBuf {
        dir.join("parts").join(run).join(format!("{first}-{end}.json"))
    }

    /// Writes the part to its place under `dir`, atomically (a reader or a resumed run never
    /// sees half a part).
    pub fn write(&self, dir: &Path) -> Result<PathBuf, PartError> {
        let path = Part::path(dir, &self.run, self.first, self.end);
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| PartError::Io { path, source }
        };
        let folder = path.parent().unwrap_or(dir);
        std::fs::create_dir_all(folder).map_err(io(folder))?;
        let json = serde_json::to_string(self).map_err(|e| PartError::Format { path: path.clone(), message: e.to_string() })?;
        let tmp = path.with_extension(format!("tmp{}", std::process::id()));
        std::fs::write(&tmp, json).map_err(io(&tmp))?;
        std::fs::rename(&tmp, &path).map_err(io(&path))?;
        Ok(path)
    }

    /// Reads a part file.
    pub fn read(path: &Path) -> Result<Part, PartError> {
        let text = std::fs::read_to_string(path).map_err(|source| PartError::Io { path: path.to_path_buf(), source })?;
        let p: Part = serde_json::from_str(&text).map_err(|e| PartError::Format { path: path.to_path_buf(), message: e.to_string() })?;
        if p.indices.len() != p.report.episodes.len() || p.invalid_indices.len() != p.report.invalid.reasons.len() {
            return Err(PartError::Format { path: path.to_path_buf(), message: "episode indices do not match the episodes".into() });
        }
        Ok(p)
    }

    /// The parts of `run` found under `dir` (none when the folder does not exist), by range.
    pub fn find(dir: &Path, run: &str) -> Result<Vec<(usize, usize, PathBuf)>, PartError> {
        let folder = dir.join("parts").join(run);
        let entries = match std::fs::read_dir(&folder) {
            Ok(e) => e,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
            Err(source) => return Err(PartError::Io { path: folder, source }),
        };
        let mut out = Vec::new();
        for e in entries {
            let e = e.map_err(|source| PartError::Io { path: folder.clone(), source })?;
            let name = e.file_name().to_string_lossy().into_owned();
            let Some(range) = name.strip_suffix(".json") else { continue };
            let Some((a, b)) = range.split_once('-') else { continue };
            if let (Ok(a), Ok(b)) = (a.parse(), b.parse()) {
                out.push((a, b, e.path()));
            }
        }
        out.sort();
        Ok(out)
    }
}
