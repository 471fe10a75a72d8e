//! A discrete Habitat-style agent as a ROS 1 node: the ground-truth pose and the goal in,
//! `action` (std_msgs/Int16, Habitat's numbering) out, one action per observation.
//!
//! Episodes: a goal on `move_base_simple/goal` starts one; the observation with
//! `header.seq == 0` is its first and pairs with the next goal received (the two topics
//! travel on separate connections, so their order is fixed by this rule, not by arrival).

use super::convert as cv;
use super::msgs::{geometry_msgs as gm, std_msgs};
use super::node::{self, RosError};
use super::sim_node::{PROBE_SEQ, READY_ACTION};
use crate::agents::AgentKind;
use std::sync::Arc;
use std::time::Duration;
use xhab_sim::env::{EnvView, TaskConfig};
use xhab_sim::geodesic::GeodesicField;
use xhab_sim::navgrid::NavGrid;
use xhab_sim::world::World;
use xhab_types::Pose2;

/// What the agent knows of the episode: the received pose, and the task's privileged state
/// that an oracle is entitled to (the scene's grid and the goal's geodesic field).
struct View {
    pose: Pose2,
    config: TaskConfig,
    grid: Arc<NavGrid>,
    field: Arc<GeodesicField>,
}

impl EnvView for View {
    fn pose(&self) -> Pose2 {
        self.pose
    }
    fn config(&self) -> &TaskConfig {
        &self.config
    }
    fn grid(&self) -> &Arc<NavGrid> {
        &self.grid
    }
    fn field(&self) -> &Arc<GeodesicField> {
        &self.field
    }
}

/// Runs the agent node `name` until `shutdown` fires (or forever): waits (up to `timeout`)
/// for the simulator to subscribe to `action`, then answers each observation.
pub async fn run(uri: &str, name: &str, world: Arc<World>, kind: AgentKind, task: TaskConfig, timeout: Duration, mut shutdown: tokio::sync::watch::Receiver<bool>) -> Result<(), RosError> {
    let nh = node::node(uri, name).await?;
    let action = node::advertise::<std_msgs::Int16>(&nh, "action", false).await?;
    let mut poses = node::subscribe::<gm::PoseStamped>(&nh, "ground_truth/pose").await?;
    let mut goals = node::subscribe::<gm::PoseStamped>(&nh, "move_base_simple/goal").await?;
    let mut agent = kind.build().ok_or_else(|| RosError::Protocol(format!("agent {} is not a discrete agent", kind.name())))?;
    tracing::debug!("agent node up");
    let mut view: Option<View> = None;
    let mut goal_probed = false;
    let mut pending = std::collections::VecDeque::new();
    let pub_err = |e: String| RosError::Node(format!("publishing on action: {e}"));
    loop {
        let m = tokio::select! {
            m = poses.recv() => match m { Some(m) => m, None => return Ok(()) },
            _ = shutdown.changed() => return Ok(()),
        };
        tracing::debug!("agent: pose seq {}", m.header.seq);
        if m.header.seq == PROBE_SEQ {
            // Handshake: answer once the goal topic has shown it is connected too.
            while let Ok(g) = goals.try_recv() {
                if g.header.seq == PROBE_SEQ {
                    goal_probed = true;
                } else {
                    pending.push_back(g);
                }
            }
            tracing::debug!("agent: probe (goal probed: {goal_probed})");
            if goal_probed {
                action.publish(&std_msgs::Int16 { data: READY_ACTION }).await.map_err(|e| pub_err(e.to_string()))?;
            }
            continue;
        }
        let pose = cv::pose2(&m.pose);
        if m.header.seq == 0 {
            let g = match pending.pop_front() {
                Some(g) => g,
                None => loop {
                    let g = node::recv(&mut goals, timeout, "goal for the new episode").await?;
                    if g.header.seq != PROBE_SEQ {
                        break g;
                    }
                },
            };
            let grid = world.grid_at(m.pose.position.z).map_err(|e| RosError::Protocol(format!("observation at height {:.3}: {e}", m.pose.position.z)))?;
            let goal = cv::pose2(&g.pose).position();
            let field = Arc::new(GeodesicField::new(&grid, &[goal]));
            agent.reset();
            view = Some(View { pose, config: task.clone(), grid, field });
        }
        let Some(v) = view.as_mut() else {
            return Err(RosError::Protocol("an observation arrived before any episode began (header.seq 0)".into()));
        };
        v.pose = pose;
        let a = agent.act(v, None);
        action.publish(&std_msgs::Int16 { data: a as i16 }).await.map_err(|e| pub_err(e.to_string()))?;
    }
}
