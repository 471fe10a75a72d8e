//! PointNav under physics: Algorithm 1 of ROS-X-Habitat. Each discrete action becomes
//! velocities held for `control_period` T at `steps_per_sec` physics steps per second:
//! forward 0.25/T m/s, turns 10/T deg/s, stop = zero velocity. Metrics as in [`crate::env`].

use crate::action::Action;
use crate::env::{observation, prepare, DiscreteEnv, EnvView, InvalidEpisode, Observation, Prepared, StepResult, TaskConfig};
use crate::episode::Episode;
use crate::goal_field::GoalField;
use crate::metrics::EpisodeMetrics;
use crate::navgrid::NavGrid;
use crate::robot::{OdometryNoise, PhysicsError, PhysicsParams, PhysicsScene, RigidRobot, RobotProfile, WheelOdometry};
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;
use std::sync::Arc;
use xhab_types::{Point2, Pose2, Twist};

/// Settings of the physics mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PhysicsConfig {
    /// Time a discrete action's velocities are held (s, default 1).
    pub control_period: f64,
    /// Physics rate and gravity.
    pub physics: PhysicsParams,
    /// Odometry noise.
    pub odometry: OdometryNoise,
    /// Forward actions in the stuck window (default 10).
    pub stuck_window: usize,
    /// Less progress than this over the window means stuck (m, default 0.05).
    pub stuck_distance: f64,
}

impl Default for PhysicsConfig {
    fn default() -> Self {
        Self { control_period: 1.0, physics: PhysicsParams::default(), odometry: OdometryNoise::default(), stuck_window: 10, stuck_distance: 0.05 }
    }
}

/// Why a physics episode could not start.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PhysicsEnvError {
    /// The episode is invalid for the agent.
    #[error(transparent)]
    Invalid(#[from] InvalidEpisode),
    /// The physics world could not be built.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
}

/// One running episode under physics.
pub struct PhysicsEnv {
    grid: Arc<NavGrid>,
    field: Arc<GoalField>,
    task: TaskConfig,
    config: PhysicsConfig,
    robot: RigidRobot,
    odom: WheelOdometry,
    start: Pose2,
    goals: Vec<Point2>,
    steps: u32,
    collisions: u32,
    path_length: f64,
    d0: f64,
    called_stop: bool,
    done: bool,
    recent_forward: VecDeque<f64>,
    stuck: bool,
}

impl PhysicsEnv {
    /// Starts `episode` under physics with the robot `profile`; `seed` drives the odometry noise.
    pub fn new(
        grid: Arc<NavGrid>,
        scene: &PhysicsScene,
        episode: &Episode,
        task: TaskConfig,
        profile: &RobotProfile,
        config: PhysicsConfig,
        seed: u64,
    ) -> Result<PhysicsEnv, PhysicsEnvError> {
        if !(config.control_period.is_finite() && config.control_period > 0.0) {
            return Err(PhysicsError::Param(format!("control_period: must be > 0, got {}", config.control_period)).into());
        }
        let Prepared { start, goals, field, d0 } = prepare(&grid, episode)?;
        let robot = RigidRobot::new(scene, profile, start, grid.floor_z, &config.physics)?;
        let odom = WheelOdometry::new(start, config.odometry.clone(), seed);
        Ok(PhysicsEnv {
            grid,
            field,
            task,
            config,
            robot,
            odom,
            start,
            goals,
            steps: 0,
            collisions: 0,
            path_length: 0.0,
            d0,
            called_stop: false,
            done: false,
            recent_forward: VecDeque::new(),
            stuck: false,
        })
    }

    /// Holds `twist` (m/s, rad/s) for `duration` (s), in whole physics steps; updates odometry.
    /// For velocity agents: the path length grows by the displacement, and once the
    /// simulated time reaches `max_episode_steps` control periods the episode is over.
    pub fn step_twist(&mut self, twist: Twist, duration: f64) {
        let n = (duration / self.robot.dt()).round().max(0.0) as usize;
        for _ in 0..n {
            self.robot.step_physics(twist);
            self.odom.update(self.robot.pose());
        }
    }

    /// One control cycle of a velocity agent: holds `twist` for `duration` (s), counts the
    /// path, and ends the episode at the time limit (`max_episode_steps` control periods).
    pub fn drive(&mut self, twist: Twist, duration: f64) {
        if self.done {
            return;
        }
        let before = self.robot.pose().position();
        self.step_twist(twist, duration);
        self.path_length += before.dist(self.robot.pose().position());
        // Control periods begun, with a tolerance for the rounding of summed physics steps
        // (60 steps of 1/60 s add up to a hair over 1 s, which is still one period).
        let periods = self.robot.sim_time() / self.config.control_period;
        self.steps = (periods - 1e-6).ceil().max(0.0) as u32;
        if self.steps >= self.task.max_episode_steps {
            self.done = true;
        }
    }

    /// A velocity agent calls `stop` (counted as one more step, as Habitat's stop action).
    pub fn call_stop(&mut self) {
        if !self.done {
            self.called_stop = true;
            self.done = true;
            self.steps += 1;
        }
    }

    /// Simulated time (s).
    pub fn sim_s(&self) -> f64 {
        self.robot.sim_time()
    }
    /// Whether the robot made no progress over the stuck window at some point.
    pub fn stuck(&self) -> bool {
        self.stuck
    }
    /// Noisy wheel odometry pose (m, rad).
    pub fn odometry(&self) -> Pose2 {
        self.odom.pose()
    }
    /// The rigid robot.
    pub fn robot(&self) -> &RigidRobot {
        &self.robot
    }
}

impl DiscreteEnv for PhysicsEnv {
    fn step(&mut self, action: Action) -> StepResult {
        if self.done {
            return StepResult { obs: self.observe(), done: true, collided: false };
        }
        let t = self.config.control_period;
        let turn = self.task.turn_angle.to_radians() / t;
        let twist = match action {
            Action::Stop => {
                self.called_stop = true;
                Twist::default()
            }
            Action::MoveForward => Twist { linear: self.task.forward_step_size / t, angular: 0.0 },
            Action::TurnLeft => Twist { linear: 0.0, angular: turn },
            Action::TurnRight => Twist { linear: 0.0, angular: -turn },
        };
        let before = self.robot.pose().position();
        if action != Action::Stop {
            self.step_twist(twist, t);
        }
        let moved = before.dist(self.robot.pose().position());
        self.path_length += moved;
        let mut collided = false;
        if action == Action::MoveForward {
            // Blocked or deflected: well short of the commanded distance.
            collided = moved < 0.8 * self.task.forward_step_size;
            self.recent_forward.push_back(moved);
            if self.recent_forward.len() > self.config.stuck_window {
                self.recent_forward.pop_front();
            }
            if self.recent_forward.len() == self.config.stuck_window && self.recent_forward.iter().sum::<f64>() < self.config.stuck_distance {
                self.stuck = true;
            }
        }
        self.steps += 1;
        self.collisions += collided as u32;
        self.done = self.called_stop || self.steps >= self.task.max_episode_steps;
        StepResult { obs: self.observe(), done: self.done, collided }
    }

    fn observe(&self) -> Observation {
        observation(self.start, self.robot.pose(), self.goals[0])
    }

    fn is_done(&self) -> bool {
        self.done
    }

    fn metrics(&self) -> EpisodeMetrics {
        // Habitat snaps a position off the navmesh to it: the distance from the nearest
        // navigable point, plus the offset, never undefined.
        let (dtg, off) = self.field.distance_snapped(&self.grid, self.pose().position());
        EpisodeMetrics::new(self.task.success_distance, self.called_stop, dtg, self.d0, self.path_length, self.steps, self.collisions).off_navigable(off)
    }

}

impl EnvView for PhysicsEnv {
    fn pose(&self) -> Pose2 {
        self.robot.pose()
    }

    fn config(&self) -> &TaskConfig {
        &self.task
    }

    fn grid(&self) -> &Arc<NavGrid> {
        &self.grid
    }

    fn field(&self) -> &Arc<GoalField> {
        &self.field
    }
}
