//! `xhab ros sim|nav|agent`: the simulator, the native stack and a discrete agent as ROS 1 nodes.

use crate::cli::{LocalizationArg, MapOdomArg, RosCommand, RosOpts};
use xhab_bridge::ros::names::Names;
use xhab_bridge::ros::sim_node::Mounts;
use crate::scene_arg::load_world;
use anyhow::{bail, Context, Result};
use rand::SeedableRng;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Duration;
use xhab_bridge::nav_agent::{Localization, NavSetup};
use xhab_bridge::ros::live::{run_live, LiveOptions};
use xhab_bridge::ros::master::Master;
use xhab_sim::sensors::{CameraParams, LidarParams, RayScene};
use xhab_types::Pose2;

/// The master: --ros-master, else $ROS_MASTER_URI, else `None` (start one).
fn master_uri(o: &RosOpts) -> Option<String> {
    o.ros_master.clone().or_else(|| std::env::var("ROS_MASTER_URI").ok().filter(|s| !s.is_empty()))
}

/// The node's names: `--name` (else `default`), then the ROS arguments and `$ROS_NAMESPACE`.
fn names(o: &RosOpts, default: &str) -> Result<Names> {
    let ns = std::env::var("ROS_NAMESPACE").ok().filter(|s| !s.is_empty());
    Ok(Names::from_args(o.name.as_deref().unwrap_or(default), &o.ros_args, ns.as_deref())?)
}

pub fn run(c: &RosCommand) -> Result<ExitCode> {
    match c {
        RosCommand::Sim(a) => {
            let mut opts = a.scene_opts.clone();
            if a.physics.physics && opts.agent_radius.is_none() {
                opts.agent_radius = Some(xhab_sim::robot::RobotProfile::named_or_file(&a.physics.robot)?.radius);
            }
            let world = load_world(&a.scene, &opts)?;
            let floor = world.default_floor().context("the scene has no floor")?;
            let grid = world.grid(floor)?;
            let (start, z) = match &a.start {
                Some(s) => {
                    let v: Vec<f64> = s.split(',').map(|t| t.trim().parse::<f64>()).collect::<std::result::Result<_, _>>().map_err(|_| anyhow::anyhow!("bad --start '{s}': expected X,Y,YAW"))?;
                    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
                        bail!("bad --start '{s}': expected three finite numbers X,Y,YAW");
                    }
                    (Pose2::new(v[0], v[1], v[2]), grid.floor_z)
                }
                None => {
                    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(a.seed);
                    let p = grid.sample_navigable_point(&[], &mut rng).context("no navigable point in the scene")?;
                    (Pose2::new(p.x, p.y, 0.0), p.z)
                }
            };
            if !(a.depth_noise >= 0.0 && a.depth_noise.is_finite()) || !(0.0..=1.0).contains(&a.edge_dropout) {
                bail!("--depth-noise must be >= 0 and --edge-dropout in [0, 1]");
            }
            let physics = super::bench::physics_setup(&world, &a.physics)?;
            let rs = Arc::new(RayScene::new(&world.scene).context("the scene has no triangles")?);
            let map = match &a.map {
                Some(m) => xhab_nav::map_server::load_map(m).with_context(|| format!("loading map {}", m.display()))?.0,
                None => grid.occupancy_grid(),
            };
            let lidar = physics.as_ref().map_or_else(LidarParams::default, |p| p.profile.laser.lidar());
            let mounts = Mounts {
                laser_frame: physics.as_ref().map_or_else(|| "laser".into(), |p| p.profile.laser.frame.clone()),
                laser: Pose2::new(lidar.mount_xy[0], lidar.mount_xy[1], 0.0),
                laser_z: lidar.mount_height,
                camera_z: physics.as_ref().map_or(CameraParams::default().mount_height, |p| p.profile.camera_height),
            };
            let amcl_map = match (&a.amcl_map, &a.map) {
                (Some(m), _) => Some(xhab_nav::map_server::load_map(m).with_context(|| format!("loading map {}", m.display()))?.0),
                (None, None) => Some(grid.slice_map(&world.scene, lidar.mount_height, xhab_bridge::nav_agent::SCAN_PLANE_HALF_BAND)),
                (None, Some(_)) => None,
            };
            let cam = super::render::camera(&a.cam, physics.as_ref().map_or(CameraParams::default().mount_height, |p| p.profile.camera_height))?;
            let o = LiveOptions {
                master: master_uri(&a.ros),
                names: names(&a.ros, "xhab_sim")?,
                mounts,
                map_odom_ground_truth: a.map_odom == MapOdomArg::GroundTruth,
                physics,
                start,
                start_z: z,
                map: Some(map),
                amcl_map,
                lidar: Some((rs.clone(), lidar)),
                scan_period: 0.1,
                camera: match a.camera {
                    true => Some((Arc::new(super::render::renderer(&a.cam, &world.scene)?), cam, a.rgb)),
                    false => None,
                },
                camera_period: 0.2,
                depth_noise: xhab_sim::sensors::DepthNoise { sigma_at_1m: a.depth_noise, edge_threshold: 0.1, edge_dropout: a.edge_dropout },
                period: a.period,
                rate: a.rate,
                lockstep: a.ros.lockstep,
                duration: a.duration,
                cmd_vel_timeout: 0.5,
                seed: a.seed,
                timeout: Duration::from_secs_f64(a.ros.ros_timeout.max(0.1)),
            };
            eprintln!("xhab: simulating {} from ({:.2}, {:.2}, yaw {:.2}){}", a.scene, start.x, start.y, start.yaw, if o.physics.is_some() { " under physics (cmd_vel)" } else { " with discrete actions (action)" });
            run_live(grid, &o)?;
        }
        RosCommand::Nav(a) => {
            // Shapes come from the files, else from the robot profile (as `bench --agent nav`).
            let robot = xhab_sim::robot::RobotProfile::named_or_file(&a.robot).with_context(|| format!("--robot {}", a.robot))?;
            let params = super::nav_params(&a.nav_params, Some(&robot))?;
            let map = match &a.map {
                Some(m) => Some(xhab_nav::map_server::load_map(m).with_context(|| format!("loading map {}", m.display()))?.0),
                None => None,
            };
            let amcl_map = match &a.amcl_map {
                Some(m) => Some(xhab_nav::map_server::load_map(m).with_context(|| format!("loading map {}", m.display()))?.0),
                None => None,
            };
            let localization = match a.localization {
                LocalizationArg::GroundTruth => Localization::GroundTruth,
                LocalizationArg::Odom => Localization::Odom,
                LocalizationArg::Amcl => Localization::Amcl,
            };
            let setup = NavSetup { params, map: None, localization, scan: None, scan_period: 0.1 };
            let o = xhab_bridge::ros::nav_node::NavNodeOptions { setup, lockstep: a.ros.lockstep, seed: a.seed, timeout: Duration::from_secs_f64(a.ros.ros_timeout.max(0.1)) };
            let master = Master::connect_or_start(master_uri(&a.ros).as_deref())?;
            eprintln!("xhab: ROS master {}", master.uri);
            let name = names(&a.ros, "xhab_nav")?;
            let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
            rt.block_on(async {
                let (_tx, rx) = tokio::sync::watch::channel(false);
                tokio::select! {
                    r = xhab_bridge::ros::nav_node::run(&master.uri, name, o, map, amcl_map, rx, None) => r,
                    _ = tokio::signal::ctrl_c() => Ok(()),
                }
            })?;
        }
        RosCommand::Agent(a) => {
            let world = Arc::new(load_world(&a.scene, &a.scene_opts)?);
            let master = Master::connect_or_start(master_uri(&a.ros).as_deref())?;
            eprintln!("xhab: ROS master {}", master.uri);
            let name = names(&a.ros, "xhab_agent")?;
            let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
            let timeout = Duration::from_secs_f64(a.ros.ros_timeout.max(0.1));
            rt.block_on(async {
                let (_tx, rx) = tokio::sync::watch::channel(false);
                tokio::select! {
                    r = xhab_bridge::ros::agent_node::run(&master.uri, name, world, xhab_bridge::agents::AgentKind::Oracle, Default::default(), timeout, false, rx) => r,
                    _ = tokio::signal::ctrl_c() => Ok(()),
                }
            })?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
