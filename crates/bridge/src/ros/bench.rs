//! The benchmark over ROS: the simulator and the agent as separate nodes talking through a real
//! rosmaster, in lock-step, so that every step and metric equals the in-process run.

use super::master::Master;
use super::node::RosError;
use super::sim_node::{Command, RobotState, SimNode};
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
    let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().map_err(|e| RosError::Node(format!("tokio runtime: {e}")))?;
    rt.block_on(run_all(&master.uri, world, ds, cfg, opts, progress))
}

async fn run_all(uri: &str, world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &RosOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    let (stop_tx, stop_rx) = tokio::sync::watch::channel(false);
    let (stats_tx, mut stats_rx) = tokio::sync::mpsc::unbounded_channel();
    let agent = match (cfg.agent, &cfg.nav) {
        (AgentKind::Nav, Some(setup)) => {
            let o = super::nav_node::NavNodeOptions { setup: setup.clone(), lockstep: true, expect_scans: setup.scan.is_some(), expect_amcl_map: setup.scan_plane_localization(), seed: cfg.seed, timeout: opts.timeout };
            let uri = uri.to_string();
            tokio::spawn(async move { super::nav_node::run(&uri, "xhab_nav", o, None, None, stop_rx, Some(stats_tx)).await })
        }
        (AgentKind::Nav, None) => return Err(RosError::Protocol("the nav agent needs its navigation setup".into())),
        (kind, _) => {
            let (uri, world, task, timeout) = (uri.to_string(), world.clone(), cfg.task.clone(), opts.timeout);
            tokio::spawn(async move { super::agent_node::run(&uri, "xhab_agent", world, kind, task, timeout, stop_rx).await })
        }
    };
    let mut sim = SimNode::new(uri, "xhab_sim", opts.timeout).await?;
    // Probes go first on the topics whose connection the trigger's answer must prove.
    match (cfg.agent, &cfg.nav) {
        (AgentKind::Nav, Some(nav)) => {
            let mut topics = vec!["move_base_simple/goal", "initialpose", "map", "ground_truth/pose"];
            if nav.scan_plane_localization() {
                topics.push(super::sim_node::AMCL_MAP_TOPIC);
            }
            if nav.scan.is_some() {
                topics.push("scan");
            }
            topics.push("odom");
            sim.handshake(&topics, true).await?
        }
        _ => sim.handshake(&["move_base_simple/goal", "ground_truth/pose"], false).await?,
    }
    let mut clock_ns: i64 = 0;
    let mut outcomes = Vec::with_capacity(ds.episodes.len());
    let mut ran = Vec::new();
    for (i, ep) in ds.episodes.iter().enumerate() {
        let t0 = Instant::now();
        let o = match make_env(&world, ep, i, cfg) {
            Err(reason) => Outcome::Invalid(InvalidRun { episode_id: ep.episode_id.clone(), reason }),
            Ok((made, grid)) => {
                let r = episode(&mut sim, made, &grid, &world.scene, ep, i, cfg, &mut clock_ns).await;
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
    Ok(outcomes)
}

/// Runs one episode through the simulator node; the agent node answers each step.
async fn episode(sim: &mut SimNode, mut made: MadeEnv, grid: &Arc<xhab_sim::navgrid::NavGrid>, world_scene: &xhab_sim::scene::Scene, ep: &xhab_sim::episode::Episode, index: usize, cfg: &RunConfig, clock_ns: &mut i64) -> Result<EpisodeRun, RosError> {
    let start_z = ep.start_position.z;
    let goal = ep.goals[0].position.xy();
    let goal_pose = Pose2::new(goal.x, goal.y, 0.0);
    let base_ns = *clock_ns;
    let stamp = |t: f64| (base_ns + (t * 1e9).round() as i64) as f64 / 1e9;
    let mut traj = cfg.record_trajectories.then(|| vec![made.as_dyn().pose()]);
    let mut aborted = false;
    let mut end_t = 0.0;
    let mut stats = crate::runner::RenderStats::default();
    // The step's camera frame (`--sensors`), rendered and published before the step's state;
    // it evaluates to the frame and its camera (for a depth scan source to flatten).
    macro_rules! camera {
        ($seq:expr, $stamp:expr, $pose:expr) => {
            match cfg.sensors.as_deref() {
                Some(rig) => {
                    let f = crate::runner::capture(rig, $pose, grid.floor_z, cfg.seed, index, $seq as u64, &mut stats).map_err(RosError::Node)?;
                    sim.publish_frame($seq, $stamp, &rig.params, &f).await?;
                    Some((rig, f))
                }
                None => None,
            }
        };
    }
    match (&mut made, cfg.agent, &cfg.nav) {
        (MadeEnv::Physics(env), AgentKind::Nav, Some(setup)) => {
            let setup: &NavSetup = setup;
            let map = setup.map.as_deref().cloned().unwrap_or_else(|| grid.occupancy_grid());
            sim.publish_map(stamp(0.0), &map).await?;
            if let Some(m) = crate::nav_agent::localization_map(setup, grid, world_scene) {
                sim.publish_amcl_map(stamp(0.0), &m).await?;
            }
            sim.publish_goal(index as u32, stamp(0.0), goal_pose, start_z).await?;
            sim.publish_initialpose(index as u32, stamp(0.0), env.odometry(), crate::nav_agent::INITIAL_STD_XY, crate::nav_agent::INITIAL_STD_YAW).await?;
            let period = setup.params.dwa.controller_period.max(1e-3);
            let mut sensor = setup.scan.as_ref().map(|s| s.sensor(cfg.seed));
            let laser_z = setup.scan.as_ref().map_or(0.0, |s| s.height());
            // The same schedule as the navigator's (a scan every scan_period from 0).
            let mut sched = ScanSchedule::new(setup.scan_period);
            let mut seq = 0u32;
            while !env.is_done() {
                let t = episode_time(env.sim_s());
                // The step's camera frame first: a depth scan source flattens it, as in-process.
                let frame = camera!(seq, stamp(t), env.pose());
                let scan = match sensor.as_mut() {
                    Some(s) if sched.due(t) => {
                        sched.taken += 1;
                        let seen = frame.as_ref().map(|(r, f)| (*r, f));
                        Some(s.scan_seen(env.pose(), grid.floor_z, seen).map_err(|e| RosError::Node(format!("scan at {t:.2} s: {e}")))?)
                    }
                    _ => None,
                };
                let st = RobotState { seq, stamp: stamp(t), truth: env.pose(), floor_z: start_z, odom: env.odometry(), twist: env.robot().twist(), scan: scan.as_ref().map(|s| (s, setup.scan_period, laser_z)) };
                sim.publish_state(&st).await?;
                match sim.next_command().await? {
                    Command::Twist(tw) => env.drive(tw, period),
                    Command::Action(0) => env.call_stop(),
                    Command::Action(-1) => {
                        aborted = true;
                        break;
                    }
                    Command::Action(a) => return Err(RosError::Protocol(format!("action {a} from the nav node (0 = stop, -1 = give up)"))),
                }
                seq += 1;
                if let Some(tr) = traj.as_mut() {
                    tr.push(env.pose());
                }
            }
            end_t = env.sim_s();
        }
        (made, _, _) => {
            let env = made.as_dyn();
            sim.publish_goal(index as u32, stamp(0.0), goal_pose, start_z).await?;
            let mut seq = 0u32;
            while !env.is_done() {
                // Discrete steps are one control period apart on the clock.
                let t = seq as f64;
                let p = env.pose();
                camera!(seq, stamp(t), p);
                let st = RobotState { seq, stamp: stamp(t), truth: p, floor_z: start_z, odom: p, twist: Default::default(), scan: None };
                sim.publish_state(&st).await?;
                match sim.next_command().await? {
                    Command::Action(a) => match Action::from_index(a as i64) {
                        Some(a) => {
                            env.step(a);
                        }
                        None => return Err(RosError::Protocol(format!("action {a} is not one of Habitat's 0..=3"))),
                    },
                    Command::Twist(_) => return Err(RosError::Protocol("discrete run: got cmd_vel where an action was expected".into())),
                }
                seq += 1;
                if let Some(tr) = traj.as_mut() {
                    tr.push(env.pose());
                }
                end_t = seq as f64;
            }
        }
    }
    // The next episode's clock starts a second after this one ended.
    *clock_ns = base_ns + (end_t * 1e9).round() as i64 + 1_000_000_000;
    let (sim_s, stuck) = match &made {
        MadeEnv::Physics(p) => (Some(p.sim_s()), Some(p.stuck() || aborted)),
        MadeEnv::Plain(_) => (None, None),
    };
    Ok(EpisodeRun { episode_id: ep.episode_id.clone(), metrics: made.as_dyn().metrics(), wall_s: 0.0, trajectory: traj, sim_s, stuck, localization_error: None, render: cfg.sensors.is_some().then_some((stats.frames, stats.seconds)) })
}
