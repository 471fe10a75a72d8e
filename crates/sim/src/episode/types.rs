//! The episode data model, in the world frame (converted from Habitat's at the file boundary).

use xhab_types::Point3;

/// A goal of a PointNav episode.
#[derive(Debug, Clone, PartialEq)]
pub struct Goal {
    /// Goal position (m, world frame).
    pub position: Point3,
    /// Goal radius as stored in the file (m).
    pub radius: f64,
}

/// A PointNav episode.
#[derive(Debug, Clone, PartialEq)]
pub struct Episode {
    /// Episode id (numbers in files are kept as their text).
    pub episode_id: String,
    /// Scene id as in the file.
    pub scene_id: String,
    /// Start position (m, world frame; z is the floor height).
    pub start_position: Point3,
    /// Start heading (rad, world frame, CCW from +x).
    pub start_yaw: f64,
    /// Goals (the nearest one counts).
    pub goals: Vec<Goal>,
    /// `info.geodesic_distance` from the file (m), if any.
    pub geodesic_distance: Option<f64>,
    /// The whole `info` object, kept for round trips.
    pub info: serde_json::Value,
}

/// A set of episodes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Dataset {
    /// The episodes, in file order.
    pub episodes: Vec<Episode>,
}
