//! A discrete Habitat-style agent as a ROS 1 node in xhab's lock-step protocol: each
//! `xhab/step` is answered on `xhab/step_reply` with an action (Habitat's numbering), chosen
//! from the ground-truth pose of that step (`ground_truth/pose`, taken by its stamp) and the
//! episode's goal (`xhab/episode`).

use super::convert as cv;
use super::msgs::{geometry_msgs as gm, xhab_msgs};
use super::names::Names;
use super::node::{self, RosError, RosNode, StampInbox};
use super::sim_node::{EPISODE_TOPIC, STEP_REPLY_TOPIC, STEP_TOPIC};
use crate::agents::AgentKind;
use crate::setup::{self, SceneOptions, SetupError};
use std::sync::Arc;
use std::time::Duration;
use xhab_sim::env::{EnvSnapshot, EnvView, TaskConfig};
use xhab_sim::world::World;

/// What `xhab ros agent` runs, as its flags give it: the oracle on a scene.
#[derive(Debug, Clone)]
pub struct AgentNodeOptions {
    /// The SCENE argument (the oracle's privileged knowledge: its grid and geodesics).
    pub scene: String,
    /// How to read it and the agent's size.
    pub scene_options: SceneOptions,
    /// Master URI; `None` starts one.
    pub master: Option<String>,
    /// The node's name, namespace and remappings.
    pub names: Names,
    /// How long to wait for a peer.
    pub timeout: Duration,
}

/// Why the agent node stopped with an error.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AgentNodeError {
    /// The scene could not be loaded.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The node failed.
    #[error(transparent)]
    Ros(#[from] RosError),
}

/// Loads the scene and runs the oracle as a free-running agent node in the foreground until
/// Ctrl-C (`xhab ros agent`).
pub fn serve(o: &AgentNodeOptions) -> Result<(), AgentNodeError> {
    let world = Arc::new(setup::load_world(&o.scene, &o.scene_options)?);
    let master = super::master::Master::connect_or_start(o.master.as_deref()).map_err(RosError::from)?;
    eprintln!("xhab: ROS master {}", master.uri);
    let (_keep, shutdown) = tokio::sync::watch::channel(false);
    let node = run(&master.uri, o.names.clone(), world, AgentKind::Oracle, TaskConfig::default(), o.timeout, false, shutdown);
    Ok(super::foreground::run_until_ctrl_c(node)?)
}

/// Waits for the announcement of episode `index` on `episodes` (older ones are skipped).
pub(crate) async fn episode_announcement(episodes: &mut tokio::sync::mpsc::UnboundedReceiver<xhab_msgs::Episode>, index: u32, timeout: Duration) -> Result<xhab_msgs::Episode, RosError> {
    let deadline = tokio::time::Instant::now() + timeout;
    loop {
        let left = deadline.saturating_duration_since(tokio::time::Instant::now());
        let e = node::recv(episodes, left, &format!("announcement of episode {index} on {EPISODE_TOPIC}")).await?;
        if e.index == index {
            return Ok(e);
        }
    }
}

/// Runs the agent node until `shutdown` fires (or forever): in xhab's lock-step protocol when
/// `lockstep`, else free-running (`xhab ros agent` beside `xhab ros sim`: a goal on
/// `move_base_simple/goal`, then one `action` (std_msgs/Int16) per `ground_truth/pose`).
pub async fn run(uri: &str, names: Names, world: Arc<World>, kind: AgentKind, task: TaskConfig, timeout: Duration, lockstep: bool, shutdown: tokio::sync::watch::Receiver<bool>) -> Result<(), RosError> {
    let node = RosNode::new(uri, names).await?;
    if lockstep {
        run_lockstep(node, world, kind, task, timeout, shutdown).await
    } else {
        run_free(node, world, kind, task, shutdown).await
    }
}

async fn run_free(node: RosNode, world: Arc<World>, kind: AgentKind, task: TaskConfig, mut shutdown: tokio::sync::watch::Receiver<bool>) -> Result<(), RosError> {
    let action = node.advertise::<super::msgs::std_msgs::Int16>("action", false).await?;
    let mut poses = node.subscribe::<gm::PoseStamped>("ground_truth/pose").await?;
    let mut goals = node.subscribe::<gm::PoseStamped>("move_base_simple/goal").await?;
    let mut agent = kind.build().ok_or_else(|| RosError::Protocol(format!("agent {} is not a discrete agent", kind.name())))?;
    let mut view: Option<EnvSnapshot> = None;
    let mut pose: Option<gm::PoseStamped> = None;
    loop {
        // A pose asks for an action; a goal starts an episode from the last pose (a
        // simulator in lock-step waits for the answer to the pose it sent before the goal).
        tokio::select! {
            m = poses.recv() => match m { Some(m) => pose = Some(m), None => return Ok(()) },
            g = goals.recv() => {
                let (Some(g), Some(m)) = (g, pose.as_ref()) else { continue };
                let z = m.pose.position.z;
                match world.grid_at(z) {
                    Ok(grid) => {
                        let goal = cv::pose2(&g.pose).position();
                        let field = grid.field(&[goal]);
                        agent.reset();
                        tracing::info!("new goal ({:.2}, {:.2})", goal.x, goal.y);
                        view = Some(EnvSnapshot::new(cv::pose2(&m.pose), task.clone(), grid, field));
                    }
                    Err(e) => tracing::warn!("goal ignored: the robot at height {z:.3}: {e}"),
                }
            }
            _ = shutdown.changed() => return Ok(()),
        }
        let (Some(v), Some(m)) = (view.as_mut(), pose.as_ref()) else { continue };
        v.set_pose(cv::pose2(&m.pose));
        let a = agent.act(v, None);
        tracing::debug!("agent: action {a:?} at ({:.2}, {:.2}), connected: {}", v.pose().x, v.pose().y, action.has_connected_clients());
        action.publish(&super::msgs::std_msgs::Int16 { data: a as i16 }).await.map_err(|e| RosError::Node(format!("publishing on action: {e}")))?;
        if a == xhab_sim::action::Action::Stop {
            view = None;
        }
    }
}

async fn run_lockstep(node: RosNode, world: Arc<World>, kind: AgentKind, task: TaskConfig, timeout: Duration, mut shutdown: tokio::sync::watch::Receiver<bool>) -> Result<(), RosError> {
    let reply = node.advertise::<xhab_msgs::StepReply>(STEP_REPLY_TOPIC, false).await?;
    let mut poses = StampInbox::new(node.subscribe::<gm::PoseStamped>("ground_truth/pose").await?);
    let mut episodes = node.subscribe::<xhab_msgs::Episode>(EPISODE_TOPIC).await?;
    let mut steps = node.subscribe::<xhab_msgs::Step>(STEP_TOPIC).await?;
    let mut agent = kind.build().ok_or_else(|| RosError::Protocol(format!("agent {} is not a discrete agent", kind.name())))?;
    let mut view: Option<(u32, EnvSnapshot)> = None;
    let mut last: Option<xhab_msgs::StepReply> = None;
    let pub_err = |e: String| RosError::Node(format!("publishing on {STEP_REPLY_TOPIC}: {e}"));
    loop {
        let s = tokio::select! {
            m = steps.recv() => match m { Some(m) => m, None => return Ok(()) },
            _ = shutdown.changed() => return Ok(()),
        };
        if let Some(l) = last.as_ref().filter(|l| (l.episode, l.step) >= (s.episode, s.step)) {
            // A step resent before our answer reached the simulator: answer it again.
            if (l.episode, l.step) == (s.episode, s.step) {
                reply.publish(l).await.map_err(|e| pub_err(e.to_string()))?;
            }
            continue;
        }
        if view.as_ref().is_none_or(|(i, _)| *i != s.episode) {
            let e = episode_announcement(&mut episodes, s.episode, timeout).await?;
            let z = e.goal.pose.position.z;
            let grid = world.grid_at(z).map_err(|x| RosError::Protocol(format!("episode {}: goal at height {z:.3}: {x}", e.episode_id)))?;
            let goal = cv::pose2(&e.goal.pose).position();
            let field = grid.field(&[goal]);
            agent.reset();
            view = Some((s.episode, EnvSnapshot::new(cv::pose2(&e.initial_pose.pose.pose), task.clone(), grid, field)));
        }
        let Some((_, v)) = view.as_mut() else { unreachable!("set above") };
        let p = poses.take((s.stamp.secs, s.stamp.nsecs), timeout, "ground truth of this step").await?;
        v.set_pose(cv::pose2(&p.pose));
        let a = agent.act(v, None);
        let r = xhab_msgs::StepReply { episode: s.episode, step: s.step, kind: xhab_msgs::StepReply::ACTION, action: a as i16, ..Default::default() };
        reply.publish(&r).await.map_err(|e| pub_err(e.to_string()))?;
        last = Some(r);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_that_does_not_load_fails_before_any_master_is_used() {
        let o = AgentNodeOptions {
            scene: "/nonexistent/house.glb".into(),
            scene_options: SceneOptions::default(),
            // Nothing listens there: reaching it would be a different error.
            master: Some("http://127.0.0.1:9/".into()),
            names: Names::from_args("xhab_agent", &[], None).unwrap(),
            timeout: Duration::from_secs(1),
        };
        let e = serve(&o).unwrap_err();
        assert!(matches!(e, AgentNodeError::Setup(_)) && e.to_string().starts_with("loading scene /nonexistent/house.glb"), "{e}");
    }
}
