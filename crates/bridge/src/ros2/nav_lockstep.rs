//! The ROS 2 nav node in lock-step with xhab's simulator (`xhab ros2 nav --lockstep`, `xhab
//! bench --agent nav --ros2`): each `xhab/step` is answered on `xhab/step_reply`, from that
//! step's odometry, scan and ground truth taken by their stamp, so that results equal the
//! in-process run's. Besides the reply it publishes what the free-running node does:
//! `cmd_vel`, `/tf` map -> odom and `amcl_pose` (when it localises).

use super::convert as cv;
use super::lockstep::{episode_announcement, lockstep_qos, stamp_key, Inbox};
use super::msgs::{geometry_msgs as gm, nav_msgs, sensor_msgs, tf2_msgs, RosType};
use super::node::{latched_qos, reliable_qos, Ros2Config, Ros2Node};
use super::xhab_msgs;
use crate::nav_agent::{Localization, NavStack, NavInputs, NavReply};
use crate::ros::names::Names;
use crate::ros::nav_node::NavNodeOptions;
use crate::ros::node::RosError;
use crate::ros::sim_node::{AMCL_MAP_TOPIC, EPISODE_TOPIC, STEP_REPLY_TOPIC, STEP_TOPIC};
use crate::ros::tf_buffer::TfBuffer;
use ros2_client::qos::History;
use ros2_client::{Publisher, Subscription};
use std::time::Duration;
use tokio::sync::{mpsc, watch};
use xhab_nav::navigator::AbortReason;
use xhab_types::{OccupancyGrid, Pose2, Twist};

/// The robot's frame (REP-105).
const BASE_FRAME: &str = "base_link";

fn publish<T: RosType>(p: &Publisher<T>, topic: &str, m: T) -> Result<(), RosError> {
    p.publish(m).map_err(|e| RosError::Node(format!("publishing on {topic}: {e}")))
}

/// The transforms that have arrived, into `buffer`.
fn absorb_tf(buffer: &mut TfBuffer, subs: [&Subscription<tf2_msgs::TFMessage>; 2]) {
    for sub in subs {
        for _ in 0..10_000 {
            match sub.take() {
                Ok(Some((m, _))) => {
                    for t in &m.transforms {
                        buffer.insert_edge(&t.header.frame_id, &t.child_frame_id, cv::pose2_of_transform(&t.transform));
                    }
                }
                Ok(None) => break,
                Err(e) => tracing::warn!("tf: a message that does not decode was dropped: {e}"),
            }
        }
    }
}

/// Runs the node until `shutdown` fires. `map`: a static map (`--map`), else the one of each
/// episode received on `map`; `amcl_map`: a static localisation map, else the episode's on
/// `amcl/map` (when it announces one), else the map. Each episode's mean localisation error is
/// sent on `stats` when the next episode begins or the node stops.
#[allow(clippy::too_many_arguments)]
pub async fn run(names: Names, config: Ros2Config, opts: NavNodeOptions, map: Option<OccupancyGrid>, amcl_map: Option<OccupancyGrid>, mut shutdown: watch::Receiver<bool>, stats: Option<mpsc::UnboundedSender<Option<[f64; 2]>>>) -> Result<(), RosError> {
    let mut node = Ros2Node::new(names, config)?;
    let cmd_vel = node.publisher::<gm::Twist>("cmd_vel", reliable_qos(10))?;
    let tf_out = node.publisher::<tf2_msgs::TFMessage>("/tf", reliable_qos(100))?;
    let amcl_pose = node.publisher::<gm::PoseWithCovarianceStamped>("amcl_pose", latched_qos())?;
    let reply = node.publisher::<xhab_msgs::StepReply>(STEP_REPLY_TOPIC, lockstep_qos())?;
    let reply_topic = node.names.resolve(STEP_REPLY_TOPIC);
    let episodes = node.subscription::<xhab_msgs::Episode>(EPISODE_TOPIC, latched_qos().history(History::KeepLast { depth: 10 }))?;
    let steps = node.subscription::<xhab_msgs::Step>(STEP_TOPIC, lockstep_qos())?;
    let mut odoms: Inbox<nav_msgs::Odometry> = Inbox::subscribe(&mut node, "odom", lockstep_qos())?;
    let mut scans: Inbox<sensor_msgs::LaserScan> = Inbox::subscribe(&mut node, "scan", lockstep_qos())?;
    let mut truths: Inbox<gm::PoseStamped> = Inbox::subscribe(&mut node, "ground_truth/pose", lockstep_qos())?;
    let mut maps: Inbox<nav_msgs::OccupancyGrid> = Inbox::subscribe(&mut node, "map", latched_qos())?;
    let mut amcl_maps: Inbox<nav_msgs::OccupancyGrid> = Inbox::subscribe(&mut node, AMCL_MAP_TOPIC, latched_qos())?;
    let tfs = node.subscription::<tf2_msgs::TFMessage>("/tf", reliable_qos(100))?;
    let tf_statics = node.subscription::<tf2_msgs::TFMessage>("/tf_static", latched_qos().history(History::KeepLast { depth: 100 }))?;
    let mut buffer = TfBuffer::new();
    let want_truth = opts.setup.localization == Localization::GroundTruth || stats.is_some();
    let mut brain: Option<(u32, NavStack, (i32, u32))> = None;
    let mut last: Option<xhab_msgs::StepReply> = None;
    let flush = |b: &Option<(u32, NavStack, (i32, u32))>| {
        if let (Some(tx), Some((_, b, _))) = (stats.as_ref(), b.as_ref()) {
            let _ = tx.send(b.localization_error());
        }
    };
    let t_out = opts.timeout;
    loop {
        let s = tokio::select! {
            m = steps.async_take() => match m {
                Ok((m, _)) => m,
                Err(e) => { tracing::warn!("{STEP_TOPIC}: a step that does not decode was dropped: {e}"); continue }
            },
            _ = shutdown.changed() => break,
        };
        if let Some(l) = last.as_ref().filter(|l| (l.episode, l.step) >= (s.episode, s.step)) {
            if (l.episode, l.step) == (s.episode, s.step) {
                publish(&reply, &reply_topic, l.clone())?;
            }
            continue;
        }
        if brain.as_ref().is_none_or(|(i, _, _)| *i != s.episode) {
            flush(&brain);
            let e = episode_announcement(&episodes, s.episode, t_out).await?;
            let m = match &map {
                Some(m) => m.clone(),
                None => cv::grid_from_msg(&maps.take(e.map_stamp, t_out, "map of the episode").await?).map_err(RosError::Protocol)?,
            };
            let am = match (&amcl_map, e.amcl_map_stamp != Default::default()) {
                (Some(a), _) => Some(a.clone()),
                (None, true) => Some(cv::grid_from_msg(&amcl_maps.take(e.amcl_map_stamp, t_out, "localisation map of the episode").await?).map_err(RosError::Protocol)?),
                (None, false) => None,
            };
            let ip = &e.initial_pose.pose;
            let spread = (ip.covariance[0].sqrt(), ip.covariance[35].sqrt());
            let b = NavStack::new(&opts.setup, &m, am.as_ref().unwrap_or(&m), cv::pose2(&e.goal.pose).position(), cv::pose2(&ip.pose), Some(spread), opts.seed);
            brain = Some((s.episode, b, stamp_key(&e.start)));
        }
        let Some((_, b, start)) = brain.as_mut() else { unreachable!("set above") };
        // What this mode does not read must not pile up.
        absorb_tf(&mut buffer, [&tf_statics, &tfs]);
        if !want_truth {
            let _ = truths.latest();
        }
        let od = odoms.take(s.stamp, t_out, "odometry of this step").await?;
        let scan = match s.scan {
            true => Some(scans.take(s.stamp, t_out, "scan of this step").await?),
            false => None,
        };
        let scan_mount = match &scan {
            Some(sc) => mount(&mut buffer, &tf_statics, &tfs, &sc.header.frame_id, t_out).await?,
            None => Pose2::default(),
        };
        let truth = match want_truth {
            true => Some(cv::pose2(&truths.take(s.stamp, t_out, "ground truth of this step").await?.pose)),
            false => None,
        };
        let t = ((s.stamp.sec as i64 - start.0 as i64) * 1_000_000_000 + (s.stamp.nanosec as i64 - start.1 as i64)) as f64 / 1e9;
        let xs = scan.as_ref().map(cv::scan_from_msg);
        let odom = cv::pose2(&od.pose.pose);
        let r = b.step(NavInputs { t, odom, twist: cv::twist2(&od.twist.twist), truth, scan: xs.as_ref(), scan_mount });
        let (kind, tw) = match r {
            NavReply::Drive(tw) => (xhab_msgs::StepReply::DRIVE, tw),
            NavReply::Stop => (xhab_msgs::StepReply::STOP, Twist::default()),
            NavReply::Abort => (xhab_msgs::StepReply::ABORT, Twist::default()),
        };
        publish(&cmd_vel, "cmd_vel", cv::twist(tw))?;
        let abort_reason = match r {
            NavReply::Abort => b.abort_reason().map_or("unknown", AbortReason::as_str).to_string(),
            _ => String::new(),
        };
        let rep = xhab_msgs::StepReply { episode: s.episode, step: s.step, kind, twist: cv::twist(tw), action: 0, abort_reason };
        publish(&reply, &reply_topic, rep.clone())?;
        last = Some(rep);
        // Localisation after the reply: the simulator steps meanwhile.
        if b.amcl().is_some() {
            let now = cv::seconds(&s.stamp);
            let m2o = b.map_to_odom();
            publish(&tf_out, "/tf", tf2_msgs::TFMessage { transforms: vec![cv::tf(now, "map", "odom", cv::transform(m2o, 0.0))] })?;
            if let Some(a) = b.amcl().filter(|_| s.scan) {
                let est = a.estimate();
                let mut m = cv::pose_with_covariance(now, m2o.compose(odom), 0.0, 0.0);
                (m.pose.covariance[0], m.pose.covariance[7], m.pose.covariance[35]) = (est.variance[0], est.variance[1], est.variance[2]);
                publish(&amcl_pose, "amcl_pose", m)?;
            }
        }
    }
    flush(&brain);
    Ok(())
}

/// Where frame `frame` (a scan's) sits on the base, waiting up to `timeout` for the static
/// transform (transient local, but it may arrive after the first scan).
async fn mount(buffer: &mut TfBuffer, tf_static: &Subscription<tf2_msgs::TFMessage>, tf: &Subscription<tf2_msgs::TFMessage>, frame: &str, timeout: Duration) -> Result<Pose2, RosError> {
    let f = frame.trim_start_matches('/');
    if f.is_empty() || f == BASE_FRAME {
        return Ok(Pose2::default());
    }
    let deadline = tokio::time::Instant::now() + timeout;
    loop {
        absorb_tf(buffer, [tf_static, tf]);
        if let Some(p) = buffer.lookup(BASE_FRAME, f) {
            return Ok(p);
        }
        match tokio::time::timeout_at(deadline, tf_static.async_take()).await {
            Ok(Ok((m, _))) => {
                for t in &m.transforms {
                    buffer.insert_edge(&t.header.frame_id, &t.child_frame_id, cv::pose2_of_transform(&t.transform));
                }
            }
            Ok(Err(e)) => tracing::warn!("/tf_static: a message that does not decode was dropped: {e}"),
            Err(_) => return Err(RosError::Timeout(format!("no transform {BASE_FRAME} -> {f} (the scan's frame) on /tf_static within {:.0} s", timeout.as_secs_f64()))),
        }
    }
}
