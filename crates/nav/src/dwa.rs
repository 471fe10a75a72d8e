//! DWA local planner (ROS dwa_local_planner parameters): samples velocities inside the
//! dynamic window, rolls each out for `sim_time`, and scores the rollouts by distance to the
//! global path, progress towards a local goal on it, and obstacle cost.
//!
//! As dwa_local_planner, the window's velocities are sampled evenly with zero added where the
//! window spans it (base_local_planner's `VelocityIterator`), standing still is no sample, and a
//! sample slower than both `min_vel_trans` and `min_vel_theta` is left out, so the robot never
//! creeps; each rollout is scored at its end (`path_costs`, `goal_costs`) and at the point
//! `forward_point_distance` ahead of it (`alignment_costs`, `goal_front_costs`).
//!
//! Fixes for known ROS failure modes: a goal or path behind the robot makes it turn in place
//! towards the path first (ROS DWA would back up or stall); in-place turns are scored by the
//! heading they reach, not all alike; the xy goal latch is reset whenever a new plan arrives; a
//! robot whose footprint already touches an obstacle (a start placed by a round radius, the
//! map's cells coarser than the geometry) may move on as long as it gets no closer to it; a
//! rollout that reaches the plan's end stops there (what lies beyond a goal beside a wall does
//! not rule out approaching it at `min_vel_trans`); a robot whose dynamic window does not
//! reach `min_vel_theta` (at rest) may still spin up in place (ROS DWA has no in-place turn
//! from rest then, and facing an obstacle finds no trajectory at all).

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
    /// Smallest translational speed of a sample that does not turn at `min_vel_theta` or
    /// more (m/s, default 0.1): a sample slower than both is left out.
    pub min_vel_trans: f64,
    /// Largest turn rate (rad/s, default 1.5).
    pub max_vel_theta: f64,
    /// Smallest turn rate of a sample that does not move at `min_vel_trans` or more (rad/s,
    /// default 0.4).
    pub min_vel_theta: f64,
    /// Forward acceleration limit (m/s^2, default 2.5).
    pub acc_lim_x: f64,
    /// Angular acceleration limit (rad/s^2, default 3.2).
    pub acc_lim_theta: f64,
    /// Rollout horizon (s, default 1.7).
    pub sim_time: f64,
    /// Rollout step (m, default 0.025).
    pub sim_granularity: f64,
    /// Forward speed samples (default 6; at least 2 unless the window is one speed; a zero is
    /// added where the window spans it).
    pub vx_samples: usize,
    /// Turn rate samples (default 20; at least 2, with zero added as for `vx_samples`).
    pub vth_samples: usize,
    /// Weight of the distance to the path (default 32).
    pub path_distance_bias: f64,
    /// Weight of the distance to the local goal (default 24).
    pub goal_distance_bias: f64,
    /// Weight of the obstacle cost (default 0.01).
    pub occdist_scale: f64,
    /// Point ahead of the rollout's end scored against the path and the local goal, besides
    /// the end itself (m, default 0.325).
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
            min_vel_trans: 0.1,
            max_vel_theta: 1.5,
            min_vel_theta: 0.4,
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
        let along = PathWindow::new(window, lg);
        // A robot that already stands in the inscribed zone (a start close to furniture, the
        // map's cells being coarser than the geometry) may move through it, never deeper; a
        // footprint that already touches an obstacle may go on touching it while the centre
        // gets no closer (its cost does not rise): turning in place, or moving away.
        let start = (cm.cost_at(here), !self.footprint_clear(pose, cm));
        let ws = velocity_samples(w_lo, w_hi, p.vth_samples);
        for v in velocity_samples(v_lo, v_hi, p.vx_samples) {
            for &w in &ws {
                if !moves_enough(v, w, p.min_vel_trans, p.min_vel_theta) {
                    continue;
                }
                let Some(score) = self.score(pose, v, w, cm, start, &along) else { continue };
                if best.is_none_or(|b| score < b.0) {
                    best = Some((score, Twist { linear: v, angular: w }));
                }
            }
        }
        // Spinning up in place: a robot that can stop this cycle but whose window does not
        // reach min_vel_theta (at rest: acc_lim_theta * controller_period) has no in-place turn
        // among the samples, so facing an obstacle it has no valid trajectory at all, and
        // move_base's full-turn recovery brings it back to the same heading. The turn at
        // min_vel_theta is scored, and the window's edge towards it commanded.
        if v_lo <= 0.0 && v_hi >= 0.0 {
            for w in [p.min_vel_theta, -p.min_vel_theta] {
                let edge = if w > 0.0 { w_hi } else { w_lo };
                if w == 0.0 || edge.abs() >= p.min_vel_theta || edge * w <= 0.0 {
                    continue;
                }
                let Some(score) = self.score(pose, 0.0, w, cm, start, &along) else { continue };
                if best.is_none_or(|b| score < b.0) {
                    best = Some((score, Twist { linear: 0.0, angular: edge }));
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
    /// `start`: the cost at the robot's centre and whether its footprint touches an obstacle.
    fn score(&self, pose: Pose2, v: f64, w: f64, cm: &Costmap, start: (u8, bool), along: &PathWindow<'_>) -> Option<f64> {
        let p = &self.params;
        let steps = ((v.abs() * p.sim_time / p.sim_granularity).max(w.abs() * p.sim_time / 0.1)).ceil().max(1.0) as usize;
        let dt = p.sim_time / steps as f64;
        let mut q = pose;
        let mut max_cost = 0u8;
        let (start_cost, start_touches) = start;
        // A rollout that reaches the plan's end (within xy_goal_tolerance) ends there: the
        // robot stops at it, so what lies beyond (a goal beside a wall) does not matter.
        let end = self.plan.last().map(|g| g.position()).filter(|g| pose.position().dist(*g) <= v.abs() * p.sim_time + p.xy_goal_tolerance);
        // The heading's sine and cosine, turned by the step's rotation (one `sin_cos` per
        // rollout, not per step; the product drifts by a few ulps over a rollout).
        let ((mut sy, mut cy), (sw, cw)) = (q.yaw.sin_cos(), (w * dt).sin_cos());
        for _ in 0..steps {
            q = Pose2::new(q.x + v * cy * dt, q.y + v * sy * dt, normalize_angle(q.yaw + w * dt));
            if w != 0.0 {
                (cy, sy) = (cy * cw - sy * sw, sy * cw + cy * sw);
            }
            let c = cm.cost_at(q.position());
            if c >= LETHAL || (c >= INSCRIBED && c > start_cost) || (!(start_touches && c <= start_cost) && !self.footprint_clear(q, cm)) {
                return None;
            }
            max_cost = max_cost.max(c);
            if end.is_some_and(|g| (q.x - g.x) * (q.x - g.x) + (q.y - g.y) * (q.y - g.y) <= p.xy_goal_tolerance * p.xy_goal_tolerance) {
                break;
            }
        }
        // Near the end of the plan the point ahead would overshoot: score the rollout's end.
        let near_end = self.plan.last().is_some_and(|g| pose.position().dist(g.position()) < 2.0 * p.forward_point_distance + p.xy_goal_tolerance);
        let ahead = Point2::new(q.x + p.forward_point_distance * cy, q.y + p.forward_point_distance * sy);
        // The point ahead must not look through an obstacle (ROS scores on obstacle-aware grid
        // distances; ours are straight-line, so a blocked point ahead falls back to the end).
        let fp = if near_end || !crate::planner::segment_cost_ok(cm, q.position(), ahead, INSCRIBED) { q.position() } else { ahead };
        // Both the rollout's end (the robot's centre: dwa_local_planner's path and goal costs)
        // and the point ahead (its alignment and goal-front costs) are scored: the point ahead
        // alone would let the centre cut inside corners, into the walls the path rounds.
        let (end_path_d, end_goal_d) = along.distances(q.position());
        let (path_d, goal_d) = if fp == q.position() { (end_path_d, end_goal_d) } else { along.distances(fp) };
        let res = cm.resolution;
        Some(p.path_distance_bias * (end_path_d + path_d) / res + p.goal_distance_bias * (end_goal_d + goal_d) / res + p.occdist_scale * max_cost as f64)
    }
}

/// The stretch of the plan the rollouts of one cycle are scored against, with what every
/// rollout would otherwise work out again: the length left from each point (summed in the
/// same order as a single rollout does) and the end's distance to the local goal.
struct PathWindow<'a> {
    points: &'a [Pose2],
    /// Per segment `i` (points `i` to `i + 1`): its start, direction, 1 / squared length
    /// (0 for a zero-length segment) and length (m).
    segments: Vec<(Point2, (f64, f64), f64, f64)>,
    /// Path length from each point to the window's end (m).
    remaining: Vec<f64>,
    end_to_goal: f64,
}

impl<'a> PathWindow<'a> {
    fn new(points: &'a [Pose2], lg: Point2) -> Self {
        let end_to_goal = lg.dist(points[points.len() - 1].position());
        let segments: Vec<_> = points
            .windows(2)
            .map(|w| {
                let (a, b) = (w[0].position(), w[1].position());
                let (dx, dy) = (b.x - a.x, b.y - a.y);
                let l2 = dx * dx + dy * dy;
                (a, (dx, dy), if l2 > 0.0 { 1.0 / l2 } else { 0.0 }, l2.sqrt())
            })
            .collect();
        let mut remaining = vec![0.0; points.len()];
        for i in (0..segments.len()).rev() {
            remaining[i] = remaining[i + 1] + segments[i].3;
        }
        Self { points, segments, remaining, end_to_goal }
    }

    /// Distance from `p` to the path (its polyline, not only its points, which lie two cells
    /// apart), and to the local goal along the path from the path's point nearest to `p` (not
    /// the straight line, which cuts corners) (m). Ties go to the first segment in plan order.
    /// Squared distances pick the segment; one square root per call.
    fn distances(&self, p: Point2) -> (f64, f64) {
        if self.segments.is_empty() {
            let d = self.points[0].position().dist(p);
            return (d, d + self.end_to_goal);
        }
        let (mut best_d2, mut best) = (f64::INFINITY, (0, 0.0));
        for (i, &(a, (dx, dy), inv_l2, _)) in self.segments.iter().enumerate() {
            let t = (((p.x - a.x) * dx + (p.y - a.y) * dy) * inv_l2).clamp(0.0, 1.0);
            let (ex, ey) = (a.x + t * dx - p.x, a.y + t * dy - p.y);
            let d2 = ex * ex + ey * ey;
            if d2 < best_d2 {
                (best_d2, best) = (d2, (i, t));
            }
        }
        let (i, t) = best;
        let d = best_d2.sqrt();
        (d, d + (1.0 - t) * self.segments[i].3 + self.remaining[i + 1] + self.end_to_goal)
    }
}

/// Velocity samples from `lo` to `hi` (base_local_planner's `VelocityIterator`): `lo` alone
/// when the window is one velocity, else `n` (at least 2) evenly spaced ones from `lo` to
/// `hi`, with a zero added between the last negative and the first positive one when the
/// window spans zero without a sample on it.
pub fn velocity_samples(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    if lo == hi {
        return vec![lo];
    }
    let n = n.max(2);
    let step = (hi - lo) / (n - 1) as f64;
    let mut out = Vec::with_capacity(n + 1);
    let mut next = lo;
    for _ in 0..n - 1 {
        let current = next;
        next += step;
        out.push(current);
        if current < 0.0 && next > 0.0 {
            out.push(0.0);
        }
    }
    // The last sample is `hi` itself, not the sum of the steps (no rounding past the limit).
    out.push(hi);
    out
}

/// Whether the sample (`v` m/s, `w` rad/s) moves: not standing still, and as fast as
/// `min_trans` (m/s) or turning as fast as `min_theta` (rad/s) (base_local_planner's
/// `SimpleTrajectoryGenerator`, with its 1e-4 slack).
pub fn moves_enough(v: f64, w: f64, min_trans: f64, min_theta: f64) -> bool {
    const EPS: f64 = 1e-4;
    let still = v == 0.0 && w == 0.0;
    let slow = v.abs() + EPS < min_trans && w.abs() + EPS < min_theta;
    !still && !slow
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
    fn spins_up_in_place_from_rest_when_every_forward_sample_meets_the_wall() {
        // At rest the angular window (acc_lim_theta * controller_period = 0.16 rad/s) is below
        // min_vel_theta (0.4), so the only samples that move are forward ones; facing the wall
        // at the edge of the inscribed zone, they all end in it. The path leaves at 0.9 rad to
        // the left (below rotate_first_angle): the robot must spin up in place, not fail.
        let cm = open(true);
        let p = DwaParams::default();
        assert!(p.acc_lim_theta * p.controller_period < p.min_vel_theta);
        let inscribed = (0..300).map(|k| 2.0 + k as f64 * 0.005).find(|&x| cm.cost_at(Point2::new(x, 2.5)) >= INSCRIBED).unwrap();
        let here = Point2::new(inscribed - 0.06, 2.5);
        let mut d = Dwa::new(p);
        d.set_plan(&straight(here, Point2::new(here.x + 1.5 * 0.9f64.cos(), here.y + 1.5 * 0.9f64.sin())));
        let t = d.compute_velocity(Pose2::new(here.x, here.y, 0.0), Twist::default(), &cm).expect("an in-place turn");
        assert_eq!(t.linear, 0.0, "{t:?}");
        assert!(t.angular > 0.0 && t.angular <= d.params.acc_lim_theta * d.params.controller_period + 1e-12, "left, within the window: {t:?}");
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
        // The wall is at x = 3.0: the nose (0.6 m ahead) must stay short of it, and the robot
        // must have driven towards it (not failed at once).
        assert!(pose.x + 0.6 * pose.yaw.cos() < 3.0, "{pose:?}");
        assert!(pose.x > 2.1, "{pose:?}");
    }

    #[test]
    fn velocity_samples_are_ross_with_zero_added() {
        let check = |lo: f64, hi: f64, n: usize, want: &[f64]| {
            let got = velocity_samples(lo, hi, n);
            assert_eq!(got.len(), want.len(), "({lo}, {hi}, {n}): {got:?}");
            for (g, w) in got.iter().zip(want) {
                assert!((g - w).abs() < 1e-12, "({lo}, {hi}, {n}): {got:?}");
            }
        };
        check(0.0, 0.25, 6, &[0.0, 0.05, 0.1, 0.15, 0.2, 0.25]);
        check(0.3, 0.3, 6, &[0.3]);
        // Fewer than two samples are two, and zero joins a window that spans it.
        check(-0.1, 0.1, 1, &[-0.1, 0.0, 0.1]);
        check(-0.3, 0.3, 4, &[-0.3, -0.1, 0.0, 0.1, 0.3]);
        // TurtleBot3's DWA window at rest: 20 samples from -0.22 to 0.22, none of them zero
        // but the one added (without it the slowest are +-0.0116 m/s, a creep).
        let v = velocity_samples(-0.22, 0.22, 20);
        assert_eq!((v.len(), v[0], v[20]), (21, -0.22, 0.22));
        assert!(v.contains(&0.0) && v.windows(2).all(|w| w[0] < w[1]), "{v:?}");
    }

    #[test]
    fn samples_slower_than_both_minimums_or_standing_still_are_left_out() {
        let cases = [
            // (v, w, min_vel_trans, min_vel_theta, moves)
            (0.0, 0.0, 0.0, 0.0, false),
            (0.0, 0.0, 0.1, 0.4, false),
            (0.0116, 0.1, 0.1, 0.4, false),
            (-0.05, -0.3, 0.1, 0.4, false),
            (0.1, 0.0, 0.1, 0.4, true),
            (-0.1, 0.0, 0.1, 0.4, true),
            (0.0, 0.4, 0.1, 0.4, true),
            (0.0, -0.39995, 0.1, 0.4, true),
            (0.01, 0.0, 0.0, 0.0, true),
        ];
        for (v, w, mt, mr, moves) in cases {
            assert_eq!(moves_enough(v, w, mt, mr), moves, "({v}, {w}) with minimums ({mt}, {mr})");
        }
    }

    /// TurtleBot3 burger's DWA (its `dwa_local_planner_params_burger.yaml`, at 10 Hz).
    fn burger() -> Dwa {
        let params = DwaParams {
            max_vel_x: 0.22,
            min_vel_x: -0.22,
            max_vel_trans: 0.22,
            min_vel_trans: 0.11,
            max_vel_theta: 2.75,
            min_vel_theta: 1.37,
            sim_time: 1.5,
            vx_samples: 20,
            goal_distance_bias: 20.0,
            occdist_scale: 0.02,
            xy_goal_tolerance: 0.05,
            controller_period: 0.1,
            ..DwaParams::default()
        };
        let mut d = Dwa::new(params);
        d.footprint = vec![[-0.105, -0.105], [-0.105, 0.105], [0.041, 0.105], [0.041, -0.105]];
        d
    }

    /// A 5 x 5 m room with a 1 x 1 m block at x, y in [2, 3] and TurtleBot3's inflation (its
    /// footprint's inscribed radius, 0.041 m; 0.2 m, 10 / m).
    fn block() -> Costmap {
        let mut m = OccupancyGrid::new(100, 100, 0.05, Pose2::default(), 0);
        for r in 40..60 {
            for c in 40..60 {
                m.set(c, r, 100);
            }
        }
        let p = CostmapParams { robot_radius: 0.041, inflation_radius: 0.2, cost_scaling_factor: 10.0, ..CostmapParams::default() };
        Costmap::from_map(&m, &p)
    }

    fn drive(pose: Pose2, t: Twist, dt: f64) -> Pose2 {
        Pose2::new(pose.x + t.linear * pose.yaw.cos() * dt, pose.y + t.linear * pose.yaw.sin() * dt, normalize_angle(pose.yaw + t.angular * dt))
    }

    #[test]
    fn a_footprint_touching_a_wall_at_the_start_gets_away_from_it() {
        // The burger beside the block, facing along it, its centre 0.08 m from the block's
        // edge (a start placed by a round radius, cells coarser than the geometry): its left
        // side lies on the block's cells, so every rollout touched it and none was valid. It
        // may turn and move, never closer.
        let cm = block();
        let mut d = burger();
        let start = Pose2::new(2.5, 1.92, 0.0);
        assert!(!d.footprint_clear(start, &cm));
        d.set_plan(&straight(Point2::new(2.5, 1.92), Point2::new(4.5, 1.0)));
        let start_cost = cm.cost_at(start.position());
        let (mut pose, mut vel) = (start, Twist::default());
        for _ in 0..50 {
            let t = d.compute_velocity(pose, vel, &cm).unwrap_or_else(|e| panic!("{e} at {pose:?}"));
            vel = t;
            pose = drive(pose, t, 0.1);
            if d.footprint_clear(pose, &cm) {
                break;
            }
            assert!(cm.cost_at(pose.position()) <= start_cost, "closer to the block at {pose:?}");
        }
        assert!(d.footprint_clear(pose, &cm), "still touching at {pose:?}");
    }

    #[test]
    fn distances_are_to_the_path_between_its_points_too() {
        // Points 0.1 m apart along y = 1; the local goal 0.5 m past the window's end.
        let plan: Vec<Pose2> = (0..=10).map(|k| Pose2::new(1.0 + 0.1 * k as f64, 1.0, 0.0)).collect();
        let w = PathWindow::new(&plan, Point2::new(2.5, 1.0));
        let check = |w: &PathWindow<'_>, p: Point2, want: (f64, f64)| {
            let got = w.distances(p);
            assert!((got.0 - want.0).abs() < 1e-9 && (got.1 - want.1).abs() < 1e-9, "{p:?}: {got:?} vs {want:?}");
        };
        // Halfway between two points: on the path, 0.95 m + 0.5 m from the local goal.
        check(&w, Point2::new(1.05, 1.0), (0.0, 1.45));
        check(&w, Point2::new(1.55, 1.2), (0.2, 0.2 + 0.45 + 0.5));
        // Off the ends: to the end points.
        check(&w, Point2::new(0.7, 1.4), (0.5, 0.5 + 1.0 + 0.5));
        check(&w, Point2::new(2.3, 1.0), (0.3, 0.3 + 0.5));
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
        // It drove up to the wall rather than stopping at the first failure.
        assert!(pose.x > 2.5, "{pose:?}");
    }
}
