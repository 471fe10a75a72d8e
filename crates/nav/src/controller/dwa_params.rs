//! [`DwaParams`]: ROS dwa_local_planner's parameters (namespace `DWAPlannerROS`).
//!
//! Defaults are noetic's code defaults, which come from `DWAPlanner.cfg` through
//! dynamic_reconfigure: `path_distance_bias` 0.6 and `goal_distance_bias` 0.8 (the ROS wiki's
//! 32 and 24 are not what the code uses). As in ROS, both multiply distances in metres (ROS
//! multiplies cell counts by the costmap resolution), so YAML values carry over unchanged.

use crate::param_error::{check_positive, check_range, ParamError};
use serde::{Deserialize, Serialize};

/// DWA local planner parameters (ROS names and noetic defaults, plus `rotate_first_angle`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DwaParams {
    /// Largest translational speed (m/s, default 0.55, range [0, 20]).
    pub max_vel_trans: f64,
    /// Smallest translational speed of a moving sample (m/s, default 0.1, range [0, 20]).
    pub min_vel_trans: f64,
    /// Largest forward speed (m/s, default 0.55, range [-20, 20]).
    pub max_vel_x: f64,
    /// Smallest forward speed; negative allows reversing (m/s, default 0, range [-20, 20]).
    pub min_vel_x: f64,
    /// Largest turn rate (rad/s, default 1.0, range [0, 20]).
    pub max_vel_theta: f64,
    /// Smallest turn rate of a turning sample (rad/s, default 0.4, range [0, 20]).
    pub min_vel_theta: f64,
    /// Forward acceleration limit (m/s^2, default 2.5, range [0, 20]).
    pub acc_lim_x: f64,
    /// Angular acceleration limit (rad/s^2, default 3.2, range [0, 20]).
    pub acc_lim_theta: f64,
    /// Goal position tolerance (m, default 0.1, range [0, 10]).
    pub xy_goal_tolerance: f64,
    /// Goal heading tolerance (rad, default 0.1, range [0, 2 pi]).
    pub yaw_goal_tolerance: f64,
    /// Once within `xy_goal_tolerance`, stay "there" while turning to the goal heading
    /// (default false); the latch survives replanning to the same goal.
    pub latch_xy_goal_tolerance: bool,
    /// Below this speed the robot counts as stopped (m/s, default 0.1).
    pub trans_stopped_vel: f64,
    /// Below this turn rate the robot counts as stopped (rad/s, default 0.1).
    pub theta_stopped_vel: f64,
    /// Horizon of each rollout (s, default 1.7, range (0, 10]).
    pub sim_time: f64,
    /// Step between collision checks along a rollout (m, default 0.025).
    pub sim_granularity: f64,
    /// Step between collision checks of a turn (rad, default 0.1).
    pub angular_sim_granularity: f64,
    /// Forward speed samples (default 3, range [1, 100]).
    pub vx_samples: i32,
    /// Turn rate samples (default 20, range [1, 200]).
    pub vth_samples: i32,
    /// Weight of the distance from the rollout to the path (1/m, default 0.6, range [0, 100]).
    pub path_distance_bias: f64,
    /// Weight of the distance from the rollout to the local goal (1/m, default 0.8, range [0, 100]).
    pub goal_distance_bias: f64,
    /// Weight of the highest cell cost along the rollout (default 0.01, range [0, 10]).
    pub occdist_scale: f64,
    /// Weight of the turn rate (s/rad, default 0, range [0, 10]).
    pub twirling_scale: f64,
    /// Distance ahead of the robot of the point that is also scored (m, default 0.325).
    pub forward_point_distance: f64,
    /// A rollout must stay clear this long beyond `sim_time`, time to stop (s, default 0.2).
    pub stop_time_buffer: f64,
    /// Travel that clears the oscillation flags (m, default 0.05).
    pub oscillation_reset_dist: f64,
    /// Turn that clears the forward/backward oscillation flags (rad, default 0.2); the flags
    /// against turning back and forth in place clear only with travel or a new plan.
    pub oscillation_reset_angle: f64,
    /// Sample only velocities reachable within one control period (true, default) or within
    /// `sim_time`.
    pub use_dwa: bool,
    /// Sum the cell costs along a rollout instead of taking the highest (default false).
    pub sum_scores: bool,
    /// Heading error to the path ahead beyond which the robot turns in place before driving
    /// (xhab extension; rad, default 1.0, range [0, pi]; pi turns it off).
    pub rotate_first_angle: f64,
}

impl Default for DwaParams {
    fn default() -> Self {
        Self {
            max_vel_trans: 0.55,
            min_vel_trans: 0.1,
            max_vel_x: 0.55,
            min_vel_x: 0.0,
            max_vel_theta: 1.0,
            min_vel_theta: 0.4,
            acc_lim_x: 2.5,
            acc_lim_theta: 3.2,
            xy_goal_tolerance: 0.1,
            yaw_goal_tolerance: 0.1,
            latch_xy_goal_tolerance: false,
            trans_stopped_vel: 0.1,
            theta_stopped_vel: 0.1,
            sim_time: 1.7,
            sim_granularity: 0.025,
            angular_sim_granularity: 0.1,
            vx_samples: 3,
            vth_samples: 20,
            path_distance_bias: 0.6,
            goal_distance_bias: 0.8,
            occdist_scale: 0.01,
            twirling_scale: 0.0,
            forward_point_distance: 0.325,
            stop_time_buffer: 0.2,
            oscillation_reset_dist: 0.05,
            oscillation_reset_angle: 0.2,
            use_dwa: true,
            sum_scores: false,
            rotate_first_angle: 1.0,
        }
    }
}

impl DwaParams {
    /// Checks ranges and that the speed limits are ordered.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("max_vel_trans", self.max_vel_trans, 0.0, 20.0)?;
        check_range("min_vel_trans", self.min_vel_trans, 0.0, 20.0)?;
        check_range("max_vel_x", self.max_vel_x, -20.0, 20.0)?;
        check_range("min_vel_x", self.min_vel_x, -20.0, 20.0)?;
        check_range("max_vel_theta", self.max_vel_theta, 0.0, 20.0)?;
        check_range("min_vel_theta", self.min_vel_theta, 0.0, 20.0)?;
        check_range("acc_lim_x", self.acc_lim_x, 0.0, 20.0)?;
        check_range("acc_lim_theta", self.acc_lim_theta, 0.0, 20.0)?;
        check_range("xy_goal_tolerance", self.xy_goal_tolerance, 0.0, 10.0)?;
        check_range(
            "yaw_goal_tolerance",
            self.yaw_goal_tolerance,
            0.0,
            std::f64::consts::TAU,
        )?;
        check_range("trans_stopped_vel", self.trans_stopped_vel, 0.0, 20.0)?;
        check_range("theta_stopped_vel", self.theta_stopped_vel, 0.0, 20.0)?;
        check_positive("sim_time", self.sim_time)?;
        check_range("sim_time", self.sim_time, 0.0, 10.0)?;
        check_positive("sim_granularity", self.sim_granularity)?;
        check_positive("angular_sim_granularity", self.angular_sim_granularity)?;
        check_range("vx_samples", self.vx_samples as f64, 1.0, 100.0)?;
        check_range("vth_samples", self.vth_samples as f64, 1.0, 200.0)?;
        check_range("path_distance_bias", self.path_distance_bias, 0.0, 100.0)?;
        check_range("goal_distance_bias", self.goal_distance_bias, 0.0, 100.0)?;
        check_range("occdist_scale", self.occdist_scale, 0.0, 10.0)?;
        check_range("twirling_scale", self.twirling_scale, 0.0, 10.0)?;
        check_range(
            "forward_point_distance",
            self.forward_point_distance,
            0.0,
            10.0,
        )?;
        check_range("stop_time_buffer", self.stop_time_buffer, 0.0, 10.0)?;
        check_range(
            "oscillation_reset_dist",
            self.oscillation_reset_dist,
            0.0,
            10.0,
        )?;
        check_range(
            "oscillation_reset_angle",
            self.oscillation_reset_angle,
            0.0,
            std::f64::consts::TAU,
        )?;
        check_range(
            "rotate_first_angle",
            self.rotate_first_angle,
            0.0,
            std::f64::consts::PI,
        )?;
        if self.min_vel_x > self.max_vel_x {
            return Err(ParamError::invalid(
                "min_vel_x",
                format!(
                    "must be <= max_vel_x ({}), got {}",
                    self.max_vel_x, self.min_vel_x
                ),
            ));
        }
        if self.max_vel_x <= 0.0 && self.min_vel_x >= 0.0 {
            return Err(ParamError::invalid(
                "max_vel_x",
                "the robot cannot move: max_vel_x and min_vel_x are both 0",
            ));
        }
        Ok(())
    }
}
