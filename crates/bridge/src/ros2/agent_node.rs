//! A discrete Habitat-style agent (the oracle) as a ROS 2 node: `xhab ros2 agent`. Free-running
//! beside `xhab ros2 sim`, a goal on `goal_pose` (Nav2's name) starts an episode from the
//! last `ground_truth/pose`, and each newer pose is answered with one `action`
//! (std_msgs/Int16, Habitat's numbering). In lock-step (`xhab bench --ros2`) each
//! `xhab/step` is answered on `xhab/step_reply`, from the pose of that step (taken by its
//! stamp) and the episode's goal (`xhab/episode`).

use super::convert as cv;
use super::lockstep::{episode_announcement, lockstep_qos, stamp_key, Inbox};
use super::msgs::{geometry_msgs as gm, std_msgs};
use super::node::{command_qos, latched_qos, reliable_qos, Ros2Config, Ros2Node};
use super::xhab_msgs;
use crate::agents::AgentKind;
use crate::ros::agent_node::AgentNodeError;
use crate::ros::names::Names;
use crate::ros::node::RosError;
use crate::ros::sim_node::{EPISODE_TOPIC, STEP_REPLY_TOPIC, STEP_TOPIC};
use crate::setup::{self, SceneOptions};
use std::sync::Arc;
use std::time::Duration;
use xhab_sim::env::{EnvSnapshot, EnvView, TaskConfig};
use xhab_sim::world::World;

/// What `xhab ros2 agent` runs, as its flags give it: the oracle on a scene.
#[derive(Debug, Clone)]
pub struct Agent2Options {
    /// The SCENE argument (the oracle's privileged knowledge: its grid and geodesics).
    pub scene: String,
    /// How to read it and the agent's size.
    pub scene_options: SceneOptions,
    /// The node's name, namespace and remappings.
    pub names: Names,
    /// The DDS domain and discovery range.
    pub config: Ros2Config,
    /// How long to wait for a peer (lock-step).
    pub timeout: Duration,
    /// Answer xhab's lock-step protocol (`xhab/step`) instead of running free.
    pub lockstep: bool,
}

/// Loads the scene and runs the oracle as a ROS 2 node (free-running, or in lock-step) in the
/// foreground until Ctrl-C (`xhab ros2 agent`).
pub fn serve(o: &Agent2Options) -> Result<(), AgentNodeError> {
    let world = Arc::new(setup::load_world(&o.scene, &o.scene_options)?);
    let (_keep, shutdown) = tokio::sync::watch::channel(false);
    eprintln!("xhab: ROS 2 node {} in DDS domain {}{}", o.names.node_name(), o.config.domain_id, if o.config.localhost_only { " (localhost only)" } else { "" });
    let node = run(o.names.clone(), o.config, world, AgentKind::Oracle, TaskConfig::default(), o.timeout, o.lockstep, shutdown);
    Ok(crate::ros::foreground::run_until_ctrl_c(node)?)
}

/// Runs the agent node until `shutdown` fires (or forever): in xhab's lock-step protocol when
/// `lockstep`, else free-running.
#[allow(clippy::too_many_arguments)]
pub async fn run(names: Names, config: Ros2Config, world: Arc<World>, kind: AgentKind, task: TaskConfig, timeout: Duration, lockstep: bool, shutdown: tokio::sync::watch::Receiver<bool>) -> Result<(), RosError> {
    let node = Ros2Node::new(names, config)?;
    let agent = kind.build().ok_or_else(|| RosError::Protocol(format!("agent {} is not a discrete agent", kind.name())))?;
    if lockstep {
        run_lockstep(node, world, agent, task, timeout, shutdown).await
    } else {
        run_free(node, world, agent, task, shutdown).await
    }
}

type Agent = Box<dyn crate::agents::DiscreteAgent>;

/// How long a free-running agent waits for a newer pose before it sends its action again
/// (wall time).
const ANSWER_AGAIN: Duration = Duration::from_secs(1);

async fn run_free(mut node: Ros2Node, world: Arc<World>, mut agent: Agent, task: TaskConfig, mut shutdown: tokio::sync::watch::Receiver<bool>) -> Result<(), RosError> {
    let action = node.publisher::<std_msgs::Int16>("action", reliable_qos(10))?;
    let action_topic = node.names.resolve("action");
    let poses = node.subscription::<gm::PoseStamped>("ground_truth/pose", command_qos())?;
    let goals = node.subscription::<gm::PoseStamped>("goal_pose", command_qos())?;
    let mut view: Option<EnvSnapshot> = None;
    let mut pose: Option<gm::PoseStamped> = None;
    // The stamp of the last pose acted on, when, and the action: a simulator in lock-step
    // publishes its state again while it waits, and one pose gets one action, sent again only
    // when the simulator still waits after ANSWER_AGAIN (the first actions of a run can reach
    // no one before discovery has matched the simulator's subscription).
    let mut acted: Option<((i32, u32), std::time::Instant, i16)> = None;
    loop {
        // A pose asks for an action; a goal starts an episode from the last pose.
        let fresh_goal = tokio::select! {
            m = poses.async_take() => match m {
                Ok((m, _)) => { pose = Some(m); false }
                Err(e) => { tracing::warn!("ground_truth/pose: a message that does not decode was dropped: {e}"); continue }
            },
            g = goals.async_take() => {
                let g = match g { Ok((g, _)) => g, Err(e) => { tracing::warn!("goal_pose: a message that does not decode was dropped: {e}"); continue } };
                let Some(m) = pose.as_ref() else {
                    tracing::warn!("goal ignored: no ground_truth/pose yet");
                    continue;
                };
                let z = m.pose.position.z;
                match world.grid_at(z) {
                    Ok(grid) => {
                        let goal = cv::pose2(&g.pose).position();
                        let field = grid.field(&[goal]);
                        agent.reset();
                        tracing::info!("new goal ({:.2}, {:.2})", goal.x, goal.y);
                        view = Some(EnvSnapshot::new(cv::pose2(&m.pose), task.clone(), grid, field));
                        true
                    }
                    Err(e) => { tracing::warn!("goal ignored: the robot at height {z:.3}: {e}"); continue }
                }
            }
            _ = shutdown.changed() => return Ok(()),
        };
        let (Some(v), Some(m)) = (view.as_mut(), pose.as_ref()) else { continue };
        let key = stamp_key(&m.header.stamp);
        let data = match acted {
            Some((k, at, a)) if !fresh_goal && key == k && at.elapsed() >= ANSWER_AGAIN => a,
            Some((k, _, _)) if !fresh_goal && key <= k => continue,
            _ => {
                v.set_pose(cv::pose2(&m.pose));
                let a = agent.act(v, None);
                tracing::debug!("agent: action {a:?} at ({:.2}, {:.2})", v.pose().x, v.pose().y);
                if a == xhab_sim::action::Action::Stop {
                    view = None;
                }
                a as i16
            }
        };
        acted = Some((key, std::time::Instant::now(), data));
        action.async_publish(std_msgs::Int16 { data }).await.map_err(|e| RosError::Node(format!("publishing on {action_topic}: {e}")))?;
    }
}

async fn run_lockstep(mut node: Ros2Node, world: Arc<World>, mut agent: Agent, task: TaskConfig, timeout: Duration, mut shutdown: tokio::sync::watch::Receiver<bool>) -> Result<(), RosError> {
    let reply = node.publisher::<xhab_msgs::StepReply>(STEP_REPLY_TOPIC, lockstep_qos())?;
    let mut poses: Inbox<gm::PoseStamped> = Inbox::subscribe(&mut node, "ground_truth/pose", lockstep_qos())?;
    let episodes = node.subscription::<xhab_msgs::Episode>(EPISODE_TOPIC, latched_qos().history(ros2_client::qos::History::KeepLast { depth: 10 }))?;
    let steps = node.subscription::<xhab_msgs::Step>(STEP_TOPIC, lockstep_qos())?;
    let reply_topic = node.names.resolve(STEP_REPLY_TOPIC);
    let mut view: Option<(u32, EnvSnapshot)> = None;
    let mut last: Option<xhab_msgs::StepReply> = None;
    let pub_err = |e: String| RosError::Node(format!("publishing on {reply_topic}: {e}"));
    loop {
        let s = tokio::select! {
            m = steps.async_take() => match m {
                Ok((m, _)) => m,
                Err(e) => { tracing::warn!("{STEP_TOPIC}: a step that does not decode was dropped: {e}"); continue }
            },
            _ = shutdown.changed() => return Ok(()),
        };
        if let Some(l) = last.as_ref().filter(|l| (l.episode, l.step) >= (s.episode, s.step)) {
            // A step resent before our answer reached the simulator: answer it again.
            if (l.episode, l.step) == (s.episode, s.step) {
                reply.async_publish(l.clone()).await.map_err(|e| pub_err(e.to_string()))?;
            }
            continue;
        }
        if view.as_ref().is_none_or(|(i, _)| *i != s.episode) {
            let e = episode_announcement(&episodes, s.episode, timeout).await?;
            let z = e.goal.pose.position.z;
            let grid = world.grid_at(z).map_err(|x| RosError::Protocol(format!("episode {}: goal at height {z:.3}: {x}", e.episode_id)))?;
            let goal = cv::pose2(&e.goal.pose).position();
            let field = grid.field(&[goal]);
            agent.reset();
            view = Some((s.episode, EnvSnapshot::new(cv::pose2(&e.initial_pose.pose.pose), task.clone(), grid, field)));
        }
        let Some((_, v)) = view.as_mut() else { unreachable!("set above") };
        let p = poses.take(s.stamp, timeout, "ground truth of this step").await?;
        v.set_pose(cv::pose2(&p.pose));
        let a = agent.act(v, None);
        let r = xhab_msgs::StepReply { episode: s.episode, step: s.step, kind: xhab_msgs::StepReply::ACTION, action: a as i16, ..Default::default() };
        reply.async_publish(r.clone()).await.map_err(|e| pub_err(e.to_string()))?;
        last = Some(r);
    }
}
