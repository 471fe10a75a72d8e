//! `xhab bench --agent ros`: benchmarks an external ROS navigation stack (move_base + amcl with
//! the user's YAML, a rospy node, `xhab ros nav`) through standard interfaces only. The
//! simulator runs in-process as a ROS node under physics; per episode it places the robot at
//! the start, publishes `initialpose`, sends the goal (the `move_base` action or
//! `move_base_simple/goal`) and advances `/clock` in ticks of one controller period, until the
//! goal reaches a terminal state (SUCCEEDED counts as Habitat's stop), the episode times out
//! (the goal is cancelled), or the robot is stuck.

use super::convert as cv;
use super::master::Master;
use super::move_base_client::{GoalInterface, MoveBaseClient};
use super::move_base_server::status;
use super::msgs::{geometry_msgs as gm, std_srvs};
use super::names::Names;
use super::node::RosError;
use super::sim_node::{Mounts, RobotState, SimNode};
use crate::nav_agent::{episode_time, ScanSchedule, INITIAL_STD_XY, INITIAL_STD_YAW};
use crate::runner::{make_env, EpisodeRun, InvalidRun, MadeEnv, Outcome, RunConfig};
use crate::scan_source::ScanSource;
use serde::{Deserialize, Serialize};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};
use xhab_sim::env::{DiscreteEnv, EnvView};
use xhab_sim::episode::Dataset;
use xhab_sim::world::World;
use xhab_types::{OccupancyGrid, Pose2, Twist};

/// How the simulated clock relates to the stack's answers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pace {
    /// After each tick, wait for the stack's `cmd_vel` (up to `grace` of wall time, then go
    /// on with the last command and count a miss).
    Lockstep {
        /// Wall time to wait for `cmd_vel` after a tick.
        grace: Duration,
    },
    /// Run at `rate` times real time, taking whatever `cmd_vel` came last.
    Realtime {
        /// Simulated seconds per wall second.
        rate: f64,
    },
}

/// Where map -> odom comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapOdom {
    /// The stack publishes it (its own amcl).
    Stack,
    /// The simulator publishes it from ground truth (as ROS's fake_localization).
    GroundTruth,
}

/// How to run an external stack.
#[derive(Debug, Clone)]
pub struct ExternalOptions {
    /// `http://host:port` of a running master; `None` starts `rosmaster` for the run.
    pub master: Option<String>,
    /// How long to wait for the stack before failing (wall time).
    pub timeout: Duration,
    /// The simulator node's name, namespace and remappings.
    pub names: Names,
    /// How goals reach the stack.
    pub goal_interface: GoalInterface,
    /// Simulated seconds after which an episode's goal is cancelled.
    pub episode_timeout: f64,
    /// Who publishes map -> odom.
    pub map_odom: MapOdom,
    /// How the clock advances.
    pub pace: Pace,
    /// Ticks per simulated second (the stack's controller frequency, Hz).
    pub controller_frequency: f64,
    /// The map to latch on `map`, if any.
    pub map: Option<OccupancyGrid>,
    /// A command that starts the stack (run with `sh -c`, stopped at the end), if any.
    pub launch: Option<String>,
    /// The laser scans published on `scan`.
    pub scan: Option<ScanSource>,
    /// Period between scans (s).
    pub scan_period: f64,
}

/// How an external stack's episode went.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RosEpisode {
    /// The goal's terminal action state (SUCCEEDED, ABORTED, PREEMPTED, ...), or `NONE`
    /// when the stack never acknowledged the goal.
    pub ros_status: String,
    /// Why the episode ended: `terminal_state`, `timeout`, `stuck` or `step_limit`.
    pub end: String,
    /// Ticks after which the stack's `cmd_vel` did not come within the grace (lock-step).
    pub cmd_vel_missed: u64,
    /// Wall time spent waiting for the stack (s).
    pub stack_wait_s: f64,
    /// Simulated time from sending the goal to its acknowledgement by the stack (s).
    pub goal_ack_s: Option<f64>,
}

/// A process started with `--launch`, stopped (its whole process group) on drop.
struct Launched(Child);

impl Drop for Launched {
    fn drop(&mut self) {
        // `--` before the negative id: procps-ng's kill reads `-TERM -1234` as signal TERM
        // to process group -1 (its first digit), i.e. to every process it may signal.
        let group = format!("-{}", self.0.id());
        let _ = Command::new("kill").args(["-s", "TERM", "--", &group]).stderr(Stdio::null()).status();
        let t = Instant::now();
        while t.elapsed() < Duration::from_secs(3) {
            if let Ok(Some(_)) = self.0.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = Command::new("kill").args(["-s", "KILL", "--", &group]).stderr(Stdio::null()).status();
        let _ = self.0.wait();
    }
}

fn launch(cmd: &str, uri: &str) -> Result<Launched, RosError> {
    use std::os::unix::process::CommandExt;
    let child = Command::new("sh")
        .args(["-c", cmd])
        .env("ROS_MASTER_URI", uri)
        .stdin(Stdio::null())
        .process_group(0)
        .spawn()
        .map_err(|e| RosError::Node(format!("--launch '{cmd}': {e}")))?;
    tracing::info!("started the stack: {cmd}");
    Ok(Launched(child))
}

/// Runs every episode of `ds` against the external stack, one at a time. `progress` is
/// called once per finished episode.
pub fn run_dataset_external(world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &ExternalOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    if cfg.physics.is_none() {
        return Err(RosError::Protocol("--agent ros drives a robot with cmd_vel: it needs physics".into()));
    }
    if !(opts.controller_frequency.is_finite() && opts.controller_frequency > 0.0) {
        return Err(RosError::Protocol(format!("--controller-frequency must be > 0 Hz, got {}", opts.controller_frequency)));
    }
    let master = Master::connect_or_start(opts.master.as_deref())?;
    // The stack runs on simulated time: set before it starts (nodes read it once).
    master.set_param_bool("/use_sim_time", true)?;
    let _stack = opts.launch.as_deref().map(|c| launch(c, &master.uri)).transpose()?;
    let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().map_err(|e| RosError::Node(format!("tokio runtime: {e}")))?;
    rt.block_on(run_all(&master.uri, world, ds, cfg, opts, progress))
}

async fn run_all(uri: &str, world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &ExternalOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    let ph = cfg.physics.as_ref().expect("checked by the caller");
    let mounts = Mounts {
        laser_frame: ph.profile.laser.frame.clone(),
        laser: opts.scan.as_ref().map_or(Pose2::default(), |s| s.mount()),
        laser_z: opts.scan.as_ref().map_or(ph.profile.laser.z, |s| s.height()),
        camera_z: cfg.sensors.as_ref().map_or(ph.profile.camera_height, |r| r.params.mount_height),
    };
    let mut sim = SimNode::new(uri, opts.names.clone(), &mounts.laser_frame, opts.timeout).await?;
    sim.publish_static_tf(&mounts).await?;
    let mut client = MoveBaseClient::new(&sim.node, opts.goal_interface).await?;
    if let Some(m) = &opts.map {
        sim.publish_map(0.0, m).await?;
    }
    let tick = 1.0 / opts.controller_frequency;
    // ROS time 0 means "no time yet": the clock starts at 1 s.
    let mut clock = Clock { t: 1.0 };
    // The stack must show itself (a status on move_base/status) before the first episode;
    // the clock runs meanwhile, so that its sim-time timers fire.
    let t0 = Instant::now();
    while !client.server_seen {
        client.absorb();
        if t0.elapsed() > opts.timeout {
            return Err(RosError::Timeout(format!(
                "no navigation stack answered on {} within {:.0} s: start it (with use_sim_time) before the run, or pass --launch",
                sim.node.names.resolve("move_base/status"),
                opts.timeout.as_secs_f64()
            )));
        }
        clock.advance(&sim, tick).await?;
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    // The stack's subscriptions are up now: the static tf and the map again, in case latching
    // missed a connection accepted as they were first published.
    sim.republish_latched().await?;
    let clear_name = sim.node.names.resolve("move_base/clear_costmaps");
    let mut clear = sim.node.nh.service_client::<std_srvs::Empty>(&clear_name).await.ok();
    let mut outcomes = Vec::with_capacity(ds.episodes.len());
    for (i, ep) in ds.episodes.iter().enumerate() {
        let t_wall = Instant::now();
        // An external stack is given one storey's map: an episode across storeys is refused.
        let made = match crate::runner::across_storeys(ep, "an external ROS stack") {
            Some(reason) => Err(reason),
            None => make_env(&world, ep, cfg.episode_index(i), cfg),
        };
        let o = match made {
            Err(reason) => Outcome::Invalid(InvalidRun { episode_id: ep.episode_id.clone(), reason }),
            Ok((MadeEnv::Physics(env), grid)) => {
                if let Some(c) = clear.as_ref() {
                    if tokio::time::timeout(Duration::from_secs(2), c.call(&std_srvs::EmptyRequest {})).await.map_or(true, |r| r.is_err()) {
                        tracing::warn!("{clear_name} did not answer: costmaps are not cleared between episodes");
                        clear = None;
                    }
                }
                if i > 0 {
                    // Again each episode, for subscribers that latching missed (see above).
                    sim.publish_static_tf(&mounts).await?;
                }
                let mut run = episode(&mut sim, &mut client, env, &grid, ep, cfg.episode_index(i), cfg, opts, &mut clock).await?;
                run.wall_s = t_wall.elapsed().as_secs_f64();
                Outcome::Ran(run)
            }
            Ok((MadeEnv::Plain(_), _)) => unreachable!("physics is on"),
        };
        outcomes.push(o);
        progress();
    }
    Ok(outcomes)
}

/// The simulated clock across episodes (s).
struct Clock {
    t: f64,
}

impl Clock {
    /// Advances by `dt` (s) and publishes `/clock` alone (between episodes).
    async fn advance(&mut self, sim: &SimNode, dt: f64) -> Result<(), RosError> {
        self.t = episode_time(self.t + dt);
        sim.publish_clock(self.t).await
    }
}

#[allow(clippy::too_many_arguments)]
async fn episode(
    sim: &mut SimNode,
    client: &mut MoveBaseClient,
    mut env: xhab_sim::physics_env::PhysicsEnv,
    grid: &Arc<xhab_sim::navgrid::NavGrid>,
    ep: &xhab_sim::episode::Episode,
    index: usize,
    cfg: &RunConfig,
    opts: &ExternalOptions,
    clock: &mut Clock,
) -> Result<EpisodeRun, RosError> {
    let tick = 1.0 / opts.controller_frequency;
    let start = clock.t;
    let stamp = |t: f64| episode_time(start + t);
    let goal = ep.goals[0].position;
    let mut traj = cfg.record_trajectories.then(|| vec![env.pose()]);
    let mut sensor = opts.scan.as_ref().map(|s| s.sensor(cfg.seed.wrapping_add(index as u64)));
    let mut sched = ScanSchedule::new(opts.scan_period);
    let mut stats = crate::runner::RenderStats::default();
    let mut cmd = Twist::default();
    let (mut missed, mut wait_s, mut ack_at) = (0u64, 0.0f64, None);
    let mut last_send = Instant::now();
    let mut sent_at = Instant::now();
    let mut last_cmd = Instant::now();
    let mut sent = false;
    let mut n = 0u64;
    let t_real = Instant::now();
    // Commands left from the last episode are not this one's.
    let _ = sim.latest_command();
    let end = loop {
        let t = episode_time(env.sim_s());
        let frame = match cfg.sensors.as_deref() {
            Some(rig) => Some((rig, crate::runner::capture(rig, env.pose(), grid.floor_z, cfg.seed, index, n, &mut stats).map_err(RosError::Node)?)),
            None => None,
        };
        let scan = sched.take(sensor.as_mut(), t, env.pose(), grid.floor_z, frame.as_ref().map(|(r, f)| (*r, f))).map_err(RosError::Node)?;
        let m2o = (opts.map_odom == MapOdom::GroundTruth).then(|| env.pose().compose(env.odometry().inverse()));
        let st = RobotState { stamp: stamp(t), truth: env.pose(), floor_z: ep.start_position.z, odom: env.odometry(), twist: env.robot().twist(), scan: scan.as_ref().map(|s| (s, opts.scan_period)), map_to_odom: m2o };
        sim.publish_state(&st).await?;
        if let Some((rig, f)) = &frame {
            sim.publish_frame(st.stamp, &rig.params, f).await?;
        }
        if !sent {
            // The robot is at the start: tell the localiser, then send the goal.
            sim.publish_initialpose(st.stamp, env.pose(), INITIAL_STD_XY, INITIAL_STD_YAW).await?;
            let target = gm::PoseStamped { header: cv::header(st.stamp, "map"), pose: cv::pose(Pose2::new(goal.x, goal.y, 0.0), goal.z) };
            client.send(&format!("xhab-{}-{}", index, ep.episode_id), st.stamp, target).await?;
            sent = true;
            last_send = Instant::now();
            sent_at = last_send;
        }
        let state = client.absorb();
        if state.is_some() && ack_at.is_none() {
            ack_at = Some(t);
        }
        if let Some(s) = state.filter(|s| status::is_terminal(*s)) {
            if s == status::SUCCEEDED {
                env.call_stop();
            }
            break "terminal_state";
        }
        if !client.acknowledged() {
            last_cmd = Instant::now();
        }
        if !client.acknowledged() && last_send.elapsed() > Duration::from_millis(500) {
            if sent_at.elapsed() > opts.timeout {
                return Err(RosError::Timeout(format!("the stack did not take the goal of episode {} within {:.0} s (no status for it on move_base/status)", ep.episode_id, opts.timeout.as_secs_f64())));
            }
            // The stack's subscriptions to a new run's publishers may not have been up: the
            // pose estimate again (the robot is where it started), then the goal.
            sim.publish_initialpose(st.stamp, env.pose(), INITIAL_STD_XY, INITIAL_STD_YAW).await?;
            client.resend().await?;
            last_send = Instant::now();
        }
        if client.acknowledged() && last_cmd.elapsed() > opts.timeout {
            return Err(RosError::Timeout(format!("no cmd_vel from the stack for {:.0} s during episode {} (is it still running?)", opts.timeout.as_secs_f64(), ep.episode_id)));
        }
        if t >= opts.episode_timeout {
            client.cancel().await?;
            break "timeout";
        }
        if env.stuck() {
            client.cancel().await?;
            break "stuck";
        }
        if env.is_done() {
            client.cancel().await?;
            break "step_limit";
        }
        match opts.pace {
            Pace::Lockstep { grace } => {
                let w = Instant::now();
                if client.acknowledged() {
                    match sim.cmd_vel_within(grace).await {
                        Some(c) => {
                            cmd = c;
                            last_cmd = Instant::now();
                        }
                        None => missed += 1,
                    }
                } else {
                    // Give the stack a moment to take the goal before the clock moves on.
                    if let Some(c) = sim.cmd_vel_within(grace.min(Duration::from_millis(50))).await {
                        cmd = c;
                    }
                }
                wait_s += w.elapsed().as_secs_f64();
                if let Some(super::sim_node::Command::Twist(c)) = sim.latest_command() {
                    cmd = c;
                }
            }
            Pace::Realtime { rate } => {
                let due = t_real + Duration::from_secs_f64((t + tick) / rate.max(1e-6));
                let w = Instant::now();
                tokio::time::sleep_until(due.into()).await;
                wait_s += w.elapsed().as_secs_f64();
                if let Some(super::sim_node::Command::Twist(c)) = sim.latest_command() {
                    cmd = c;
                    last_cmd = Instant::now();
                }
            }
        }
        if !(cmd.linear.is_finite() && cmd.angular.is_finite()) {
            tracing::warn!("cmd_vel with a non-finite value ignored (the base stops)");
            cmd = Twist::default();
        }
        env.drive(cmd, tick);
        n += 1;
        if let Some(tr) = traj.as_mut() {
            tr.push(env.pose());
        }
    };
    let end_t = stamp(env.sim_s());
    if client.acknowledged() && !client.state.is_some_and(status::is_terminal) {
        // The goal was cancelled: the stack reports it PREEMPTED once its clock moves on (a
        // rospy.Rate, a sim-time timer). Tick the clock through the second between episodes,
        // the robot standing still, until it does (at most 50 ms of wall time a tick).
        for k in 1..(1.0 / tick).floor() as u32 {
            clock.t = episode_time(end_t + k as f64 * tick);
            sim.publish_clock(clock.t).await?;
            let deadline = Instant::now() + Duration::from_millis(50);
            while !client.absorb().is_some_and(status::is_terminal) && Instant::now() < deadline {
                tokio::time::sleep(Duration::from_millis(2)).await;
            }
            if client.state.is_some_and(status::is_terminal) {
                break;
            }
        }
    }
    let ros_status = client.state.map_or("NONE", status::name).to_string();
    client.clear();
    // The robot stands still for a tick while the next episode is set up.
    let _ = sim.cmd_vel_within(Duration::from_millis(1)).await;
    clock.t = end_t;
    clock.advance(sim, 1.0).await?;
    Ok(EpisodeRun {
        episode_id: ep.episode_id.clone(),
        metrics: env.metrics(),
        wall_s: 0.0,
        trajectory: traj,
        sim_s: Some(env.sim_s()),
        stuck: Some(env.stuck()),
        stuck_cause: env.stuck_cause().map(str::to_string),
        abort_reason: None,
        final_localization: None,
        localization_error: None,
        render: cfg.sensors.is_some().then_some((stats.frames, stats.seconds)),
        ros: Some(RosEpisode { ros_status, end: end.to_string(), cmd_vel_missed: missed, stack_wait_s: wait_s, goal_ack_s: ack_at }),
    })
}
