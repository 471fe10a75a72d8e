//! A benchmark's episodes in lock-step through a simulator node, written once against
//! [`LockstepTransport`] (ROS 1's `bench --ros`, ROS 2's `bench --ros2`): per episode the
//! maps and the announcement, then per step the state and the agent's answer, so that every
//! step and metric equals the in-process run.

use super::lockstep::{EpisodeStart, LockstepTransport, StepAnswer};
use super::state::{Mounts, RobotState};
use crate::agents::AgentKind;
use crate::nav_agent::{episode_time, NavSetup, ScanSchedule};
use crate::ros::node::RosError;
use crate::runner::{make_env, EpisodeRun, InvalidRun, EpisodeEnv, Outcome, RunConfig};
use std::sync::Arc;
use std::time::Instant;
use xhab_sim::action::Action;
use xhab_sim::env::{DiscreteEnv, EnvView};
use xhab_sim::episode::{Dataset, Episode};
use xhab_sim::navgrid::NavGrid;
use xhab_sim::world::World;
use xhab_types::Pose2;

/// An episode's environment as [`make_env`] builds it (or why it cannot run).
pub(crate) type Made = Result<(EpisodeEnv, Arc<NavGrid>), String>;

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

/// Runs every episode of `ds` through `sim`, one at a time; `first` is the first episode's
/// environment when it was built beforehand (while the nodes connected). `transport` names
/// the transport in the reason an episode across storeys is refused ("ROS", "ROS 2").
/// Returns the outcomes in file order and the positions of those that ran; the first error
/// ends the run. `progress` is called once per finished episode.
pub(crate) async fn run_lockstep_dataset<T: LockstepTransport>(sim: &mut T, world: &Arc<World>, ds: &Dataset, cfg: &RunConfig, first: Option<tokio::task::JoinHandle<Made>>, transport: &str, progress: &(dyn Fn() + Sync)) -> Result<(Vec<Outcome>, Vec<usize>), RosError> {
    sim.publish_static_tf(&mounts(cfg)).await?;
    let mut first = first;
    // ROS time 0 means "no time yet" (and a zero stamp "none" in xhab_msgs): start at 1 s.
    let mut clock_ns: i64 = 1_000_000_000;
    let mut outcomes = Vec::with_capacity(ds.episodes.len());
    let mut ran = Vec::new();
    for (i, ep) in ds.episodes.iter().enumerate() {
        let t0 = Instant::now();
        let made = match first.take() {
            Some(h) => h.await.map_err(|e| RosError::Node(format!("building the first episode: {e}")))?,
            None => make_env(world, ep, cfg.episode_index(i), cfg),
        };
        // The agent's side of the ROS interface knows one storey's grid: an episode across
        // storeys is refused, not run wrong.
        let made = match crate::runner::across_storeys(ep, transport) {
            Some(reason) => Err(reason),
            None => made,
        };
        let o = match made {
            Err(reason) => Outcome::Invalid(InvalidRun { episode_id: ep.episode_id.clone(), reason }),
            Ok((made, grid)) => {
                let mut run = run_episode(sim, made, &grid, &world.scene, ep, cfg.episode_index(i), cfg, &mut clock_ns).await?;
                run.wall_s = t0.elapsed().as_secs_f64();
                ran.push(outcomes.len());
                Outcome::Ran(run)
            }
        };
        outcomes.push(o);
        progress();
    }
    Ok((outcomes, ran))
}

/// Runs one episode through the simulator node; the agent node answers each step.
#[allow(clippy::too_many_arguments)]
async fn run_episode<T: LockstepTransport>(sim: &mut T, mut made: EpisodeEnv, grid: &Arc<NavGrid>, world_scene: &xhab_sim::scene::Scene, ep: &Episode, index: usize, cfg: &RunConfig, clock_ns: &mut i64) -> Result<EpisodeRun, RosError> {
    let start_z = ep.start_position.z;
    let goal = ep.goals[0].position.xy();
    let goal_pose = Pose2::new(goal.x, goal.y, 0.0);
    let goal_z = ep.goals[0].position.z;
    let base_ns = *clock_ns;
    let stamp = |t: f64| (base_ns + (t * 1e9).round() as i64) as f64 / 1e9;
    let announce = |init: Pose2, map_stamp: Option<f64>, amcl_map_stamp: Option<f64>| EpisodeStart {
        index: index as u32,
        episode_id: ep.episode_id.clone(),
        start: stamp(0.0),
        goal: goal_pose,
        goal_z,
        initial_pose: init,
        initial_std: (crate::nav_agent::INITIAL_STD_XY, crate::nav_agent::INITIAL_STD_YAW),
        map_stamp,
        amcl_map_stamp,
    };
    let mut traj = cfg.record_trajectories.then(|| vec![made.as_dyn().pose()]);
    let mut aborted: Option<String> = None;
    let mut end_t = 0.0;
    let mut stats = crate::camera_capture::RenderStats::default();
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
                Some(rig) => Some((rig, crate::camera_capture::capture(rig, $pose, grid.floor_z, cfg.seed, index, $n as u64, &mut stats).map_err(RosError::Node)?)),
                None => None,
            }
        };
    }
    match (&mut made, cfg.agent, &cfg.nav) {
        (EpisodeEnv::Physics(env), AgentKind::Nav, Some(setup)) => {
            let setup: &NavSetup = setup;
            let map = setup.map.as_deref().cloned().unwrap_or_else(|| grid.occupancy_grid());
            sim.publish_map(stamp(0.0), &map).await?;
            let amcl_map = crate::nav_agent::localization_map(setup, grid, world_scene);
            if let Some(m) = &amcl_map {
                sim.publish_amcl_map(stamp(0.0), m).await?;
            }
            sim.publish_episode(&announce(env.odometry(), Some(stamp(0.0)), amcl_map.as_ref().map(|_| stamp(0.0)))).await?;
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
                match sim.lockstep(&st, frame.as_ref().map(|(r, f)| (&r.params, f)), ep_index, step).await? {
                    StepAnswer::Drive(tw) => env.drive(tw, period),
                    StepAnswer::Stop => env.call_stop(),
                    StepAnswer::Abort(reason) => {
                        // The nav node says why; an agent that does not is `unknown`.
                        aborted = Some(if reason.is_empty() { "unknown".to_string() } else { reason });
                        break;
                    }
                    StepAnswer::Action(a) => return Err(RosError::Protocol(format!("discrete action {a} from the nav node (DRIVE, STOP or ABORT expected)"))),
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
            sim.publish_episode(&announce(start, None, None)).await?;
            let mut step = 0u32;
            while !env.is_done() {
                // Discrete steps are one second apart on the clock.
                let t = step as f64;
                let p = env.pose();
                let frame = camera!(step, p);
                let st = RobotState { stamp: stamp(t), truth: p, floor_z: start_z, odom: p, twist: Default::default(), scan: None, map_to_odom: None };
                match sim.lockstep(&st, frame.as_ref().map(|(r, f)| (&r.params, f)), ep_index, step).await? {
                    StepAnswer::Action(a) => match Action::from_index(a as i64) {
                        Some(a) => {
                            env.step(a);
                        }
                        None => return Err(RosError::Protocol(format!("action {a} is not one of Habitat's 0..=3"))),
                    },
                    other => return Err(RosError::Protocol(format!("step reply {other:?} where an action was expected (discrete run)"))),
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
        EpisodeEnv::Physics(p) => (Some(p.sim_s()), Some(p.stuck()), p.stuck_cause().map(str::to_string)),
        EpisodeEnv::Plain(_) => (None, None, None),
    };
    Ok(EpisodeRun { episode_id: ep.episode_id.clone(), metrics: made.as_dyn().metrics(), wall_s: 0.0, trajectory: traj, sim_s, stuck, stuck_cause, abort_reason: aborted, final_localization: None, localization_error: None, render: cfg.sensors.is_some().then_some((stats.frames, stats.seconds)), ros: None })
}

/// Ends a lock-step run: stops the agent node (`stop`), waits for it, and hands each nav
/// episode that ran its localisation error from `stats` (one per episode, in order). When the
/// run failed, the agent's own failure, if it had one within 2 s, is named as the cause.
pub(crate) async fn finish_lockstep_run(
    run: Result<(Vec<Outcome>, Vec<usize>), RosError>,
    stop: tokio::sync::watch::Sender<bool>,
    agent: tokio::task::JoinHandle<Result<(), RosError>>,
    stats: &mut tokio::sync::mpsc::UnboundedReceiver<Option<[f64; 2]>>,
    cfg: &RunConfig,
) -> Result<Vec<Outcome>, RosError> {
    let _ = stop.send(true);
    let (mut outcomes, ran) = match run {
        Ok(r) => r,
        Err(e) => {
            if let Ok(Ok(Err(a))) = tokio::time::timeout(std::time::Duration::from_secs(2), agent).await {
                return Err(RosError::Protocol(format!("the agent node failed: {a} (the simulator then reported: {e})")));
            }
            return Err(e);
        }
    };
    match agent.await {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(e),
        Err(e) => return Err(RosError::Node(format!("agent node task: {e}"))),
    }
    if cfg.agent == AgentKind::Nav {
        for &k in &ran {
            if let (Some(stat), Outcome::Ran(r)) = (stats.recv().await, &mut outcomes[k]) {
                r.localization_error = stat;
            }
        }
    }
    Ok(outcomes)
}
