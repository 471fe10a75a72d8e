//! `xhab ros sim`: the simulator as a long-running ROS node that real ROS tools (move_base,
//! amcl, rviz, rosbag, rostopic) drive and watch, free-running at a real-time factor or in
//! lock-step with one controller.

use super::master::Master;
use super::node::RosError;
use super::names::Names;
use super::sim_node::{Mounts, SimNode};
use crate::robot_io::run_sim;
use crate::runner::PhysicsSetup;
use crate::setup::{self, CameraOptions, EnvOptions, EnvSetup, PhysicsOptions, SceneOptions, SetupError};
use rand::SeedableRng;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;
use xhab_sim::navgrid::NavGrid;
use xhab_sim::sensors::{CameraParams, LidarParams, RayScene, Renderer};
use xhab_types::{OccupancyGrid, Pose2};

/// How `xhab ros sim` runs.
#[derive(Debug, Clone)]
pub struct StandaloneOptions {
    /// Master URI; `None` starts one.
    pub master: Option<String>,
    /// The node's name, namespace and remappings.
    pub names: Names,
    /// The laser's and the camera's mounts (static tf).
    pub mounts: Mounts,
    /// Publish map -> odom from ground truth (as fake_localization), for stacks without a
    /// localiser.
    pub map_odom_ground_truth: bool,
    /// Physics (velocity commands on `cmd_vel`); `None`: discrete actions on `action`.
    pub physics: Option<PhysicsSetup>,
    /// Where the robot starts (world frame) and the height of its floor (m).
    pub start: Pose2,
    /// Height of the start's floor (m).
    pub start_z: f64,
    /// The map to publish (latched), if any.
    pub map: Option<OccupancyGrid>,
    /// The map to publish on `amcl/map` (latched), the one to localise on, if any.
    pub amcl_map: Option<OccupancyGrid>,
    /// The planar lidar, published on `scan` every `scan_period`.
    pub lidar: Option<(Arc<RayScene>, LidarParams)>,
    /// Period between scans (s).
    pub scan_period: f64,
    /// The camera (depth, and RGB when the flag is set), published every `camera_period`.
    pub camera: Option<(Arc<Renderer>, CameraParams, bool)>,
    /// Period between camera frames (s).
    pub camera_period: f64,
    /// Depth noise (off by default).
    pub depth_noise: xhab_sim::sensors::DepthNoise,
    /// Period of the state loop (s): odom, tf, clock and one physics interval per cycle.
    pub period: f64,
    /// Simulated seconds per wall second (0 = as fast as possible).
    pub rate: f64,
    /// Lock-step: each cycle waits for one `cmd_vel` before advancing.
    pub lockstep: bool,
    /// Stop after this much simulated time (s), if given.
    pub duration: Option<f64>,
    /// Seconds without `cmd_vel` after which the base stops (free-running).
    pub cmd_vel_timeout: f64,
    /// Seed of odometry and lidar noise.
    pub seed: u64,
    /// How long lock-step waits for a command (s).
    pub timeout: Duration,
}

/// What `xhab ros sim` simulates, as its flags give it.
#[derive(Debug, Clone)]
pub struct SimSpec {
    /// The SCENE argument: a file or `procedural[:SEED]`.
    pub scene: String,
    /// How to read it; under physics the grid is built for the robot's radius unless one is given.
    pub scene_options: SceneOptions,
    /// Physics (velocity commands on `cmd_vel`) with this robot; `None`: discrete actions.
    pub physics: Option<PhysicsOptions>,
    /// The map to publish on `map` (map_server YAML); `None`: the scene's own map.
    pub map: Option<PathBuf>,
    /// The map to publish on `amcl/map` (map_server YAML); `None`: the scene cut at the
    /// lidar's height without `map`, nothing with it.
    pub amcl_map: Option<PathBuf>,
    /// Start pose (world frame: m, m, rad) on the lowest floor; `None`: a random navigable
    /// point from `seed`.
    pub start: Option<Pose2>,
    /// Publish the depth camera.
    pub publish_camera: bool,
    /// Also publish RGB images (with the camera).
    pub rgb: bool,
    /// The camera (its height defaults to the robot's under physics, else 1.25 m).
    pub camera: CameraOptions,
    /// Depth noise at 1 m (m, growing with depth squared; 0 = off).
    pub depth_noise: f64,
    /// Probability that a depth pixel on an edge reads no return (0 = off).
    pub edge_dropout: f64,
    /// Simulated seconds per wall second (0: as fast as possible).
    pub rate: f64,
    /// Period of the state loop (s).
    pub period: f64,
    /// Stop after this much simulated time (s), if given.
    pub duration: Option<f64>,
    /// Seed of the start pose and the noise.
    pub seed: u64,
    /// Publish map -> odom from ground truth (as fake_localization).
    pub map_odom_ground_truth: bool,
    /// Master URI; `None` starts one.
    pub master: Option<String>,
    /// The node's name, namespace and remappings.
    pub names: Names,
    /// Lock-step: each cycle waits for one command.
    pub lockstep: bool,
    /// How long lock-step waits for a command.
    pub timeout: Duration,
}

impl SimSpec {
    /// `xhab ros sim SCENE` with its flags' defaults (discrete actions, the scene's own map, a
    /// random start from seed 0, no camera or noise, real time at a 0.05 s period, a master
    /// started for the run, node `xhab_sim`, free-running) and a lock-step timeout of 1 s.
    pub fn new(scene: impl Into<String>) -> SimSpec {
        SimSpec {
            scene: scene.into(),
            scene_options: SceneOptions::default(),
            physics: None,
            map: None,
            amcl_map: None,
            start: None,
            publish_camera: false,
            rgb: false,
            camera: CameraOptions::default(),
            depth_noise: 0.0,
            edge_dropout: 0.0,
            rate: 1.0,
            period: 0.05,
            duration: None,
            seed: 0,
            map_odom_ground_truth: false,
            master: None,
            names: Names::plain("xhab_sim"),
            lockstep: false,
            timeout: Duration::from_secs(1),
        }
    }
}

/// The simulator `xhab ros sim` runs: the floor's grid and the node's options, ready for
/// [`run_standalone`].
#[derive(Debug, Clone)]
pub struct StandaloneSim {
    /// The grid of the lowest floor.
    pub grid: Arc<NavGrid>,
    /// The node's options.
    pub options: StandaloneOptions,
    /// Which renderer the camera uses and why (with the camera), for a log line.
    pub renderer_note: Option<String>,
}

impl StandaloneSim {
    /// Loads the scene and builds the robot, its physics, sensors, maps and start pose as
    /// `spec` asks (the environment through [`EnvSetup::build`], as `xhab bench` does).
    pub fn build(spec: &SimSpec) -> Result<StandaloneSim, SetupError> {
        let mut env = EnvOptions::new(spec.scene.clone());
        env.scene_options = spec.scene_options.clone();
        env.physics = spec.physics.clone();
        env.sensors = match (spec.publish_camera, spec.rgb) {
            (false, _) => Vec::new(),
            (true, false) => vec!["depth".into()],
            (true, true) => vec!["depth".into(), "rgb".into()],
        };
        env.camera = spec.camera.clone();
        env.depth_noise = spec.depth_noise;
        env.edge_dropout = spec.edge_dropout;
        let setup = EnvSetup::build(&env)?;
        let world = &setup.world;
        let grid = world.grid(setup::floor_index(world, "auto")?)?;
        let (start, start_z) = match spec.start {
            Some(p) => (p, grid.floor_z),
            None => {
                let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(spec.seed);
                let p = grid.sample_navigable_point(&[], &mut rng).ok_or(SetupError::NoNavigablePoint)?;
                (Pose2::new(p.x, p.y, 0.0), p.z)
            }
        };
        let physics = setup.physics.clone();
        let camera_z = physics.as_ref().map_or(CameraParams::default().mount_height, |p| p.profile.camera_height);
        // The camera's options are checked even when it is off.
        setup::camera_params(&spec.camera, camera_z)?;
        let rays = Arc::new(setup::ray_scene(&world.scene)?);
        let map = match &spec.map {
            Some(m) => setup::load_static_map(m)?,
            None => grid.occupancy_grid(),
        };
        let lidar = physics.as_ref().map_or_else(LidarParams::default, |p| p.profile.laser.lidar());
        let mounts = Mounts {
            laser_frame: physics.as_ref().map_or_else(|| "laser".into(), |p| p.profile.laser.frame.clone()),
            laser: Pose2::new(lidar.mount_xy[0], lidar.mount_xy[1], 0.0),
            laser_z: lidar.mount_height,
            camera_z,
        };
        let amcl_map = match (&spec.amcl_map, &spec.map) {
            (Some(m), _) => Some(setup::load_static_map(m)?),
            (None, None) => Some(grid.slice_map(&world.scene, lidar.mount_height, crate::nav_agent::SCAN_PLANE_HALF_BAND)),
            (None, Some(_)) => None,
        };
        let options = StandaloneOptions {
            master: spec.master.clone(),
            names: spec.names.clone(),
            mounts,
            map_odom_ground_truth: spec.map_odom_ground_truth,
            physics,
            start,
            start_z,
            map: Some(map),
            amcl_map,
            lidar: Some((rays, lidar)),
            scan_period: 0.1,
            camera: setup.sensors.as_ref().map(|rig| (rig.renderer.clone(), rig.params.clone(), rig.rgb)),
            camera_period: 0.2,
            depth_noise: setup::depth_noise(spec.depth_noise, spec.edge_dropout)?,
            period: spec.period,
            rate: spec.rate,
            lockstep: spec.lockstep,
            duration: spec.duration,
            cmd_vel_timeout: 0.5,
            seed: spec.seed,
            timeout: spec.timeout,
        };
        Ok(StandaloneSim { grid, options, renderer_note: setup.renderer_note })
    }
}

/// Runs the simulator node until `duration` passes or the process is interrupted.
pub fn run_standalone(grid: Arc<NavGrid>, o: &StandaloneOptions) -> Result<(), RosError> {
    let master = Master::connect_or_start(o.master.as_deref())?;
    eprintln!("xhab: ROS master {}{}", master.uri, if master.owned() { " (started for this run)" } else { "" });
    super::foreground::run_until_ctrl_c(serve(&master.uri, grid, o))
}

async fn serve(uri: &str, grid: Arc<NavGrid>, o: &StandaloneOptions) -> Result<(), RosError> {
    let mut sim = SimNode::new(uri, o.names.clone(), &o.mounts.laser_frame, o.timeout).await?;
    run_sim(&mut sim, grid, o).await
}

#[cfg(test)]
mod tests {
    use super::*;
    use xhab_sim::sensors::RendererKind;

    fn spec() -> SimSpec {
        SimSpec { camera: CameraOptions { renderer: Some(RendererKind::Raster), resolution: 16, ..Default::default() }, ..SimSpec::new("procedural:3") }
    }

    #[test]
    fn the_simulator_is_built_from_its_spec() {
        let sim = StandaloneSim::build(&spec()).unwrap();
        let o = &sim.options;
        assert!(sim.grid.is_navigable(o.start.position()), "a random start is navigable");
        assert_eq!(o.start_z, sim.grid.floor_z);
        assert!(o.physics.is_none() && o.camera.is_none() && sim.renderer_note.is_none());
        assert!(o.map.is_some() && o.amcl_map.is_some() && o.lidar.is_some());
        assert_eq!(o.mounts.laser_frame, "laser");
        // Under physics, with the camera: the robot's mounts, its radius, the camera at its height.
        let robot = PhysicsOptions { robot: "turtlebot3_burger".into(), ..Default::default() };
        let given = Pose2::new(1.0, 2.0, 0.5);
        let sim = StandaloneSim::build(&SimSpec { physics: Some(robot), publish_camera: true, rgb: true, start: Some(given), ..spec() }).unwrap();
        let o = &sim.options;
        let ph = o.physics.as_ref().expect("physics");
        assert_eq!(ph.profile.name, "turtlebot3_burger");
        assert!((sim.grid.params.radius - ph.profile.radius).abs() < 1e-12);
        assert_eq!(o.mounts.laser_frame, ph.profile.laser.frame);
        let (_, cam, rgb) = o.camera.as_ref().expect("camera");
        assert!(*rgb && cam.width == 16 && (cam.mount_height - ph.profile.camera_height).abs() < 1e-12);
        assert!(sim.renderer_note.as_deref().is_some_and(|n| n.starts_with("raster")));
        assert_eq!(o.start, given);
    }

    #[test]
    fn bad_options_are_errors_naming_the_flag_or_file() {
        let e = |s: SimSpec| StandaloneSim::build(&s).expect_err("should fail").to_string();
        assert_eq!(e(SimSpec { depth_noise: -1.0, ..spec() }), "--depth-noise must be >= 0 and --edge-dropout in [0, 1]");
        // The camera's options are checked even with the camera off.
        assert!(e(SimSpec { camera: CameraOptions { resolution: 0, ..Default::default() }, ..spec() }).contains("--resolution"));
        assert!(e(SimSpec { map: Some("/nonexistent/map.yaml".into()), ..spec() }).starts_with("loading map /nonexistent/map.yaml"));
        assert!(e(SimSpec { physics: Some(PhysicsOptions { robot: "no_such_robot".into(), ..Default::default() }), ..spec() }).starts_with("--robot no_such_robot"));
    }
}
