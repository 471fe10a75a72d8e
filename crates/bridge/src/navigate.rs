//! One run of the native navigation stack from a start to a goal (`xhab navigate`): the
//! robot under physics with its lidar, localised by ground truth, on a static map; the run
//! and the global plan drawn over that map.

use crate::agents::AgentKind;
use crate::benchmark::{nav_params, ParamError, ParamFile};
use crate::map_picture::MapPicture;
use crate::nav_agent::{Localization, NavSetup};
use crate::runner::{run_episode, Outcome, RunConfig};
use crate::scan_source::ScanSource;
use crate::setup::{self, PhysicsOptions, SceneOptions, SetupError};
use std::path::PathBuf;
use std::sync::Arc;
use xhab_nav::costmap::Costmap;
use xhab_sim::env::TaskConfig;
use xhab_sim::episode::{Episode, Goal};
use xhab_types::{OccupancyGrid, Point2, Point3, Pose2};

/// One navigation run, as `xhab navigate`'s flags give it.
#[derive(Debug, Clone)]
pub struct NavigateOptions {
    /// The SCENE argument: a file or `procedural[:SEED]`.
    pub scene: String,
    /// How to read it; the grids are built for the robot's radius unless one is given.
    pub scene_options: SceneOptions,
    /// Static map (map_server YAML); `None`: the map `xhab map` makes of the lowest floor.
    pub map: Option<PathBuf>,
    /// Start pose on the lowest floor (world/map frame: m, m, rad).
    pub start: Pose2,
    /// Goal on the lowest floor (world/map frame, m).
    pub goal: Point2,
    /// ROS parameter files, layered in order (`FILE[@NAMESPACE]`).
    pub nav_params: Vec<ParamFile>,
    /// Robot profile: a built-in name or a YAML file.
    pub robot: String,
    /// Time limit (simulated s, > 0).
    pub time_limit: f64,
}

impl NavigateOptions {
    /// A run of the `habitat` robot in `scene` from `start` to `goal` with every default
    /// (the scene's own map, default parameters, 500 s).
    pub fn new(scene: impl Into<String>, start: Pose2, goal: Point2) -> Self {
        Self { scene: scene.into(), scene_options: SceneOptions::default(), map: None, start, goal, nav_params: Vec::new(), robot: "habitat".into(), time_limit: 500.0 }
    }
}

/// A finished run: its outcome and what its picture shows.
#[derive(Debug)]
pub struct NavigateRun {
    /// The episode's outcome (with its trajectory when it ran).
    pub outcome: Outcome,
    /// The static map the stack planned on.
    pub map: OccupancyGrid,
    /// The global planner's path from start to goal on that map, if it found one (m).
    pub plan: Option<Vec<Point2>>,
    /// The start pose.
    pub start: Pose2,
    /// The goal.
    pub goal: Point2,
    /// Warnings for the user (unknown nav parameters), in order.
    pub warnings: Vec<String>,
}

impl NavigateRun {
    /// The run drawn over the map: the plan in blue, the trajectory in orange, the start in
    /// green and the goal in red.
    pub fn picture(&self) -> MapPicture<'_> {
        let mut pic = MapPicture::new(&self.map);
        if let Some(plan) = &self.plan {
            pic.polyline(plan, [60, 160, 255]);
        }
        if let Outcome::Ran(r) = &self.outcome {
            if let Some(t) = &r.trajectory {
                let pts: Vec<Point2> = t.iter().map(|p| p.position()).collect();
                pic.polyline(&pts, [230, 120, 0]);
            }
        }
        pic.dot(self.start.position(), 4, [0, 170, 0]);
        pic.dot(self.goal, 4, [220, 0, 0]);
        pic
    }
}

/// Why the run could not start. Messages name the flag or file, as the CLI spells them.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum NavigateError {
    /// The scene, robot, physics or map could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The nav parameter files could not be loaded.
    #[error(transparent)]
    NavParams(#[from] ParamError),
    /// The time limit is not a positive number.
    #[error("--time-limit must be a positive number of seconds")]
    BadTimeLimit,
}

/// Runs the native stack once as `o` describes: the robot's profile sizes the grid (unless a
/// radius is given) and the costmaps (where the files give no shape), physics with the
/// default settings, its lidar, ground-truth localisation; the episode lies on the lowest floor.
pub fn navigate_once(o: &NavigateOptions) -> Result<NavigateRun, NavigateError> {
    if !(o.time_limit > 0.0 && o.time_limit.is_finite()) {
        return Err(NavigateError::BadTimeLimit);
    }
    let profile = setup::robot_profile(&o.robot)?;
    let mut scene_options = o.scene_options.clone();
    scene_options.agent_radius.get_or_insert(profile.radius);
    let world = setup::load_geometry(&o.scene, &scene_options)?;
    let floor = setup::floor_index(&world, "auto")?;
    let z = world.floors[floor].z;
    let (params, warnings) = nav_params(&o.nav_params, Some(&profile))?;
    let map = match &o.map {
        Some(m) => setup::load_static_map(m)?,
        None => world.grid(floor).map_err(SetupError::Grid)?.occupancy_grid(),
    };
    let ep = Episode {
        episode_id: "navigate".into(),
        scene_id: o.scene.clone(),
        start_position: Point3::new(o.start.x, o.start.y, z),
        start_yaw: o.start.yaw,
        goals: vec![Goal { position: Point3::new(o.goal.x, o.goal.y, z), radius: 0.2 }],
        geodesic_distance: None,
        info: serde_json::Value::Null,
    };
    let physics = setup::physics_setup(&world, &PhysicsOptions { robot: o.robot.clone(), ..Default::default() })?;
    let task = TaskConfig { max_episode_steps: (o.time_limit / physics.config.control_period).ceil() as u32, ..Default::default() };
    let rays = setup::ray_scene(&world.scene)?;
    let nav = NavSetup {
        params: params.clone(),
        map: Some(Arc::new(map.clone())),
        localization: Localization::GroundTruth,
        scan: Some(ScanSource::lidar(Arc::new(rays), physics.profile.laser.lidar())),
        scan_period: 0.1,
    };
    let cfg = RunConfig { agent: AgentKind::Nav, task, threads: 1, record_trajectories: true, sensors: None, physics: Some(physics), seed: 0, nav: Some(nav), episode_indices: None };
    let outcome = run_episode(&world, &ep, 0, &cfg);
    let cm = Costmap::from_map(&map, &params.global_costmap);
    let plan = xhab_nav::planner::plan(&cm, o.start.position(), o.goal, &params.planner).ok().map(|p| p.iter().map(|q| q.position()).collect());
    Ok(NavigateRun { outcome, map, plan, start: o.start, goal: o.goal, warnings })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn across_the_house() -> NavigateOptions {
        NavigateOptions::new("procedural:1", Pose2::new(8.2, 6.75, 0.0), Point2::new(3.95, 1.3))
    }

    #[test]
    fn the_stack_reaches_the_goal_and_the_run_is_drawn() {
        let run = navigate_once(&across_the_house()).unwrap();
        let Outcome::Ran(r) = &run.outcome else { panic!("{:?}", run.outcome) };
        assert!(r.metrics.success > 0.0, "{:?}", r.metrics);
        assert!(r.sim_s.is_some_and(|s| s > 0.0 && s <= 500.0));
        let traj = r.trajectory.as_ref().expect("the trajectory is recorded");
        assert!(traj.len() > 2);
        let plan = run.plan.as_ref().expect("a plan across the house");
        assert!(plan.first().unwrap().dist(run.start.position()) < 0.2 && plan.last().unwrap().dist(run.goal) < 0.2, "{plan:?}");
        assert!(run.warnings.is_empty());
        let pic = run.picture();
        let bare = MapPicture::new(&run.map);
        assert_eq!(pic.image().dimensions(), bare.image().dimensions());
        assert_ne!(pic.image().as_raw(), bare.image().as_raw(), "nothing drawn");
    }

    #[test]
    fn an_unreachable_goal_is_an_invalid_outcome_and_bad_options_are_errors() {
        let run = navigate_once(&NavigateOptions { goal: Point2::new(2.0, 2.0), ..across_the_house() }).unwrap();
        assert!(matches!(&run.outcome, Outcome::Invalid(i) if i.reason.contains("not navigable")), "{:?}", run.outcome);
        let e = |o: NavigateOptions| navigate_once(&o).expect_err("should fail").to_string();
        assert_eq!(e(NavigateOptions { time_limit: 0.0, ..across_the_house() }), "--time-limit must be a positive number of seconds");
        assert!(e(NavigateOptions { robot: "no_such_robot".into(), ..across_the_house() }).starts_with("--robot no_such_robot"));
        assert!(e(NavigateOptions { map: Some("/nonexistent/map.yaml".into()), ..across_the_house() }).starts_with("loading map /nonexistent/map.yaml"));
        assert!(e(NavigateOptions { scene: "/nonexistent/house.glb".into(), ..across_the_house() }).starts_with("loading scene /nonexistent/house.glb"));
    }
}
