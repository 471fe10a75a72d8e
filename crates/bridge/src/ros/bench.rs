//! The benchmark over ROS: the simulator and the agent as separate nodes talking through a real
//! rosmaster, in lock-step, so that every step and metric equals the in-process run.

use super::convert as cv;
use super::master::Master;
use super::msgs::{geometry_msgs as gm, xhab_msgs};
use super::names::Names;
use super::node::RosError;
use super::sim_node::{Mounts, RobotState, SimNode};
use crate::agents::AgentKind;
use crate::nav_agent::{episode_time, NavSetup, ScanSchedule};
use crate::runner::{make_env, EpisodeRun, InvalidRun, MadeEnv, Outcome, RunConfig};
use std::sync::Arc;
use std::time::{Duration, Instant};
use xhab_sim::action::Action;
use xhab_sim::env::{DiscreteEnv, EnvView};
use xhab_sim::episode::Dataset;
use xhab_sim::world::World;
use xhab_types::Pose2;

/// Where the ROS run finds its master, and how patient it is.
#[derive(Debug, Clone)]
pub struct RosOptions {
    /// `http://host:port` of a running master; `None` starts `rosmaster` for the run.
    pub master: Option<String>,
    /// How long to wait for a peer before failing (s).
    pub timeout: Duration,
}

impl Default for RosOptions {
    fn default() -> Self {
        Self { master: None, timeout: Duration::from_secs(30) }
    }
}

/// Runs every episode of `ds` over ROS, one at a time (lock-step is sequential by nature).
/// `progress` is called once per finished episode.
pub fn run_dataset_ros(world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &RosOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    let master = Master::connect_or_start(opts.master.as_deref())?;
    // One thread for both nodes: lock-step hands the turn back and forth, and a wake-up on the
    // same thread costs a fraction of one across threads.
    let rt = tokio::runtime::Builder::new_current_thread().enable_all().build().map_err(|e| RosError::Node(format!("tokio runtime: {e}")))?;
    rt.block_on(run_all(&master.uri, world, ds, cfg, opts, progress))
}

async fn run_all(uri: &str, world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &RosOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    let (stop_tx, stop_rx) = tokio::sync::watch::channel(false);
    let (stats_tx, mut stats_rx) = tokio::sync::mpsc::unbounded_channel();
    let agent = match (cfg.agent, &cfg.nav) {
        (AgentKind::Nav, Some(setup)) => {
            let o = super::nav_node::NavNodeOptions { setup: setup.scored(cfg.task.success_distance), lockstep: true, seed: cfg.seed, timeout: opts.timeout };
            let uri = uri.to_string();
            tokio::spawn(async move { super::nav_node::run(&uri, Names::plain("xhab_nav"), o, None, None, stop_rx, Some(stats_tx)).await })
        }
        (AgentKind::Nav, None) => return Err(RosError::Protocol("the nav agent needs its navigation setup".into())),
        (kind, _) => {
            let (uri, world, task, timeout) = (uri.to_string(), world.clone(), cfg.task.clone(), opts.timeout);
            tokio::spawn(async move { super::agent_node::run(&uri, Names::plain("xhab_agent"), world, kind, task, timeout, true, stop_rx).await })
        }
    };
    let t_start = Instant::now();
    // The first episode's environment (its geodesic field) is built on another thread while
    // the nodes register and connect, which is mostly waiting on the master.
    let mut first = ds.episodes.first().map(|ep| {
        let (w, ep, c) = (world.clone(), ep.clone(), cfg.clone());
        tokio::task::spawn_blocking(move || make_env(&w, &ep, c.episode_index(0), &c))
    });
    let mounts = mounts(cfg);
    let mut sim = SimNode::new(uri, Names::plain("xhab_sim"), &mounts.laser_frame, opts.timeout).await?;
    sim.publish_static_tf(&mounts).await?;
    tracing::debug!("ros bench: nodes up in {:.3} s", t_start.elapsed().as_secs_f64());
    // ROS time 0 means "no time yet" (and a zero stamp "none" in xhab_msgs): start at 1 s.
    let mut clock_ns: i64 = 1_000_000_000;
    let mut outcomes = Vec::with_capacity(ds.episodes.len());
    let mut ran = Vec::new();
    for (i, ep) in ds.episodes.iter().enumerate() {
        let t0 = Instant::now();
        let made = match first.take() {
            Some(h) => h.await.map_err(|e| RosError::Node(format!("building the first episode: {e}")))?,
            None => make_env(&world, ep, cfg.episode_index(i), cfg),
        };
        // The agent's side of the ROS interface knows one storey's grid: an episode across
        // storeys is refused, not run wrong.
        let made = match crate::runner::across_storeys(ep, "ROS") {
            Some(reason) => Err(reason),
            None => made,
        };
        let o = match made {
            Err(reason) => Outcome::Invalid(InvalidRun { episode_id: ep.episode_id.clone(), reason }),
            Ok((made, grid)) => {
                let r = episode(&mut sim, made, &grid, &world.scene, ep, cfg.episode_index(i), cfg, &mut clock_ns).await;
                match r {
                    Ok(mut run) => {
                        run.wall_s = t0.elapsed().as_secs_f64();
                        ran.push(outcomes.len());
                        Outcome::Ran(run)
                    }
                    Err(e) => {
                        let _ = stop_tx.send(true);
                        // The agent's own failure, if it had one, is the cause.
                        if let Ok(Ok(Err(a))) = tokio::time::timeout(Duration::from_secs(2), agent).await {
                            return Err(RosError::Protocol(format!("the agent node failed: {a} (the simulator then reported: {e})")));
                        }
                        return Err(e);
                    }
                }
            }
        };
        outcomes.push(o);
        progress();
    }
    tracing::debug!("ros bench: episodes done at {:.3} s", t_start.elapsed().as_secs_f64());
    let _ = stop_tx.send(true);
    match agent.await {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(e),
        Err(e) => return Err(RosError::Node(format!("agent node task: {e}"))),
    }
    if cfg.agent == AgentKind::Nav {
        for &k in &ran {
            if let (Some(stat), Outcome::Ran(r)) = (stats_rx.recv().await, &mut outcomes[k]) {
                r.localization_error = stat;
            }
        }
    }
    tracing::debug!("ros bench: agent stopped at {:.3} s", t_start.elapsed().as_secs_f64());
    Ok(outcomes)
}

/// The sensor mounts of the run's robot (the laser of the nav setup's scan source, the
/// camera of `--sensors`).
pub(crate) fn mounts(cfg: &RunConfig) -> Mounts {
    let mut m = Mounts::default();
    if let Some(ph) = &cfg.physics {
        m.laser_frame = ph.profile.laser.frame.clone();
        m.camera_z = ph.profile.camera_height;
    }
    if let Some(src) = cfg.nav.as_ref().and_then(|n| n.scan.as_ref()) {
        m.laser = src.mount();
        m.laser_z = src.height();
    }
    if let Some(rig) = cfg.sensors.as_deref() {
        m.camera_z = rig.params.mount_height;
    }
    m
}

/// The announcement of episode `index` starting at `start` (s).
fn announcement(index: usize, ep: &xhab_sim::episode::Episode, start: f64, goal: Pose2, init: Pose2, map_stamp: Option<f64>, amcl_map_stamp: Option<f64>) -> xhab_msgs::Episode {
    let zero = cv::time(0.0);
    xhab_msgs::Episode {
        index: index as u32,
        episode_id: ep.episode_id.clone(),
        start: cv::time(start),
        goal: gm::PoseStamped { header: cv::header(start, "map"), pose: cv::pose(goal, ep.goals[0].position.z) },
        initial_pose: cv::pose_with_covariance(start, init, crate::nav_agent::INITIAL_STD_XY, crate::nav_agent::INITIAL_STD_YAW),
        map_stamp: map_stamp.map_or(zero.clone(), cv::time),
        amcl_map_stamp: amcl_map_stamp.map_or(zero, cv::time),
    }
}

/// Runs one episode through the simulator node; the agent node answers each step.
#[allow(clippy::too_many_arguments)]
async fn episode(sim: &mut SimNode, mut made: MadeEnv, grid: &Arc<xhab_sim::navgrid::NavGrid>, world_scene: &xhab_sim::scene::Scene, ep: &xhab_sim::episode::Episode, index: usize, cfg: &RunConfig, clock_ns: &mut i64) -> Result<EpisodeRun, RosError> {
    let start_z = ep.start_position.z;
    let goal = ep.goals[0].position.xy();
    let goal_pose = Pose2::new(goal.x, goal.y, 0.0);
    let base_ns = *clock_ns;
    let stamp = |t: f64| (base_ns + (t * 1e9).round() as i64) as f64 / 1e9;
    let mut traj = cfg.record_trajectories.then(|| vec![made.as_dyn().pose()]);
    let mut aborted: Option<String> = None;
    let mut end_t = 0.0;
    let mut stats = crate::runner::RenderStats::default();
    let ep_index = index as u32;
    if index > 0 {
        // Again each episode: a subscriber (rosbag record) whose connection was being accepted
        // as the run's first came would have missed it (roslibrust's latching).
        sim.publish_static_tf(&mounts(cfg)).await?;
    }
    // The step's camera frame (`--sensors`), rendered before the step's state is published;
    // it evaluates to the frame and its camera (for a depth scan source to flatten).
    macro_rules! camera {
        ($n:expr, $pose:expr) => {
            match cfg.sensors.as_deref() {
                Some(rig) => Some((rig, crate::runner::capture(rig, $pose, grid.floor_z, cfg.seed, index, $n as u64, &mut stats).map_err(RosError::Node)?)),
                None => None,
            }
        };
    }
    match (&mut made, cfg.agent, &cfg.nav) {
        (MadeEnv::Physics(env), AgentKind::Nav, Some(setup)) => {
            let setup: &NavSetup = setup;
            let map = setup.map.as_deref().cloned().unwrap_or_else(|| grid.occupancy_grid());
            sim.publish_map(stamp(0.0), &map).await?;
            let amcl_map = crate::nav_agent::localization_map(setup, grid, world_scene);
            if let Some(m) = &amcl_map {
                sim.publish_amcl_map(stamp(0.0), m).await?;
            }
            sim.publish_episode(&announcement(index, ep, stamp(0.0), goal_pose, env.odometry(), Some(stamp(0.0)), amcl_map.as_ref().map(|_| stamp(0.0)))).await?;
            let period = setup.params.dwa.controller_period.max(1e-3);
            let mut sensor = setup.scan.as_ref().map(|s| s.sensor(cfg.seed));
            // The same schedule as the navigator's (a scan every scan_period from 0).
            let mut sched = ScanSchedule::new(setup.scan_period);
            let mut step = 0u32;
            while !env.is_done() {
                let t = episode_time(env.sim_s());
                // The step's camera frame first: a depth scan source flattens it, as in-process.
                let frame = camera!(step, env.pose());
                let scan = sched.take(sensor.as_mut(), t, env.pose(), grid.floor_z, frame.as_ref().map(|(r, f)| (*r, f))).map_err(RosError::Node)?;
                let st = RobotState { stamp: stamp(t), truth: env.pose(), floor_z: start_z, odom: env.odometry(), twist: env.robot().twist(), scan: scan.as_ref().map(|s| (s, setup.scan_period)), map_to_odom: None };
                let r = sim.lockstep(&st, frame.as_ref().map(|(r, f)| (&r.params, f)), ep_index, step).await?;
                match r.kind {
                    xhab_msgs::StepReply::DRIVE => env.drive(cv::twist2(&r.twist), period),
                    xhab_msgs::StepReply::STOP => env.call_stop(),
                    xhab_msgs::StepReply::ABORT => {
                        // The nav node says why; an agent that does not is `unknown`.
                        aborted = Some(if r.abort_reason.is_empty() { "unknown".to_string() } else { r.abort_reason.clone() });
                        break;
                    }
                    k => return Err(RosError::Protocol(format!("step reply kind {k} from the nav node (DRIVE, STOP or ABORT expected)"))),
                }
                step += 1;
                if let Some(tr) = traj.as_mut() {
                    tr.push(env.pose());
                }
            }
            end_t = env.sim_s();
        }
        (made, _, _) => {
            let env = made.as_dyn();
            let start = env.pose();
            sim.publish_episode(&announcement(index, ep, stamp(0.0), goal_pose, start, None, None)).await?;
            let mut step = 0u32;
            while !env.is_done() {
                // Discrete steps are one second apart on the clock.
                let t = step as f64;
                let p = env.pose();
                let frame = camera!(step, p);
                let st = RobotState { stamp: stamp(t), truth: p, floor_z: start_z, odom: p, twist: Default::default(), scan: None, map_to_odom: None };
                let r = sim.lockstep(&st, frame.as_ref().map(|(r, f)| (&r.params, f)), ep_index, step).await?;
                match (r.kind, Action::from_index(r.action as i64)) {
                    (xhab_msgs::StepReply::ACTION, Some(a)) => {
                        env.step(a);
                    }
                    (xhab_msgs::StepReply::ACTION, None) => return Err(RosError::Protocol(format!("action {} is not one of Habitat's 0..=3", r.action))),
                    (k, _) => return Err(RosError::Protocol(format!("step reply kind {k} where an action was expected (discrete run)"))),
                }
                step += 1;
                if let Some(tr) = traj.as_mut() {
                    tr.push(env.pose());
                }
                end_t = step as f64;
            }
        }
    }
    // The next episode's clock starts a second after this one ended.
    *clock_ns = base_ns + (end_t * 1e9).round() as i64 + 1_000_000_000;
    let (sim_s, stuck, stuck_cause) = match &made {
        MadeEnv::Physics(p) => (Some(p.sim_s()), Some(p.stuck()), p.stuck_cause().map(str::to_string)),
        MadeEnv::Plain(_) => (None, None, None),
    };
    Ok(EpisodeRun { episode_id: ep.episode_id.clone(), metrics: made.as_dyn().metrics(), wall_s: 0.0, trajectory: traj, sim_s, stuck, stuck_cause, abort_reason: aborted, final_localization: None, localization_error: None, render: cfg.sensors.is_some().then_some((stats.frames, stats.seconds)), ros: None })
}
