//! How a benchmark runs its episodes: the agent, the task, threads, seeds, physics, the nav
//! stack's setup and the camera.

use crate::agents::AgentKind;
use std::sync::Arc;
use xhab_sim::env::TaskConfig;
use xhab_sim::physics_env::PhysicsConfig;
use xhab_sim::robot::{PhysicsScene, RobotProfile};
use xhab_sim::sensors::CameraRig;

/// How to run a benchmark.
#[derive(Debug, Clone)]
pub struct RunConfig {
    /// The agent.
    pub agent: AgentKind,
    /// The task settings.
    pub task: TaskConfig,
    /// Worker threads (1 = sequential).
    pub threads: usize,
    /// Keep each episode's trajectory (poses after each step).
    pub record_trajectories: bool,
    /// Run under physics (Algorithm 1) instead of teleporting.
    pub physics: Option<PhysicsSetup>,
    /// Seed of everything random in a run (odometry noise); episode i uses seed + i.
    pub seed: u64,
    /// The native navigation stack's setup, for the `nav` agent (which needs physics).
    pub nav: Option<crate::nav_agent::NavSetup>,
    /// The camera whose frames every observation carries (`--sensors`), if any.
    pub sensors: Option<Arc<CameraRig>>,
    /// Each episode's index in its file when the dataset is a selection of the file (seeds
    /// derive from the index, so a slice reproduces those episodes of the whole run);
    /// `None`: the dataset is the whole file.
    pub episode_indices: Option<Arc<[usize]>>,
}

impl RunConfig {
    /// The index in its file of the dataset's `i`-th episode (its seeds derive from it).
    pub fn episode_index(&self, i: usize) -> usize {
        self.episode_indices.as_ref().and_then(|v| v.get(i).copied()).unwrap_or(i)
    }
}

/// What a physics run needs: the scene's shared rigid mesh, the robot and the settings.
#[derive(Debug, Clone)]
pub struct PhysicsSetup {
    /// The scene as a static trimesh, shared by every episode.
    pub scene: Arc<PhysicsScene>,
    /// The robot.
    pub profile: RobotProfile,
    /// Control period, physics rate, odometry noise, stuck detection.
    pub config: PhysicsConfig,
}
