//! A benchmark as data, and the one function that runs it: [`run_bench`] is what
//! `xhab bench`, `xhab.bench` (Python) and experiments call, so every front end builds the
//! scene, robot, camera, nav stack and transport the same way and fails with the same messages.

use crate::agents::AgentKind;
use crate::nav_agent::{Localization, NavSetup};
use crate::report::{BenchReport, RosCheck};
use crate::ros::bench::{run_dataset_ros, RosOptions};
use crate::ros::external::{run_dataset_external, ExternalOptions, MapOdom, Pace};
use crate::ros::master::Master;
use crate::ros::move_base_client::GoalInterface;
use crate::ros::names::{NameError, Names};
use crate::ros::node::RosError;
use crate::runner::{run_dataset_until, Outcome, RunConfig};
use crate::scan_source::ScanSource;
use crate::setup::{self, EnvOptions, EnvSetup, PhysicsOptions, SetupError};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use xhab_nav::depth_to_scan::DepthToScanParams;
use xhab_nav::navigator::NavParams;
use xhab_nav::ros_params::load_nav_params;
pub use xhab_nav::ros_params::{ParamError, ParamFile};
use xhab_sim::episode::Dataset;
use xhab_sim::robot::RobotProfile;
use xhab_sim::sensors::{CameraRig, Renderer};
use xhab_sim::world::World;
use xhab_types::OccupancyGrid;

/// Where the nav agent's (or an external stack's) laser scans come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ScanKind {
    /// The robot's planar lidar at its mount (TurtleBot3 LDS-01 by default).
    #[default]
    Lidar,
    /// The depth camera through depthimage_to_laserscan.
    Depth,
}

/// The native navigation stack's options (`--agent nav`); scans also feed `--agent ros`.
#[derive(Debug, Clone, Default)]
pub struct NavOptions {
    /// Localisation source.
    pub localization: Localization,
    /// Static map (map_server YAML); `None`: the map `xhab map` makes of the episode's floor.
    pub map: Option<PathBuf>,
    /// ROS parameter files, layered in order (`FILE[@NAMESPACE]`).
    pub params: Vec<ParamFile>,
    /// Laser scans, or `None` to run on the static map alone (no obstacle layer, no AMCL).
    pub scans: Option<ScanKind>,
}

/// How `--agent ros` (ROS 1) and `--agent ros2` (ROS 2) drive an external stack.
#[derive(Debug, Clone)]
pub struct ExternalSpec {
    /// The master (`http://HOST:PORT`); `None`: `$ROS_MASTER_URI`, or one started for the run.
    pub master: Option<String>,
    /// The simulator node's ROS arguments: ROS 1's `from:=to` remappings, `__ns:=NS`,
    /// `__name:=N`; with `--agent ros2`, ROS 2's (`-r from:=to`, `-r __ns:=/NS`, ...).
    pub ros_args: Vec<String>,
    /// How goals reach the stack.
    pub goal_interface: GoalInterface,
    /// Simulated seconds after which an episode's goal is cancelled (s).
    pub episode_timeout: f64,
    /// Who publishes map -> odom.
    pub map_odom: MapOdom,
    /// The clock runs at `rate` simulated seconds per wall second instead of in lock-step.
    pub realtime: bool,
    /// Simulated seconds per wall second when `realtime`.
    pub rate: f64,
    /// Wall seconds to wait for cmd_vel after each tick in lock-step (s).
    pub cmd_vel_grace: f64,
    /// Clock ticks per simulated second (Hz): the stack's controller_frequency.
    pub controller_frequency: f64,
    /// A command that starts the stack (`sh -c`), stopped at the end.
    pub launch: Option<String>,
}

impl Default for ExternalSpec {
    fn default() -> Self {
        Self {
            master: None,
            ros_args: Vec::new(),
            goal_interface: GoalInterface::Action,
            episode_timeout: 120.0,
            map_odom: MapOdom::Stack,
            realtime: false,
            rate: 1.0,
            cmd_vel_grace: 0.5,
            controller_frequency: 20.0,
            launch: None,
        }
    }
}

/// Where the agent runs relative to the simulator.
#[derive(Debug, Clone, Default)]
pub enum Transport {
    /// In this process.
    #[default]
    InProcess,
    /// xhab's agent and simulator as separate ROS 1 nodes in lock-step (`--ros`).
    Ros,
    /// In-process, then over ROS; the two must agree (`--compare-ros`).
    CompareRos,
    /// xhab's agent and simulator as separate ROS 2 nodes in lock-step (`--ros2`), in the DDS
    /// domain of `$ROS_DOMAIN_ID` (loopback only with `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`).
    Ros2,
    /// In-process, then over ROS 2; the two must agree (`--compare-ros2`).
    CompareRos2,
}

impl Transport {
    /// Whether the run is in-process, then remote, compared.
    pub fn compares(&self) -> bool {
        matches!(self, Transport::CompareRos | Transport::CompareRos2)
    }
}

/// Everything one benchmark run needs, as `xhab bench`'s flags give it.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Scene, physics, camera and task. The `nav` and `ros` agents drive with velocities:
    /// they run under physics, with the default robot when `env.physics` is `None`.
    pub env: EnvOptions,
    /// The episodes file (Habitat PointNav `.json.gz` or `.json`).
    pub episodes: PathBuf,
    /// Run only these episodes of the file (0-based, ascending), each with the seeds it has
    /// in the whole file's run; `None`: every episode.
    pub episode_indices: Option<Vec<usize>>,
    /// The agent.
    pub agent: AgentKind,
    /// Worker threads for in-process runs (results do not depend on it).
    pub threads: usize,
    /// Seed of the run's randomness; episode i uses seed + i.
    pub seed: u64,
    /// Keep each episode's trajectory.
    pub record_trajectories: bool,
    /// The nav stack (`nav`) and the scans (`nav`, `ros`).
    pub nav: NavOptions,
    /// In-process or over ROS (xhab's own agents).
    pub transport: Transport,
    /// The master for `--ros`/`--compare-ros` (`None`: one started for the run).
    pub ros_master: Option<String>,
    /// How long to wait for a ROS peer before failing.
    pub ros_timeout: Duration,
    /// The external stack (`--agent ros` only).
    pub external: ExternalSpec,
}

impl BenchOptions {
    /// The oracle on `episodes` in `scene`, in-process, with every default.
    pub fn new(scene: impl Into<String>, episodes: impl Into<PathBuf>) -> Self {
        Self {
            env: EnvOptions::new(scene),
            episodes: episodes.into(),
            episode_indices: None,
            agent: AgentKind::Oracle,
            threads: 1,
            seed: 0,
            record_trajectories: false,
            nav: NavOptions { scans: Some(ScanKind::Lidar), ..Default::default() },
            transport: Transport::InProcess,
            ros_master: None,
            ros_timeout: Duration::from_secs(30),
            external: ExternalSpec::default(),
        }
    }
}

/// Why a benchmark could not run. Messages name the flag or file, as the CLI spells them.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BenchError {
    /// The environment could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The nav parameter files could not be loaded.
    #[error("--nav-params")]
    NavParams(#[source] ParamError),
    /// Options that do not go together or are out of range.
    #[error("{0}")]
    Options(String),
    /// Bad simulator node names (`--ros-arg`).
    #[error("--ros-arg")]
    Names(#[source] NameError),
    /// The run over ROS failed.
    #[error("running the benchmark over ROS")]
    Ros(#[source] RosError),
    /// The external stack's run failed.
    #[error("benchmarking the external ROS stack")]
    External(#[source] RosError),
    /// The run was cancelled (its cancel flag was set).
    #[error("the benchmark was cancelled")]
    Cancelled,
}

/// A finished benchmark: the report `--out` writes, the per-episode outcomes (with
/// trajectories when asked for), and what was loaded for it.
#[derive(Debug)]
pub struct BenchRun {
    /// The report.
    pub report: BenchReport,
    /// One outcome per episode, in file order.
    pub outcomes: Vec<Outcome>,
    /// The world the run used.
    pub world: Arc<World>,
    /// The episodes.
    pub dataset: Dataset,
    /// Which renderer the camera used and why (runs that render).
    pub renderer_note: Option<String>,
    /// Warnings for the user (unknown nav parameters, invalid episodes), in order.
    pub warnings: Vec<String>,
}

/// The navigation parameters of `files` (xhab's defaults without files) and the loader's
/// warnings; each costmap the files leave without a shape takes `robot`'s radius and
/// footprint. The one place every command loads nav parameters.
pub fn nav_params(files: &[ParamFile], robot: Option<&RobotProfile>) -> Result<(NavParams, Vec<String>), ParamError> {
    let mut loaded = load_nav_params(files)?;
    if let Some(r) = robot {
        loaded.size_to_robot(r.radius, r.footprint.as_deref());
    }
    Ok((loaded.params, loaded.warnings))
}

/// Progress of a benchmark: `(episodes finished, episodes in all)`; with `CompareRos` every
/// episode runs twice and counts twice.
pub type BenchProgress<'a> = dyn Fn(usize, usize) + Sync + 'a;

/// Runs the benchmark `o` describes; `progress` is called once per finished episode.
/// Invalid episodes are reported, not errors.
pub fn run_bench(o: &BenchOptions, progress: &BenchProgress<'_>) -> Result<BenchRun, BenchError> {
    run_bench_until(o, &AtomicBool::new(false), progress)
}

/// [`run_bench`] that ends with [`BenchError::Cancelled`] once `cancel` is set (e.g. on
/// Ctrl-C from another thread); in-process runs check it before each episode.
pub fn run_bench_until(o: &BenchOptions, cancel: &AtomicBool, progress: &BenchProgress<'_>) -> Result<BenchRun, BenchError> {
    let mut env = o.env.clone();
    if (o.agent == AgentKind::Nav || o.agent.is_external()) && env.physics.is_none() {
        env.physics = Some(PhysicsOptions::default());
    }
    if o.agent.is_external() && !matches!(o.transport, Transport::InProcess) {
        return Err(BenchError::Options(format!("--agent {} already runs over ROS: drop --ros/--compare-ros/--ros2/--compare-ros2", o.agent.name())));
    }
    let setup = EnvSetup::build(&env)?;
    let mut dataset = setup::read_episodes(&o.episodes)?;
    let selection = select_episodes(&mut dataset, o.episode_indices.as_deref(), &o.episodes)?;
    let total = dataset.episodes.len() * if o.transport.compares() { 2 } else { 1 };
    let finished = AtomicUsize::new(0);
    let tick = || progress(finished.fetch_add(1, Ordering::Relaxed) + 1, total);
    let progress: &(dyn Fn() + Sync) = &tick;
    let mut warnings = Vec::new();
    let robot = setup.physics.as_ref().map(|p| &p.profile);
    let needs_scans = o.agent == AgentKind::Nav || o.agent.is_external();
    let scan = if needs_scans { scan_source(o, &env, &setup)? } else { None };
    let nav = match o.agent {
        AgentKind::Nav => {
            if o.nav.scans.is_none() && o.nav.localization == Localization::Amcl {
                return Err(BenchError::Options("--localization amcl needs laser scans: drop --no-scans".into()));
            }
            let (params, w) = nav_params(&o.nav.params, robot).map_err(BenchError::NavParams)?;
            warnings.extend(w);
            let map = static_map(o)?.map(Arc::new);
            Some(NavSetup { params, map, localization: o.nav.localization, scan: scan.clone(), scan_period: 0.1 })
        }
        AgentKind::Oracle | AgentKind::Ros | AgentKind::Ros2 => None,
    };
    let mut cfg = setup.run_config(o.agent, o.threads, o.seed);
    cfg.record_trajectories = o.record_trajectories;
    cfg.nav = nav;
    cfg.episode_indices = selection;
    let scene = setup.scene.clone();
    let file = o.episodes.display().to_string();
    let world = setup.world.clone();
    let (report, outcomes) = match o.agent {
        AgentKind::Ros => {
            let ext = external_options(o, static_map(o)?, scan)?;
            let t0 = Instant::now();
            let out = run_dataset_external(world.clone(), &dataset, &cfg, &ext, progress).map_err(BenchError::External)?;
            (BenchReport::new(&out, t0.elapsed().as_secs_f64(), &cfg, o.agent.name(), &scene, &file, true), out)
        }
        AgentKind::Ros2 => {
            let ext = external_options(o, static_map(o)?, scan)?;
            let t0 = Instant::now();
            let out = run_ros2_external(world.clone(), &dataset, &cfg, &ext, progress)?;
            (BenchReport::new(&out, t0.elapsed().as_secs_f64(), &cfg, o.agent.name(), &scene, &file, true), out)
        }
        _ => run_transport(o, &world, &dataset, &cfg, &scene, &file, cancel, progress)?,
    };
    for i in &report.invalid.reasons {
        warnings.push(format!("episode {} is invalid and left out: {}", i.episode_id, i.reason));
    }
    Ok(BenchRun { report, outcomes, world, dataset, renderer_note: setup.renderer_note.clone(), warnings })
}

/// `--agent ros2`: the external ROS 2 stack's run, in the DDS domain of the environment
/// (`ROS_DOMAIN_ID`, `ROS_AUTOMATIC_DISCOVERY_RANGE`).
#[cfg(feature = "ros2")]
fn run_ros2_external(world: Arc<World>, ds: &Dataset, cfg: &RunConfig, ext: &ExternalOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, BenchError> {
    let config = crate::ros2::node::Ros2Config::from_env(|k| std::env::var(k).ok()).map_err(BenchError::External)?;
    crate::ros2::external::run_dataset_external(world, ds, cfg, ext, config, progress).map_err(BenchError::External)
}

/// `--agent ros2` without the `ros2` feature: an error saying so.
#[cfg(not(feature = "ros2"))]
fn run_ros2_external(_: Arc<World>, _: &Dataset, _: &RunConfig, _: &ExternalOptions, _: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, BenchError> {
    Err(BenchError::Options("--agent ros2: this build of xhab-bridge has no ROS 2 (feature `ros2`)".into()))
}

/// Keeps the episodes at `indices` (ascending, in range) in `ds`; their indices in the file,
/// for the runner's seeds, or `None` when every episode stays.
fn select_episodes(ds: &mut Dataset, indices: Option<&[usize]>, file: &std::path::Path) -> Result<Option<Arc<[usize]>>, BenchError> {
    let Some(indices) = indices else { return Ok(None) };
    let n = ds.episodes.len();
    if let Some(&bad) = indices.iter().find(|&&i| i >= n) {
        return Err(BenchError::Options(format!("episode index {bad} is out of range: {} has {n} episodes", file.display())));
    }
    if indices.windows(2).any(|w| w[0] >= w[1]) {
        return Err(BenchError::Options("episode indices must be strictly ascending".into()));
    }
    let all = std::mem::take(&mut ds.episodes);
    let mut keep = indices.iter().peekable();
    ds.episodes = all.into_iter().enumerate().filter(|(i, _)| keep.next_if_eq(&i).is_some()).map(|(_, e)| e).collect();
    Ok(Some(indices.into()))
}

/// Runs xhab's own agent in-process, over ROS, or both (and compares them).
#[allow(clippy::too_many_arguments)]
fn run_transport(o: &BenchOptions, world: &Arc<World>, ds: &Dataset, cfg: &RunConfig, scene: &str, file: &str, cancel: &AtomicBool, progress: &(dyn Fn() + Sync)) -> Result<(BenchReport, Vec<Outcome>), BenchError> {
    let name = cfg.agent.name();
    let local = || bench_loaded(world, ds, cfg, scene, file, cancel, progress);
    if matches!(o.transport, Transport::InProcess) {
        return local();
    }
    if matches!(o.transport, Transport::Ros2 | Transport::CompareRos2) {
        return run_over_ros2(o, world, ds, cfg, scene, file, &local, progress);
    }
    // The master is infrastructure, started (when not given) before the run is timed, as the
    // scene is loaded before the in-process run is.
    let master = match &o.ros_master {
        Some(_) => None,
        None => Some(Master::start().map_err(|e| BenchError::Ros(e.into()))?),
    };
    let ros = RosOptions { master: o.ros_master.clone().or_else(|| master.as_ref().map(|m| m.uri.clone())), timeout: o.ros_timeout };
    let remote = || -> Result<(BenchReport, Vec<Outcome>), BenchError> {
        let t0 = Instant::now();
        let out = run_dataset_ros(world.clone(), ds, cfg, &ros, progress).map_err(BenchError::Ros)?;
        Ok((BenchReport::new(&out, t0.elapsed().as_secs_f64(), cfg, name, scene, file, true), out))
    };
    run_compared(o.transport.compares(), &local, &remote)
}

/// A run and its episodes.
type Ran = Result<(BenchReport, Vec<Outcome>), BenchError>;

/// `remote` alone, or (`compare`) `local` then `remote`, the remote report carrying the wall
/// time ratio (`ros_overhead`) and the comparison of every episode (`ros_check`).
fn run_compared(compare: bool, local: &dyn Fn() -> Ran, remote: &dyn Fn() -> Ran) -> Ran {
    if !compare {
        return remote();
    }
    let (l, l_out) = local()?;
    let (mut r, r_out) = remote()?;
    r.aggregate.ros_overhead = Some(r.aggregate.wall_s / l.aggregate.wall_s.max(1e-9));
    r.ros_check = Some(compare_outcomes(&l_out, &r_out));
    Ok((r, r_out))
}

/// Runs xhab's own agent over ROS 2, or in-process and over ROS 2 (and compares them).
#[allow(clippy::too_many_arguments)]
fn run_over_ros2(o: &BenchOptions, world: &Arc<World>, ds: &Dataset, cfg: &RunConfig, scene: &str, file: &str, local: &dyn Fn() -> Result<(BenchReport, Vec<Outcome>), BenchError>, progress: &(dyn Fn() + Sync)) -> Result<(BenchReport, Vec<Outcome>), BenchError> {
    #[cfg(feature = "ros2")]
    {
        use crate::ros2::bench::{run_dataset_ros2, Ros2BenchOptions};
        use crate::ros2::node::Ros2Config;
        let config = Ros2Config::from_env(|k| std::env::var(k).ok()).map_err(BenchError::Ros)?;
        let opts = Ros2BenchOptions { config, timeout: o.ros_timeout };
        let remote = || -> Result<(BenchReport, Vec<Outcome>), BenchError> {
            let t0 = Instant::now();
            let out = run_dataset_ros2(world.clone(), ds, cfg, &opts, progress).map_err(BenchError::Ros)?;
            Ok((BenchReport::new(&out, t0.elapsed().as_secs_f64(), cfg, cfg.agent.name(), scene, file, true), out))
        };
        run_compared(o.transport.compares(), local, &remote)
    }
    #[cfg(not(feature = "ros2"))]
    {
        let _ = (o, world, ds, cfg, scene, file, local, progress);
        Err(BenchError::Options("--ros2/--compare-ros2: this xhab was built without ROS 2 (feature `ros2` of xhab-bridge)".into()))
    }
}

/// Runs `cfg`'s agent in this process on every episode of `ds` in the loaded `world` and
/// builds the report (`scene` and `episodes_file` name them in it); `progress` is called once
/// per finished episode. Ends with [`BenchError::Cancelled`] once `cancel` is set.
pub fn bench_loaded(world: &World, ds: &Dataset, cfg: &RunConfig, scene: &str, episodes_file: &str, cancel: &AtomicBool, progress: &(dyn Fn() + Sync)) -> Result<(BenchReport, Vec<Outcome>), BenchError> {
    let t0 = Instant::now();
    let out = run_dataset_until(world, ds, cfg, cancel, progress).map_err(|_| BenchError::Cancelled)?;
    Ok((BenchReport::new(&out, t0.elapsed().as_secs_f64(), cfg, cfg.agent.name(), scene, episodes_file, false), out))
}

/// The static map of `--map`, if given.
fn static_map(o: &BenchOptions) -> Result<Option<OccupancyGrid>, BenchError> {
    match &o.nav.map {
        Some(m) => Ok(Some(setup::load_static_map(m)?)),
        None => Ok(None),
    }
}

/// The laser scans of `o.nav.scans`: the robot's lidar at its mount, or the depth camera
/// through depthimage_to_laserscan (sharing the observation camera's renderer when there is one).
fn scan_source(o: &BenchOptions, env: &EnvOptions, s: &EnvSetup) -> Result<Option<ScanSource>, BenchError> {
    let robot = s.physics.as_ref().map(|p| &p.profile);
    Ok(match o.nav.scans {
        None => None,
        Some(ScanKind::Lidar) => {
            let rs = setup::ray_scene(&s.world.scene)?;
            let lidar = robot.map_or_else(Default::default, |r| r.laser.lidar());
            Some(ScanSource::lidar(Arc::new(rs), lidar))
        }
        Some(ScanKind::Depth) => {
            let renderer: Arc<Renderer> = match &s.sensors {
                Some(rig) => rig.renderer.clone(),
                None => Arc::new(setup::build_renderer(env.camera.renderer, &s.world.scene)?.0),
            };
            let height = robot.map_or(xhab_sim::sensors::CameraParams::default().mount_height, |r| r.camera_height);
            let params = setup::camera_params(&env.camera, height)?;
            let noise = setup::depth_noise(env.depth_noise, env.edge_dropout)?;
            Some(ScanSource::Depth { rig: Arc::new(CameraRig { renderer, params, rgb: false, noise }), params: DepthToScanParams::default() })
        }
    })
}

/// How `--agent ros`/`ros2` drives the stack under test, checked.
fn external_options(o: &BenchOptions, map: Option<OccupancyGrid>, scan: Option<ScanSource>) -> Result<ExternalOptions, BenchError> {
    let e = &o.external;
    let positive = |x: f64| x > 0.0 && x.is_finite();
    if !positive(e.episode_timeout) || !positive(e.rate) || !positive(e.controller_frequency) || !(e.cmd_vel_grace >= 0.0 && e.cmd_vel_grace.is_finite()) {
        return Err(BenchError::Options("--episode-timeout, --rate and --controller-frequency must be > 0 and --cmd-vel-grace >= 0".into()));
    }
    let pace = if e.realtime { Pace::Realtime { rate: e.rate } } else { Pace::Lockstep { grace: Duration::from_secs_f64(e.cmd_vel_grace) } };
    let env_var = |k: &str| std::env::var(k).ok().filter(|s| !s.is_empty());
    Ok(ExternalOptions {
        master: e.master.clone().or_else(|| env_var("ROS_MASTER_URI")),
        timeout: o.ros_timeout,
        names: external_names(o.agent, &e.ros_args, env_var("ROS_NAMESPACE").as_deref()).map_err(BenchError::Names)?,
        goal_interface: e.goal_interface,
        episode_timeout: e.episode_timeout,
        map_odom: e.map_odom,
        pace,
        controller_frequency: e.controller_frequency,
        map,
        launch: e.launch.clone(),
        scan,
        scan_period: 0.1,
    })
}

/// The simulator node's names: ROS 1's `from:=to` arguments, or (`--agent ros2`) ROS 2's
/// `--ros-args -r from:=to ...`.
fn external_names(agent: AgentKind, args: &[String], ns: Option<&str>) -> Result<Names, NameError> {
    #[cfg(feature = "ros2")]
    if agent == AgentKind::Ros2 {
        return crate::ros2::node::names_from_ros_args("xhab_sim", args, ns);
    }
    let _ = agent;
    Names::from_args("xhab_sim", args, ns)
}

/// How a run over ROS compares with the same run in-process.
pub fn compare_outcomes(a: &[Outcome], b: &[Outcome]) -> RosCheck {
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
                if m.steps != n.steps || m.collisions != n.collisions || m.called_stop != n.called_stop || x.abort_reason != y.abort_reason {
                    other_steps += 1;
                }
            }
            (Outcome::Invalid(_), Outcome::Invalid(_)) => {}
            _ => same_set = false,
        }
    }
    RosCheck { identical: same_set && other_steps == 0 && max_diff <= 1e-9, max_metric_diff: max_diff, episodes_with_other_steps: other_steps }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn procedural_episodes(dir: &std::path::Path) -> PathBuf {
        let w = setup::load_world("procedural:3", &Default::default()).unwrap();
        let ds = setup::generate(&w, "procedural:3", "auto", 4, 1, "procedural:3").unwrap();
        std::fs::create_dir_all(dir).unwrap();
        let p = dir.join("eps.json.gz");
        xhab_sim::episode::write_dataset(&ds, &p).unwrap();
        p
    }

    #[test]
    fn oracle_and_nav_run_through_one_entry_point() {
        let dir = std::env::temp_dir().join(format!("xhab-benchmark-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let eps = procedural_episodes(&dir);
        let mut o = BenchOptions::new("procedural:3", &eps);
        let oracle = run_bench(&o, &|_, _| {}).unwrap();
        assert_eq!(oracle.report.agent, "oracle");
        assert_eq!(oracle.report.aggregate.episodes, 4);
        assert!(oracle.report.aggregate.success > 0.99, "{:?}", oracle.report.aggregate);
        assert!(oracle.report.physics.is_none());
        // The nav agent runs under physics even when none was asked for.
        o.agent = AgentKind::Nav;
        o.threads = 2;
        let nav = run_bench(&o, &|_, _| {}).unwrap();
        assert!(nav.report.physics.is_some() && nav.report.nav.is_some());
        assert_eq!(nav.report.aggregate.episodes, 4);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn bad_options_are_errors_naming_the_flag() {
        let mut o = BenchOptions::new("procedural:3", "/nonexistent/eps.json.gz");
        let e = run_bench(&o, &|_, _| {}).unwrap_err().to_string();
        assert!(e.contains("/nonexistent/eps.json.gz"), "{e}");
        o.agent = AgentKind::Ros;
        o.transport = Transport::Ros;
        assert!(run_bench(&o, &|_, _| {}).unwrap_err().to_string().contains("drop --ros"));
        o.transport = Transport::InProcess;
        o.agent = AgentKind::Nav;
        o.nav.scans = None;
        o.nav.localization = Localization::Amcl;
        o.episodes = procedural_episodes(&std::env::temp_dir().join(format!("xhab-benchmark-bad-{}", std::process::id())));
        assert!(run_bench(&o, &|_, _| {}).unwrap_err().to_string().contains("needs laser scans"));
    }
}
