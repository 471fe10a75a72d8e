//! [`GoalChecker`]: has the robot arrived? The xy tolerance with its optional latch, the yaw
//! tolerance, and the stop-then-rotate commands of base_local_planner's
//! LatchedStopRotateController.
//!
//! Difference from ROS: ROS clears the latch whenever a plan is set, and move_base sets one on
//! every replan, so a robot that reached the goal position and then drifted while turning
//! drives back and forth. Here the latch clears only when the goal itself moves.

use super::dwa_params::DwaParams;
use xhab_types::{normalize_angle, Pose2, Twist};

/// Goal arrival state for one goal.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GoalChecker {
    goal: Option<Pose2>,
    latched: bool,
}

impl GoalChecker {
    /// Takes the goal of a new plan; the latch is kept when the goal is the same (within the
    /// xy and yaw tolerances).
    pub fn set_goal(&mut self, goal: Pose2, p: &DwaParams) {
        let same = self.goal.is_some_and(|g| {
            g.position().dist(goal.position()) <= p.xy_goal_tolerance.max(1e-9)
                && normalize_angle(g.yaw - goal.yaw).abs() <= p.yaw_goal_tolerance.max(1e-9)
        });
        if !same {
            self.latched = false;
        }
        self.goal = Some(goal);
    }

    /// Forgets the goal and the latch.
    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// The current goal.
    pub fn goal(&self) -> Option<Pose2> {
        self.goal
    }

    /// Whether the robot at `pose` is within the xy tolerance (or latched there).
    pub fn position_reached(&mut self, pose: Pose2, p: &DwaParams) -> bool {
        let Some(g) = self.goal else { return false };
        if p.latch_xy_goal_tolerance && self.latched {
            return true;
        }
        let reached = pose.position().dist(g.position()) <= p.xy_goal_tolerance;
        if reached && p.latch_xy_goal_tolerance {
            self.latched = true;
        }
        reached
    }

    /// Whether the goal is reached: position, heading (unless `ignore_yaw`) and stopped.
    pub fn goal_reached(
        &mut self,
        pose: Pose2,
        vel: Twist,
        ignore_yaw: bool,
        p: &DwaParams,
    ) -> bool {
        let Some(g) = self.goal else { return false };
        if !self.position_reached(pose, p) {
            return false;
        }
        let yaw_ok = ignore_yaw || normalize_angle(g.yaw - pose.yaw).abs() <= p.yaw_goal_tolerance;
        yaw_ok && stopped(vel, p)
    }

    /// The command once the position is reached: brake to a stop within the acceleration
    /// limits over one period `dt` (s), then turn towards the goal heading (unless
    /// `ignore_yaw`) at the speed from which it can still stop in time.
    pub fn stop_and_rotate(
        &self,
        pose: Pose2,
        vel: Twist,
        dt: f64,
        ignore_yaw: bool,
        p: &DwaParams,
    ) -> Twist {
        let Some(g) = self.goal else {
            return Twist::default();
        };
        let brake = |v: f64, a: f64| v.signum() * (v.abs() - a * dt).max(0.0);
        if !stopped(vel, p) {
            return Twist {
                linear: brake(vel.linear, p.acc_lim_x),
                angular: brake(vel.angular, p.acc_lim_theta),
            };
        }
        let err = normalize_angle(g.yaw - pose.yaw);
        if ignore_yaw || err.abs() <= p.yaw_goal_tolerance {
            return Twist::default();
        }
        let speed = (2.0 * p.acc_lim_theta * err.abs())
            .sqrt()
            .clamp(p.min_vel_theta, p.max_vel_theta);
        let w = (err.signum() * speed).clamp(
            vel.angular - p.acc_lim_theta * dt,
            vel.angular + p.acc_lim_theta * dt,
        );
        Twist {
            linear: 0.0,
            angular: w,
        }
    }
}

/// Whether `vel` is below the stopped thresholds.
pub fn stopped(vel: Twist, p: &DwaParams) -> bool {
    vel.linear.abs() <= p.trans_stopped_vel && vel.angular.abs() <= p.theta_stopped_vel
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latch_survives_a_replan_to_the_same_goal() {
        let p = DwaParams {
            latch_xy_goal_tolerance: true,
            ..Default::default()
        };
        let mut g = GoalChecker::default();
        let goal = Pose2::new(1.0, 1.0, 1.5);
        g.set_goal(goal, &p);
        assert!(g.position_reached(Pose2::new(1.05, 1.0, 0.0), &p));
        // Drifted out while turning, then replanned to the same goal: still latched.
        g.set_goal(goal, &p);
        assert!(g.position_reached(Pose2::new(1.2, 1.0, 0.0), &p));
        assert!(!g.goal_reached(Pose2::new(1.2, 1.0, 0.0), Twist::default(), false, &p));
        assert!(g.goal_reached(Pose2::new(1.2, 1.0, 1.45), Twist::default(), false, &p));
        // A new goal clears the latch.
        g.set_goal(Pose2::new(3.0, 1.0, 0.0), &p);
        assert!(!g.position_reached(Pose2::new(1.2, 1.0, 0.0), &p));
    }

    #[test]
    fn brakes_then_turns_the_short_way() {
        let p = DwaParams::default();
        let mut g = GoalChecker::default();
        g.set_goal(Pose2::new(0.0, 0.0, -1.0), &p);
        let t = g.stop_and_rotate(
            Pose2::default(),
            Twist {
                linear: 0.3,
                angular: 0.0,
            },
            0.05,
            false,
            &p,
        );
        assert!((t.linear - 0.175).abs() < 1e-12 && t.angular == 0.0);
        let t = g.stop_and_rotate(Pose2::default(), Twist::default(), 0.05, false, &p);
        assert!(t.linear == 0.0 && t.angular < 0.0, "{t:?}");
        assert_eq!(
            g.stop_and_rotate(Pose2::default(), Twist::default(), 0.05, true, &p),
            Twist::default()
        );
    }
}
