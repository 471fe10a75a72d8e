//! Habitat's PointNav metrics (habitat-lab 0.3 definitions).

use serde::{Deserialize, Serialize};

/// Metrics of one episode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EpisodeMetrics {
    /// 1 if `stop` was called with distance_to_goal < success_distance, else 0.
    pub success: f64,
    /// Success weighted by path length: success * d0 / max(d0, P).
    pub spl: f64,
    /// max(0, 1 - dtg / d0) * d0 / max(d0, P).
    pub soft_spl: f64,
    /// Geodesic distance from the agent to the nearest goal at the end (m).
    pub distance_to_goal: f64,
    /// Actions taken, `stop` included.
    pub steps: u32,
    /// Actions whose motion was blocked or deflected by an obstacle.
    pub collisions: u32,
    /// Length of the path actually travelled, P (m).
    pub path_length: f64,
    /// Geodesic distance from start to goal at reset, d0 (m).
    pub start_distance: f64,
    /// Whether the agent called `stop`.
    pub called_stop: bool,
    /// When the agent ended off its navigable region (where the geodesic is undefined): the
    /// distance (m) from its position to the nearest navigable point, from which
    /// `distance_to_goal` is then measured (this offset included). `None` on the region.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub off_navigable_m: Option<f64>,
}

impl EpisodeMetrics {
    /// The metrics of an episode from its state: whether stop was called, the final distance
    /// to goal `dtg`, d0 and the path length P (m), and the counts.
    pub fn new(success_distance: f64, called_stop: bool, dtg: f64, d0: f64, path_length: f64, steps: u32, collisions: u32) -> Self {
        let success = called_stop && dtg < success_distance;
        let (spl, soft_spl) = spl(success, d0, path_length, dtg);
        EpisodeMetrics {
            success: if success { 1.0 } else { 0.0 },
            spl,
            soft_spl,
            distance_to_goal: dtg,
            steps,
            collisions,
            path_length,
            start_distance: d0,
            called_stop,
            off_navigable_m: None,
        }
    }

    /// The metrics of an episode ending at a point `off` (m) from the navigable region
    /// (`dtg` measured from its nearest navigable point, the offset included).
    pub fn off_navigable(mut self, off: Option<f64>) -> Self {
        self.off_navigable_m = off;
        self
    }
}

/// SPL and soft SPL from their ingredients (m).
pub fn spl(success: bool, d0: f64, path_length: f64, dtg: f64) -> (f64, f64) {
    let ratio = if d0 <= 0.0 { 1.0 } else { d0 / d0.max(path_length) };
    let spl = if success { ratio } else { 0.0 };
    let soft = if d0 <= 0.0 { if success { 1.0 } else { 0.0 } } else { (1.0 - dtg / d0).max(0.0) * ratio };
    (spl, soft)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spl_matches_habitat() {
        assert_eq!(spl(true, 5.0, 5.0, 0.1), (1.0, 0.98));
        assert_eq!(spl(true, 5.0, 10.0, 0.1).0, 0.5);
        assert_eq!(spl(false, 5.0, 4.0, 1.0), (0.0, 0.8));
        assert_eq!(spl(false, 5.0, 4.0, 6.0).1, 0.0);
    }
}
