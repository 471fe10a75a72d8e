//! What came of one episode: its metrics and what else the run recorded, or why it could not
//! run.

use serde::{Deserialize, Serialize};
use xhab_sim::metrics::EpisodeMetrics;
use xhab_types::Pose2;

/// The outcome of one episode that ran.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EpisodeRun {
    /// The episode's id.
    pub episode_id: String,
    /// Its metrics.
    pub metrics: EpisodeMetrics,
    /// Wall time of the episode, reset included (s).
    pub wall_s: f64,
    /// Poses from the start, one per step (when recorded).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trajectory: Option<Vec<Pose2>>,
    /// Simulated time (s), physics runs only.
    pub sim_s: Option<f64>,
    /// Whether the robot got stuck (no progress over the stuck window), physics runs only.
    pub stuck: Option<bool>,
    /// Why it got stuck, when a step higher than its `step_height` held it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stuck_cause: Option<String>,
    /// Why the navigator gave up, when it did (nav runs): `goal_unreachable_for_costmap`,
    /// `start_blocked`, `controller_failed`, `no_progress`, or `unknown` (over ROS).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub abort_reason: Option<String>,
    /// Localisation position error (m) and the filter's position spread (m) at its last
    /// update (AMCL runs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub final_localization: Option<[f64; 2]>,
    /// Mean localisation error against ground truth: position (m), heading (rad), over the
    /// filter's updates (AMCL runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub localization_error: Option<[f64; 2]>,
    /// Camera frames rendered, and the wall time spent rendering them (s) (`--sensors` runs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub render: Option<(u64, f64)>,
    /// How an external ROS stack's episode went (`--agent ros` runs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ros: Option<crate::ros::external::RosEpisode>,
}

/// An episode that could not run, and why.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct InvalidRun {
    /// The episode's id.
    pub episode_id: String,
    /// Why, in words.
    pub reason: String,
}

/// What happened to one episode (one per episode: the variants' size difference costs
/// nothing).
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)]
pub enum Outcome {
    /// It ran.
    Ran(EpisodeRun),
    /// It was invalid for the agent.
    Invalid(InvalidRun),
}
