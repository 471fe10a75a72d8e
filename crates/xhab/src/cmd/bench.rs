//! `xhab bench`: an agent on every episode of a dataset; metrics as JSON, CSV and a table.

use crate::cli::{AgentArg, BenchArgs, GoalInterfaceArg, LocalizationArg, MapOdomArg, PaceArg, PhysicsOpts, ScanSourceArg};
use xhab_bridge::ros::external::{run_dataset_external, ExternalOptions, MapOdom, Pace};
use xhab_bridge::ros::move_base_client::GoalInterface;
use xhab_bridge::ros::names::Names;
use xhab_bridge::nav_agent::{Localization, NavSetup};
use xhab_bridge::report::{episodes_csv, BenchReport, RosCheck};
use crate::report::MapPicture;
use crate::scene_arg::load_world;
use anyhow::{Context, Result};
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;
use xhab_bridge::agents::AgentKind;
use std::sync::Arc;
use xhab_bridge::ros::bench::{run_dataset_ros, RosOptions};
use xhab_bridge::runner::{run_dataset, Aggregate, Outcome, PhysicsSetup, RunConfig};
use xhab_bridge::setup::PhysicsOptions;
use xhab_sim::robot::RobotProfile;
use xhab_sim::sensors::{CameraParams, CameraRig, DepthNoise, RayScene, Renderer};
use xhab_bridge::scan_source::ScanSource;
use xhab_nav::depth_to_scan::DepthToScanParams;
use xhab_sim::env::TaskConfig;
use xhab_sim::episode::Dataset;
use xhab_sim::world::World;
use xhab_types::Point2;

pub fn run(a: &BenchArgs, quiet: bool) -> Result<ExitCode> {
    let mut opts = a.scene_opts.clone();
    let mut physics_opts = a.physics.clone();
    // The nav agent drives with velocities: it always runs under physics.
    physics_opts.physics |= matches!(a.agent, AgentArg::Nav | AgentArg::Ros);
    if physics_opts.physics && opts.agent_radius.is_none() {
        // Plan for the robot that drives.
        opts.agent_radius = Some(RobotProfile::named_or_file(&a.physics.robot).with_context(|| format!("--robot {}", a.physics.robot))?.radius);
    }
    let world = load_world(&a.scene, &opts)?;
    let ds = xhab_bridge::setup::read_episodes(&a.episodes)?;
    let agent = match a.agent {
        AgentArg::Oracle => AgentKind::Oracle,
        AgentArg::Nav => AgentKind::Nav,
        AgentArg::Ros => AgentKind::Ros,
    };
    let task = TaskConfig { success_distance: a.success_distance, max_episode_steps: a.max_steps, ..Default::default() };
    let physics = physics_setup(&world, &physics_opts)?;
    let camera_height = physics.as_ref().map_or(CameraParams::default().mount_height, |p| p.profile.camera_height);
    let renderer = run_renderer(a, &world)?;
    let sensors = sensor_rig(a, renderer.clone(), camera_height)?;
    let nav = match a.agent {
        AgentArg::Nav => Some(nav_setup(a, physics.as_ref().map(|p| &p.profile), &world, renderer, camera_height)?),
        AgentArg::Oracle | AgentArg::Ros => None,
    };
    let cfg = RunConfig { agent, task, threads: a.threads.max(1), record_trajectories: a.trajectories.is_some(), physics, seed: a.seed, nav, sensors };
    // The master is infrastructure, started (when not given) before the run is timed, as the
    // scene is loaded before the in-process run is.
    let master = match (a.ros || a.compare_ros, &a.ros_master) {
        (true, None) => Some(xhab_bridge::ros::master::Master::start().context("starting rosmaster for the run")?),
        _ => None,
    };
    let ros = (a.ros || a.compare_ros).then(|| RosOptions {
        master: a.ros_master.clone().or_else(|| master.as_ref().map(|m| m.uri.clone())),
        timeout: std::time::Duration::from_secs_f64(a.ros_timeout.max(0.1)),
    });
    if a.agent == AgentArg::Ros {
        if a.ros || a.compare_ros {
            anyhow::bail!("--agent ros already runs over ROS: drop --ros/--compare-ros");
        }
        let ext = external_options(a, &world, cfg.physics.as_ref().map(|p| &p.profile), renderer_for_scans(a, &world)?, camera_height)?;
        let world = Arc::new(world);
        let name = a.episodes.display().to_string();
        let (report, outcomes) = bench(&world, &ds, &cfg, &a.scene, &name, quiet, Transport::External(&ext))?;
        return finish(a, &world, &ds, report, &outcomes, agent);
    }
    if ros.is_some() && cfg.threads > 1 {
        eprintln!("xhab: note: over ROS episodes run one at a time (lock-step); --threads applies to the in-process run only");
    }
    let world = Arc::new(world);
    let name = a.episodes.display().to_string();
    let (report, outcomes) = if a.compare_ros {
        let (local, local_out) = bench(&world, &ds, &cfg, &a.scene, &name, quiet, Transport::InProcess)?;
        let (mut remote, remote_out) = bench(&world, &ds, &cfg, &a.scene, &name, quiet, Transport::Ros(ros.as_ref().expect("set with --compare-ros")))?;
        let diff = compare_outcomes(&local_out, &remote_out);
        remote.aggregate.ros_overhead = Some(remote.aggregate.wall_s / local.aggregate.wall_s.max(1e-9));
        remote.ros_check = Some(diff.clone());
        eprintln!(
            "xhab: over ROS {:.2} s, in-process {:.2} s (overhead {:.2}x); results {} (max metric difference {:.1e}, {} episodes with other steps)",
            remote.aggregate.wall_s, local.aggregate.wall_s, remote.aggregate.ros_overhead.unwrap_or(0.0),
            if diff.identical { "identical" } else { "DIFFER" }, diff.max_metric_diff, diff.episodes_with_other_steps
        );
        (remote, remote_out)
    } else {
        let t = ros.as_ref().map_or(Transport::InProcess, Transport::Ros);
        bench(&world, &ds, &cfg, &a.scene, &name, quiet, t)?
    };
    if report.ros_check.as_ref().is_some_and(|c| !c.identical) {
        finish(a, &world, &ds, report, &outcomes, agent)?;
        anyhow::bail!("--compare-ros: the run over ROS differs from the in-process run (see ros_check in the JSON)");
    }
    finish(a, &world, &ds, report, &outcomes, agent)
}

/// Writes the trajectories, JSON and CSV a run asked for, and prints its table.
fn finish(a: &BenchArgs, world: &World, ds: &Dataset, report: BenchReport, outcomes: &[Outcome], agent: AgentKind) -> Result<ExitCode> {
    if let Some(dir) = &a.trajectories {
        draw_trajectories(world, ds, outcomes, dir)?;
    }
    if let Some(out) = &a.out {
        super::ensure_parent(out)?;
        let json = serde_json::to_string_pretty(&report)?;
        std::fs::write(out, json + "\n").with_context(|| format!("writing {}", out.display()))?;
    }
    if let Some(csv) = &a.csv {
        super::ensure_parent(csv)?;
        std::fs::write(csv, episodes_csv(&report.episodes)).with_context(|| format!("writing {}", csv.display()))?;
    }
    print_table(&report.aggregate, report.invalid.count, agent.name());
    print_ros_ends(&report);
    Ok(ExitCode::SUCCESS)
}

/// The renderer `--renderer` picks, built once per run (`None` when nothing renders).
fn run_renderer(a: &BenchArgs, world: &World) -> Result<Option<Arc<Renderer>>> {
    let depth_scans = a.agent == AgentArg::Nav && a.scan_source == ScanSourceArg::Depth && !a.no_scans;
    if a.sensors.is_empty() && !depth_scans {
        return Ok(None);
    }
    Ok(Some(Arc::new(super::render::renderer(&a.camera, &world.scene)?)))
}

/// The camera of `--sensors` (None without it): which images, resolution, noise.
fn sensor_rig(a: &BenchArgs, renderer: Option<Arc<Renderer>>, camera_height: f64) -> Result<Option<Arc<CameraRig>>> {
    let rgb = xhab_bridge::setup::parse_sensors(&a.sensors)?;
    let noise = xhab_bridge::setup::depth_noise(a.depth_noise, a.edge_dropout)?;
    let Some(renderer) = renderer.filter(|_| !a.sensors.is_empty()) else { return Ok(None) };
    let params = super::render::camera(&a.camera, camera_height)?;
    Ok(Some(Arc::new(CameraRig { renderer, params, rgb, noise })))
}

/// The nav agent's setup: parameters (ROS files, sized to the robot where they give no shape), map, localisation.
fn nav_setup(a: &BenchArgs, robot: Option<&RobotProfile>, world: &World, renderer: Option<Arc<Renderer>>, camera_height: f64) -> Result<NavSetup> {
    let params = super::nav_params(&a.nav_params, robot)?;
    let map = match &a.map {
        Some(m) => Some(Arc::new(xhab_nav::map_server::load_map(m).with_context(|| format!("loading map {}", m.display()))?.0)),
        None => None,
    };
    let localization = match a.localization {
        LocalizationArg::GroundTruth => Localization::GroundTruth,
        LocalizationArg::Odom => Localization::Odom,
        LocalizationArg::Amcl => Localization::Amcl,
    };
    if a.no_scans && localization == Localization::Amcl {
        anyhow::bail!("--localization amcl needs laser scans: drop --no-scans");
    }
    let scan = scan_source(a, world, robot, renderer, camera_height)?;
    Ok(NavSetup { params, map, localization, scan, scan_period: 0.1 })
}

/// The laser scans of `--scan-source` (None with `--no-scans`): the robot's lidar at its
/// mount, or the depth camera through depthimage_to_laserscan.
fn scan_source(a: &BenchArgs, world: &World, robot: Option<&RobotProfile>, renderer: Option<Arc<Renderer>>, camera_height: f64) -> Result<Option<ScanSource>> {
    Ok(match (a.no_scans, a.scan_source) {
        (true, _) => None,
        (false, ScanSourceArg::Lidar) => {
            let rs = RayScene::new(&world.scene).context("the scene has no triangles to scan")?;
            let lidar = robot.map_or_else(Default::default, |r| r.laser.lidar());
            Some(ScanSource::lidar(Arc::new(rs), lidar))
        }
        (false, ScanSourceArg::Depth) => {
            let renderer = renderer.context("a renderer for the depth scans")?;
            let params = super::render::camera(&a.camera, camera_height)?;
            let noise = DepthNoise { sigma_at_1m: a.depth_noise, edge_threshold: 0.1, edge_dropout: a.edge_dropout };
            Some(ScanSource::Depth { rig: Arc::new(CameraRig { renderer, params, rgb: false, noise }), params: DepthToScanParams::default() })
        }
    })
}

/// The physics setup of `--physics` (None without it): the scene's rigid mesh, the robot.
pub fn physics_setup(world: &World, o: &PhysicsOpts) -> Result<Option<PhysicsSetup>> {
    if !o.physics {
        return Ok(None);
    }
    let options = PhysicsOptions { robot: o.robot.clone(), control_period: o.control_period, steps_per_sec: o.steps_per_sec };
    Ok(Some(xhab_bridge::setup::physics_setup(world, &options)?))
}

/// Where a benchmark's agent runs.
#[derive(Debug, Clone, Copy)]
pub enum Transport<'a> {
    /// In this process.
    InProcess,
    /// As a separate ROS node in lock-step (`--ros`).
    Ros(&'a RosOptions),
    /// An external ROS stack (`--agent ros`).
    External(&'a ExternalOptions),
}

/// The renderer for depth scans of an external stack (`--scan-source depth`), if needed.
fn renderer_for_scans(a: &BenchArgs, world: &World) -> Result<Option<Arc<Renderer>>> {
    if a.scan_source == ScanSourceArg::Depth && !a.no_scans {
        return Ok(Some(Arc::new(super::render::renderer(&a.camera, &world.scene)?)));
    }
    Ok(None)
}

/// How `--agent ros` drives the stack under test.
fn external_options(a: &BenchArgs, world: &World, robot: Option<&RobotProfile>, renderer: Option<Arc<Renderer>>, camera_height: f64) -> Result<ExternalOptions> {
    let map = match &a.map {
        Some(m) => Some(xhab_nav::map_server::load_map(m).with_context(|| format!("loading map {}", m.display()))?.0),
        None => None,
    };
    if !(a.episode_timeout > 0.0) || !(a.cmd_vel_grace >= 0.0 && a.cmd_vel_grace.is_finite()) || !(a.rate > 0.0 && a.rate.is_finite()) {
        anyhow::bail!("--episode-timeout and --rate must be > 0 and --cmd-vel-grace >= 0");
    }
    let scan = scan_source(a, world, robot, renderer, camera_height)?;
    Ok(ExternalOptions {
        master: a.ros_master.clone().or_else(|| std::env::var("ROS_MASTER_URI").ok().filter(|s| !s.is_empty())),
        timeout: std::time::Duration::from_secs_f64(a.ros_timeout.max(0.1)),
        names: Names::from_args("xhab_sim", &a.ros_args, std::env::var("ROS_NAMESPACE").ok().filter(|s| !s.is_empty()).as_deref())?,
        goal_interface: match a.goal_interface {
            GoalInterfaceArg::Action => GoalInterface::Action,
            GoalInterfaceArg::Simple => GoalInterface::Simple,
        },
        episode_timeout: a.episode_timeout,
        map_odom: match a.map_odom {
            MapOdomArg::Stack => MapOdom::Stack,
            MapOdomArg::GroundTruth => MapOdom::GroundTruth,
        },
        pace: match a.pace {
            PaceArg::Lockstep => Pace::Lockstep { grace: std::time::Duration::from_secs_f64(a.cmd_vel_grace) },
            PaceArg::Realtime => Pace::Realtime { rate: a.rate },
        },
        controller_frequency: a.controller_frequency,
        map,
        launch: a.launch.clone(),
        scan,
        scan_period: 0.1,
    })
}

/// Runs the benchmark and builds its report (warnings for invalid episodes on stderr).
pub fn bench(world: &Arc<World>, ds: &Dataset, cfg: &RunConfig, scene: &str, episodes_file: &str, quiet: bool, transport: Transport<'_>) -> Result<(BenchReport, Vec<Outcome>)> {
    let pb = super::progress(ds.episodes.len(), quiet, cfg.agent.name());
    let t0 = Instant::now();
    let outcomes = match transport {
        Transport::InProcess => run_dataset(world, ds, cfg, &|| pb.inc(1)),
        Transport::Ros(o) => run_dataset_ros(world.clone(), ds, cfg, o, &|| pb.inc(1)).context("running the benchmark over ROS")?,
        Transport::External(o) => run_dataset_external(world.clone(), ds, cfg, o, &|| pb.inc(1)).context("benchmarking the external ROS stack")?,
    };
    let wall = t0.elapsed().as_secs_f64();
    pb.finish_and_clear();
    let report = BenchReport::new(&outcomes, wall, cfg, cfg.agent.name(), scene, episodes_file, !matches!(transport, Transport::InProcess));
    for i in &report.invalid.reasons {
        eprintln!("xhab: warning: episode {} is invalid and left out: {}", i.episode_id, i.reason);
    }
    Ok((report, outcomes))
}

/// How a run over ROS compares with the same run in-process.
fn compare_outcomes(a: &[Outcome], b: &[Outcome]) -> RosCheck {
    let mut max_diff = 0.0f64;
    let mut other_steps = 0;
    let mut same_set = a.len() == b.len();
    for (x, y) in a.iter().zip(b) {
        match (x, y) {
            (Outcome::Ran(x), Outcome::Ran(y)) => {
                let (m, n) = (&x.metrics, &y.metrics);
                for (p, q) in [(m.success, n.success), (m.spl, n.spl), (m.soft_spl, n.soft_spl), (m.distance_to_goal, n.distance_to_goal), (m.path_length, n.path_length)] {
                    max_diff = max_diff.max((p - q).abs());
                }
                if m.steps != n.steps || m.collisions != n.collisions || m.called_stop != n.called_stop {
                    other_steps += 1;
                }
            }
            (Outcome::Invalid(_), Outcome::Invalid(_)) => {}
            _ => same_set = false,
        }
    }
    RosCheck { identical: same_set && other_steps == 0 && max_diff <= 1e-9, max_metric_diff: max_diff, episodes_with_other_steps: other_steps }
}

/// How an external stack's episodes ended (`--agent ros`): terminal action states and why
/// each episode stopped (the failures line above counts them by Habitat's causes only).
fn print_ros_ends(report: &BenchReport) {
    let mut states: std::collections::BTreeMap<&str, usize> = Default::default();
    let mut ends: std::collections::BTreeMap<&str, usize> = Default::default();
    for e in &report.episodes {
        if let (Some(s), Some(end)) = (e.ros_status.as_deref(), e.ros_end.as_deref()) {
            *states.entry(s).or_default() += 1;
            *ends.entry(end).or_default() += 1;
        }
    }
    if states.is_empty() {
        return;
    }
    let list = |m: &std::collections::BTreeMap<&str, usize>| m.iter().map(|(k, n)| format!("{n} {k}")).collect::<Vec<_>>().join(", ");
    println!("ros: goals ended {}; episodes ended by {}", list(&states), list(&ends));
}

/// Prints the summary table on stdout.
pub fn print_table(a: &Aggregate, invalid: usize, agent: &str) {
    println!("{:<8} {:>8} {:>8} {:>8} {:>8} {:>10} {:>8} {:>10} {:>8} {:>12}", "agent", "episodes", "success", "spl", "soft_spl", "dtg_m", "steps", "collisions", "wall_s", "steps_per_s");
    println!(
        "{:<8} {:>8} {:>8.3} {:>8.3} {:>8.3} {:>10.3} {:>8.1} {:>10.1} {:>8.2} {:>12.0}",
        agent, a.episodes, a.success, a.spl, a.soft_spl, a.distance_to_goal, a.steps, a.collisions, a.wall_s, a.steps_per_s
    );
    if let (Some(sim), Some(rtf), Some(stuck)) = (a.sim_s, a.real_time_factor, a.stuck) {
        println!("physics: {sim:.0} s simulated, {rtf:.0}x real time, stuck in {:.1}% of episodes", stuck * 100.0);
    }
    let f = &a.failures;
    if f.stuck + f.stopped_outside + f.step_limit + f.goal_unreachable_for_costmap + f.aborted > 0 {
        println!(
            "failures: {} stuck, {} stopped outside the goal, {} ran out of steps, {} aborted (goal unreachable for the costmap), {} aborted (other)",
            f.stuck, f.stopped_outside, f.step_limit, f.goal_unreachable_for_costmap, f.aborted
        );
    }
    if invalid > 0 {
        println!("({invalid} invalid episodes left out)");
    }
}

/// Draws each episode's trajectory over the floor's map into `dir/EPISODE_ID.png`.
pub fn draw_trajectories(world: &World, ds: &Dataset, outcomes: &[Outcome], dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    for (ep, o) in ds.episodes.iter().zip(outcomes) {
        let Outcome::Ran(r) = o else { continue };
        let Some(traj) = &r.trajectory else { continue };
        let grid = world.grid_at(ep.start_position.z)?;
        let map = grid.occupancy_grid();
        let mut pic = MapPicture::new(&map);
        let goals: Vec<Point2> = ep.goals.iter().map(|g| g.position.xy()).collect();
        let field = xhab_sim::geodesic::GeodesicField::new(&grid, &goals);
        pic.polyline(&field.path(&grid, ep.start_position.xy()), [60, 160, 255]);
        let pts: Vec<Point2> = traj.iter().map(|p| p.position()).collect();
        pic.polyline(&pts, [230, 120, 0]);
        pic.dot(ep.start_position.xy(), 4, [0, 170, 0]);
        for g in &goals {
            pic.dot(*g, 4, [220, 0, 0]);
        }
        let name: String = r.episode_id.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect();
        pic.save(&dir.join(format!("{name}.png")))?;
    }
    Ok(())
}
