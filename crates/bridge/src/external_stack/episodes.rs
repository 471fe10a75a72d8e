//! The benchmark loop of an external stack, written once against [`StackSim`] and
//! [`GoalClient`]: wait for the stack, then per episode place the robot, publish
//! `initialpose`, send the goal and tick the clock until the goal ends, times out or the
//! robot is stuck.

use super::interfaces::{GoalClient, StackSim};
use super::options::{ExternalOptions, MapOdom, Pace, RosEpisode};
use crate::nav_agent::{episode_time, ScanSchedule, INITIAL_STD_XY, INITIAL_STD_YAW};
use crate::robot_io::{Command, Mounts, RobotState};
use crate::ros::node::RosError;
use crate::runner::{make_env, EpisodeRun, InvalidRun, EpisodeEnv, Outcome, RunConfig};
use std::sync::Arc;
use std::time::{Duration, Instant};
use xhab_sim::env::{DiscreteEnv, EnvView};
use xhab_sim::episode::Dataset;
use xhab_sim::world::World;
use xhab_types::{Point3, Pose2, Twist};

/// The sensor mounts the simulator node announces for a run of `cfg` (physics on).
pub fn mounts(cfg: &RunConfig, opts: &ExternalOptions) -> Mounts {
    let ph = cfg.physics.as_ref().expect("an external stack runs under physics");
    Mounts {
        laser_frame: ph.profile.laser.frame.clone(),
        laser: opts.scan.as_ref().map_or(Pose2::default(), |s| s.mount()),
        laser_z: opts.scan.as_ref().map_or(ph.profile.laser.z, |s| s.height()),
        camera_z: cfg.sensors.as_ref().map_or(ph.profile.camera_height, |r| r.params.mount_height),
    }
}

/// Checks what every transport needs: physics, a positive controller frequency; `agent`
/// names the flag value in the message.
pub fn check(cfg: &RunConfig, opts: &ExternalOptions, agent: &str) -> Result<(), RosError> {
    if cfg.physics.is_none() {
        return Err(RosError::Protocol(format!("--agent {agent} drives a robot with cmd_vel: it needs physics")));
    }
    if !(opts.controller_frequency.is_finite() && opts.controller_frequency > 0.0) {
        return Err(RosError::Protocol(format!("--controller-frequency must be > 0 Hz, got {}", opts.controller_frequency)));
    }
    Ok(())
}

/// Runs every episode of `ds` against the stack behind `client`, one at a time, on the
/// simulator node `sim` (static transforms and map published here first). `progress` is
/// called once per finished episode.
#[allow(clippy::too_many_arguments)]
pub async fn run_episodes<S: StackSim, C: GoalClient>(sim: &mut S, client: &mut C, mounts: &Mounts, world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &ExternalOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    sim.publish_static_tf(mounts).await?;
    if let Some(m) = &opts.map {
        sim.publish_map(0.0, m).await?;
    }
    let tick = 1.0 / opts.controller_frequency;
    // ROS time 0 means "no time yet": the clock starts at 1 s.
    let mut clock = Clock { t: 1.0 };
    // The stack must show itself before the first episode; the clock runs meanwhile, so that
    // its sim-time timers fire.
    let t0 = Instant::now();
    while !client.server_seen() {
        client.absorb();
        if t0.elapsed() > opts.timeout {
            return Err(RosError::Timeout(format!(
                "no navigation stack answered on {} within {:.0} s: start it (with use_sim_time) before the run, or pass --launch",
                client.status_topic(),
                opts.timeout.as_secs_f64()
            )));
        }
        clock.advance(sim, tick).await?;
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    // The stack's subscriptions are up now: the static tf and the map again, in case latching
    // missed a connection accepted as they were first published.
    sim.republish_latched().await?;
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
            Ok((EpisodeEnv::Physics(env), grid)) => {
                client.before_episode().await;
                if i > 0 {
                    // Again each episode, for subscribers that latching missed (see above).
                    sim.publish_static_tf(mounts).await?;
                }
                let mut run = episode(sim, client, env, &grid, ep, cfg.episode_index(i), cfg, opts, &mut clock).await?;
                run.wall_s = t_wall.elapsed().as_secs_f64();
                Outcome::Ran(run)
            }
            Ok((EpisodeEnv::Plain(_), _)) => unreachable!("physics is on"),
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
    async fn advance<S: StackSim>(&mut self, sim: &S, dt: f64) -> Result<(), RosError> {
        self.t = episode_time(self.t + dt);
        sim.publish_clock(self.t).await
    }
}

#[allow(clippy::too_many_arguments)]
async fn episode<S: StackSim, C: GoalClient>(
    sim: &mut S,
    client: &mut C,
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
    let mut stats = crate::camera_capture::RenderStats::default();
    let mut cmd = Twist::default();
    let (mut missed, mut wait_s, mut ack_at) = (0u64, 0.0f64, None);
    let mut last_send = Instant::now();
    let mut sent_at = Instant::now();
    let mut last_cmd = Instant::now();
    let mut sent = false;
    let mut n = 0u64;
    let t_real = Instant::now();
    let acknowledged = |c: &C| c.state().is_some();
    // Commands left from the last episode are not this one's.
    let _ = sim.latest_command();
    let end = loop {
        let t = episode_time(env.sim_s());
        let frame = match cfg.sensors.as_deref() {
            Some(rig) => Some((rig, crate::camera_capture::capture(rig, env.pose(), grid.floor_z, cfg.seed, index, n, &mut stats).map_err(RosError::Node)?)),
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
            client.send(&format!("xhab-{}-{}", index, ep.episode_id), st.stamp, Point3::new(goal.x, goal.y, goal.z)).await?;
            sent = true;
            last_send = Instant::now();
            sent_at = last_send;
        }
        let state = client.absorb();
        if state.is_some() && ack_at.is_none() {
            ack_at = Some(t);
        }
        if let Some(s) = state.filter(|s| s.terminal) {
            if s.succeeded {
                env.call_stop();
            }
            break "terminal_state";
        }
        if !acknowledged(client) {
            last_cmd = Instant::now();
        }
        if !acknowledged(client) && last_send.elapsed() > Duration::from_millis(500) {
            if sent_at.elapsed() > opts.timeout {
                return Err(RosError::Timeout(format!("the stack did not take the goal of episode {} within {:.0} s (no status for it on {})", ep.episode_id, opts.timeout.as_secs_f64(), client.status_topic())));
            }
            // The stack's subscriptions to a new run's publishers may not have been up: the
            // pose estimate again (the robot is where it started), then the goal.
            sim.publish_initialpose(st.stamp, env.pose(), INITIAL_STD_XY, INITIAL_STD_YAW).await?;
            client.resend().await?;
            last_send = Instant::now();
        }
        if acknowledged(client) && last_cmd.elapsed() > opts.timeout {
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
                if acknowledged(client) {
                    match sim.cmd_vel_within(grace).await {
                        Some(c) => {
                            cmd = c;
                            last_cmd = Instant::now();
                        }
                        None => missed += 1,
                    }
                } else if client.acknowledges_at_once() {
                    // The clock stands until the stack has taken the goal.
                    let deadline = Instant::now() + grace;
                    while client.absorb().is_none() && Instant::now() < deadline {
                        tokio::time::sleep(Duration::from_millis(1)).await;
                    }
                } else {
                    // Give the stack a moment to take the goal before the clock moves on.
                    if let Some(c) = sim.cmd_vel_within(grace.min(Duration::from_millis(50))).await {
                        cmd = c;
                    }
                }
                wait_s += w.elapsed().as_secs_f64();
                if let Some(Command::Twist(c)) = sim.latest_command() {
                    cmd = c;
                }
            }
            Pace::Realtime { rate } => {
                let due = t_real + Duration::from_secs_f64((t + tick) / rate.max(1e-6));
                let w = Instant::now();
                tokio::time::sleep_until(due.into()).await;
                wait_s += w.elapsed().as_secs_f64();
                if let Some(Command::Twist(c)) = sim.latest_command() {
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
    if acknowledged(client) && !client.state().is_some_and(|s| s.terminal) {
        // The goal was cancelled: the stack reports it over once its clock moves on (a
        // rospy.Rate, a sim-time timer). Tick the clock through the second between episodes,
        // the robot standing still, until it does (at most 50 ms of wall time a tick).
        for k in 1..(1.0 / tick).floor() as u32 {
            clock.t = episode_time(end_t + k as f64 * tick);
            sim.publish_clock(clock.t).await?;
            let deadline = Instant::now() + Duration::from_millis(50);
            while !client.absorb().is_some_and(|s| s.terminal) && Instant::now() < deadline {
                tokio::time::sleep(Duration::from_millis(2)).await;
            }
            if client.state().is_some_and(|s| s.terminal) {
                break;
            }
        }
    }
    let ros_status = client.state().map_or("NONE", |s| s.name).to_string();
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
