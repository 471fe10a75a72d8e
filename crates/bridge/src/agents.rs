//! Agents that act in the discrete simulator.

use serde::{Deserialize, Serialize};
use xhab_sim::action::Action;
use xhab_sim::env::DiscreteEnv;
use xhab_sim::oracle::ShortestPathFollower;

/// An agent of discrete actions. It sees the environment through `env` (its observation,
/// and privileged state for oracles).
pub trait DiscreteAgent: Send {
    /// The next action.
    fn act(&mut self, env: &dyn DiscreteEnv) -> Action;
    /// Called before each episode.
    fn reset(&mut self) {}
}

/// Which agent `xhab bench --agent` runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AgentKind {
    /// Greedy shortest-path follower (Habitat's ShortestPathFollower).
    Oracle,
}

impl AgentKind {
    /// A fresh agent of this kind.
    pub fn build(self) -> Box<dyn DiscreteAgent> {
        match self {
            AgentKind::Oracle => Box::new(OracleAgent(ShortestPathFollower::new())),
        }
    }
    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            AgentKind::Oracle => "oracle",
        }
    }
}

struct OracleAgent(ShortestPathFollower);

impl DiscreteAgent for OracleAgent {
    fn act(&mut self, env: &dyn DiscreteEnv) -> Action {
        self.0.act(env)
    }
    fn reset(&mut self) {
        self.0.reset();
    }
}
