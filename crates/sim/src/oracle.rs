//! The shortest-path follower: a greedy oracle over discrete actions, as Habitat's
//! ShortestPathFollower.

use crate::action::Action;
use crate::env::DiscreteEnv;
use xhab_types::normalize_angle;

/// Chooses the action that follows the geodesic shortest path: stop inside the success
/// radius, otherwise face the path's next bend point (within half a turn) and move forward.
#[derive(Debug, Clone, Default)]
pub struct ShortestPathFollower {
    stuck: u32,
}

impl ShortestPathFollower {
    /// A follower.
    pub fn new() -> Self {
        Self::default()
    }

    /// The next action for the agent in `env`.
    pub fn act(&mut self, env: &dyn DiscreteEnv) -> Action {
        let cfg = env.config();
        let d = env.distance_to_goal();
        // Stop a safe margin inside the strict success radius.
        if d < cfg.success_distance * 0.95 {
            return Action::Stop;
        }
        let pose = env.pose();
        let Some(wp) = env.field().next_waypoint(env.grid(), pose.position(), 0.5 * cfg.forward_step_size) else {
            return Action::Stop;
        };
        let bearing = normalize_angle((wp.y - pose.y).atan2(wp.x - pose.x) - pose.yaw);
        let half_turn = 0.5 * cfg.turn_angle.to_radians();
        if bearing.abs() <= half_turn + 1e-9 {
            Action::MoveForward
        } else if bearing > 0.0 {
            Action::TurnLeft
        } else {
            Action::TurnRight
        }
    }

    /// Forgets the episode's state.
    pub fn reset(&mut self) {
        self.stuck = 0;
    }
}
