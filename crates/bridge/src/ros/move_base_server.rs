//! The server side of move_base's action (move_base_msgs/MoveBaseAction over
//! `move_base/{goal,cancel,status,feedback,result}`), as actionlib's SimpleActionServer runs
//! it: one goal at a time, a new goal preempts the current one, a cancel preempts it, and
//! terminal states stay in the status list for a while after the result.

use super::convert as cv;
use super::msgs::{actionlib_msgs as al, geometry_msgs as gm, move_base_msgs as mb};
use super::node::{RosError, RosNode};
use roslibrust::ros1::Publisher;
use tokio::sync::mpsc;

/// actionlib_msgs/GoalStatus codes.
pub mod status {
    /// The goal has not been processed yet.
    pub const PENDING: u8 = 0;
    /// The goal is being processed.
    pub const ACTIVE: u8 = 1;
    /// Cancelled after it started.
    pub const PREEMPTED: u8 = 2;
    /// Achieved.
    pub const SUCCEEDED: u8 = 3;
    /// The server gave up.
    pub const ABORTED: u8 = 4;
    /// Refused without processing.
    pub const REJECTED: u8 = 5;
    /// Cancelled before it started.
    pub const RECALLED: u8 = 8;
    /// The client lost track of it.
    pub const LOST: u8 = 9;

    /// Whether `s` is terminal (the goal is over).
    pub fn is_terminal(s: u8) -> bool {
        matches!(s, PREEMPTED | SUCCEEDED | ABORTED | REJECTED | RECALLED | LOST)
    }

    /// The name of a status code, as actionlib spells it.
    pub fn name(s: u8) -> &'static str {
        match s {
            PENDING => "PENDING",
            ACTIVE => "ACTIVE",
            PREEMPTED => "PREEMPTED",
            SUCCEEDED => "SUCCEEDED",
            ABORTED => "ABORTED",
            REJECTED => "REJECTED",
            6 => "PREEMPTING",
            7 => "RECALLING",
            RECALLED => "RECALLED",
            LOST => "LOST",
            _ => "UNKNOWN",
        }
    }
}

/// How long a finished goal stays in the status list (s of ROS time, actionlib's default).
const STATUS_LIST_TIMEOUT: f64 = 5.0;

/// What the server asks its owner to do after taking in the client's messages.
#[derive(Debug, Clone, PartialEq)]
pub enum ServerEvent {
    /// Start on this goal (the previous one, if any, was preempted).
    NewGoal(gm::PoseStamped),
    /// Stop: the current goal was cancelled.
    Cancelled,
}

/// The move_base action server's topics and goal bookkeeping.
pub struct MoveBaseServer {
    goals: mpsc::UnboundedReceiver<mb::MoveBaseActionGoal>,
    cancels: mpsc::UnboundedReceiver<al::GoalID>,
    status_pub: Publisher<al::GoalStatusArray>,
    feedback_pub: Publisher<mb::MoveBaseActionFeedback>,
    result_pub: Publisher<mb::MoveBaseActionResult>,
    /// The goal being worked on.
    current: Option<al::GoalID>,
    /// Finished goals: (status, when it finished, s).
    finished: Vec<(al::GoalStatus, f64)>,
    /// Goals taken from `move_base_simple/goal` so far (they are named by it).
    simple_goals: u64,
}

impl MoveBaseServer {
    /// Advertises and subscribes the action's topics under `move_base/`.
    pub async fn new(node: &RosNode) -> Result<Self, RosError> {
        Ok(Self {
            goals: node.subscribe("move_base/goal").await?,
            cancels: node.subscribe("move_base/cancel").await?,
            status_pub: node.advertise("move_base/status", false).await?,
            feedback_pub: node.advertise("move_base/feedback", false).await?,
            result_pub: node.advertise("move_base/result", false).await?,
            current: None,
            finished: Vec::new(),
            simple_goals: 0,
        })
    }

    /// Whether a goal is being worked on.
    pub fn active(&self) -> bool {
        self.current.is_some()
    }

    /// Takes in goals and cancels that arrived; `now` is the ROS time (s). Returns what the
    /// owner must do, in order.
    pub async fn poll(&mut self, now: f64) -> Result<Vec<ServerEvent>, RosError> {
        self.forget_finished(now);
        let mut out = Vec::new();
        while let Ok(g) = self.goals.try_recv() {
            let mut id = g.goal_id.clone();
            if id.id.is_empty() {
                id.id = format!("xhab-goal-{}.{:09}", g.header.stamp.secs, g.header.stamp.nsecs);
            }
            if self.current.as_ref().is_some_and(|c| c.id == id.id) || self.finished.iter().any(|(s, _)| s.goal_id.id == id.id) {
                continue; // the same goal again (a client resending it)
            }
            if self.current.is_some() {
                self.finish(status::PREEMPTED, "preempted by a new goal", now).await?;
            }
            self.current = Some(id);
            out.push(ServerEvent::NewGoal(g.goal.target_pose));
        }
        while let Ok(c) = self.cancels.try_recv() {
            let Some(cur) = self.current.as_ref() else { continue };
            // actionlib: an empty id with a zero stamp cancels everything; a stamp cancels
            // goals accepted at or before it; an id cancels that goal.
            let all = c.id.is_empty() && c.stamp.secs == 0 && c.stamp.nsecs == 0;
            let by_stamp = c.id.is_empty() && (cur.stamp.secs, cur.stamp.nsecs) <= (c.stamp.secs, c.stamp.nsecs);
            if all || by_stamp || c.id == cur.id {
                self.finish(status::PREEMPTED, "cancelled", now).await?;
                out.push(ServerEvent::Cancelled);
            }
        }
        Ok(out)
    }

    /// Takes a goal that came on `move_base_simple/goal` as move_base does: as an action goal
    /// of its own, under a new id (preempting the current one), so that its fate shows on
    /// `move_base/status` and `move_base/result`.
    pub async fn adopt(&mut self, now: f64) -> Result<(), RosError> {
        if self.current.is_some() {
            self.finish(status::PREEMPTED, "preempted by move_base_simple/goal", now).await?;
        }
        self.simple_goals += 1;
        let stamp = cv::time(now);
        let id = format!("move_base_simple-{}-{}.{:09}", self.simple_goals, stamp.secs, stamp.nsecs);
        self.current = Some(al::GoalID { stamp, id });
        Ok(())
    }

    /// Ends the current goal with `code` (SUCCEEDED, ABORTED, PREEMPTED) and publishes the result.
    pub async fn finish(&mut self, code: u8, text: &str, now: f64) -> Result<(), RosError> {
        let Some(id) = self.current.take() else { return Ok(()) };
        let st = al::GoalStatus { goal_id: id, status: code, text: text.to_string() };
        let r = mb::MoveBaseActionResult { header: cv::header(now, ""), status: st.clone(), result: mb::MoveBaseResult {} };
        self.result_pub.publish(&r).await.map_err(|e| RosError::Node(format!("publishing on move_base/result: {e}")))?;
        self.finished.push((st, now));
        self.publish_status(now).await
    }

    /// Drops finished goals older than the status list keeps them, or from the future (the
    /// clock restarted: their ids may come again).
    fn forget_finished(&mut self, now: f64) {
        self.finished.retain(|(_, t)| now - t <= STATUS_LIST_TIMEOUT && *t <= now + 1e-9);
    }

    /// Publishes the status list (the current goal, and goals finished lately).
    pub async fn publish_status(&mut self, now: f64) -> Result<(), RosError> {
        self.forget_finished(now);
        let mut list: Vec<al::GoalStatus> = self.finished.iter().map(|(s, _)| s.clone()).collect();
        if let Some(id) = &self.current {
            list.push(al::GoalStatus { goal_id: id.clone(), status: status::ACTIVE, text: "This goal has been accepted by the simple action server".into() });
        }
        let m = al::GoalStatusArray { header: cv::header(now, ""), status_list: list };
        self.status_pub.publish(&m).await.map_err(|e| RosError::Node(format!("publishing on move_base/status: {e}")))
    }

    /// Publishes feedback (the robot's pose in the global frame) for the current goal.
    pub async fn feedback(&self, now: f64, pose: gm::PoseStamped) -> Result<(), RosError> {
        let Some(id) = &self.current else { return Ok(()) };
        let m = mb::MoveBaseActionFeedback {
            header: cv::header(now, ""),
            status: al::GoalStatus { goal_id: id.clone(), status: status::ACTIVE, text: String::new() },
            feedback: mb::MoveBaseFeedback { base_position: pose },
        };
        self.feedback_pub.publish(&m).await.map_err(|e| RosError::Node(format!("publishing on move_base/feedback: {e}")))
    }
}
