//! [`DwaController`]: the DWA local planner (ROS dwa_local_planner's algorithm and names).
//!
//! Each cycle: advance along the plan to the point nearest the robot; if the goal position is
//! reached, brake and turn to the goal heading; if the plan ahead lies more than
//! `rotate_first_angle` off the heading, turn in place towards it; otherwise sample
//! `vx_samples` x `vth_samples` velocities in the dynamic window, roll each out for
//! `sim_time` (cut short at an obstacle the robot could still stop for, with
//! `stop_time_buffer` to spare; dropped if it could not), drop those that reverse an
//! oscillation, and take the cheapest of
//!
//! ```text
//! path_distance_bias * (path(end) + path(nose)) + goal_distance_bias * (goal(end) + goal_front(nose))
//!   + occdist_scale * obstacle cost + twirling_scale * |w| + 0.01 * heading error at the end
//! ```
//!
//! where `path`/`goal` are distances (m) through free cells to the local plan and to the
//! local goal, and `nose` is the point `forward_point_distance` ahead of the rollout's end.
//! Once the goal is within reach, rollouts end where they reach it and the obstacle cost is
//! counted above the goal's own cost, so a goal near a wall is approached rather than avoided.
//!
//! Fixes of ROS failure modes: ROS drops every rollout that meets an obstacle within
//! `sim_time`, so the robot stalls short of goals near walls; here only a rollout the robot
//! could not stop on in time is dropped. A goal or path behind the robot makes it turn in place first
//! (ROS arcs away or stalls); in-place turns are scored by where they leave the nose and by
//! the heading error, so they are not all alike; a nose in an obstacle falls back to the
//! rollout's end instead of rejecting the rollout; the turning oscillation flags survive large
//! turns; the xy goal latch survives replanning to the same goal.

use super::dwa_params::DwaParams;
use super::goal_checker::GoalChecker;
use super::map_grid::DistanceGrid;
use super::oscillation::OscillationGuard;
use super::trajectory::{CollisionChecker, Rollout, RolloutSpec};
use super::{ControlError, Controller};
use crate::costmap_2d::{Costmap2D, Footprint};
use crate::param_error::{check_positive, ParamError};
use xhab_types::{normalize_angle, Point2, Pose2, Twist};

/// Weight of the end heading's error towards the path ahead (per rad): a tie-breaker.
const HEADING_WEIGHT: f64 = 0.01;
/// Shortest lookahead along the plan for the heading towards it (m).
const MIN_CARROT_DISTANCE: f64 = 0.25;
/// How far along the plan the nearest point is searched each cycle (m).
const PROGRESS_WINDOW: f64 = 2.0;

/// The DWA controller.
#[derive(Debug, Clone)]
pub struct DwaController {
    params: DwaParams,
    footprint: Footprint,
    period: f64,
    plan: Vec<Pose2>,
    progress: usize,
    goal: GoalChecker,
    oscillation: OscillationGuard,
    ignore_goal_yaw: bool,
    speed_limit: f64,
    best: Vec<Pose2>,
}

impl DwaController {
    /// A controller with `params` (checked) for a robot of `footprint`, called at
    /// `controller_frequency` (Hz; the dynamic window spans one period).
    pub fn new(
        params: DwaParams,
        footprint: Footprint,
        controller_frequency: f64,
    ) -> Result<Self, ParamError> {
        params.validate()?;
        check_positive("controller_frequency", controller_frequency)?;
        Ok(Self {
            params,
            footprint,
            period: 1.0 / controller_frequency,
            plan: Vec::new(),
            progress: 0,
            goal: GoalChecker::default(),
            oscillation: OscillationGuard::default(),
            ignore_goal_yaw: false,
            speed_limit: f64::INFINITY,
            best: Vec::new(),
        })
    }

    /// Parameters.
    pub fn params(&self) -> &DwaParams {
        &self.params
    }
    /// Replaces the footprint.
    pub fn set_footprint(&mut self, footprint: Footprint) {
        self.footprint = footprint;
    }
    /// Arrival ignores the goal heading (PointNav) when `ignore` (default false).
    pub fn set_ignore_goal_yaw(&mut self, ignore: bool) {
        self.ignore_goal_yaw = ignore;
    }
    /// The plan being followed.
    pub fn plan(&self) -> &[Pose2] {
        &self.plan
    }
    /// The rollout chosen last cycle (world frame; empty when turning in place or stopping).
    pub fn last_trajectory(&self) -> &[Pose2] {
        &self.best
    }

    /// Moves `progress` to the plan point nearest `here` within the window ahead.
    fn update_progress(&mut self, here: Point2) {
        let (mut best, mut best_d) = (self.progress, f64::INFINITY);
        let mut along = 0.0;
        for i in self.progress..self.plan.len() {
            if i > self.progress {
                along += self.plan[i - 1].position().dist(self.plan[i].position());
            }
            if along > PROGRESS_WINDOW {
                break;
            }
            let d = self.plan[i].position().dist(here);
            if d < best_d {
                best_d = d;
                best = i;
            }
        }
        self.progress = best;
    }

    /// The plan point at least `dist` (m) along the plan from the progress point.
    fn point_ahead(&self, dist: f64) -> Point2 {
        let mut along = 0.0;
        for i in self.progress + 1..self.plan.len() {
            along += self.plan[i - 1].position().dist(self.plan[i].position());
            if along >= dist {
                return self.plan[i].position();
            }
        }
        self.plan[self.plan.len() - 1].position()
    }

    /// Turns in place towards heading error `err` (rad), the short way unless an oscillation
    /// or a collision forbids it, braking any forward motion.
    fn rotate_in_place(
        &self,
        pose: Pose2,
        vel: Twist,
        err: f64,
        checker: &CollisionChecker,
    ) -> Option<Twist> {
        let p = &self.params;
        let dt = self.period;
        let v = vel.linear.signum() * (vel.linear.abs() - p.acc_lim_x * dt).max(0.0);
        let preferred = if err >= 0.0 { 1.0 } else { -1.0 };
        for dir in [preferred, -preferred] {
            if !self.oscillation.allows(0.0, dir) {
                continue;
            }
            let remaining = if dir == preferred {
                err.abs()
            } else {
                std::f64::consts::TAU - err.abs()
            };
            let speed = (2.0 * p.acc_lim_theta * remaining)
                .sqrt()
                .clamp(p.min_vel_theta, p.max_vel_theta);
            let w = (dir * speed).clamp(
                vel.angular - p.acc_lim_theta * dt,
                vel.angular + p.acc_lim_theta * dt,
            );
            let clear = checker
                .rollout(pose, 0.0, dir * speed, &RolloutSpec::from_params(p))
                .is_some();
            if clear {
                return Some(Twist {
                    linear: v,
                    angular: w,
                });
            }
        }
        None
    }

    /// Samples of `[lo, hi]`: `n` evenly spaced, plus 0 when inside.
    fn samples(lo: f64, hi: f64, n: i32) -> Vec<f64> {
        if hi < lo {
            return Vec::new();
        }
        let n = n.max(1) as usize;
        let mut v: Vec<f64> = if n == 1 || hi - lo < 1e-12 {
            vec![hi]
        } else {
            (0..n)
                .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
                .collect()
        };
        if lo < 0.0 && hi > 0.0 && !v.contains(&0.0) {
            v.push(0.0);
        }
        v
    }

    fn finish(&mut self, pose: Pose2, t: Twist, best: Vec<Pose2>) -> Result<Twist, ControlError> {
        let p = &self.params;
        self.oscillation.update(
            pose,
            t.linear,
            t.angular,
            p.min_vel_trans,
            p.oscillation_reset_dist,
            p.oscillation_reset_angle,
        );
        self.best = best;
        Ok(t)
    }
}

/// Distance maps of one cycle.
struct Maps {
    path: DistanceGrid,
    goal: DistanceGrid,
    goal_front: Option<DistanceGrid>,
    near_goal: bool,
    /// The local plan (for the heading term).
    local: Vec<Pose2>,
    /// Cost level not counted against rollouts: the final goal's own cost once it is in reach.
    occ_allowance: f64,
    /// The final goal, when rollouts may reach it this cycle: they stop there.
    goal_in_reach: Option<Point2>,
}

impl Maps {
    /// The point `MIN_CARROT_DISTANCE` along the local plan beyond its point nearest `p`.
    fn carrot(&self, p: Point2) -> Point2 {
        let nearest = (0..self.local.len())
            .min_by(|&a, &b| {
                self.local[a]
                    .position()
                    .dist(p)
                    .total_cmp(&self.local[b].position().dist(p))
            })
            .unwrap_or(0);
        let mut along = 0.0;
        for i in nearest + 1..self.local.len() {
            along += self.local[i - 1].position().dist(self.local[i].position());
            if along >= MIN_CARROT_DISTANCE {
                return self.local[i].position();
            }
        }
        self.local.last().map_or(p, |q| q.position())
    }
}

impl DwaController {
    fn score(&self, r: &Rollout, cm: &Costmap2D, maps: &Maps) -> Option<f64> {
        let p = &self.params;
        let end = *r.poses.last()?;
        let nose = Point2::new(
            end.x + p.forward_point_distance * end.yaw.cos(),
            end.y + p.forward_point_distance * end.yaw.sin(),
        );
        let path_end = maps.path.at(cm, end.position())?;
        let goal_end = maps.goal.at(cm, end.position())?;
        let align = if maps.near_goal {
            0.0
        } else {
            maps.path
                .at(cm, nose)
                .unwrap_or(path_end + p.forward_point_distance)
        };
        let goal_front = match &maps.goal_front {
            Some(g) => g
                .at(cm, nose)
                .unwrap_or(goal_end + p.forward_point_distance),
            None => goal_end,
        };
        let occ = if p.sum_scores {
            r.sum_cost
        } else {
            (r.max_cost as f64 - maps.occ_allowance).max(0.0)
        };
        let carrot = maps.carrot(end.position());
        let heading = if end.position().dist(carrot) < 1e-6 {
            0.0
        } else {
            normalize_angle((carrot.y - end.y).atan2(carrot.x - end.x) - end.yaw).abs()
        };
        Some(
            p.path_distance_bias * (path_end + align)
                + p.goal_distance_bias * (goal_end + goal_front)
                + p.occdist_scale * occ
                + p.twirling_scale * r.w.abs()
                + HEADING_WEIGHT * heading,
        )
    }
}

/// Ends a rollout at its first pose within `radius` (m) of `goal`, where the robot would stop,
/// and recounts its costs.
fn cut_at_goal(r: &mut Rollout, goal: Point2, radius: f64, cm: &Costmap2D) {
    let Some(k) = r
        .poses
        .iter()
        .position(|q| q.position().dist(goal) <= radius)
    else {
        return;
    };
    r.poses.truncate(k + 1);
    let costs: Vec<u8> = r
        .poses
        .iter()
        .map(|q| cm.cost_at(q.position()).unwrap_or(0))
        .collect();
    r.max_cost = costs.iter().copied().max().unwrap_or(0);
    r.sum_cost = costs.iter().map(|&c| c as f64).sum();
}

impl Controller for DwaController {
    fn set_plan(&mut self, plan: &[Pose2]) {
        self.plan = plan.to_vec();
        self.progress = 0;
        self.oscillation.reset();
        match plan.last() {
            Some(&g) => self.goal.set_goal(g, &self.params),
            None => self.goal.clear(),
        }
    }

    fn compute_velocity(
        &mut self,
        pose: Pose2,
        vel: Twist,
        cm: &Costmap2D,
    ) -> Result<Twist, ControlError> {
        if self.plan.is_empty() {
            return Err(ControlError::NoPlan);
        }
        if !cm.contains(pose.position()) {
            return Err(ControlError::RobotOffCostmap);
        }
        let params = self.params.clone();
        let p = &params;
        let footprint = self.footprint.clone();
        let checker = CollisionChecker {
            costmap: cm,
            footprint: &footprint,
        };
        self.update_progress(pose.position());
        if self.goal.position_reached(pose, p) {
            let t = self
                .goal
                .stop_and_rotate(pose, vel, self.period, self.ignore_goal_yaw, p);
            return self.finish(pose, t, Vec::new());
        }
        let local: Vec<Pose2> = self.plan[self.progress..]
            .iter()
            .copied()
            .take_while(|q| cm.contains(q.position()))
            .collect();
        let Some(&local_goal) = local.last() else {
            return Err(ControlError::PlanOffCostmap);
        };
        let final_goal = self.plan[self.plan.len() - 1].position();
        let carrot = self.point_ahead(p.forward_point_distance.max(MIN_CARROT_DISTANCE));
        // Goal or path behind: turn towards it first.
        let err = normalize_angle((carrot.y - pose.y).atan2(carrot.x - pose.x) - pose.yaw);
        if err.abs() > p.rotate_first_angle && pose.position().dist(carrot) > p.xy_goal_tolerance {
            if let Some(t) = self.rotate_in_place(pose, vel, err, &checker) {
                return self.finish(pose, t, Vec::new());
            }
        }
        let goal_cell = |q: Point2| cm.world_to_map(q).map(|(x, y)| cm.index(x, y));
        let goal = DistanceGrid::from_cells(
            cm,
            &goal_cell(local_goal.position())
                .into_iter()
                .collect::<Vec<_>>(),
        );
        let dir = (local_goal.y - pose.y).atan2(local_goal.x - pose.x);
        let front = Point2::new(
            local_goal.x + p.forward_point_distance * dir.cos(),
            local_goal.y + p.forward_point_distance * dir.sin(),
        );
        // The nose is drawn to a point beyond the local goal, so that the centre stops on it;
        // when that point is in an obstacle the nose is not scored against the goal.
        let goal_front = match goal_cell(front) {
            Some(c) if cm.costs()[c] < crate::costmap_2d::INSCRIBED => {
                Some(DistanceGrid::from_cells(cm, &[c]))
            }
            _ => None,
        };
        let maps = Maps {
            path: DistanceGrid::from_path(cm, &local),
            goal,
            goal_front,
            near_goal: pose.position().dist(final_goal) <= p.forward_point_distance,
            local,
            occ_allowance: 0.0,
            goal_in_reach: None,
        };
        let mut maps = maps;
        if pose.position().dist(final_goal)
            <= p.max_vel_x.abs().max(p.min_vel_x.abs()) * p.sim_time + p.xy_goal_tolerance
        {
            maps.occ_allowance = cm
                .cost_at(final_goal)
                .map_or(0.0, |c| c.min(crate::costmap_2d::MAX_NON_OBSTACLE) as f64);
            maps.goal_in_reach = Some(final_goal);
        }
        // The dynamic window.
        let span = if p.use_dwa { self.period } else { p.sim_time };
        let v_max = p.max_vel_x.min(p.max_vel_trans).min(self.speed_limit);
        let (v_lo, v_hi) = (
            (vel.linear - p.acc_lim_x * span).max(p.min_vel_x),
            (vel.linear + p.acc_lim_x * span).min(v_max),
        );
        let (w_lo, w_hi) = (
            (vel.angular - p.acc_lim_theta * span).max(-p.max_vel_theta),
            (vel.angular + p.acc_lim_theta * span).min(p.max_vel_theta),
        );
        let spec = RolloutSpec::from_params(p);
        let mut best: Option<(f64, Rollout)> = None;
        // Fastest first, so that among equal scores the quickest wins.
        let mut vs = Self::samples(v_lo, v_hi, p.vx_samples);
        vs.sort_by(|a, b| b.total_cmp(a));
        for &v in &vs {
            for &w in &Self::samples(w_lo, w_hi, p.vth_samples) {
                if (v.abs() < p.min_vel_trans && w.abs() < p.min_vel_theta)
                    || v.abs() > p.max_vel_trans
                    || !self.oscillation.allows(v, w)
                {
                    continue;
                }
                let Some(mut r) = checker.rollout(pose, v, w, &spec) else {
                    continue;
                };
                if let Some(g) = maps.goal_in_reach {
                    cut_at_goal(&mut r, g, 0.5 * p.xy_goal_tolerance, cm);
                }
                let Some(s) = self.score(&r, cm, &maps) else {
                    continue;
                };
                if best.as_ref().is_none_or(|b| s < b.0) {
                    best = Some((s, r));
                }
            }
        }
        let Some((_, r)) = best else {
            return Err(ControlError::NoValidTrajectory);
        };
        self.finish(
            pose,
            Twist {
                linear: r.v,
                angular: r.w,
            },
            r.poses,
        )
    }

    fn is_goal_reached(&mut self, pose: Pose2, vel: Twist) -> bool {
        let p = self.params.clone();
        self.goal.goal_reached(pose, vel, self.ignore_goal_yaw, &p)
    }

    fn set_speed_limit(&mut self, max_vel_trans: f64) {
        self.speed_limit = if max_vel_trans > 0.0 {
            max_vel_trans
        } else {
            f64::INFINITY
        };
    }

    fn reset(&mut self) {
        self.plan.clear();
        self.progress = 0;
        self.goal.clear();
        self.oscillation.reset();
        self.best.clear();
    }
}
