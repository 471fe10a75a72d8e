//! `xhab map --explore` as one call: the scene loaded for the robot, its lidar, depth camera
//! and physics built, the floor explored ([`crate::explore::explore`]) and the map it built
//! compared with the map the scene's geometry gives.

use crate::benchmark::{nav_params, ParamError, ParamFile};
use crate::explore::{default_start, explore, Exploration, ExploreError, ExploreParams, ExploreSensors};
use crate::map_picture::MapPicture;
use crate::setup::{self, CameraOptions, SceneOptions, SetupError};
use xhab_sim::sensors::RendererKind;
use xhab_nav::map_agreement::{map_agreement, MapAgreement};
use xhab_sim::robot::{PhysicsError, PhysicsScene};
use xhab_types::{OccupancyGrid, Point2, Pose2};

/// What `xhab map --explore` asks for.
#[derive(Debug, Clone)]
pub struct ExploreOptions {
    /// The SCENE argument.
    pub scene: String,
    /// How to read it; the agent radius defaults to the robot's.
    pub scene_options: SceneOptions,
    /// `auto` or a floor height (m).
    pub floor: String,
    /// Robot profile name or YAML file.
    pub robot: String,
    /// Start pose (m, m, rad); `None`: the floor's default start.
    pub start: Option<Pose2>,
    /// ROS parameter files of the navigator.
    pub nav_params: Vec<ParamFile>,
    /// Simulated seconds before giving up (s).
    pub max_time: f64,
    /// Seed (lidar noise).
    pub seed: u64,
    /// The depth camera's renderer; `None`: auto.
    pub renderer: Option<RendererKind>,
}

/// A finished exploration and how its map compares with the scene's.
#[derive(Debug)]
pub struct ExplorationRun {
    /// The run.
    pub exploration: Exploration,
    /// Where it started.
    pub start: Pose2,
    /// The robot's name.
    pub robot: String,
    /// The built map against the map of the scene's geometry.
    pub agreement: MapAgreement,
    /// Which renderer the depth camera used and why.
    pub renderer_note: String,
    /// The nav parameter loader's warnings.
    pub warnings: Vec<String>,
}

impl ExplorationRun {
    /// The built map with the robot's path (orange) and start (green).
    pub fn picture(&self) -> MapPicture<'_> {
        let mut pic = MapPicture::new(&self.exploration.map);
        let pts: Vec<Point2> = self.exploration.trajectory.iter().map(|p| p.position()).collect();
        pic.polyline(&pts, [230, 120, 0]);
        pic.dot(self.start.position(), 4, [0, 170, 0]);
        pic
    }

    /// Free area (m^2) and occupied cells of the built map.
    pub fn counts(&self) -> (f64, usize) {
        let m: &OccupancyGrid = &self.exploration.map;
        let free = m.data.iter().filter(|&&v| v == xhab_types::GRID_FREE).count();
        let occ = m.data.iter().filter(|&&v| v == xhab_types::GRID_OCCUPIED).count();
        (free as f64 * m.resolution * m.resolution, occ)
    }
}

/// Why an exploration could not run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExplorationRunError {
    /// The scene, floor, robot or camera could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The nav parameter files could not be loaded.
    #[error("--nav-params")]
    NavParams(#[source] ParamError),
    /// The start is not navigable, or the floor has no navigable cell.
    #[error("{0}")]
    Start(String),
    /// The physics world could not be built.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
    /// The exploration failed.
    #[error(transparent)]
    Explore(#[from] ExploreError),
}

/// Explores the scene of `o` with its robot and compares the map built with the scene's.
pub fn explore_scene(o: &ExploreOptions) -> Result<ExplorationRun, ExplorationRunError> {
    let profile = setup::robot_profile(&o.robot)?;
    let mut scene_options = o.scene_options.clone();
    scene_options.agent_radius.get_or_insert(profile.radius);
    let world = setup::load_geometry(&o.scene, &scene_options)?;
    let floor = setup::floor_index(&world, &o.floor)?;
    let grid = world.grid(floor).map_err(SetupError::from)?;
    let (nav, warnings) = nav_params(&o.nav_params, Some(&profile)).map_err(ExplorationRunError::NavParams)?;
    let start = match o.start {
        Some(s) => s,
        None => default_start(&grid).ok_or_else(|| ExplorationRunError::Start("the floor has no navigable cell to start from".into()))?,
    };
    if !grid.is_navigable(start.position()) {
        return Err(ExplorationRunError::Start(format!("--start ({:.2}, {:.2}) is not navigable for the robot", start.x, start.y)));
    }
    let physics = PhysicsScene::new(&world.scene)?;
    let rays = setup::ray_scene(&world.scene)?;
    let cam_opts = CameraOptions { renderer: o.renderer, camera_height: Some(profile.camera_height), ..Default::default() };
    let (renderer, why) = setup::build_renderer(cam_opts.renderer, &world.scene)?;
    let cam = setup::camera_params(&cam_opts, profile.camera_height)?;
    let mut params = ExploreParams { max_time: o.max_time, ..Default::default() };
    // Obstacles are what the robot would hit: from the highest step it climbs to its height.
    params.projection.min_obstacle_height = grid.params.max_climb;
    params.projection.max_obstacle_height = profile.height;
    let sensors = ExploreSensors { rays: &rays, camera: Some((&renderer, cam)) };
    let exploration = explore(&grid, &physics, &sensors, &profile, &nav, &params, start, o.seed)?;
    let agreement = map_agreement(&exploration.map, &grid.occupancy_grid(), start.position());
    Ok(ExplorationRun { exploration, start, robot: profile.name.clone(), agreement, renderer_note: format!("{}{why}", renderer.name()), warnings })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options() -> ExploreOptions {
        ExploreOptions {
            scene: "procedural:3".into(),
            scene_options: SceneOptions::default(),
            floor: "auto".into(),
            robot: "turtlebot3_burger".into(),
            start: None,
            nav_params: Vec::new(),
            max_time: 20.0,
            seed: 0,
            renderer: Some(RendererKind::Raycast),
        }
    }

    #[test]
    fn bad_inputs_are_errors_naming_them() {
        let mut o = options();
        o.start = Some(Pose2::new(1000.0, 1000.0, 0.0));
        assert!(explore_scene(&o).unwrap_err().to_string().contains("--start (1000.00, 1000.00) is not navigable"));
        let mut o = options();
        o.robot = "no_such_robot".into();
        assert!(explore_scene(&o).unwrap_err().to_string().contains("no_such_robot"));
    }

    #[test]
    fn a_short_exploration_maps_free_space_the_scene_has() {
        let run = explore_scene(&options()).unwrap();
        assert_eq!(run.robot, "turtlebot3_burger");
        let (free_m2, _) = run.counts();
        assert!(free_m2 > 1.0, "{free_m2} m^2 free after 20 s");
        assert!(run.agreement.free_coverage > 0.0 && run.agreement.free_occupied_in_reference < 0.05, "{:?}", run.agreement);
        assert!(run.exploration.sim_s <= 20.0 + 1e-9);
    }
}
