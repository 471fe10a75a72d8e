//! The native navigation stack as a move_base-compatible ROS 1 node. In: `scan`, `odom`,
//! `map` (and `amcl/map`), `/tf` and `/tf_static`, `initialpose`, `move_base_simple/goal`,
//! the `move_base` action. Out: `cmd_vel`, `amcl_pose`, `particlecloud`, `/tf` map -> odom
//! (only when it localises), `move_base/GlobalPlanner/plan`, `move_base/DWAPlannerROS/local_plan`,
//! the action's status, feedback and result; service `move_base/clear_costmaps`.
//!
//! Free-running (a robot, `xhab ros sim`, `xhab bench --agent ros`), it runs a controller step
//! on each odometry message at least one controller period (sim time, from the stamps) after
//! the last, with the newest scan. Lock-step with xhab's simulator (`xhab bench --ros`), it
//! answers each `xhab/step` on `xhab/step_reply`, taking that step's odometry, scan and ground
//! truth by their stamp, so results equal the in-process run's.

use super::agent_node::episode_announcement;
use super::convert as cv;
use super::move_base_server::{status, MoveBaseServer, ServerEvent};
use super::msgs::{geometry_msgs as gm, nav_msgs, sensor_msgs, std_srvs, tf2_msgs, xhab_msgs};
use super::names::Names;
use super::node::{RosError, RosNode, StampInbox};
use super::sim_node::{AMCL_MAP_TOPIC, EPISODE_TOPIC, STEP_REPLY_TOPIC, STEP_TOPIC};
use super::tf_buffer::TfBuffer;
use super::master::Master;
use crate::benchmark::{nav_params, ParamError, ParamFile};
use crate::nav_agent::{Localization, NavStack, NavInputs, NavReply, NavSetup};
use crate::setup::{self, SetupError};
use roslibrust::ros1::Publisher;
use xhab_nav::navigator::AbortReason;
use std::path::PathBuf;
use std::time::Duration;
use tokio::sync::{mpsc, watch};
use xhab_types::{OccupancyGrid, Point2, Pose2, Twist};

/// How the node runs.
#[derive(Debug, Clone)]
pub struct NavNodeOptions {
    /// The stack's setup (parameters, localisation, scan period).
    pub setup: NavSetup,
    /// Lock-step with xhab's simulator (one reply per `xhab/step`).
    pub lockstep: bool,
    /// Seed of AMCL.
    pub seed: u64,
    /// How long to wait for a peer (s).
    pub timeout: Duration,
}

/// What `xhab ros nav` runs, as its flags give it.
#[derive(Debug, Clone)]
pub struct NavNodeSpec {
    /// The static map (map_server YAML); `None`: the map received on `map`.
    pub map: Option<PathBuf>,
    /// The map AMCL localises on (map_server YAML); `None`: the one received on `amcl/map`,
    /// else the navigation map.
    pub amcl_map: Option<PathBuf>,
    /// Localisation.
    pub localization: Localization,
    /// ROS parameter files, layered in order (`FILE[@NAMESPACE]`).
    pub nav_params: Vec<ParamFile>,
    /// Robot profile (built-in name or YAML file) whose size the costmaps take where the
    /// files give no footprint or robot_radius.
    pub robot: String,
    /// Seed of AMCL.
    pub seed: u64,
    /// Lock-step with xhab's simulator.
    pub lockstep: bool,
    /// How long to wait for a peer.
    pub timeout: Duration,
}

/// The nav node ready to run: its options, the static maps, and the warnings of its
/// parameter files.
#[derive(Debug, Clone)]
pub struct NavNodeSetup {
    /// The node's options (parameters sized to the robot).
    pub options: NavNodeOptions,
    /// The static map, if given.
    pub map: Option<OccupancyGrid>,
    /// The static localisation map, if given.
    pub amcl_map: Option<OccupancyGrid>,
    /// Warnings for the user (unknown nav parameters), in order.
    pub warnings: Vec<String>,
}

/// Why the nav node could not be set up. Messages name the flag or file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum NavNodeSetupError {
    /// The robot or a map could not be loaded.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The nav parameter files could not be loaded.
    #[error(transparent)]
    NavParams(#[from] ParamError),
}

impl NavNodeSetup {
    /// Loads the robot, the parameters (their costmaps sized to the robot, as `xhab bench
    /// --agent nav` does) and the maps `spec` names.
    pub fn build(spec: &NavNodeSpec) -> Result<NavNodeSetup, NavNodeSetupError> {
        let robot = setup::robot_profile(&spec.robot)?;
        let (params, warnings) = nav_params(&spec.nav_params, Some(&robot))?;
        let map = spec.map.as_deref().map(setup::load_static_map).transpose()?;
        let amcl_map = spec.amcl_map.as_deref().map(setup::load_static_map).transpose()?;
        let setup = NavSetup { params, map: None, localization: spec.localization, scan: None, scan_period: 0.1 };
        let options = NavNodeOptions { setup, lockstep: spec.lockstep, seed: spec.seed, timeout: spec.timeout };
        Ok(NavNodeSetup { options, map, amcl_map, warnings })
    }
}

/// Runs the node `node` as `names` in the foreground, with the master at `master` (`None`:
/// one started for it), until Ctrl-C.
pub fn serve(master: Option<&str>, names: Names, node: NavNodeSetup) -> Result<(), RosError> {
    let master = Master::connect_or_start(master)?;
    eprintln!("xhab: ROS master {}", master.uri);
    let (_keep, shutdown) = watch::channel(false);
    super::foreground::run_until_ctrl_c(run(&master.uri, names, node.options, node.map, node.amcl_map, shutdown, None))
}

/// The robot's frame (REP-105).
const BASE_FRAME: &str = "base_link";

struct Outputs {
    cmd_vel: Publisher<gm::Twist>,
    amcl_pose: Publisher<gm::PoseWithCovarianceStamped>,
    particlecloud: Publisher<gm::PoseArray>,
    tf: Publisher<tf2_msgs::TFMessage>,
    plan: Publisher<nav_msgs::Path>,
    local_plan: Publisher<nav_msgs::Path>,
}

fn perr(topic: &str, e: impl std::fmt::Display) -> RosError {
    RosError::Node(format!("publishing on {topic}: {e}"))
}

impl Outputs {
    async fn new(node: &RosNode) -> Result<Self, RosError> {
        Ok(Outputs {
            cmd_vel: node.advertise("cmd_vel", false).await?,
            amcl_pose: node.advertise("amcl_pose", false).await?,
            particlecloud: node.advertise("particlecloud", false).await?,
            tf: node.advertise("/tf", false).await?,
            plan: node.advertise("move_base/GlobalPlanner/plan", false).await?,
            local_plan: node.advertise("move_base/DWAPlannerROS/local_plan", false).await?,
        })
    }

    async fn drive(&self, tw: Twist) -> Result<(), RosError> {
        self.cmd_vel.publish(&cv::twist(tw)).await.map_err(|e| perr("cmd_vel", e))
    }

    /// Localisation (map -> odom when AMCL runs) and the local plan at every step; the pose
    /// estimate, particles and global plan when `scanned` (a scan came: 10 Hz, not 20).
    async fn report(&self, brain: &NavStack, stamp: f64, odom: Pose2, cmd: Twist, dwa_sim_time: f64, scanned: bool) -> Result<(), RosError> {
        let m2o = brain.map_to_odom();
        if brain.amcl().is_some() {
            let m = tf2_msgs::TFMessage { transforms: vec![cv::tf(stamp, "map", "odom", cv::transform(m2o, 0.0))] };
            self.tf.publish(&m).await.map_err(|e| perr("/tf", e))?;
        }
        if let Some(a) = brain.amcl().filter(|_| scanned) {
            let est = a.estimate();
            let mut m = cv::pose_with_covariance(stamp, m2o.compose(odom), 0.0, 0.0);
            m.pose.covariance[0] = est.variance[0];
            m.pose.covariance[7] = est.variance[1];
            m.pose.covariance[35] = est.variance[2];
            self.amcl_pose.publish(&m).await.map_err(|e| perr("amcl_pose", e))?;
            let poses = a.particles().iter().map(|(p, _)| cv::pose(*p, 0.0)).collect();
            self.particlecloud.publish(&gm::PoseArray { header: cv::header(stamp, "map"), poses }).await.map_err(|e| perr("particlecloud", e))?;
        }
        let path = |poses: Vec<Pose2>, frame: &str| nav_msgs::Path {
            header: cv::header(stamp, frame),
            poses: poses.into_iter().map(|p| gm::PoseStamped { header: cv::header(stamp, frame), pose: cv::pose(p, 0.0) }).collect(),
        };
        if scanned {
            self.plan.publish(&path(brain.navigator().plan().to_vec(), "map")).await.map_err(|e| perr("plan", e))?;
        }
        // The local plan: the trajectory DWA chose, rolled out over its sim_time (odom frame).
        let mut p = odom;
        let mut local = vec![p];
        let n = 10;
        let dt = dwa_sim_time / n as f64;
        for _ in 0..n {
            p = p.compose(Pose2::new(cmd.linear * dt, 0.0, cmd.angular * dt));
            local.push(p);
        }
        self.local_plan.publish(&path(local, "odom")).await.map_err(|e| perr("local_plan", e))
    }
}

/// The inputs both modes read.
struct Inputs {
    scans: StampInbox<sensor_msgs::LaserScan>,
    maps: StampInbox<nav_msgs::OccupancyGrid>,
    amcl_maps: StampInbox<nav_msgs::OccupancyGrid>,
    truths: StampInbox<gm::PoseStamped>,
    tf: mpsc::UnboundedReceiver<tf2_msgs::TFMessage>,
    tf_static: mpsc::UnboundedReceiver<tf2_msgs::TFMessage>,
    buffer: TfBuffer,
}

impl Inputs {
    fn absorb_tf(&mut self) {
        while let Ok(m) = self.tf_static.try_recv() {
            self.buffer.insert(&m);
        }
        while let Ok(m) = self.tf.try_recv() {
            self.buffer.insert(&m);
        }
    }

    /// Where frame `frame` (a scan's) sits on the base, waiting up to `timeout` for the
    /// static transform (it is latched, but may arrive after the first scan).
    async fn mount(&mut self, frame: &str, timeout: Duration) -> Result<Pose2, RosError> {
        let deadline = tokio::time::Instant::now() + timeout;
        loop {
            self.absorb_tf();
            if let Some(p) = self.buffer.lookup(BASE_FRAME, frame) {
                return Ok(p);
            }
            if frame.is_empty() || frame.trim_start_matches('/') == BASE_FRAME {
                return Ok(Pose2::default());
            }
            match tokio::time::timeout_at(deadline, self.tf_static.recv()).await {
                Ok(Some(m)) => self.buffer.insert(&m),
                _ => return Err(RosError::Timeout(format!("no transform {BASE_FRAME} -> {frame} (the scan's frame) on /tf_static within {:.0} s", timeout.as_secs_f64()))),
            }
        }
    }
}

fn stamp_of(t: &roslibrust::codegen::integral_types::Time) -> (i32, i32) {
    (t.secs, t.nsecs)
}

/// Runs the node until `shutdown` fires. `map`: a static map (`--map`), else the one received
/// on `map`; `amcl_map`: a static localisation map (`--amcl-map`), else the one received on
/// `amcl/map`, else the map. In lock-step runs, each episode's mean localisation error is
/// sent on `stats` when the next episode begins or the node stops.
pub async fn run(uri: &str, names: Names, opts: NavNodeOptions, map: Option<OccupancyGrid>, amcl_map: Option<OccupancyGrid>, shutdown: watch::Receiver<bool>, stats: Option<mpsc::UnboundedSender<Option<[f64; 2]>>>) -> Result<(), RosError> {
    let node = RosNode::new(uri, names).await?;
    let out = Outputs::new(&node).await?;
    let inputs = Inputs {
        scans: StampInbox::new(node.subscribe("scan").await?),
        maps: StampInbox::new(node.subscribe("map").await?),
        amcl_maps: StampInbox::new(node.subscribe(AMCL_MAP_TOPIC).await?),
        truths: StampInbox::new(node.subscribe("ground_truth/pose").await?),
        tf: node.subscribe("/tf").await?,
        tf_static: node.subscribe("/tf_static").await?,
        buffer: TfBuffer::new(),
    };
    if opts.lockstep {
        lockstep(&node, out, inputs, opts, map, amcl_map, shutdown, stats).await
    } else {
        free_running(&node, out, inputs, opts, map, amcl_map, shutdown).await
    }
}

#[allow(clippy::too_many_arguments)]
async fn lockstep(node: &RosNode, out: Outputs, mut inp: Inputs, opts: NavNodeOptions, map: Option<OccupancyGrid>, amcl_map: Option<OccupancyGrid>, mut shutdown: watch::Receiver<bool>, stats: Option<mpsc::UnboundedSender<Option<[f64; 2]>>>) -> Result<(), RosError> {
    let reply = node.advertise::<xhab_msgs::StepReply>(STEP_REPLY_TOPIC, false).await?;
    let mut episodes = node.subscribe::<xhab_msgs::Episode>(EPISODE_TOPIC).await?;
    let mut steps = node.subscribe::<xhab_msgs::Step>(STEP_TOPIC).await?;
    let mut odoms = StampInbox::new(node.subscribe::<nav_msgs::Odometry>("odom").await?);
    let want_truth = opts.setup.localization == Localization::GroundTruth || stats.is_some();
    let mut brain: Option<(u32, NavStack, (i32, i32))> = None;
    let mut last: Option<xhab_msgs::StepReply> = None;
    let flush = |b: &Option<(u32, NavStack, (i32, i32))>| {
        if let (Some(tx), Some((_, b, _))) = (stats.as_ref(), b.as_ref()) {
            let _ = tx.send(b.localization_error());
        }
    };
    let t_out = opts.timeout;
    loop {
        let s = tokio::select! {
            m = steps.recv() => match m { Some(m) => m, None => break },
            _ = shutdown.changed() => break,
        };
        if let Some(l) = last.as_ref().filter(|l| (l.episode, l.step) >= (s.episode, s.step)) {
            if (l.episode, l.step) == (s.episode, s.step) {
                reply.publish(l).await.map_err(|e| perr(STEP_REPLY_TOPIC, e))?;
            }
            continue;
        }
        if brain.as_ref().is_none_or(|(i, _, _)| *i != s.episode) {
            flush(&brain);
            let e = episode_announcement(&mut episodes, s.episode, t_out).await?;
            let m = match &map {
                Some(m) => m.clone(),
                None => cv::grid_from_msg(&inp.maps.take(stamp_of(&e.map_stamp), t_out, "map of the episode").await?).map_err(RosError::Protocol)?,
            };
            let am = match (&amcl_map, e.amcl_map_stamp.secs != 0 || e.amcl_map_stamp.nsecs != 0) {
                (Some(a), _) => Some(a.clone()),
                (None, true) => Some(cv::grid_from_msg(&inp.amcl_maps.take(stamp_of(&e.amcl_map_stamp), t_out, "localisation map of the episode").await?).map_err(RosError::Protocol)?),
                (None, false) => None,
            };
            let ip = &e.initial_pose.pose;
            let spread = (ip.covariance[0].sqrt(), ip.covariance[35].sqrt());
            let b = NavStack::new(&opts.setup, &m, am.as_ref().unwrap_or(&m), cv::pose2(&e.goal.pose).position(), cv::pose2(&ip.pose), Some(spread), opts.seed);
            brain = Some((s.episode, b, stamp_of(&e.start)));
        }
        let Some((_, b, start)) = brain.as_mut() else { unreachable!("set above") };
        let stamp = stamp_of(&s.stamp);
        // What this mode does not read must not pile up in the channels.
        inp.absorb_tf();
        if !want_truth {
            let _ = inp.truths.latest();
        }
        let od = odoms.take(stamp, t_out, "odometry of this step").await?;
        let scan = match s.scan {
            true => Some(inp.scans.take(stamp, t_out, "scan of this step").await?),
            false => None,
        };
        let scan_mount = match &scan {
            Some(sc) => inp.mount(&sc.header.frame_id, t_out).await?,
            None => Pose2::default(),
        };
        let truth = match want_truth {
            true => Some(cv::pose2(&inp.truths.take(stamp, t_out, "ground truth of this step").await?.pose)),
            false => None,
        };
        let t = ((stamp.0 as i64 - start.0 as i64) * 1_000_000_000 + (stamp.1 as i64 - start.1 as i64)) as f64 / 1e9;
        let xs = scan.as_ref().map(cv::scan_from_msg);
        let odom = cv::pose2(&od.pose.pose);
        let r = b.step(NavInputs { t, odom, twist: cv::twist2(&od.twist.twist), truth, scan: xs.as_ref(), scan_mount });
        let (kind, tw) = match r {
            NavReply::Drive(tw) => (xhab_msgs::StepReply::DRIVE, tw),
            NavReply::Stop => (xhab_msgs::StepReply::STOP, Twist::default()),
            NavReply::Abort => (xhab_msgs::StepReply::ABORT, Twist::default()),
        };
        out.drive(tw).await?;
        let abort_reason = match r {
            NavReply::Abort => b.abort_reason().map_or("unknown", AbortReason::as_str).to_string(),
            _ => String::new(),
        };
        let rep = xhab_msgs::StepReply { episode: s.episode, step: s.step, kind, twist: cv::twist(tw), action: 0, abort_reason };
        reply.publish(&rep).await.map_err(|e| perr(STEP_REPLY_TOPIC, e))?;
        last = Some(rep);
        out.report(b, cv::seconds(&s.stamp), odom, tw, opts.setup.params.dwa.sim_time, s.scan).await?;
    }
    flush(&brain);
    Ok(())
}

/// The pose of a goal given in `frame`, in the map frame.
fn goal_in_map(buffer: &TfBuffer, frame: &str, p: Pose2, map_to_odom: Pose2) -> Option<Point2> {
    match frame.trim_start_matches('/') {
        "" | "map" => Some(p.position()),
        "odom" => Some(map_to_odom.compose(p).position()),
        f => buffer.lookup("map", f).map(|t| t.compose(p).position()),
    }
}

#[allow(clippy::too_many_arguments)]
async fn free_running(node: &RosNode, out: Outputs, mut inp: Inputs, opts: NavNodeOptions, map: Option<OccupancyGrid>, amcl_map: Option<OccupancyGrid>, mut shutdown: watch::Receiver<bool>) -> Result<(), RosError> {
    let mut odoms = node.subscribe::<nav_msgs::Odometry>("odom").await?;
    let mut simple_goals = node.subscribe::<gm::PoseStamped>("move_base_simple/goal").await?;
    let mut inits = node.subscribe::<gm::PoseWithCovarianceStamped>("initialpose").await?;
    let mut server = MoveBaseServer::new(node).await?;
    let (clear_tx, mut clear_rx) = mpsc::unbounded_channel::<()>();
    let _clear = node
        .nh
        .advertise_service::<std_srvs::Empty, _>(&node.names.resolve("move_base/clear_costmaps"), move |_req| {
            let _ = clear_tx.send(());
            Ok(std_srvs::EmptyResponse {})
        })
        .await
        .map_err(|e| RosError::Node(format!("advertising move_base/clear_costmaps: {e}")))?;
    // Without its own localiser the node reads map -> odom from tf (someone else's amcl, or
    // the simulator's ground truth); it then steers by that pose.
    let mut setup = opts.setup.clone();
    let tf_localised = setup.localization == Localization::Odom;
    if tf_localised {
        setup.localization = Localization::GroundTruth;
    }
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
    let mut ticker = tokio::time::interval(Duration::from_millis(200));
    let period = setup.params.dwa.controller_period;
    loop {
        let od = tokio::select! {
            m = odoms.recv() => match m { Some(m) => Some(m), None => break },
            _ = ticker.tick() => None,
            c = clear_rx.recv() => {
                if c.is_some() {
                    if let Some(b) = brain.as_mut() { b.clear_costmaps(); }
                    tracing::info!("costmaps cleared");
                }
                continue;
            }
            _ = shutdown.changed() => break,
        };
        inp.absorb_tf();
        let now = match &od {
            Some(o) => cv::seconds(&o.header.stamp),
            None => last_odom.map_or(0.0, |(t, _)| t),
        };
        if let (Some(_), Some((t, _))) = (&od, last_odom) {
            if now + 1e-9 < t {
                // A new simulation (another benchmark run) restarted the clock: start over
                // from the next odometry, keeping the goal and an initial pose of the new run.
                tracing::warn!("ROS time moved backwards ({t:.3} s -> {now:.3} s): the stack starts over");
                (brain, last_tick, pending_scan, last_odom) = (None, None, None, None);
                init = init.filter(|i| i.2 <= now + 1e-9);
                goal_pending = goal.is_some();
            }
        }
        if let Some(m) = inp.maps.latest() {
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
        if let Some(m) = inp.amcl_maps.latest() {
            match cv::grid_from_msg(&m) {
                Ok(g) if amcl_map.is_none() => current_amcl_map = Some(g),
                Ok(_) => {}
                Err(e) => tracing::warn!("{AMCL_MAP_TOPIC}: {e}"),
            }
        }
        if let Some(t) = inp.truths.latest() {
            truth = Some(cv::pose2(&t.pose));
        }
        let m2o = brain.as_ref().map_or(Pose2::default(), |b| b.map_to_odom());
        while let Ok(ip) = inits.try_recv() {
            let p = cv::pose2(&ip.pose.pose);
            let spread = (ip.pose.covariance[0].sqrt(), ip.pose.covariance[35].sqrt());
            init = Some((p, spread, cv::seconds(&ip.header.stamp)));
            if let (Some(b), Some((_, o))) = (brain.as_mut(), last_odom) {
                b.set_initial_pose(p, o, spread);
            }
            tracing::info!("initial pose ({:.2}, {:.2}, {:.2})", p.x, p.y, p.yaw);
        }
        while let Ok(g) = simple_goals.try_recv() {
            match goal_in_map(&inp.buffer, &g.header.frame_id, cv::pose2(&g.pose), m2o) {
                Some(p) => {
                    server.adopt(now).await?;
                    goal = Some(p);
                    goal_pending = true;
                }
                None => tracing::warn!("goal in frame '{}' ignored: no transform to map", g.header.frame_id),
            }
        }
        for ev in server.poll(now).await? {
            match ev {
                ServerEvent::NewGoal(g) => match goal_in_map(&inp.buffer, &g.header.frame_id, cv::pose2(&g.pose), m2o) {
                    Some(p) => {
                        goal = Some(p);
                        goal_pending = true;
                    }
                    None => server.finish(status::ABORTED, &format!("no transform from '{}' to map", g.header.frame_id), now).await?,
                },
                ServerEvent::Cancelled => {
                    goal = None;
                    goal_pending = false;
                    out.drive(Twist::default()).await?;
                }
            }
        }
        let Some(od) = od else {
            server.publish_status(now).await?;
            continue;
        };
        let odom = cv::pose2(&od.pose.pose);
        last_odom = Some((now, odom));
        if goal_pending {
            if let (Some(g), Some(m)) = (goal, current_map.as_ref()) {
                match brain.as_mut() {
                    Some(b) => b.set_goal(g, now),
                    None => {
                        let (start, spread) = match init {
                            Some((p, s, _)) => (p, Some(s)),
                            None => (odom, None),
                        };
                        let mut b = NavStack::new(&setup, m, current_amcl_map.as_ref().unwrap_or(m), g, start, spread, opts.seed);
                        b.set_initial_pose(start, odom, spread.unwrap_or((crate::nav_agent::INITIAL_STD_XY, crate::nav_agent::INITIAL_STD_YAW)));
                        b.set_goal(g, now);
                        brain = Some(b);
                    }
                }
                goal_pending = false;
                tracing::info!("new goal ({:.2}, {:.2})", g.x, g.y);
            }
        }
        if let Some(s) = inp.scans.latest() {
            pending_scan = Some(s);
        }
        let Some(b) = brain.as_mut() else { continue };
        if goal.is_none() || last_tick.is_some_and(|l| now < l + period - 1e-6) {
            continue;
        }
        last_tick = Some(now);
        let scan = pending_scan.take();
        let scan_mount = match &scan {
            Some(s) => inp.mount(&s.header.frame_id, opts.timeout).await?,
            None => Pose2::default(),
        };
        let pose_now = match (tf_localised, setup.localization) {
            (true, _) => Some(inp.buffer.lookup("map", "odom").unwrap_or_default().compose(odom)),
            (false, Localization::GroundTruth) => truth,
            _ => None,
        };
        let xs = scan.as_ref().map(cv::scan_from_msg);
        let r = b.step(NavInputs { t: now, odom, twist: cv::twist2(&od.twist.twist), truth: pose_now, scan: xs.as_ref(), scan_mount });
        let tw = match r {
            NavReply::Drive(tw) => tw,
            NavReply::Stop | NavReply::Abort => {
                let (code, text) = if r == NavReply::Stop { (status::SUCCEEDED, "goal reached") } else { (status::ABORTED, "failed to reach the goal") };
                server.finish(code, text, now).await?;
                tracing::info!("goal {}", text);
                goal = None;
                Twist::default()
            }
        };
        out.drive(tw).await?;
        out.report(b, now, odom, tw, setup.params.dwa.sim_time, xs.is_some()).await?;
        if goal.is_some() {
            let pose = b.map_to_odom().compose(odom);
            server.feedback(now, gm::PoseStamped { header: cv::header(now, "map"), pose: cv::pose(pose, 0.0) }).await?;
        }
        server.publish_status(now).await?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> NavNodeSpec {
        NavNodeSpec { map: None, amcl_map: None, localization: Localization::Amcl, nav_params: Vec::new(), robot: "turtlebot3_burger".into(), seed: 3, lockstep: false, timeout: Duration::from_secs(1) }
    }

    #[test]
    fn the_costmaps_take_the_robots_size_and_files_warn_or_fail() {
        let node = NavNodeSetup::build(&spec()).unwrap();
        let robot = setup::robot_profile("turtlebot3_burger").unwrap();
        let (sized, _) = nav_params(&[], Some(&robot)).unwrap();
        assert_eq!(node.options.setup.params, sized);
        assert_eq!((node.options.seed, node.options.setup.localization), (3, Localization::Amcl));
        assert!(node.map.is_none() && node.amcl_map.is_none() && node.warnings.is_empty());
        let dir = std::env::temp_dir().join(format!("xhab-nav-node-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let y = dir.join("nav.yaml");
        std::fs::write(&y, "DWAPlannerROS:\n  no_such_key: 1\n").unwrap();
        let node = NavNodeSetup::build(&NavNodeSpec { nav_params: vec![y.to_str().unwrap().parse().unwrap()], ..spec() }).unwrap();
        assert!(node.warnings.iter().any(|w| w.contains("no_such_key")), "{:?}", node.warnings);
        std::fs::write(&y, "DWAPlannerROS:\n  sim_granularity: 0\n").unwrap();
        let e = NavNodeSetup::build(&NavNodeSpec { nav_params: vec![y.to_str().unwrap().parse().unwrap()], ..spec() }).unwrap_err().to_string();
        assert!(e.contains("nav.yaml: DWAPlannerROS/sim_granularity"), "{e}");
        let e = NavNodeSetup::build(&NavNodeSpec { amcl_map: Some(dir.join("none.yaml")), ..spec() }).unwrap_err().to_string();
        assert!(e.starts_with("loading map"), "{e}");
        assert!(NavNodeSetup::build(&NavNodeSpec { robot: "no_such_robot".into(), ..spec() }).unwrap_err().to_string().starts_with("--robot no_such_robot"));
        std::fs::remove_dir_all(&dir).ok();
    }
}
