//! Agents that act in the discrete simulator.

use serde::{Deserialize, Serialize};
use xhab_sim::action::Action;
use xhab_sim::env::{EnvView, Observation};
use xhab_sim::oracle::ShortestPathFollower;
use xhab_sim::sensors::CameraFrame;

/// An agent of discrete actions. It sees the environment through `env` (its observation,
/// and privileged state for oracles) and, when the run renders them, the camera's images.
pub trait DiscreteAgent: Send {
    /// The next action, given the camera frame of this step (`--sensors`).
    fn act(&mut self, env: &dyn EnvView, frame: Option<&CameraFrame>) -> Action;
    /// The next action, given also the task's observation of this step (GPS, compass, point
    /// goal), as the in-process runner calls it. Agents that read only `env` keep this
    /// default, which calls [`DiscreteAgent::act`].
    fn act_observed(&mut self, env: &dyn EnvView, obs: &Observation, frame: Option<&CameraFrame>) -> Action {
        let _ = obs;
        self.act(env, frame)
    }
    /// Called before each episode.
    fn reset(&mut self) {}
}

/// Which agent `xhab bench --agent` runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AgentKind {
    /// Greedy shortest-path follower (Habitat's ShortestPathFollower).
    Oracle,
    /// The native navigation stack (costmap, planner, DWA, navigator) with velocity commands.
    Nav,
    /// An external ROS navigation stack, driven through its standard interfaces
    /// (`xhab bench --agent ros`).
    Ros,
    /// An external ROS 2 navigation stack (Nav2, or any node offering `navigate_to_pose`),
    /// driven through its standard interfaces (`xhab bench --agent ros2`).
    Ros2,
}

impl AgentKind {
    /// A fresh discrete agent of this kind; `None` for the nav agent, which drives with
    /// velocities (see `nav_agent`).
    pub fn build(self) -> Option<Box<dyn DiscreteAgent>> {
        match self {
            AgentKind::Oracle => Some(Box::new(OracleAgent(ShortestPathFollower::new()))),
            AgentKind::Nav | AgentKind::Ros | AgentKind::Ros2 => None,
        }
    }
    /// Whether this is an external stack benchmarked over ROS (`ros`, `ros2`).
    pub fn is_external(self) -> bool {
        matches!(self, AgentKind::Ros | AgentKind::Ros2)
    }
    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            AgentKind::Oracle => "oracle",
            AgentKind::Nav => "nav",
            AgentKind::Ros => "ros",
            AgentKind::Ros2 => "ros2",
        }
    }
}

struct OracleAgent(ShortestPathFollower);

impl DiscreteAgent for OracleAgent {
    fn act(&mut self, env: &dyn EnvView, _frame: Option<&CameraFrame>) -> Action {
        self.0.act(env)
    }
    fn reset(&mut self) {
        self.0.reset();
    }
}
