//! The shortest-path follower: a greedy oracle over discrete actions, as Habitat's
//! ShortestPathFollower.

use crate::action::Action;
use crate::env::EnvView;
use crate::kinematic::try_step;
use xhab_types::{normalize_angle, Point2};

/// Chooses the action that follows the geodesic shortest path: stop inside the success
/// radius; otherwise face the path's next bend point that the agent sees (within half a turn)
/// and move forward. When a forward move would make no progress (a corner the agent's disc
/// catches on), it looks for the heading whose forward move reduces the geodesic distance
/// most, turns to it and moves, as Habitat's greedy follower does.
#[derive(Debug, Clone, Default)]
pub struct ShortestPathFollower {
    /// A heading (rad) to turn to and then move along, chosen when the direct way is blocked.
    detour: Option<f64>,
}

/// Where a forward move from `p` along heading `yaw` ends.
fn forward(env: &dyn EnvView, p: Point2, yaw: f64) -> Point2 {
    let step = env.config().forward_step_size;
    let (s, c) = yaw.sin_cos();
    try_step(env.grid(), p, Point2::new(p.x + c * step, p.y + s * step)).0
}

/// Least geodesic progress of a forward move that counts as progress (m).
const MIN_PROGRESS: f64 = 0.01;

impl ShortestPathFollower {
    /// A follower.
    pub fn new() -> Self {
        Self::default()
    }

    /// The next action for the agent in `env`.
    pub fn act(&mut self, env: &dyn EnvView) -> Action {
        let cfg = env.config();
        let d = env.distance_to_goal();
        // Stop a safe margin inside the strict success radius.
        if d < cfg.success_distance * 0.95 {
            return Action::Stop;
        }
        let pose = env.pose();
        let turn = cfg.turn_angle.to_radians();
        let half_turn = 0.5 * turn + 1e-9;
        // Off the navigable region (a body under physics can drift there, over a drop's edge
        // say): head back to the nearest navigable cell first, as Habitat snaps to its navmesh.
        if !env.grid().is_navigable(pose.position()) && self.detour.is_none() {
            if let Some((i, _)) = env.grid().nearest_cell_where(pose.position(), |j| env.grid().is_nav_cell(j)) {
                let c = env.grid().center(i);
                let bearing = normalize_angle((c[1] - pose.y).atan2(c[0] - pose.x) - pose.yaw);
                if bearing.abs() > half_turn {
                    return if bearing > 0.0 { Action::TurnLeft } else { Action::TurnRight };
                }
                return Action::MoveForward;
            }
        }
        if let Some(target) = self.detour {
            let e = normalize_angle(target - pose.yaw);
            if e.abs() <= half_turn {
                self.detour = None;
                return Action::MoveForward;
            }
            return if e > 0.0 { Action::TurnLeft } else { Action::TurnRight };
        }
        let Some(wp) = env.field().next_waypoint(env.grid(), pose.position(), 0.5 * cfg.forward_step_size) else {
            return self.best_heading(env, d);
        };
        let bearing = normalize_angle((wp.y - pose.y).atan2(wp.x - pose.x) - pose.yaw);
        if bearing.abs() > half_turn {
            return if bearing > 0.0 { Action::TurnLeft } else { Action::TurnRight };
        }
        if self.progress(env, pose.yaw, d) >= MIN_PROGRESS {
            Action::MoveForward
        } else {
            self.best_heading(env, d)
        }
    }

    /// Geodesic progress (m) of a forward move along heading `yaw` from the agent's position.
    fn progress(&self, env: &dyn EnvView, yaw: f64, d: f64) -> f64 {
        d - env.field().distance(env.grid(), forward(env, env.pose().position(), yaw))
    }

    /// Turns towards the heading (a whole number of turns away) whose forward move makes the most
    /// geodesic progress, preferring small turns; moves forward if that is the current one.
    fn best_heading(&mut self, env: &dyn EnvView, d: f64) -> Action {
        let yaw = env.pose().yaw;
        let turn = env.config().turn_angle.to_radians();
        let n = (std::f64::consts::PI / turn).round().max(1.0) as i64;
        let mut best: Option<(f64, i64)> = None;
        for k in 0..=n {
            for k in if k == 0 { vec![0] } else { vec![k, -k] } {
                let g = self.progress(env, yaw + k as f64 * turn, d);
                if g >= MIN_PROGRESS && best.is_none_or(|b| g > b.0 + 1e-6) {
                    best = Some((g, k));
                }
            }
        }
        match best {
            Some((_, k)) => self.take_heading(k, yaw, turn),
            None => self.two_moves(env, d),
        }
    }

    /// Moves forward (k = 0) or starts turning to `yaw + k * turn`, remembering the target.
    fn take_heading(&mut self, k: i64, yaw: f64, turn: f64) -> Action {
        if k == 0 {
            return Action::MoveForward;
        }
        self.detour = Some(normalize_angle(yaw + k as f64 * turn));
        if k > 0 { Action::TurnLeft } else { Action::TurnRight }
    }

    /// No single move helps (a move overshoots past a corner): the best first heading of two
    /// consecutive moves; turns in place when even that fails (the step limit ends the episode).
    fn two_moves(&mut self, env: &dyn EnvView, d: f64) -> Action {
        let yaw = env.pose().yaw;
        let turn = env.config().turn_angle.to_radians();
        let n = (std::f64::consts::PI / turn).round().max(1.0) as i64;
        let p = env.pose().position();
        let mut best: Option<(f64, i64)> = None;
        for k in -n + 1..=n {
            let p1 = forward(env, p, yaw + k as f64 * turn);
            if p1.dist(p) < 1e-3 {
                continue;
            }
            for j in -n + 1..=n {
                let p2 = forward(env, p1, yaw + j as f64 * turn);
                let g = d - env.field().distance(env.grid(), p2);
                if g >= MIN_PROGRESS && best.is_none_or(|b| g > b.0 + 1e-6) {
                    best = Some((g, k));
                }
            }
        }
        match best {
            Some((_, k)) => self.take_heading(k, yaw, turn),
            None => Action::TurnLeft,
        }
    }

    /// Forgets the episode's state.
    pub fn reset(&mut self) {
        self.detour = None;
    }
}
