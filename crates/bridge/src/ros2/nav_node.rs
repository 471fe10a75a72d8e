//! The native navigation stack as a ROS 2 node, with Nav2's names. In: `scan`, `odom`, `map`
//! (and `amcl/map`, transient local), `/tf` and `/tf_static`, `initialpose`, `goal_pose`,
//! `ground_truth/pose` (with `--localization ground_truth`). Out: `cmd_vel`, `amcl_pose`
//! (transient local, as Nav2's amcl), `/tf` map -> odom (only when it localises). Serves
//! the `navigate_to_pose` action ([`super::navigate_action`]), which also reports the fate
//! of `goal_pose` goals.
//!
//! It runs a controller step on each odometry message at least one controller period (sim
//! time, from the stamps) after the last, with the newest scan: the same `NavStack` as
//! in-process runs and `xhab ros nav`. A goal ends when the stack stops (reached) or aborts;
//! the base then gets a zero `cmd_vel`.

use super::convert as cv;
use super::msgs::{geometry_msgs as gm, nav_msgs, sensor_msgs, tf2_msgs, RosType};
use super::msgs::nav2_msgs::NavigateToPoseResult;
use super::navigate_action::{distance_remaining, GoalEnd, NavigateServer, Request};
use super::node::{command_qos, latched_qos, reliable_qos, sensor_data_qos, Ros2Config, Ros2Node};
use crate::nav_agent::{Localization, NavStack, NavInputs, NavReply, INITIAL_STD_XY, INITIAL_STD_YAW};
use crate::ros::names::Names;
use crate::ros::nav_node::{NavNodeOptions, NavNodeSetup};
use crate::ros::node::RosError;
use crate::ros::sim_node::AMCL_MAP_TOPIC;
use crate::ros::tf_buffer::TfBuffer;
use ros2_client::{Publisher, Subscription};
use std::time::Duration;
use xhab_types::{OccupancyGrid, Point2, Pose2, Twist};

/// The robot's frame (REP-105).
const BASE_FRAME: &str = "base_link";
/// How often the node looks at its subscriptions when nothing came (wall time).
const POLL: Duration = Duration::from_millis(2);

/// Runs the node `names` in the DDS domain of `config` in the foreground until Ctrl-C.
pub fn serve(names: Names, config: Ros2Config, node: NavNodeSetup) -> Result<(), RosError> {
    crate::ros::foreground::run_until_ctrl_c(async move {
        eprintln!("xhab: ROS 2 node {} in DDS domain {}{}", names.node_name(), config.domain_id, if config.localhost_only { " (localhost only)" } else { "" });
        run(names, config, node.options, node.map, node.amcl_map).await
    })
}

/// All samples waiting on `sub`, oldest first; samples that fail to decode are logged and
/// skipped (at most 10,000 a call, so that a flood cannot stall the node).
fn drain<T: RosType>(sub: &Subscription<T>, topic: &str) -> Vec<T> {
    let mut out = Vec::new();
    for _ in 0..10_000 {
        match sub.take() {
            Ok(Some((m, _))) => out.push(m),
            Ok(None) => break,
            Err(e) => tracing::warn!("{topic}: a message that does not decode was dropped: {e}"),
        }
    }
    out
}

fn publish<T: RosType>(p: &Publisher<T>, topic: &str, m: T) -> Result<(), RosError> {
    p.publish(m).map_err(|e| RosError::Node(format!("publishing on {topic}: {e}")))
}

/// The pose of a goal given in `frame`, in the map frame.
fn goal_in_map(buffer: &TfBuffer, frame: &str, p: Pose2, map_to_odom: Pose2) -> Option<Point2> {
    match frame.trim_start_matches('/') {
        "" | "map" => Some(p.position()),
        "odom" => Some(map_to_odom.compose(p).position()),
        f => buffer.lookup("map", f).map(|t| t.compose(p).position()),
    }
}

/// Runs the node until the future is dropped. `map`: a static map (`--map`), else the one
/// received on `map`; `amcl_map`: a static localisation map, else the one received on
/// `amcl/map`, else the map. With `opts.lockstep`, the lock-step node of [`super::nav_lockstep`].
pub async fn run(names: Names, config: Ros2Config, opts: NavNodeOptions, map: Option<OccupancyGrid>, amcl_map: Option<OccupancyGrid>) -> Result<(), RosError> {
    if opts.lockstep {
        let (_keep, shutdown) = tokio::sync::watch::channel(false);
        return super::nav_lockstep::run(names, config, opts, map, amcl_map, shutdown, None).await;
    }
    let mut node = Ros2Node::new(names, config)?;
    let cmd_vel = node.publisher::<gm::Twist>("cmd_vel", reliable_qos(10))?;
    let tf_out = node.publisher::<tf2_msgs::TFMessage>("/tf", reliable_qos(100))?;
    let amcl_pose = node.publisher::<gm::PoseWithCovarianceStamped>("amcl_pose", latched_qos())?;
    // Best-effort subscriptions match reliable and best-effort publishers alike.
    let scans = node.subscription::<sensor_msgs::LaserScan>("scan", sensor_data_qos())?;
    let odoms = node.subscription::<nav_msgs::Odometry>("odom", command_qos().history(ros2_client::qos::History::KeepLast { depth: 50 }))?;
    let maps = node.subscription::<nav_msgs::OccupancyGrid>("map", latched_qos())?;
    let amcl_maps = node.subscription::<nav_msgs::OccupancyGrid>(AMCL_MAP_TOPIC, latched_qos())?;
    let tfs = node.subscription::<tf2_msgs::TFMessage>("/tf", reliable_qos(100))?;
    let tf_statics = node.subscription::<tf2_msgs::TFMessage>("/tf_static", latched_qos().history(ros2_client::qos::History::KeepLast { depth: 100 }))?;
    let inits = node.subscription::<gm::PoseWithCovarianceStamped>("initialpose", command_qos())?;
    let goals = node.subscription::<gm::PoseStamped>("goal_pose", command_qos())?;
    let truths = node.subscription::<gm::PoseStamped>("ground_truth/pose", command_qos())?;
    let mut action = NavigateServer::new(&mut node, "navigate_to_pose")?;

    // Without its own localiser the node reads map -> odom from tf (someone else's amcl, or
    // the simulator's ground truth); it then steers by that pose.
    let mut setup = opts.setup.clone();
    let tf_localised = setup.localization == Localization::Odom;
    if tf_localised {
        setup.localization = Localization::GroundTruth;
    }
    let period = setup.params.dwa.controller_period;
    let mut buffer = TfBuffer::new();
    let mut current_map = map.clone();
    let mut current_amcl_map = amcl_map.clone();
    let mut brain: Option<NavStack> = None;
    let mut goal: Option<Point2> = None;
    let mut goal_pending = false;
    let mut init: Option<(Pose2, (f64, f64), f64)> = None; // pose, spread, stamp
    let mut last_tick: Option<f64> = None;
    let mut last_odom: Option<(f64, Pose2)> = None;
    let mut pending_scan: Option<sensor_msgs::LaserScan> = None;
    let mut truth: Option<Pose2> = None;
    loop {
        // Odometry first: what a peer sent before it (the tick's scan and tf, `initialpose`,
        // a goal) has arrived by then and is taken below, whatever the threads' timing.
        let od_now = drain(&odoms, "odom").pop();
        // A goal starts at the first odometry taken after it (never at one that came along
        // with it, which may have been sent before it).
        let goal_due = goal_pending;
        for m in drain(&tf_statics, "/tf_static").into_iter().chain(drain(&tfs, "/tf")) {
            for t in &m.transforms {
                buffer.insert_edge(&t.header.frame_id, &t.child_frame_id, cv::pose2_of_transform(&t.transform));
            }
        }
        if let Some(m) = drain(&maps, "map").pop() {
            match cv::grid_from_msg(&m) {
                Ok(g) if map.is_none() => {
                    if let Some(b) = brain.as_mut() {
                        b.set_map(&g);
                    }
                    current_map = Some(g);
                }
                Ok(_) => {}
                Err(e) => tracing::warn!("map: {e}"),
            }
        }
        if let Some(m) = drain(&amcl_maps, AMCL_MAP_TOPIC).pop() {
            match cv::grid_from_msg(&m) {
                Ok(g) if amcl_map.is_none() => current_amcl_map = Some(g),
                Ok(_) => {}
                Err(e) => tracing::warn!("{AMCL_MAP_TOPIC}: {e}"),
            }
        }
        if let Some(t) = drain(&truths, "ground_truth/pose").pop() {
            truth = Some(cv::pose2(&t.pose));
        }
        if let Some(s) = drain(&scans, "scan").pop() {
            pending_scan = Some(s);
        }
        for ip in drain(&inits, "initialpose") {
            let p = cv::pose2(&ip.pose.pose);
            if !(p.x.is_finite() && p.y.is_finite() && p.yaw.is_finite()) {
                tracing::warn!("initialpose with a non-finite pose ignored");
                continue;
            }
            let spread = (ip.pose.covariance[0].max(0.0).sqrt(), ip.pose.covariance[35].max(0.0).sqrt());
            init = Some((p, spread, cv::seconds(&ip.header.stamp)));
            // With the odometry of this instant when it came along (an episode's start).
            if let (Some(b), Some(o)) = (brain.as_mut(), od_now.as_ref().map(|o| cv::pose2(&o.pose.pose)).or(last_odom.map(|l| l.1))) {
                b.set_initial_pose(p, o, spread);
            }
            tracing::info!("initial pose ({:.2}, {:.2}, {:.2})", p.x, p.y, p.yaw);
        }
        let m2o = brain.as_ref().map_or(Pose2::default(), |b| b.map_to_odom());
        // Goals from `goal_pose` (adopted by the action), then the action's requests in order
        // (`None`: the current goal was cancelled).
        let now_s = last_odom.map_or(0.0, |o| o.0);
        let topic = drain(&goals, "goal_pose").into_iter().map(|g| (Some(g), true));
        let requests = action.poll(now_s)?.into_iter().map(|r| match r {
            Request::Goal(g) => (Some(g), false),
            Request::Cancel => (None, false),
        });
        for (g, from_topic) in topic.chain(requests).collect::<Vec<_>>() {
            let refused = match g {
                None => Some(None),
                Some(g) => match goal_in_map(&buffer, &g.header.frame_id, cv::pose2(&g.pose), m2o) {
                    Some(p) if p.x.is_finite() && p.y.is_finite() => {
                        goal = Some(p);
                        goal_pending = true;
                        if from_topic {
                            action.adopt(now_s)?;
                        }
                        None
                    }
                    Some(_) => Some(Some((NavigateToPoseResult::UNKNOWN, "a goal with a non-finite position".to_string()))),
                    None => Some(Some((NavigateToPoseResult::TF_ERROR, format!("a goal in frame '{}': no transform to map", g.header.frame_id)))),
                },
            };
            match refused {
                None => {}
                Some(Some((code, why))) if from_topic => tracing::warn!("{why} ignored (code {code})"),
                Some(end) => {
                    // The action's goal replaced the old one: the base stops.
                    if let Some((code, why)) = end {
                        tracing::warn!("{why}: aborted");
                        action.finish(GoalEnd::Aborted(code, why))?;
                    } else {
                        tracing::info!("goal cancelled");
                    }
                    (goal, goal_pending) = (None, false);
                    publish(&cmd_vel, "cmd_vel", cv::twist(Twist::default()))?;
                }
            }
        }
        let Some(od) = od_now else {
            tokio::time::sleep(POLL).await;
            continue;
        };
        let now = cv::seconds(&od.header.stamp);
        if let Some((t, _)) = last_odom {
            if now + 1e-9 < t {
                tracing::warn!("ROS time moved backwards ({t:.3} s -> {now:.3} s): the stack starts over");
                (brain, last_tick, pending_scan) = (None, None, None);
                init = init.filter(|i| i.2 <= now + 1e-9);
                goal_pending = goal.is_some();
            }
        }
        let odom = cv::pose2(&od.pose.pose);
        last_odom = Some((now, odom));
        if goal_pending && goal_due {
            if let (Some(g), Some(m)) = (goal, current_map.as_ref()) {
                match brain.as_mut() {
                    Some(b) => b.set_goal(g, now),
                    None => {
                        let (start, spread) = match init {
                            Some((p, s, _)) => (p, Some(s)),
                            None => (odom, None),
                        };
                        let mut b = NavStack::new(&setup, m, current_amcl_map.as_ref().unwrap_or(m), g, start, spread, opts.seed);
                        b.set_initial_pose(start, odom, spread.unwrap_or((INITIAL_STD_XY, INITIAL_STD_YAW)));
                        b.set_goal(g, now);
                        brain = Some(b);
                    }
                }
                goal_pending = false;
                tracing::info!("new goal ({:.2}, {:.2})", g.x, g.y);
            }
        }
        let Some(b) = brain.as_mut() else { continue };
        if goal.is_none() || goal_pending || last_tick.is_some_and(|l| now < l + period - 1e-6) {
            continue;
        }
        last_tick = Some(now);
        // The scan's mount on the base, from tf; a scan whose frame tf does not know yet is
        // skipped (the static transforms are latched and come soon).
        let scan = pending_scan.take().and_then(|s| {
            let f = s.header.frame_id.trim_start_matches('/');
            let mount = if f.is_empty() || f == BASE_FRAME { Some(Pose2::default()) } else { buffer.lookup(BASE_FRAME, f) };
            match mount {
                Some(m) => Some((cv::scan_from_msg(&s), m)),
                None => {
                    tracing::debug!("scan skipped: no transform {BASE_FRAME} -> {f} yet");
                    None
                }
            }
        });
        let pose_now = match (tf_localised, setup.localization) {
            (true, _) => Some(buffer.lookup("map", "odom").unwrap_or_default().compose(odom)),
            (false, Localization::GroundTruth) => truth,
            _ => None,
        };
        let r = b.step(NavInputs { t: now, odom, twist: cv::twist2(&od.twist.twist), truth: pose_now, scan: scan.as_ref().map(|(s, _)| s), scan_mount: scan.as_ref().map_or(Pose2::default(), |(_, m)| *m) });
        let tw = match r {
            NavReply::Drive(tw) => tw,
            NavReply::Stop | NavReply::Abort => {
                tracing::info!("goal {}", if r == NavReply::Stop { "reached" } else { "aborted: failed to reach it" });
                action.finish(if r == NavReply::Stop { GoalEnd::Reached } else { GoalEnd::navigator_abort(b.abort_reason()) })?;
                goal = None;
                Twist::default()
            }
        };
        publish(&cmd_vel, "cmd_vel", cv::twist(tw))?;
        let m2o = b.map_to_odom();
        if let Some(g) = goal {
            let here = m2o.compose(odom);
            action.feedback(now, cv::pose(here, 0.0), distance_remaining(b.navigator().plan(), here.position(), g), tw.linear, b.navigator().recoveries())?;
        }
        if b.amcl().is_some() {
            publish(&tf_out, "/tf", tf2_msgs::TFMessage { transforms: vec![cv::tf(now, "map", "odom", cv::transform(m2o, 0.0))] })?;
            if let Some(a) = b.amcl().filter(|_| scan.is_some()) {
                let est = a.estimate();
                let mut m = cv::pose_with_covariance(now, m2o.compose(odom), 0.0, 0.0);
                (m.pose.covariance[0], m.pose.covariance[7], m.pose.covariance[35]) = (est.variance[0], est.variance[1], est.variance[2]);
                publish(&amcl_pose, "amcl_pose", m)?;
            }
        }
    }
}
