//! The client side of a navigation stack's goal interface: the `move_base` action
//! (move_base_msgs/MoveBaseAction, as actionlib's client speaks it) or `move_base_simple/goal`
//! with the goal's fate read from `move_base/status` and `move_base/result`.

use super::convert as cv;
use super::move_base_server::status;
use super::msgs::{actionlib_msgs as al, geometry_msgs as gm, move_base_msgs as mb, std_srvs};
use super::node::{RosError, RosNode};
use crate::external_stack::{GoalClient, GoalState};
use roslibrust::ros1::{Publisher, ServiceClient};
use std::collections::HashSet;
use std::time::Duration;
use tokio::sync::mpsc;
use xhab_types::{Point3, Pose2};

pub use crate::external_stack::GoalInterface;

/// A goal's client: sends it, follows its status, cancels it.
pub struct MoveBaseClient {
    interface: GoalInterface,
    goal_pub: Publisher<mb::MoveBaseActionGoal>,
    cancel_pub: Publisher<al::GoalID>,
    simple_pub: Publisher<gm::PoseStamped>,
    statuses: mpsc::UnboundedReceiver<al::GoalStatusArray>,
    results: mpsc::UnboundedReceiver<mb::MoveBaseActionResult>,
    /// Goal ids seen before ours was sent (the simple interface learns its goal's id as the
    /// first new one).
    seen: HashSet<String>,
    goal: Option<(String, mb::MoveBaseActionGoal)>,
    /// The last status of our goal.
    pub state: Option<u8>,
    /// Whether any status message came from a server.
    pub server_seen: bool,
    /// move_base's `clear_costmaps`, called before each episode while it answers (`None`:
    /// not looked up yet; it is once the stack is up, before the first episode).
    clear: Option<Option<ServiceClient<std_srvs::Empty>>>,
    nh: roslibrust::ros1::NodeHandle,
    clear_name: String,
    status_name: String,
}

impl MoveBaseClient {
    /// Subscribes and advertises the action's topics under `move_base/` (and
    /// `move_base_simple/goal`).
    pub async fn new(node: &RosNode, interface: GoalInterface) -> Result<Self, RosError> {
        let clear_name = node.names.resolve("move_base/clear_costmaps");
        Ok(Self {
            clear: None,
            nh: node.nh.clone(),
            clear_name,
            status_name: node.names.resolve("move_base/status"),
            interface,
            goal_pub: node.advertise("move_base/goal", false).await?,
            cancel_pub: node.advertise("move_base/cancel", false).await?,
            simple_pub: node.advertise("move_base_simple/goal", false).await?,
            statuses: node.subscribe("move_base/status").await?,
            results: node.subscribe("move_base/result").await?,
            seen: HashSet::new(),
            goal: None,
            state: None,
            server_seen: false,
        })
    }

    /// Sends a new goal `id` (`target` in its frame) stamped `now` (s).
    pub async fn send(&mut self, id: &str, now: f64, target: gm::PoseStamped) -> Result<(), RosError> {
        self.absorb();
        let m = mb::MoveBaseActionGoal {
            header: cv::header(now, ""),
            goal_id: al::GoalID { stamp: cv::time(now), id: id.to_string() },
            goal: mb::MoveBaseGoal { target_pose: target },
        };
        self.goal = Some((id.to_string(), m));
        self.state = None;
        self.resend().await
    }

    /// Publishes the goal again (actionlib ignores a goal id it already has; a stack's
    /// connection may not have been up the first time).
    pub async fn resend(&self) -> Result<(), RosError> {
        let Some((_, m)) = &self.goal else { return Ok(()) };
        match self.interface {
            GoalInterface::Action => self.goal_pub.publish(m).await.map_err(|e| RosError::Node(format!("publishing on move_base/goal: {e}"))),
            GoalInterface::Simple => self.simple_pub.publish(&m.goal.target_pose).await.map_err(|e| RosError::Node(format!("publishing on move_base_simple/goal: {e}"))),
        }
    }

    /// Whether the stack has taken the goal (a status for it has come).
    pub fn acknowledged(&self) -> bool {
        self.state.is_some()
    }

    /// Takes in status and result messages; returns our goal's state, if known.
    pub fn absorb(&mut self) -> Option<u8> {
        while let Ok(a) = self.statuses.try_recv() {
            self.server_seen = true;
            for s in &a.status_list {
                self.note(&s.goal_id.id, s.status);
            }
        }
        while let Ok(r) = self.results.try_recv() {
            self.note(&r.status.goal_id.id, r.status.status);
        }
        self.state
    }

    fn note(&mut self, id: &str, st: u8) {
        let Some((ours, _)) = self.goal.as_mut() else {
            self.seen.insert(id.to_string());
            return;
        };
        if self.interface == GoalInterface::Simple && self.state.is_none() && !self.seen.contains(id) && id != ours {
            *ours = id.to_string(); // the stack named our simple goal
        }
        if id == ours {
            // A terminal state is final; status lists may still show it ACTIVE a little later.
            if !self.state.is_some_and(status::is_terminal) {
                self.state = Some(st);
            }
        } else {
            self.seen.insert(id.to_string());
        }
    }

    /// Cancels our goal.
    pub async fn cancel(&mut self) -> Result<(), RosError> {
        let Some((id, _)) = &self.goal else { return Ok(()) };
        let m = al::GoalID { stamp: cv::time(0.0), id: id.clone() };
        self.cancel_pub.publish(&m).await.map_err(|e| RosError::Node(format!("publishing on move_base/cancel: {e}")))
    }

    /// Forgets the goal (between episodes); its id stays known as not ours.
    pub fn clear(&mut self) {
        if let Some((id, _)) = self.goal.take() {
            self.seen.insert(id);
        }
        self.state = None;
    }
}

impl GoalClient for MoveBaseClient {
    async fn send(&mut self, id: &str, stamp: f64, position: Point3) -> Result<(), RosError> {
        let target = gm::PoseStamped { header: cv::header(stamp, "map"), pose: cv::pose(Pose2::new(position.x, position.y, 0.0), position.z) };
        MoveBaseClient::send(self, id, stamp, target).await
    }

    async fn resend(&mut self) -> Result<(), RosError> {
        MoveBaseClient::resend(self).await
    }

    fn absorb(&mut self) -> Option<GoalState> {
        MoveBaseClient::absorb(self).map(goal_state)
    }

    fn state(&self) -> Option<GoalState> {
        self.state.map(goal_state)
    }

    fn server_seen(&self) -> bool {
        self.server_seen
    }

    async fn cancel(&mut self) -> Result<(), RosError> {
        MoveBaseClient::cancel(self).await
    }

    fn clear(&mut self) {
        MoveBaseClient::clear(self)
    }

    async fn before_episode(&mut self) {
        if self.clear.is_none() {
            self.clear = Some(self.nh.service_client::<std_srvs::Empty>(&self.clear_name).await.ok());
        }
        if let Some(Some(c)) = self.clear.as_ref() {
            if tokio::time::timeout(Duration::from_secs(2), c.call(&std_srvs::EmptyRequest {})).await.map_or(true, |r| r.is_err()) {
                tracing::warn!("{} did not answer: costmaps are not cleared between episodes", self.clear_name);
                self.clear = Some(None);
            }
        }
    }

    fn status_topic(&self) -> String {
        self.status_name.clone()
    }
}

/// An actionlib status code as a transport-neutral state.
fn goal_state(s: u8) -> GoalState {
    GoalState { name: status::name(s), terminal: status::is_terminal(s), succeeded: s == status::SUCCEEDED }
}
