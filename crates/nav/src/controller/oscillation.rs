//! [`OscillationGuard`]: forbids reversing the direction of travel or of an in-place turn
//! until the robot has moved on, as base_local_planner's oscillation cost function.
//!
//! Difference from ROS: there, a turn of `oscillation_reset_angle` (0.2 rad) clears every
//! flag, so a robot turning back and forth in place by more than that is never caught. Here
//! the turning flags clear only with `oscillation_reset_dist` of travel or a new plan; the
//! forward/backward flags clear with either, as in ROS.

use xhab_types::{normalize_angle, Pose2};

/// Direction-reversal flags of the DWA controller.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OscillationGuard {
    forward_pos: bool,
    forward_neg: bool,
    forward_pos_only: bool,
    forward_neg_only: bool,
    rotating_pos: bool,
    rotating_neg: bool,
    rot_pos_only: bool,
    rot_neg_only: bool,
    flag_pose: Pose2,
}

impl OscillationGuard {
    /// Whether a command of forward speed `v` (m/s) and turn rate `w` (rad/s) may be taken.
    pub fn allows(&self, v: f64, w: f64) -> bool {
        !((self.forward_pos_only && v < 0.0)
            || (self.forward_neg_only && v > 0.0)
            || (self.rot_pos_only && w < 0.0)
            || (self.rot_neg_only && w > 0.0))
    }

    /// Clears every flag (a new plan).
    pub fn reset(&mut self) {
        *self = Self {
            flag_pose: self.flag_pose,
            ..Self::default()
        };
    }

    /// Records the command `(v, w)` chosen at `pose`; turning flags are set only by commands
    /// slower than `min_vel_trans` (m/s), i.e. turns in place. Flags clear once the robot is
    /// `reset_dist` (m) from where the last flag was set, the forward/backward ones also after
    /// `reset_angle` (rad) of turning.
    pub fn update(
        &mut self,
        pose: Pose2,
        v: f64,
        w: f64,
        min_vel_trans: f64,
        reset_dist: f64,
        reset_angle: f64,
    ) {
        let mut flag_set = false;
        if v < 0.0 {
            if self.forward_pos {
                self.forward_neg_only = true;
                flag_set = true;
            }
            self.forward_pos = false;
            self.forward_neg = true;
        }
        if v > 0.0 {
            if self.forward_neg {
                self.forward_pos_only = true;
                flag_set = true;
            }
            self.forward_neg = false;
            self.forward_pos = true;
        }
        if v.abs() <= min_vel_trans {
            if w < 0.0 {
                if self.rotating_pos {
                    self.rot_neg_only = true;
                    flag_set = true;
                }
                self.rotating_pos = false;
                self.rotating_neg = true;
            }
            if w > 0.0 {
                if self.rotating_neg {
                    self.rot_pos_only = true;
                    flag_set = true;
                }
                self.rotating_neg = false;
                self.rotating_pos = true;
            }
        }
        if flag_set {
            self.flag_pose = pose;
        }
        if !(self.forward_pos_only
            || self.forward_neg_only
            || self.rot_pos_only
            || self.rot_neg_only)
        {
            return;
        }
        let moved = pose.position().dist(self.flag_pose.position()) > reset_dist;
        let turned = normalize_angle(pose.yaw - self.flag_pose.yaw).abs() > reset_angle;
        if moved {
            self.reset();
        } else if turned {
            self.forward_pos = false;
            self.forward_neg = false;
            self.forward_pos_only = false;
            self.forward_neg_only = false;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turning_back_in_place_is_refused_until_the_robot_travels() {
        let mut g = OscillationGuard::default();
        let p = Pose2::new(1.0, 1.0, 0.0);
        g.update(p, 0.0, 0.5, 0.1, 0.05, 0.2);
        assert!(g.allows(0.0, -0.5));
        g.update(Pose2::new(1.0, 1.0, 0.5), 0.0, -0.5, 0.1, 0.05, 0.2);
        // Reversed once: now only negative turns until it moves; a large turn does not clear it.
        assert!(!g.allows(0.0, 0.5) && g.allows(0.0, -0.5));
        g.update(Pose2::new(1.0, 1.0, -1.0), 0.0, -0.5, 0.1, 0.05, 0.2);
        assert!(!g.allows(0.0, 0.5));
        g.update(Pose2::new(1.1, 1.0, -1.0), 0.2, 0.0, 0.1, 0.05, 0.2);
        assert!(g.allows(0.0, 0.5));
    }
}
