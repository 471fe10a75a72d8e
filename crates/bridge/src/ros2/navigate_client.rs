//! The client side of a ROS 2 stack's goal interface (`xhab bench --agent ros2`): the
//! `navigate_to_pose` action (nav2_msgs/action/NavigateToPose, on ros2-client's action
//! client), or `goal_pose` with the goal's fate read from `navigate_to_pose/_action/status`
//! (the goal is the first new id there), as Nav2's bt_navigator reports both.

use super::convert as cv;
use super::msgs::action_msgs::GoalStatus;
use super::msgs::geometry_msgs as gm;
use super::msgs::nav2_msgs::{NavigateToPoseFeedback, NavigateToPoseGoal, NavigateToPoseResult};
use super::node::{reliable_qos, Ros2Node};
use crate::external_stack::{GoalClient, GoalInterface, GoalState};
use crate::ros::node::RosError;
use ros2_client::action::{ActionClient, ActionClientQosPolicies, GoalId};
use ros2_client::dds::rustdds::DomainParticipant;
use ros2_client::{ActionTypeName, Name, Publisher, RmwRequestId, ServiceMapping};
use std::collections::HashSet;
use xhab_types::{Point3, Pose2};

/// The state of a goal the server refused (ROS 2 has no status for it).
const REJECTED: GoalState = GoalState { name: "REJECTED", terminal: true, succeeded: false };

/// A goal we sent.
struct Sent {
    goal: NavigateToPoseGoal,
    /// The pending goal request (action).
    request: Option<RmwRequestId>,
    /// The goal's id: ours (action) or the first new one on the status topic (`goal_pose`).
    id: Option<[u8; 16]>,
}

/// A goal's client: sends it, follows its status, cancels it.
pub struct NavigateClient {
    interface: GoalInterface,
    action: ActionClient<NavigateToPoseGoal, NavigateToPoseResult, NavigateToPoseFeedback>,
    simple: Publisher<gm::PoseStamped>,
    participant: DomainParticipant,
    /// The DDS topic a server reads (the action's goal requests, or `goal_pose`).
    server_topic: String,
    status_name: String,
    goal: Option<Sent>,
    /// Goal ids that are not ours.
    seen: HashSet<[u8; 16]>,
    state: Option<GoalState>,
}

fn goal_state(s: i8) -> GoalState {
    GoalState { name: GoalStatus::name(s), terminal: GoalStatus::is_terminal(s), succeeded: s == GoalStatus::STATUS_SUCCEEDED }
}

impl NavigateClient {
    /// The client of `action` (e.g. `navigate_to_pose`, resolved with the node's names) and
    /// of `goal_pose`, on `node`.
    pub fn new(node: &mut Ros2Node, action: &str, interface: GoalInterface) -> Result<Self, RosError> {
        let name = node.names.resolve(action);
        let n = Name::parse(&name).map_err(|e| RosError::Node(format!("action name {name}: {e}")))?;
        // Feedback is not read: keep one sample. Status arrays are drained at every look.
        let qos = ActionClientQosPolicies { goal_service: reliable_qos(10), result_service: reliable_qos(10), cancel_service: reliable_qos(10), feedback_subscription: reliable_qos(1), status_subscription: reliable_qos(50) };
        let client = node
            .node
            .create_action_client(ServiceMapping::Enhanced, &n, &ActionTypeName::new("nav2_msgs", "NavigateToPose"), qos)
            .map_err(|e| RosError::Node(format!("the action client of {name}: {e}")))?;
        let goal_topic = node.names.resolve("goal_pose");
        let server_topic = match interface {
            GoalInterface::Action => format!("rq{name}/_action/send_goalRequest"),
            GoalInterface::Simple => format!("rt{goal_topic}"),
        };
        Ok(Self {
            interface,
            action: client,
            simple: node.publisher("goal_pose", reliable_qos(10))?,
            participant: node.participant(),
            server_topic,
            status_name: format!("{name}/_action/status"),
            goal: None,
            seen: HashSet::new(),
            state: None,
        })
    }

    fn note(&mut self, id: [u8; 16], st: GoalState) {
        let Some(g) = self.goal.as_mut() else {
            self.seen.insert(id);
            return;
        };
        if self.interface == GoalInterface::Simple && g.id.is_none() && !self.seen.contains(&id) {
            g.id = Some(id); // the stack named our goal_pose goal
        }
        if g.id == Some(id) {
            // A terminal state is final.
            if !self.state.is_some_and(|s| s.terminal) {
                self.state = Some(st);
            }
        } else {
            self.seen.insert(id);
        }
    }
}

impl GoalClient for NavigateClient {
    async fn send(&mut self, _id: &str, stamp: f64, position: Point3) -> Result<(), RosError> {
        self.absorb();
        let pose = gm::PoseStamped { header: cv::header(stamp, "map"), pose: cv::pose(Pose2::new(position.x, position.y, 0.0), position.z) };
        self.goal = Some(Sent { goal: NavigateToPoseGoal { pose, behavior_tree: String::new() }, request: None, id: None });
        self.state = None;
        self.resend().await
    }

    async fn resend(&mut self) -> Result<(), RosError> {
        let Some(g) = self.goal.as_mut() else { return Ok(()) };
        match self.interface {
            GoalInterface::Action => {
                // A new id each time: an earlier request the server took late is not ours.
                if let Some(old) = g.id {
                    self.seen.insert(old);
                }
                let (request, id) = self.action.send_goal(g.goal.clone()).map_err(|e| RosError::Node(format!("sending a goal to {}: {e:?}", self.status_name.trim_end_matches("/_action/status"))))?;
                (g.request, g.id) = (Some(request), Some(*id.uuid.as_bytes()));
            }
            GoalInterface::Simple => self.simple.async_publish(g.goal.pose.clone()).await.map_err(|e| RosError::Node(format!("publishing on goal_pose: {e:?}")))?,
        }
        Ok(())
    }

    fn absorb(&mut self) -> Option<GoalState> {
        if let Some(req) = self.goal.as_ref().and_then(|g| g.request) {
            match self.action.receive_goal_response(req) {
                Ok(Some(r)) => {
                    if let Some(g) = self.goal.as_mut() {
                        g.request = None;
                    }
                    if !r.accepted {
                        self.state = Some(REJECTED);
                    } else if self.state.is_none() {
                        self.state = Some(goal_state(GoalStatus::STATUS_ACCEPTED));
                    }
                }
                Ok(None) => {}
                Err(e) => tracing::warn!("a goal response that does not decode was dropped: {e:?}"),
            }
        }
        for _ in 0..1000 {
            match self.action.receive_status() {
                Ok(Some(a)) => {
                    for s in a.status_list {
                        self.note(*s.goal_info.goal_id.uuid.as_bytes(), goal_state(s.status as i8));
                    }
                }
                Ok(None) => break,
                Err(e) => tracing::warn!("{}: a status that does not decode was dropped: {e:?}", self.status_name),
            }
        }
        self.state
    }

    fn state(&self) -> Option<GoalState> {
        self.state
    }

    fn server_seen(&self) -> bool {
        self.participant.discovered_readers().iter().any(|r| r.subscription_topic_data.topic_name == self.server_topic)
    }

    async fn cancel(&mut self) -> Result<(), RosError> {
        // Over `goal_pose` too: the stack's action cancels the goal it named.
        let Some(id) = self.goal.as_ref().and_then(|g| g.id) else { return Ok(()) };
        let id: GoalId = serde_json::from_value(serde_json::json!({ "uuid": id })).map_err(|e| RosError::Node(format!("goal id: {e}")))?;
        self.action.cancel_goal(id).map(|_| ()).map_err(|e| RosError::Node(format!("cancelling a goal on {}: {e:?}", self.status_name.trim_end_matches("/_action/status"))))
    }

    fn clear(&mut self) {
        if let Some(id) = self.goal.take().and_then(|g| g.id) {
            self.seen.insert(id);
        }
        self.state = None;
    }

    fn acknowledges_at_once(&self) -> bool {
        // The action's goal response comes at once; over `goal_pose` the status may be on a
        // timer of the stack's.
        self.interface == GoalInterface::Action
    }

    fn status_topic(&self) -> String {
        self.status_name.clone()
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_goal_id_is_built_from_its_bytes() {
        let b: [u8; 16] = std::array::from_fn(|i| i as u8 * 3);
        let id: ros2_client::action::GoalId = serde_json::from_value(serde_json::json!({ "uuid": b })).unwrap();
        assert_eq!(id.uuid.as_bytes(), &b);
    }
}
