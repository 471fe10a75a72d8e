//! PointNav under physics: Algorithm 1 of ROS-X-Habitat. Each discrete action becomes
//! velocities held for `control_period` T at `steps_per_sec` physics steps per second:
//! forward 0.25/T m/s, turns 10/T deg/s, stop = zero velocity. Metrics as in [`crate::env`].

use crate::action::Action;
use crate::env::{observation, prepare, DiscreteEnv, EnvView, InvalidEpisode, Observation, CheckedEpisode, StepResult, TaskConfig};
use crate::episode::Episode;
use crate::goal_field::GoalField;
use crate::metrics::EpisodeMetrics;
use crate::navgrid::NavGrid;
use crate::storey_route::StoreyRoute;
use crate::world::World;
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

/// The control period must be a positive number of seconds.
fn check_control_period(config: &PhysicsConfig) -> Result<(), PhysicsError> {
    if config.control_period.is_finite() && config.control_period > 0.0 {
        Ok(())
    } else {
        Err(PhysicsError::Param(format!("control_period: must be > 0, got {}", config.control_period)))
    }
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
    /// Why the robot got stuck, when a step it cannot climb holds it.
    stuck_cause: Option<String>,
    /// On an episode across storeys: the way, and the storey the robot counts on now.
    route: Option<(Arc<StoreyRoute>, usize)>,
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
        check_control_period(&config)?;
        let CheckedEpisode { start, goals, field, d0 } = prepare(&grid, episode)?;
        let floor_z = grid.floor_z;
        PhysicsEnv::starting((grid, field), scene, (task, config), profile, (start, floor_z), goals, d0, seed, None)
    }

    /// An episode at its start: the robot placed at `start` on ground at `z` (m), odometry
    /// seeded with `seed`, nothing yet done.
    #[allow(clippy::too_many_arguments)]
    fn starting(
        (grid, field): (Arc<NavGrid>, Arc<GoalField>),
        scene: &PhysicsScene,
        (task, config): (TaskConfig, PhysicsConfig),
        profile: &RobotProfile,
        (start, z): (Pose2, f64),
        goals: Vec<Point2>,
        d0: f64,
        seed: u64,
        route: Option<(Arc<StoreyRoute>, usize)>,
    ) -> Result<PhysicsEnv, PhysicsEnvError> {
        let robot = RigidRobot::new(scene, profile, start, z, &config.physics)?;
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
            stuck_cause: None,
            route,
        })
    }

    /// Starts `episode` in `world` under physics, on whichever storeys its start and goals
    /// stand (as [`KinematicEnv::in_world`](crate::env::KinematicEnv::in_world)): on one storey this is
    /// [`PhysicsEnv::new`] on that storey's grid; across storeys the robot's storey follows it
    /// up and down the flights, d0 is the 3D geodesic and the path is measured in 3D. Whether
    /// the robot can climb a flight is up to its body and its profile's `step_height`.
    #[allow(clippy::too_many_arguments)]
    pub fn in_world(
        world: &World,
        scene: &PhysicsScene,
        episode: &Episode,
        task: TaskConfig,
        profile: &RobotProfile,
        config: PhysicsConfig,
        seed: u64,
    ) -> Result<PhysicsEnv, PhysicsEnvError> {
        // The discrete environment checks the episode and lays out the way.
        let plan = crate::env::KinematicEnv::in_world(world, episode, task.clone())?;
        let Some((route, storey)) = plan.route() else {
            return PhysicsEnv::new(plan.grid().clone(), scene, episode, task, profile, config, seed);
        };
        check_control_period(&config)?;
        let goals = episode.goals.iter().map(|g| g.position.xy()).collect();
        let parts = (plan.grid().clone(), plan.field().clone());
        PhysicsEnv::starting(parts, scene, (task, config), profile, (plan.pose(), plan.height()), goals, plan.start_distance(), seed, Some((route, storey)))
    }

    /// The robot moved from `before` (planar, and its body at height `z_before`, m): the
    /// path's length, measured in 3D across storeys; on a flight, the storey it counts on.
    fn moved(&mut self, before: Point2, z_before: f64) -> f64 {
        let p = self.robot.pose().position();
        let planar = before.dist(p);
        match &mut self.route {
            None => planar,
            Some((route, storey)) => {
                let k = route.storey_at(*storey, p);
                if k != *storey {
                    if let Some((g, f)) = route.leg(k) {
                        (self.grid, self.field, *storey) = (g.clone(), f.clone(), k);
                    }
                }
                (planar.powi(2) + (self.robot.z() - z_before).powi(2)).sqrt()
            }
        }
    }

    /// Why the robot got stuck, when a step it cannot climb holds it ("a step 0.17 m high
    /// ahead, above the robot's step_height 0 m").
    pub fn stuck_cause(&self) -> Option<&str> {
        self.stuck_cause.as_deref()
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
        let (before, z) = (self.robot.pose().position(), self.robot.z());
        self.step_twist(twist, duration);
        self.path_length += self.moved(before, z);
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

    /// A step ahead of the robot higher than it climbs, described; `None` when there is none
    /// (a wall or an object holds it).
    fn step_ahead(&self) -> Option<String> {
        let p = self.robot.profile();
        if let Some(d) = self.robot.cliff() {
            return Some(format!("a drop of {d:.2} m ahead, deeper than the robot's step_height {} m ({})", p.step_height, p.name));
        }
        let rise = self.robot.rise_ahead(0.05)?;
        (rise > p.step_height + 0.01 && rise < p.height).then(|| {
            format!("a step {rise:.2} m high ahead, above the robot's step_height {} m ({})", p.step_height, p.name)
        })
    }

    /// A step or drop beside the robot, in any of 16 directions from its heading on, that it
    /// cannot climb, described; `None` when there is none.
    fn step_around(&self) -> Option<String> {
        let p = self.robot.profile();
        let yaw = self.robot.pose().yaw;
        let cliff = p.step_height.max(crate::robot::MIN_CLIFF) + 0.01;
        (0..16).find_map(|k| {
            let h = yaw + k as f64 * std::f64::consts::PI / 8.0;
            match (self.robot.rise_toward(h, 0.05), self.robot.drop_at(h, p.radius + 0.05)) {
                (Some(r), _) if r > p.step_height + 0.01 && r < p.height => {
                    Some(format!("a step {r:.2} m high ahead, above the robot's step_height {} m ({})", p.step_height, p.name))
                }
                (_, Some(d)) if d > cliff => Some(format!("a drop of {d:.2} m ahead, deeper than the robot's step_height {} m ({})", p.step_height, p.name)),
                _ => None,
            }
        })
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
        let (before, z) = (self.robot.pose().position(), self.robot.z());
        if action != Action::Stop {
            self.step_twist(twist, t);
        }
        let moved = self.moved(before, z);
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
                if !self.stuck {
                    self.stuck_cause = self.step_ahead();
                }
                self.stuck = true;
            }
        }
        self.steps += 1;
        self.collisions += collided as u32;
        self.done = self.called_stop || self.steps >= self.task.max_episode_steps;
        // Across storeys, a robot that runs out of steps at a step or drop it cannot take is
        // stuck there, whatever it was doing last (turning to find a way round, say).
        if self.done && !self.called_stop && !self.stuck && self.route.is_some() {
            if let Some(cause) = self.step_around() {
                self.stuck = true;
                self.stuck_cause = Some(cause);
            }
        }
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

    fn height(&self) -> f64 {
        match self.route {
            // The ground under the body: the floor, or a tread.
            Some(_) => self.robot.ground_z().unwrap_or(self.grid.floor_z),
            None => self.grid.floor_z,
        }
    }
}
