//! DWA local planner (ROS dwa_local_planner parameters): samples velocities inside the
//! dynamic window, rolls each out for `sim_time`, and scores the rollouts by distance to the
//! global path, progress towards a local goal on it, and obstacle cost.
//!
//! Fixes for known ROS failure modes: a goal or path behind the robot makes it turn in place
//! towards the path first (ROS DWA would back up or stall); in-place turns are scored by the
//! heading they reach, not all alike; the xy goal latch is reset whenever a new plan arrives.

use crate::costmap::{Costmap, INSCRIBED, LETHAL};
use serde::{Deserialize, Serialize};
use xhab_types::{normalize_angle, Point2, Pose2, Twist};

/// DWA parameters (ROS names; noetic dwa_local_planner defaults unless noted).
///
/// The scores weigh distances in cells (`bias * d / resolution`), not metres as noetic's
/// DWA does, so `path_distance_bias` and `goal_distance_bias` default to the values ROS
/// documented before noetic (32 and 24; noetic's are 0.6 and 0.8).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DwaParams {
    /// Largest forward speed (m/s, default 0.5).
    pub max_vel_x: f64,
    /// Smallest forward speed (m/s, default 0; negative lets the robot back up).
    pub min_vel_x: f64,
    /// Largest translational speed, whatever the direction (m/s, default 0.55).
    pub max_vel_trans: f64,
    /// Largest turn rate (rad/s, default 1.5).
    pub max_vel_theta: f64,
    /// Forward acceleration limit (m/s^2, default 2.5).
    pub acc_lim_x: f64,
    /// Angular acceleration limit (rad/s^2, default 3.2).
    pub acc_lim_theta: f64,
    /// Rollout horizon (s, default 1.7).
    pub sim_time: f64,
    /// Rollout step (m, default 0.025).
    pub sim_granularity: f64,
    /// Forward speed samples (default 6).
    pub vx_samples: usize,
    /// Turn rate samples (default 20).
    pub vth_samples: usize,
    /// Weight of the distance to the path (default 32).
    pub path_distance_bias: f64,
    /// Weight of the distance to the local goal (default 24).
    pub goal_distance_bias: f64,
    /// Weight of the obstacle cost (default 0.01).
    pub occdist_scale: f64,
    /// Point ahead of the robot scored against the path (m, default 0.325).
    pub forward_point_distance: f64,
    /// Goal reached within this distance (m, default 0.1).
    pub xy_goal_tolerance: f64,
    /// Heading error beyond which the robot turns in place first (rad, default 1.0).
    pub rotate_first_angle: f64,
    /// How far along the path the local goal lies (m, default 1.5).
    pub local_goal_distance: f64,
    /// Controller period (s, default 0.05 = 20 Hz).
    pub controller_period: f64,
}

impl Default for DwaParams {
    fn default() -> Self {
        Self {
            max_vel_x: 0.5,
            min_vel_x: 0.0,
            max_vel_trans: 0.55,
            max_vel_theta: 1.5,
            acc_lim_x: 2.5,
            acc_lim_theta: 3.2,
            sim_time: 1.7,
            sim_granularity: 0.025,
            vx_samples: 6,
            vth_samples: 20,
            path_distance_bias: 32.0,
            goal_distance_bias: 24.0,
            occdist_scale: 0.01,
            forward_point_distance: 0.325,
            xy_goal_tolerance: 0.1,
            rotate_first_angle: 1.0,
            local_goal_distance: 1.5,
            controller_period: 0.05,
        }
    }
}

/// Why no velocity was found.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ControlError {
    /// No plan has been set.
    #[error("no plan")]
    NoPlan,
    /// Every sampled trajectory hits an obstacle.
    #[error("no valid trajectory")]
    NoValidTrajectory,
}

/// The DWA controller following one global plan.
#[derive(Debug, Clone)]
pub struct Dwa {
    /// Parameters.
    pub params: DwaParams,
    /// Footprint polygon in the base frame (m); empty for a round robot (the costmap's
    /// inscribed radius then decides collisions alone).
    pub footprint: Vec<[f64; 2]>,
    plan: Vec<Pose2>,
    /// Index of the plan point nearest to the robot (only moves forward).
    progress: usize,
    xy_latched: bool,
}

impl Dwa {
    /// A controller with `params`.
    pub fn new(params: DwaParams) -> Self {
        Self { params, footprint: Vec::new(), plan: Vec::new(), progress: 0, xy_latched: false }
    }

    /// Follows a new plan (resets the goal latch).
    pub fn set_plan(&mut self, plan: &[Pose2]) {
        self.plan = plan.to_vec();
        self.progress = 0;
        self.xy_latched = false;
    }

    /// Whether the robot at `pose` is within `xy_goal_tolerance` of the plan's end.
    pub fn is_goal_reached(&mut self, pose: Pose2) -> bool {
        let Some(g) = self.plan.last() else { return false };
        if pose.position().dist(g.position()) <= self.params.xy_goal_tolerance {
            self.xy_latched = true;
        }
        self.xy_latched
    }

    /// The velocity command for the robot at `pose` moving at `vel`.
    pub fn compute_velocity(&mut self, pose: Pose2, vel: Twist, cm: &Costmap) -> Result<Twist, ControlError> {
        if self.plan.is_empty() {
            return Err(ControlError::NoPlan);
        }
        let p = self.params.clone();
        let here = pose.position();
        // Advance along the plan (never backwards), within a window.
        let end = (self.progress + 200).min(self.plan.len());
        let (mut best_i, mut best_d) = (self.progress, f64::INFINITY);
        for i in self.progress..end {
            let d = self.plan[i].position().dist(here);
            if d < best_d {
                best_d = d;
                best_i = i;
            }
        }
        self.progress = best_i;
        let mut local = self.progress;
        let mut acc = 0.0;
        while local + 1 < self.plan.len() && acc < p.local_goal_distance {
            acc += self.plan[local].position().dist(self.plan[local + 1].position());
            local += 1;
        }
        let lg = self.plan[local].position();
        // Goal or path behind: turn in place first, towards the path a little ahead (not the
        // local goal, which may lie around a corner).
        let mut near = self.progress;
        let mut acc = 0.0;
        while near + 1 < self.plan.len() && acc < 0.4 {
            acc += self.plan[near].position().dist(self.plan[near + 1].position());
            near += 1;
        }
        let carrot = self.plan[near].position();
        let heading_err = normalize_angle((carrot.y - here.y).atan2(carrot.x - here.x) - pose.yaw);
        if heading_err.abs() > p.rotate_first_angle && here.dist(carrot) > p.xy_goal_tolerance {
            let w = (heading_err * 1.5).clamp(-p.max_vel_theta, p.max_vel_theta);
            let w = w.clamp(vel.angular - p.acc_lim_theta * p.controller_period, vel.angular + p.acc_lim_theta * p.controller_period);
            return Ok(Twist { linear: 0.0, angular: w });
        }
        let window = &self.plan[self.progress..=local.max(self.progress)];
        let dt = p.controller_period;
        let (v_lo, v_hi) = ((vel.linear - p.acc_lim_x * dt).max(p.min_vel_x).max(-p.max_vel_trans), (vel.linear + p.acc_lim_x * dt).min(p.max_vel_x).min(p.max_vel_trans));
        let (w_lo, w_hi) = ((vel.angular - p.acc_lim_theta * dt).max(-p.max_vel_theta), (vel.angular + p.acc_lim_theta * dt).min(p.max_vel_theta));
        let mut best: Option<(f64, Twist)> = None;
        let mut along = PathWindow::new(window, lg);
        for i in 0..p.vx_samples.max(1) {
            let v = if p.vx_samples <= 1 { v_hi } else { v_lo + (v_hi - v_lo) * i as f64 / (p.vx_samples - 1) as f64 };
            for j in 0..p.vth_samples.max(1) {
                let w = if p.vth_samples <= 1 { 0.0 } else { w_lo + (w_hi - w_lo) * j as f64 / (p.vth_samples - 1) as f64 };
                let Some(score) = self.score(pose, v, w, cm, &mut along) else { continue };
                if best.is_none_or(|b| score < b.0) {
                    best = Some((score, Twist { linear: v, angular: w }));
                }
            }
        }
        best.map(|b| b.1).ok_or(ControlError::NoValidTrajectory)
    }

    /// Whether no edge of the footprint at `q` crosses a lethal cell (round robots: true).
    fn footprint_clear(&self, q: Pose2, cm: &Costmap) -> bool {
        let n = self.footprint.len();
        if n < 3 {
            return true;
        }
        let (s, c) = q.yaw.sin_cos();
        let world = |v: [f64; 2]| Point2::new(q.x + c * v[0] - s * v[1], q.y + s * v[0] + c * v[1]);
        (0..n).all(|i| {
            let (a, b) = (world(self.footprint[i]), world(self.footprint[(i + 1) % n]));
            let k = (a.dist(b) / (cm.resolution * 0.5)).ceil().max(1.0) as usize;
            (0..=k).all(|j| {
                let t = j as f64 / k as f64;
                cm.cost_at(Point2::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y))) < LETHAL
            })
        })
    }

    /// Cost of the rollout at (v, w): lower is better; `None` when it hits an obstacle.
    fn score(&self, pose: Pose2, v: f64, w: f64, cm: &Costmap, along: &mut PathWindow<'_>) -> Option<f64> {
        let p = &self.params;
        let steps = ((v.abs() * p.sim_time / p.sim_granularity).max(w.abs() * p.sim_time / 0.1)).ceil().max(1.0) as usize;
        let dt = p.sim_time / steps as f64;
        let mut q = pose;
        let mut max_cost = 0u8;
        // A robot that already stands in the inscribed zone (a start close to furniture, the
        // map's cells being coarser than the geometry) may move through it, never deeper.
        let start_cost = cm.cost_at(pose.position());
        // The heading's sine and cosine, worked out again only when it changes.
        let (mut yaw, (mut sy, mut cy)) = (q.yaw, q.yaw.sin_cos());
        for _ in 0..steps {
            if q.yaw.to_bits() != yaw.to_bits() {
                yaw = q.yaw;
                (sy, cy) = yaw.sin_cos();
            }
            q = Pose2::new(q.x + v * cy * dt, q.y + v * sy * dt, normalize_angle(q.yaw + w * dt));
            let c = cm.cost_at(q.position());
            if c >= LETHAL || (c >= INSCRIBED && c > start_cost) || !self.footprint_clear(q, cm) {
                return None;
            }
            max_cost = max_cost.max(c);
        }
        // Near the end of the plan the point ahead would overshoot: score the rollout's end.
        let near_end = self.plan.last().is_some_and(|g| pose.position().dist(g.position()) < 2.0 * p.forward_point_distance + p.xy_goal_tolerance);
        let ahead = Point2::new(q.x + p.forward_point_distance * q.yaw.cos(), q.y + p.forward_point_distance * q.yaw.sin());
        // The point ahead must not look through an obstacle (ROS scores on obstacle-aware grid
        // distances; ours are straight-line, so a blocked point ahead falls back to the end).
        let fp = if near_end || !crate::planner::segment_cost_ok(cm, q.position(), ahead, INSCRIBED) { q.position() } else { ahead };
        // Distance to the path, and to the local goal along the path from the path point
        // nearest to the scored point (not the straight line, which cuts corners).
        let (near_i, path_d) = along.nearest(fp);
        let goal_d = path_d + along.remaining(near_i) + along.end_to_goal;
        let res = cm.resolution;
        Some(p.path_distance_bias * path_d / res + p.goal_distance_bias * goal_d / res + p.occdist_scale * max_cost as f64)
    }
}

/// The stretch of the plan the rollouts of one cycle are scored against, with what every
/// rollout would otherwise work out again: the length left from each point (summed in the
/// same order as a single rollout does) and the end's distance to the local goal.
struct PathWindow<'a> {
    points: &'a [Pose2],
    remaining: Vec<Option<f64>>,
    end_to_goal: f64,
}

impl<'a> PathWindow<'a> {
    fn new(points: &'a [Pose2], lg: Point2) -> Self {
        let end_to_goal = lg.dist(points[points.len() - 1].position());
        Self { points, remaining: vec![None; points.len()], end_to_goal }
    }

    /// The first point nearest to `fp` and its distance (m). Squared distances narrow the
    /// candidates down to near-ties, which the exact distance settles in plan order.
    fn nearest(&self, fp: Point2) -> (usize, f64) {
        let sq = |a: &Pose2| (a.x - fp.x) * (a.x - fp.x) + (a.y - fp.y) * (a.y - fp.y);
        let least = self.points.iter().map(sq).fold(f64::INFINITY, f64::min);
        let (mut near_i, mut path_d) = (0, f64::INFINITY);
        for (i, a) in self.points.iter().enumerate() {
            if !(sq(a) <= least * (1.0 + 1e-9)) {
                continue;
            }
            let d = a.position().dist(fp);
            if d < path_d {
                path_d = d;
                near_i = i;
            }
        }
        (near_i, path_d)
    }

    /// Path length from point `i` to the window's end (m).
    fn remaining(&mut self, i: usize) -> f64 {
        *self.remaining[i].get_or_insert_with(|| self.points[i..].windows(2).map(|w| w[0].position().dist(w[1].position())).sum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::costmap::CostmapParams;
    use xhab_types::OccupancyGrid;

    fn open(wall: bool) -> Costmap {
        let mut m = OccupancyGrid::new(100, 100, 0.05, Pose2::default(), 0);
        if wall {
            for r in 0..100 {
                m.set(60, r, 100);
            }
        }
        Costmap::from_map(&m, &CostmapParams::default())
    }

    fn straight(a: Point2, b: Point2) -> Vec<Pose2> {
        (0..=40).map(|k| Pose2::new(a.x + (b.x - a.x) * k as f64 / 40.0, a.y + (b.y - a.y) * k as f64 / 40.0, (b.y - a.y).atan2(b.x - a.x))).collect()
    }

    #[test]
    fn drives_straight_at_a_goal_ahead() {
        let cm = open(false);
        let mut d = Dwa::new(DwaParams::default());
        d.set_plan(&straight(Point2::new(1.0, 2.5), Point2::new(4.0, 2.5)));
        let t = d.compute_velocity(Pose2::new(1.0, 2.5, 0.0), Twist { linear: 0.4, angular: 0.0 }, &cm).unwrap();
        assert!(t.linear > 0.3 && t.angular.abs() < 0.2, "{t:?}");
    }

    #[test]
    fn turns_in_place_towards_a_goal_behind() {
        let cm = open(false);
        let mut d = Dwa::new(DwaParams::default());
        d.set_plan(&straight(Point2::new(2.0, 2.5), Point2::new(0.5, 2.5)));
        let t = d.compute_velocity(Pose2::new(2.0, 2.5, 0.3), Twist::default(), &cm).unwrap();
        assert_eq!(t.linear, 0.0);
        assert!(t.angular > 0.0, "turns left, the short way: {t:?}");
    }

    #[test]
    fn a_long_footprint_keeps_its_corners_off_the_wall() {
        let cm = open(true);
        let mut d = Dwa::new(DwaParams::default());
        // A 1.2 m long robot whose nose would reach the wall well before its centre does.
        d.footprint = vec![[-0.1, -0.1], [0.6, -0.1], [0.6, 0.1], [-0.1, 0.1]];
        d.set_plan(&straight(Point2::new(2.0, 2.5), Point2::new(4.0, 2.5)));
        let mut pose = Pose2::new(2.0, 2.5, 0.0);
        let mut vel = Twist::default();
        for _ in 0..100 {
            let Ok(t) = d.compute_velocity(pose, vel, &cm) else { break };
            vel = t;
            pose = Pose2::new(pose.x + t.linear * pose.yaw.cos() * 0.05, pose.y + t.linear * pose.yaw.sin() * 0.05, pose.yaw + t.angular * 0.05);
        }
        // The wall is at x = 3.0: the nose (0.6 m ahead) must stay short of it.
        assert!(pose.x + 0.6 * pose.yaw.cos() < 3.0, "{pose:?}");
    }

    #[test]
    fn never_drives_into_a_wall() {
        let cm = open(true);
        let mut d = Dwa::new(DwaParams::default());
        // A plan straight through the wall at x = 3: every fast forward rollout hits it.
        d.set_plan(&straight(Point2::new(2.2, 2.5), Point2::new(4.0, 2.5)));
        let mut pose = Pose2::new(2.2, 2.5, 0.0);
        let mut vel = Twist::default();
        for _ in 0..100 {
            match d.compute_velocity(pose, vel, &cm) {
                Ok(t) => {
                    vel = t;
                    pose = Pose2::new(pose.x + t.linear * pose.yaw.cos() * 0.05, pose.y + t.linear * pose.yaw.sin() * 0.05, pose.yaw + t.angular * 0.05);
                }
                Err(_) => break,
            }
            assert!(cm.cost_at(pose.position()) < INSCRIBED, "entered the wall's inscribed zone at {pose:?}");
        }
    }
}
