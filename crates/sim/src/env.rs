//! The discrete PointNav simulator: Habitat's actions, no physics, and the task's metrics.

use crate::action::Action;
use crate::episode::Episode;
use crate::goal_field::GoalField;
use crate::kinematic::try_step;
use crate::metrics::EpisodeMetrics;
use crate::navgrid::NavGrid;
use crate::storey_route::StoreyRoute;
use crate::world::World;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use xhab_types::{normalize_angle, Point2, Pose2};

/// The PointNav task's settings (Habitat defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TaskConfig {
    /// Distance of `move_forward` (m, default 0.25).
    pub forward_step_size: f64,
    /// Angle of `turn_left` / `turn_right` (degrees, default 10).
    pub turn_angle: f64,
    /// Actions after which an episode ends (default 500).
    pub max_episode_steps: u32,
    /// Success radius around the goal, strict (m, default 0.2).
    pub success_distance: f64,
}

impl Default for TaskConfig {
    fn default() -> Self {
        Self { forward_step_size: 0.25, turn_angle: 10.0, max_episode_steps: 500, success_distance: 0.2 }
    }
}

/// What the agent observes after each step (no images in this mode).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Observation {
    /// Ground-truth pose in the world frame (m, rad).
    pub pose: Pose2,
    /// GPS: position relative to the episode start, in the start's frame (m).
    pub gps: Point2,
    /// Compass: heading relative to the start heading (rad, in (-pi, pi]).
    pub compass: f64,
    /// Goal relative to the agent, polar: distance (m) and bearing (rad, CCW, 0 ahead).
    pub pointgoal: [f64; 2],
}

/// Why an episode cannot be run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum InvalidEpisode {
    /// The start is not navigable for the agent.
    #[error("start ({x:.3}, {y:.3}) is not navigable for the agent")]
    StartNotNavigable {
        /// x (m, world).
        x: f64,
        /// y (m, world).
        y: f64,
    },
    /// A goal is not navigable for the agent.
    #[error("goal ({x:.3}, {y:.3}) is not navigable for the agent")]
    GoalNotNavigable {
        /// x (m, world).
        x: f64,
        /// y (m, world).
        y: f64,
    },
    /// No goal can be reached from the start (another island).
    #[error("no goal is reachable from the start")]
    Unreachable,
    /// The episode has no goal.
    #[error("the episode has no goal")]
    NoGoal,
    /// A point of the episode stands on no storey of the scene.
    #[error("{what} ({x:.3}, {y:.3}, height {z:.3}) stands on no storey of the scene")]
    NoStorey {
        /// Which point: "start" or "goal".
        what: &'static str,
        /// x (m, world).
        x: f64,
        /// y (m, world).
        y: f64,
        /// z (m, world).
        z: f64,
    },
    /// The episode's goals stand on different storeys.
    #[error("the episode's goals stand on different storeys")]
    GoalsOnSeveralStoreys,
}

/// The result of one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepResult {
    /// The observation after the step.
    pub obs: Observation,
    /// Whether the episode is over (stop called or the step limit reached).
    pub done: bool,
    /// Whether the motion was blocked or deflected.
    pub collided: bool,
}

/// An episode checked against a grid: start pose, goals, their geodesic field and d0.
pub(crate) struct CheckedEpisode {
    pub start: Pose2,
    pub goals: Vec<Point2>,
    pub field: Arc<GoalField>,
    pub d0: f64,
}

/// Checks that the episode's start and goals are navigable and connected; builds its field.
pub(crate) fn prepare(grid: &NavGrid, episode: &Episode) -> Result<CheckedEpisode, InvalidEpisode> {
    let start = Pose2::new(episode.start_position.x, episode.start_position.y, normalize_angle(episode.start_yaw));
    if !grid.is_navigable(start.position()) {
        return Err(InvalidEpisode::StartNotNavigable { x: start.x, y: start.y });
    }
    if episode.goals.is_empty() {
        return Err(InvalidEpisode::NoGoal);
    }
    let goals: Vec<Point2> = episode.goals.iter().map(|g| g.position.xy()).collect();
    for g in &goals {
        if !grid.is_navigable(*g) {
            return Err(InvalidEpisode::GoalNotNavigable { x: g.x, y: g.y });
        }
    }
    let field = grid.field(&goals);
    let d0 = field.distance(grid, start.position());
    if !d0.is_finite() {
        return Err(InvalidEpisode::Unreachable);
    }
    Ok(CheckedEpisode { start, goals, field, d0 })
}

/// The observation of an agent at `pose` in an episode that started at `start`.
pub(crate) fn observation(start: Pose2, pose: Pose2, goal: Point2) -> Observation {
    let rel = start.inverse().compose(pose);
    let (dx, dy) = (goal.x - pose.x, goal.y - pose.y);
    Observation { pose, gps: rel.position(), compass: rel.yaw, pointgoal: [dx.hypot(dy), normalize_angle(dy.atan2(dx) - pose.yaw)] }
}

/// What an agent sees of a running PointNav episode: the pose and, for oracles, the task's
/// privileged state. A simulator implements it, and so does an agent's view built from ROS
/// messages.
pub trait EnvView {
    /// The agent's ground-truth pose (m, rad).
    fn pose(&self) -> Pose2;
    /// Geodesic distance from the agent to the nearest goal (m).
    fn distance_to_goal(&self) -> f64 {
        self.field().distance(self.grid(), self.pose().position())
    }
    /// The task settings.
    fn config(&self) -> &TaskConfig;
    /// The navigation grid of the episode's floor.
    fn grid(&self) -> &Arc<NavGrid>;
    /// The geodesic field towards the episode's goals.
    fn field(&self) -> &Arc<GoalField>;
    /// Height of the agent's feet (m, world z): its floor's, or on a flight of stairs the
    /// surface under it.
    fn height(&self) -> f64 {
        self.grid().floor_z
    }
}

/// A running PointNav episode that runners step, with or without physics.
pub trait DiscreteEnv: EnvView + Send {
    /// Applies one action (Habitat's discrete actions).
    fn step(&mut self, action: Action) -> StepResult;
    /// The observation at the current state.
    fn observe(&self) -> Observation;
    /// Whether the episode is over.
    fn is_done(&self) -> bool;
    /// The metrics so far (final once the episode is done).
    fn metrics(&self) -> EpisodeMetrics;
}

/// One running episode on one floor, kinematic: the agent teleports with Habitat's discrete
/// actions and slides along obstacles (no physics; [`crate::physics_env::PhysicsEnv`] has it).
#[derive(Debug, Clone)]
pub struct KinematicEnv {
    grid: Arc<NavGrid>,
    field: Arc<GoalField>,
    config: TaskConfig,
    start: Pose2,
    goals: Vec<Point2>,
    pose: Pose2,
    steps: u32,
    collisions: u32,
    path_length: f64,
    d0: f64,
    called_stop: bool,
    done: bool,
    /// On an episode across storeys: the way, and the storey the agent counts on now.
    route: Option<(Arc<StoreyRoute>, usize)>,
    /// Height of the agent's feet (m).
    height: f64,
}

impl KinematicEnv {
    /// Starts `episode` on `grid` (the grid of the episode's floor).
    pub fn new(grid: Arc<NavGrid>, episode: &Episode, config: TaskConfig) -> Result<KinematicEnv, InvalidEpisode> {
        let CheckedEpisode { start, goals, field, d0 } = prepare(&grid, episode)?;
        Ok(KinematicEnv::starting(grid, field, config, start, goals, d0, None))
    }

    /// An episode at its start on `grid` with `field`, nothing yet done.
    fn starting(grid: Arc<NavGrid>, field: Arc<GoalField>, config: TaskConfig, start: Pose2, goals: Vec<Point2>, d0: f64, route: Option<(Arc<StoreyRoute>, usize)>) -> KinematicEnv {
        KinematicEnv {
            height: grid.surface_height(start.position()),
            grid,
            field,
            config,
            start,
            goals,
            pose: start,
            steps: 0,
            collisions: 0,
            path_length: 0.0,
            d0,
            called_stop: false,
            done: false,
            route,
        }
    }

    /// Starts `episode` in `world`, on whichever storeys its start and goals stand
    /// ([`World::storey_of`]). On one storey this is [`KinematicEnv::new`] on that storey's grid; across
    /// storeys the agent walks each storey's grid on the way and changes grid on the flights
    /// between them (see [`StoreyRoute`]), its height following the surface under it, and d0
    /// is the 3D geodesic of [`crate::storey_path`].
    pub fn in_world(world: &World, episode: &Episode, config: TaskConfig) -> Result<KinematicEnv, InvalidEpisode> {
        let sp = episode.start_position;
        let start = world.storey_of(sp).ok_or(InvalidEpisode::NoStorey { what: "start", x: sp.x, y: sp.y, z: sp.z })?;
        let goal = goal_storey(world, episode)?;
        if goal == start {
            let grid = world.grid(start).map_err(|_| InvalidEpisode::StartNotNavigable { x: sp.x, y: sp.y })?;
            return KinematicEnv::new(grid, episode, config);
        }
        let goals: Vec<Point2> = episode.goals.iter().map(|g| g.position.xy()).collect();
        let route = StoreyRoute::new(world, start, goal, &goals).ok_or(InvalidEpisode::Unreachable)?;
        let (gg, _) = route.leg(goal).ok_or(InvalidEpisode::Unreachable)?;
        for g in &goals {
            if !gg.is_navigable(*g) {
                return Err(InvalidEpisode::GoalNotNavigable { x: g.x, y: g.y });
            }
        }
        let (grid, field) = route.leg(start).cloned().ok_or(InvalidEpisode::Unreachable)?;
        let pose = Pose2::new(sp.x, sp.y, normalize_angle(episode.start_yaw));
        if !grid.is_navigable(pose.position()) {
            return Err(InvalidEpisode::StartNotNavigable { x: sp.x, y: sp.y });
        }
        let d0 = episode.goals.iter().map(|g| crate::storey_path::distance(world, sp, g.position)).fold(f64::INFINITY, f64::min);
        if !d0.is_finite() {
            return Err(InvalidEpisode::Unreachable);
        }
        Ok(KinematicEnv::starting(grid, field, config, pose, goals, d0, Some((Arc::new(route), start))))
    }
}

impl KinematicEnv {
    /// On an episode across storeys, its way and the storey the agent counts on now.
    pub fn route(&self) -> Option<(Arc<StoreyRoute>, usize)> {
        self.route.clone()
    }

    /// The geodesic distance from the start to the nearest goal at reset, d0 (m).
    pub fn start_distance(&self) -> f64 {
        self.d0
    }
}

/// The storey all of `episode`'s goals stand on.
fn goal_storey(world: &World, episode: &Episode) -> Result<usize, InvalidEpisode> {
    let mut storey = None;
    for g in &episode.goals {
        let p = g.position;
        let k = world.storey_of(p).ok_or(InvalidEpisode::NoStorey { what: "goal", x: p.x, y: p.y, z: p.z })?;
        if storey.is_some_and(|s| s != k) {
            return Err(InvalidEpisode::GoalsOnSeveralStoreys);
        }
        storey = Some(k);
    }
    storey.ok_or(InvalidEpisode::NoGoal)
}

impl DiscreteEnv for KinematicEnv {
    /// Applies one action. Steps after the episode ended change nothing.
    fn step(&mut self, action: Action) -> StepResult {
        if self.done {
            return StepResult { obs: self.observe(), done: true, collided: false };
        }
        let mut collided = false;
        match action {
            Action::Stop => self.called_stop = true,
            Action::MoveForward => {
                let (s, c) = self.pose.yaw.sin_cos();
                let from = self.pose.position();
                let to = Point2::new(from.x + c * self.config.forward_step_size, from.y + s * self.config.forward_step_size);
                let (end, hit) = try_step(&self.grid, from, to);
                match &mut self.route {
                    // On a storey with stairs the agent's height follows the surface there too.
                    None if self.grid.has_stairs() => {
                        let z = self.grid.surface_height(end);
                        self.path_length += (from.dist(end).powi(2) + (z - self.height).powi(2)).sqrt();
                        self.height = z;
                    }
                    None => self.path_length += from.dist(end),
                    Some((route, storey)) => {
                        // Across storeys the path is measured in 3D, and on a flight the agent
                        // may now count on the next storey.
                        let k = route.storey_at(*storey, end);
                        if k != *storey {
                            if let Some((g, f)) = route.leg(k) {
                                (self.grid, self.field, *storey) = (g.clone(), f.clone(), k);
                            }
                        }
                        let z = self.grid.surface_height(end);
                        self.path_length += (from.dist(end).powi(2) + (z - self.height).powi(2)).sqrt();
                        self.height = z;
                    }
                }
                self.pose.x = end.x;
                self.pose.y = end.y;
                collided = hit;
            }
            Action::TurnLeft => self.pose.yaw = normalize_angle(self.pose.yaw + self.config.turn_angle.to_radians()),
            Action::TurnRight => self.pose.yaw = normalize_angle(self.pose.yaw - self.config.turn_angle.to_radians()),
        }
        self.steps += 1;
        if collided {
            self.collisions += 1;
        }
        self.done = self.called_stop || self.steps >= self.config.max_episode_steps;
        StepResult { obs: self.observe(), done: self.done, collided }
    }

    /// The observation at the current pose.
    fn observe(&self) -> Observation {
        observation(self.start, self.pose, self.goals[0])
    }

    /// The metrics so far (final once the episode is done).
    fn metrics(&self) -> EpisodeMetrics {
        // Habitat snaps a position off the navmesh to it: the distance from the nearest
        // navigable point, plus the offset, never undefined.
        let (dtg, off) = self.field.distance_snapped(&self.grid, self.pose().position());
        EpisodeMetrics::new(self.config.success_distance, self.called_stop, dtg, self.d0, self.path_length, self.steps, self.collisions).off_navigable(off)
    }

    /// Whether the episode is over.
    fn is_done(&self) -> bool {
        self.done
    }
}

impl EnvView for KinematicEnv {
    /// The agent's ground-truth pose (m, rad).
    fn pose(&self) -> Pose2 {
        self.pose
    }
    /// The task settings.
    fn config(&self) -> &TaskConfig {
        &self.config
    }
    /// The navigation grid of the episode's floor.
    fn grid(&self) -> &Arc<NavGrid> {
        &self.grid
    }
    /// The geodesic field towards the episode's goals.
    fn field(&self) -> &Arc<GoalField> {
        &self.field
    }
    /// Height of the agent's feet (m).
    fn height(&self) -> f64 {
        self.height
    }
}

/// A snapshot of what an oracle sees of a running episode: pose, task, grid and geodesic
/// field (the grid and field are shared, so a snapshot is cheap).
#[derive(Debug, Clone)]
pub struct EnvSnapshot {
    pose: Pose2,
    config: TaskConfig,
    grid: Arc<NavGrid>,
    field: Arc<GoalField>,
}

impl EnvSnapshot {
    /// The snapshot of `env` now.
    pub fn of(env: &dyn EnvView) -> Self {
        EnvSnapshot { pose: env.pose(), config: env.config().clone(), grid: env.grid().clone(), field: env.field().clone() }
    }

    /// A view of an episode known from outside an environment (a ROS agent node's): the
    /// agent at `pose`, the task, its floor's grid and its goals' field.
    pub fn new(pose: Pose2, config: TaskConfig, grid: Arc<NavGrid>, field: Arc<GoalField>) -> Self {
        EnvSnapshot { pose, config, grid, field }
    }

    /// Moves the agent to `pose` (m, rad).
    pub fn set_pose(&mut self, pose: Pose2) {
        self.pose = pose;
    }
}

impl EnvView for EnvSnapshot {
    fn pose(&self) -> Pose2 {
        self.pose
    }
    fn config(&self) -> &TaskConfig {
        &self.config
    }
    fn grid(&self) -> &Arc<NavGrid> {
        &self.grid
    }
    fn field(&self) -> &Arc<GoalField> {
        &self.field
    }
}
