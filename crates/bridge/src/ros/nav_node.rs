//! The native navigation stack as a move_base-compatible ROS 1 node: `scan`, `odom`, `map`,
//! `move_base_simple/goal` and `initialpose` in; `cmd_vel`, `amcl_pose`, `particlecloud`, tf
//! map -> odom and the global plan out. It drives any ROS simulator or robot.
//!
//! Free-running, it runs a controller step on each odometry message at least one controller
//! period (sim time, from the stamps) after the last. Lock-step (the simulator waits for each
//! reply), every odometry message gets exactly one reply: `cmd_vel`, or `action` 0 (goal
//! reached: stop) or -1 (gave up); the step's scan (due every `LaserScan.scan_time` from the
//! episode's start) and ground truth are awaited by sequence number, so arrival order across
//! topics never changes the result. An odometry message with `header.seq == 0` begins an episode
//! and pairs with the next map, goal and initial pose received (and localisation map, when
//! one is expected on `amcl/map`; without one AMCL localises on `map`).

use super::convert as cv;
use super::msgs::{geometry_msgs as gm, nav_msgs, sensor_msgs, std_msgs, tf2_msgs};
use super::node::{self, Inbox, RosError};
use super::sim_node::{AMCL_MAP_TOPIC, PROBE_SEQ, READY_ACTION};
use crate::nav_agent::{NavBrain, NavInputs, NavReply, NavSetup};
use roslibrust::ros1::Publisher;
use std::time::Duration;
use tokio::sync::{mpsc, watch};
use xhab_types::{OccupancyGrid, Pose2};

/// How the node runs.
#[derive(Debug, Clone)]
pub struct NavNodeOptions {
    /// The stack's setup (parameters, localisation, scan period).
    pub setup: NavSetup,
    /// Lock-step with the simulator (one reply per odometry message).
    pub lockstep: bool,
    /// Whether scans come (lock-step waits for each due scan).
    pub expect_scans: bool,
    /// Whether each lock-step episode brings a localisation map on `amcl/map`.
    pub expect_amcl_map: bool,
    /// Seed of AMCL.
    pub seed: u64,
    /// How long to wait for a peer (s).
    pub timeout: Duration,
}

struct Outputs {
    cmd_vel: Publisher<gm::Twist>,
    action: Publisher<std_msgs::Int16>,
    amcl_pose: Publisher<gm::PoseWithCovarianceStamped>,
    particlecloud: Publisher<gm::PoseArray>,
    tf: Publisher<tf2_msgs::TFMessage>,
    plan: Publisher<nav_msgs::Path>,
}

impl Outputs {
    async fn reply(&self, r: NavReply, lockstep: bool) -> Result<(), RosError> {
        let e = |t: &str, e: String| RosError::Node(format!("publishing on {t}: {e}"));
        match (r, lockstep) {
            (NavReply::Drive(tw), _) => self.cmd_vel.publish(&cv::twist(tw)).await.map_err(|x| e("cmd_vel", x.to_string())),
            (NavReply::Stop, true) => self.action.publish(&std_msgs::Int16 { data: 0 }).await.map_err(|x| e("action", x.to_string())),
            (NavReply::Abort, true) => self.action.publish(&std_msgs::Int16 { data: -1 }).await.map_err(|x| e("action", x.to_string())),
            (_, false) => self.cmd_vel.publish(&gm::Twist::default()).await.map_err(|x| e("cmd_vel", x.to_string())),
        }
    }

    /// Localisation and plan outputs, each only when someone listens.
    async fn report(&self, brain: &NavBrain, stamp: f64, odom: Pose2) -> Result<(), RosError> {
        let m2o = brain.map_to_odom();
        if self.tf.has_connected_clients() {
            let m = tf2_msgs::TFMessage { transforms: vec![cv::tf(stamp, "map", "odom", cv::transform(m2o, 0.0))] };
            let _ = self.tf.publish(&m).await;
        }
        if let Some(a) = brain.amcl() {
            if self.amcl_pose.has_connected_clients() {
                let est = a.estimate();
                let mut m = cv::pose_with_covariance(0, stamp, m2o.compose(odom), 0.0, 0.0);
                m.pose.covariance[0] = est.variance[0];
                m.pose.covariance[7] = est.variance[1];
                m.pose.covariance[35] = est.variance[2];
                let _ = self.amcl_pose.publish(&m).await;
            }
            if self.particlecloud.has_connected_clients() {
                let poses = a.particles().iter().map(|(p, _)| cv::pose(*p, 0.0)).collect();
                let _ = self.particlecloud.publish(&gm::PoseArray { header: cv::header(0, stamp, "map"), poses }).await;
            }
        }
        if self.plan.has_connected_clients() {
            let poses = brain.navigator().plan().iter().map(|p| gm::PoseStamped { header: cv::header(0, stamp, "map"), pose: cv::pose(*p, 0.0) }).collect();
            let _ = self.plan.publish(&nav_msgs::Path { header: cv::header(0, stamp, "map"), poses }).await;
        }
        Ok(())
    }
}

/// Runs the node `name` until `shutdown` fires. `map`: a static map (`--map`), else the one
/// received on `map`; `amcl_map`: a static localisation map (`--amcl-map`), else the one
/// received on `amcl/map`, else the map. In lock-step runs, each episode's mean localisation error is sent on
/// `stats` when the next episode begins or the node stops.
pub async fn run(uri: &str, name: &str, opts: NavNodeOptions, map: Option<OccupancyGrid>, amcl_map: Option<OccupancyGrid>, mut shutdown: watch::Receiver<bool>, stats: Option<mpsc::UnboundedSender<Option<[f64; 2]>>>) -> Result<(), RosError> {
    let nh = node::node(uri, name).await?;
    let out = Outputs {
        cmd_vel: node::advertise(&nh, "cmd_vel", false).await?,
        action: node::advertise(&nh, "action", false).await?,
        amcl_pose: node::advertise(&nh, "amcl_pose", false).await?,
        particlecloud: node::advertise(&nh, "particlecloud", false).await?,
        tf: node::advertise(&nh, "tf", false).await?,
        plan: node::advertise(&nh, "move_base/GlobalPlanner/plan", false).await?,
    };
    let mut odoms = node::subscribe::<nav_msgs::Odometry>(&nh, "odom").await?;
    let mut scans = Inbox::new(node::subscribe::<sensor_msgs::LaserScan>(&nh, "scan").await?);
    let mut maps = Inbox::new(node::subscribe::<nav_msgs::OccupancyGrid>(&nh, "map").await?);
    let mut amcl_maps = Inbox::new(node::subscribe::<nav_msgs::OccupancyGrid>(&nh, AMCL_MAP_TOPIC).await?);
    let mut goals = Inbox::new(node::subscribe::<gm::PoseStamped>(&nh, "move_base_simple/goal").await?);
    let mut inits = Inbox::new(node::subscribe::<gm::PoseWithCovarianceStamped>(&nh, "initialpose").await?);
    let want_truth = opts.lockstep && (opts.setup.localization == crate::nav_agent::Localization::GroundTruth || stats.is_some());
    let mut truths = if want_truth { Some(Inbox::new(node::subscribe::<gm::PoseStamped>(&nh, "ground_truth/pose").await?)) } else { None };
    let mut current_map = map.clone();
    let mut current_amcl_map = amcl_map.clone();
    let expect_amcl_map = opts.expect_amcl_map && amcl_map.is_none();
    let mut brain: Option<NavBrain> = None;
    let mut episode_start_ns = 0i64;
    let mut last_tick: Option<f64> = None;
    let mut pending_scan = None;
    let flush = |b: &Option<NavBrain>| {
        if let (Some(tx), Some(b)) = (stats.as_ref(), b.as_ref()) {
            let _ = tx.send(b.localization_error());
        }
    };
    loop {
        let od = tokio::select! {
            m = odoms.recv() => match m { Some(m) => m, None => break },
            _ = shutdown.changed() => break,
        };
        if od.header.seq == PROBE_SEQ {
            // Handshake: answer on both reply topics once every input has shown a probe.
            goals.absorb();
            inits.absorb();
            maps.absorb();
            amcl_maps.absorb();
            scans.absorb();
            if let Some(t) = truths.as_mut() {
                t.absorb();
            }
            let ready = goals.probed && inits.probed && (map.is_some() || maps.probed) && (!expect_amcl_map || amcl_maps.probed) && (!opts.expect_scans || scans.probed) && truths.as_ref().is_none_or(|t| t.probed);
            if ready && opts.lockstep {
                let e = |x: String| RosError::Node(format!("publishing the handshake answer: {x}"));
                out.action.publish(&std_msgs::Int16 { data: READY_ACTION }).await.map_err(|x| e(x.to_string()))?;
                let probe = gm::Twist { linear: gm::Vector3 { x: 0.0, y: 0.0, z: 1.0 }, ..Default::default() };
                out.cmd_vel.publish(&probe).await.map_err(|x| e(x.to_string()))?;
            }
            continue;
        }
        let stamp_ns = od.header.stamp.secs as i64 * 1_000_000_000 + od.header.stamp.nsecs as i64;
        let odom = cv::pose2(&od.pose.pose);
        let twist = cv::twist2(&od.twist.twist);
        if opts.lockstep {
            if od.header.seq == 0 {
                flush(&brain);
                if map.is_none() {
                    let m = maps.next(opts.timeout, "map for the new episode").await?;
                    current_map = Some(cv::grid_from_msg(&m).map_err(RosError::Protocol)?);
                }
                if expect_amcl_map {
                    let m = amcl_maps.next(opts.timeout, "localisation map for the new episode").await?;
                    current_amcl_map = Some(cv::grid_from_msg(&m).map_err(RosError::Protocol)?);
                }
                let g = goals.next(opts.timeout, "goal for the new episode").await?;
                let ip = inits.next(opts.timeout, "initial pose for the new episode").await?;
                let spread = (ip.pose.covariance[0].sqrt(), ip.pose.covariance[35].sqrt());
                let m = current_map.as_ref().ok_or_else(|| RosError::Protocol("no map".into()))?;
                let am = current_amcl_map.as_ref().unwrap_or(m);
                brain = Some(NavBrain::new(&opts.setup, m, am, cv::pose2(&g.pose).position(), cv::pose2(&ip.pose.pose), Some(spread), opts.seed));
                episode_start_ns = stamp_ns;
            }
            let Some(b) = brain.as_mut() else {
                return Err(RosError::Protocol("odometry arrived before any episode began (header.seq 0)".into()));
            };
            let t = (stamp_ns - episode_start_ns) as f64 / 1e9;
            let scan = if opts.expect_scans && b.scan_due(t) {
                let s = scans.next(opts.timeout, "scan due at this step").await?;
                if s.header.seq != od.header.seq {
                    return Err(RosError::Protocol(format!("scan seq {} where odometry seq {} was expected", s.header.seq, od.header.seq)));
                }
                Some(cv::scan_from_msg(&s))
            } else {
                None
            };
            let truth = match truths.as_mut() {
                Some(rx) => {
                    let g = rx.next(opts.timeout, "ground truth of this step").await?;
                    Some(cv::pose2(&g.pose))
                }
                None => None,
            };
            let r = b.step(NavInputs { t, odom, twist, truth, scan: scan.as_ref() });
            out.reply(r, true).await?;
            out.report(b, stamp_ns as f64 / 1e9, odom).await?;
            continue;
        }
        // Free-running: take the newest map, goal and initial pose; feed every new scan.
        if let Some(m) = maps.latest() {
            match cv::grid_from_msg(&m) {
                Ok(g) if map.is_none() => current_map = Some(g),
                Ok(_) => {}
                Err(e) => tracing::warn!("map: {e}"),
            }
        }
        if let Some(m) = amcl_maps.latest() {
            match cv::grid_from_msg(&m) {
                Ok(g) if amcl_map.is_none() => current_amcl_map = Some(g),
                Ok(_) => {}
                Err(e) => tracing::warn!("{AMCL_MAP_TOPIC}: {e}"),
            }
        }
        let init = inits.latest().map(|ip| (cv::pose2(&ip.pose.pose), (ip.pose.covariance[0].sqrt(), ip.pose.covariance[35].sqrt())));
        let goal = goals.latest().map(|g| cv::pose2(&g.pose).position());
        let t = stamp_ns as f64 / 1e9;
        if let (Some(g), Some(m)) = (goal, current_map.as_ref()) {
            let (start, spread) = match (init, brain.as_ref()) {
                (Some((p, s)), _) => (p, Some(s)),
                (None, Some(b)) => (b.map_to_odom().compose(odom), Some((0.1, 0.1))),
                (None, None) => (odom, None),
            };
            brain = Some(NavBrain::new(&opts.setup, m, current_amcl_map.as_ref().unwrap_or(m), g, start, spread, opts.seed));
            tracing::info!("new goal ({:.2}, {:.2})", g.x, g.y);
        }
        let Some(b) = brain.as_mut() else { continue };
        if let Some(s) = scans.latest() {
            pending_scan = Some(cv::scan_from_msg(&s));
        }
        let period = opts.setup.params.dwa.controller_period;
        if last_tick.is_some_and(|l| t < l + period - 1e-6) {
            continue;
        }
        last_tick = Some(t);
        let scan = pending_scan.take();
        let r = b.step(NavInputs { t, odom, twist, truth: None, scan: scan.as_ref() });
        out.reply(r, false).await?;
        out.report(b, t, odom).await?;
    }
    flush(&brain);
    Ok(())
}

