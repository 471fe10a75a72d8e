//! The `navigate_to_pose` action server of `xhab ros2 nav` (nav2_msgs/action/NavigateToPose,
//! on ros2-client's action server): goals are accepted and executed at once, a new goal
//! preempts the old one (which ends ABORTED, as with Nav2's bt_navigator), a cancel ends it
//! CANCELED, the navigator's end SUCCEEDED or ABORTED with Nav2's error code for its reason.
//! Goals that come on `goal_pose` are adopted as goals of the action, so that
//! `navigate_to_pose/_action/status` tells their fate too, as Nav2 does.

use super::convert as cv;
use super::msgs::action_msgs::{CancelGoalRequest, CancelGoalResponse, GoalStatus};
use super::msgs::nav2_msgs::{NavigateToPoseFeedback, NavigateToPoseGoal, NavigateToPoseResult};
use super::msgs::{builtin_interfaces, geometry_msgs as gm};
use super::node::{latched_qos, reliable_qos, Ros2Node};
use crate::ros::node::RosError;
use ros2_client::action::{ActionServer, GetResultResponse, GoalId, GoalInfo, GoalStatusEnum, SendGoalResponse};
use ros2_client::action_msgs as ra;
use ros2_client::{ActionTypeName, Name, RmwRequestId, ServiceMapping};
use xhab_nav::navigator::AbortReason;

/// Terminal goals kept for their result requests and in the status list.
const KEEP_TERMINAL: usize = 16;

/// How the current goal ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GoalEnd {
    /// The navigator reached it.
    Reached,
    /// It was given up: Nav2's error code and a message.
    Aborted(u16, String),
}

impl GoalEnd {
    /// The end of a goal the navigator gave up for `reason` (`None`: not known), with the
    /// code Nav2's planner or controller server reports for that trouble.
    pub fn navigator_abort(reason: Option<AbortReason>) -> GoalEnd {
        let code = match reason {
            Some(AbortReason::GoalUnreachableForCostmap) => NavigateToPoseResult::NO_VALID_PATH,
            Some(AbortReason::StartBlocked) => NavigateToPoseResult::START_OCCUPIED,
            Some(AbortReason::ControllerFailed) => NavigateToPoseResult::NO_VALID_CONTROL,
            Some(AbortReason::NoProgress) => NavigateToPoseResult::FAILED_TO_MAKE_PROGRESS,
            None => NavigateToPoseResult::UNKNOWN,
        };
        GoalEnd::Aborted(code, format!("the navigator gave up: {}", reason.map_or("unknown", AbortReason::as_str)))
    }
}

/// What a client asked for since the last look.
#[derive(Debug, Clone, PartialEq)]
pub enum Request {
    /// A new goal, accepted and now the current one.
    Goal(gm::PoseStamped),
    /// The current goal was cancelled: stop.
    Cancel,
}

/// One goal the server knows.
struct Goal {
    id: GoalId,
    /// When it was accepted (s, sim time).
    accepted: f64,
    status: i8,
    result: NavigateToPoseResult,
    /// Result requests waiting for it to end.
    waiting: Vec<RmwRequestId>,
}

/// The action server, polled from the node's loop.
pub struct NavigateServer {
    server: ActionServer<NavigateToPoseGoal, NavigateToPoseResult, NavigateToPoseFeedback>,
    /// Oldest first; the current goal, if any, is the last and not terminal.
    goals: Vec<Goal>,
    name: String,
}

fn status_enum(s: i8) -> GoalStatusEnum {
    match s {
        GoalStatus::STATUS_ACCEPTED => GoalStatusEnum::Accepted,
        GoalStatus::STATUS_EXECUTING => GoalStatusEnum::Executing,
        GoalStatus::STATUS_CANCELING => GoalStatusEnum::Canceling,
        GoalStatus::STATUS_SUCCEEDED => GoalStatusEnum::Succeeded,
        GoalStatus::STATUS_CANCELED => GoalStatusEnum::Canceled,
        GoalStatus::STATUS_ABORTED => GoalStatusEnum::Aborted,
        _ => GoalStatusEnum::Unknown,
    }
}

fn stamp(t: f64) -> ros2_client::builtin_interfaces::Time {
    ros2_client::builtin_interfaces::Time::from_nanos((t.max(0.0) * 1e9).round() as i64)
}

fn duration(s: f64) -> builtin_interfaces::Duration {
    let t = cv::time(s.max(0.0));
    builtin_interfaces::Duration { sec: t.sec, nanosec: t.nanosec }
}

impl NavigateServer {
    /// Serves `action` (resolved with the node's names, e.g. `navigate_to_pose`) on `node`.
    pub fn new(node: &mut Ros2Node, action: &str) -> Result<NavigateServer, RosError> {
        let name = node.names.resolve(action);
        let n = Name::parse(&name).map_err(|e| RosError::Node(format!("action name {name}: {e}")))?;
        // rcl's defaults: services reliable and volatile, feedback reliable, status latched.
        let qos = ros2_client::action::ActionServerQosPolicies {
            goal_service: reliable_qos(10),
            result_service: reliable_qos(10),
            cancel_service: reliable_qos(10),
            feedback_publisher: reliable_qos(10),
            status_publisher: latched_qos(),
        };
        let server = node
            .node
            .create_action_server(ServiceMapping::Enhanced, &n, &ActionTypeName::new("nav2_msgs", "NavigateToPose"), qos)
            .map_err(|e| RosError::Node(format!("serving the action {name}: {e}")))?;
        Ok(NavigateServer { server, goals: Vec::new(), name })
    }

    fn current(&mut self) -> Option<&mut Goal> {
        self.goals.last_mut().filter(|g| !GoalStatus::is_terminal(g.status))
    }

    /// The current goal's id, if a goal runs.
    pub fn current_goal(&self) -> Option<[u8; 16]> {
        self.goals.last().filter(|g| !GoalStatus::is_terminal(g.status)).map(|g| *g.id.uuid.as_bytes())
    }

    fn err(&self, what: &str, e: impl std::fmt::Debug) -> RosError {
        RosError::Node(format!("{}: {what}: {e:?}", self.name))
    }

    /// Ends the goal at `i` with `status` and `result`, answering its waiting result requests.
    fn end(&mut self, i: usize, status: i8, result: NavigateToPoseResult) -> Result<(), RosError> {
        let g = &mut self.goals[i];
        g.status = status;
        g.result = result;
        let waiting = std::mem::take(&mut g.waiting);
        let resp = GetResultResponse { status: status_enum(status), result: g.result.clone() };
        for r in waiting {
            self.server.send_result(r, resp.clone()).map_err(|e| self.err("sending a result", e))?;
        }
        Ok(())
    }

    /// Makes a new goal `id` the current one at `now` (s), preempting the old one (ABORTED,
    /// as Nav2's action server ends a goal a newer one replaces).
    fn start(&mut self, id: GoalId, now: f64) -> Result<(), RosError> {
        if self.current().is_some() {
            let i = self.goals.len() - 1;
            self.end(i, GoalStatus::STATUS_ABORTED, NavigateToPoseResult { error_code: NavigateToPoseResult::NONE, error_msg: "preempted by a newer goal".into() })?;
        }
        self.goals.push(Goal { id, accepted: now, status: GoalStatus::STATUS_EXECUTING, result: NavigateToPoseResult::default(), waiting: Vec::new() });
        let terminal = self.goals.iter().filter(|g| GoalStatus::is_terminal(g.status)).count();
        if terminal > KEEP_TERMINAL {
            let mut drop = terminal - KEEP_TERMINAL;
            self.goals.retain(|g| {
                let keep = drop == 0 || !GoalStatus::is_terminal(g.status) || !g.waiting.is_empty();
                if !keep {
                    drop -= 1;
                }
                keep
            });
        }
        Ok(())
    }

    /// Publishes the states of every goal the server knows on `<action>/_action/status`.
    fn publish_status(&self) -> Result<(), RosError> {
        let status_list = self.goals.iter().map(|g| ra::GoalStatus { goal_info: GoalInfo { goal_id: g.id, stamp: stamp(g.accepted) }, status: status_enum(g.status) }).collect();
        self.server.send_goal_statuses(ra::GoalStatusArray { status_list }).map_err(|e| self.err("publishing the goal states", e))
    }

    /// Takes the clients' requests at `now` (s): goals (accepted, each preempting the one
    /// before), cancels (the goals end CANCELED at once) and result requests (answered when
    /// their goal has ended). What the navigator must do, in order.
    pub fn poll(&mut self, now: f64) -> Result<Vec<Request>, RosError> {
        let mut out = Vec::new();
        let mut changed = false;
        loop {
            match self.server.receive_goal() {
                Ok(Some((req, g))) => {
                    self.start(g.goal_id, now)?;
                    self.server.send_goal_response(req, SendGoalResponse { accepted: true, stamp: stamp(now) }).map_err(|e| self.err("answering a goal", e))?;
                    out.push(Request::Goal(g.goal.pose));
                    changed = true;
                }
                Ok(None) => break,
                Err(e) => {
                    tracing::warn!("{}: a goal request that does not decode was dropped: {e:?}", self.name);
                    break;
                }
            }
        }
        loop {
            match self.server.receive_cancel_request() {
                Ok(Some((req, c))) => {
                    let resp = self.cancel(&c, now)?;
                    if !resp.goals_canceling.is_empty() {
                        changed = true;
                        if self.current_goal().is_none() && out.last() != Some(&Request::Cancel) {
                            out.push(Request::Cancel);
                        }
                    }
                    let resp = ra::CancelGoalResponse {
                        return_code: match resp.return_code {
                            CancelGoalResponse::ERROR_NONE => ra::CancelGoalResponseEnum::None,
                            CancelGoalResponse::ERROR_UNKNOWN_GOAL_ID => ra::CancelGoalResponseEnum::UnknownGoal,
                            CancelGoalResponse::ERROR_GOAL_TERMINATED => ra::CancelGoalResponseEnum::GoalTerminated,
                            _ => ra::CancelGoalResponseEnum::Rejected,
                        },
                        goals_canceling: resp.goals_canceling.iter().map(|i| GoalInfo { goal_id: self.goals.iter().find(|g| *g.id.uuid.as_bytes() == i.goal_id.uuid).map_or(GoalId::ZERO, |g| g.id), stamp: stamp(cv::seconds(&i.stamp)) }).collect(),
                    };
                    self.server.send_cancel_response(req, resp).map_err(|e| self.err("answering a cancel request", e))?;
                }
                Ok(None) => break,
                Err(e) => {
                    tracing::warn!("{}: a cancel request that does not decode was dropped: {e:?}", self.name);
                    break;
                }
            }
        }
        loop {
            match self.server.receive_result_request() {
                Ok(Some((req, r))) => match self.goals.iter_mut().find(|g| g.id == r.goal_id) {
                    Some(g) if GoalStatus::is_terminal(g.status) => {
                        let resp = GetResultResponse { status: status_enum(g.status), result: g.result.clone() };
                        self.server.send_result(req, resp).map_err(|e| self.err("sending a result", e))?;
                    }
                    Some(g) => g.waiting.push(req),
                    None => {
                        let resp = GetResultResponse { status: GoalStatusEnum::Unknown, result: NavigateToPoseResult::default() };
                        self.server.send_result(req, resp).map_err(|e| self.err("sending a result", e))?;
                    }
                },
                Ok(None) => break,
                Err(e) => {
                    tracing::warn!("{}: a result request that does not decode was dropped: {e:?}", self.name);
                    break;
                }
            }
        }
        if changed {
            self.publish_status()?;
        }
        Ok(out)
    }

    /// Applies a cancel request (action_msgs/CancelGoal's rules) at `now`: the matching goals
    /// end CANCELED (the navigator stops at once, so CANCELING does not last).
    fn cancel(&mut self, req: &ra::CancelGoalRequest, now: f64) -> Result<CancelGoalResponse, RosError> {
        // ros2-client keeps the request's fields to itself: read it as our own type, which
        // has the same fields.
        let req: CancelGoalRequest = serde_json::to_value(req).and_then(serde_json::from_value).map_err(|e| self.err("reading a cancel request", e))?;
        let (id, before) = (req.goal_info.goal_id.uuid, cv::seconds(&req.goal_info.stamp));
        let all = id == [0; 16];
        let matches = |g: &Goal| (!all && *g.id.uuid.as_bytes() == id) || (before > 0.0 && g.accepted <= before + 1e-9) || (all && before == 0.0);
        let mut resp = CancelGoalResponse::default();
        let mut known = false;
        for i in 0..self.goals.len() {
            if !matches(&self.goals[i]) {
                continue;
            }
            known = true;
            if GoalStatus::is_terminal(self.goals[i].status) {
                continue;
            }
            let g = &self.goals[i];
            resp.goals_canceling.push(super::msgs::action_msgs::GoalInfo { goal_id: super::msgs::unique_identifier_msgs::UUID { uuid: *g.id.uuid.as_bytes() }, stamp: cv::time(g.accepted) });
            self.end(i, GoalStatus::STATUS_CANCELED, NavigateToPoseResult { error_code: NavigateToPoseResult::NONE, error_msg: format!("cancelled at {now:.3} s") })?;
        }
        resp.return_code = match (resp.goals_canceling.is_empty(), known, all) {
            (false, _, _) => CancelGoalResponse::ERROR_NONE,
            (true, true, false) => CancelGoalResponse::ERROR_GOAL_TERMINATED,
            (true, false, false) => CancelGoalResponse::ERROR_UNKNOWN_GOAL_ID,
            (true, _, true) => CancelGoalResponse::ERROR_NONE,
        };
        Ok(resp)
    }

    /// Adopts a goal that came on `goal_pose` at `now` (s) as a goal of the action (a new
    /// id, executing, preempting the current one).
    pub fn adopt(&mut self, now: f64) -> Result<(), RosError> {
        self.start(GoalId::new_random(), now)?;
        self.publish_status()
    }

    /// Ends the current goal, if any, as `end` says.
    pub fn finish(&mut self, end: GoalEnd) -> Result<(), RosError> {
        if self.current().is_none() {
            return Ok(());
        }
        let i = self.goals.len() - 1;
        match end {
            GoalEnd::Reached => self.end(i, GoalStatus::STATUS_SUCCEEDED, NavigateToPoseResult::default())?,
            GoalEnd::Aborted(error_code, error_msg) => self.end(i, GoalStatus::STATUS_ABORTED, NavigateToPoseResult { error_code, error_msg })?,
        }
        self.publish_status()
    }

    /// Publishes feedback on the current goal, if any, at `now` (s): the robot at `pose` in
    /// `map`, `remaining` m of plan left at `speed` m/s, after `recoveries` recoveries.
    pub fn feedback(&mut self, now: f64, pose: gm::Pose, remaining: f64, speed: f64, recoveries: u32) -> Result<(), RosError> {
        let Some(g) = self.current() else { return Ok(()) };
        let (id, accepted) = (g.id, g.accepted);
        let eta = if speed.abs() > 1e-3 { remaining / speed.abs() } else { 0.0 };
        let f = NavigateToPoseFeedback {
            current_pose: gm::PoseStamped { header: cv::header(now, "map"), pose },
            navigation_time: duration(now - accepted),
            estimated_time_remaining: duration(eta),
            number_of_recoveries: recoveries.min(i16::MAX as u32) as i16,
            distance_remaining: remaining as f32,
        };
        self.server.send_feedback(id, f).map_err(|e| self.err("publishing feedback", e))
    }
}

/// The length (m) of `plan` left from `here`: to its nearest waypoint, then along it; the
/// straight line to `goal` without a plan.
pub fn distance_remaining(plan: &[xhab_types::Pose2], here: xhab_types::Point2, goal: xhab_types::Point2) -> f64 {
    let Some((i, d)) = plan.iter().enumerate().map(|(i, p)| (i, p.position().dist(here))).min_by(|a, b| a.1.total_cmp(&b.1)) else {
        return here.dist(goal);
    };
    d + plan[i..].windows(2).map(|w| w[0].position().dist(w[1].position())).sum::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;
    use xhab_types::{Point2, Pose2};

    #[test]
    fn the_rest_of_the_plan_is_measured_from_the_nearest_waypoint() {
        let plan = [Pose2::new(0.0, 0.0, 0.0), Pose2::new(1.0, 0.0, 0.0), Pose2::new(1.0, 2.0, 0.0)];
        assert!((distance_remaining(&plan, Point2::new(0.9, 0.1), Point2::new(1.0, 2.0)) - (0.1f64.hypot(0.1) + 2.0)).abs() < 1e-9);
        assert!((distance_remaining(&[], Point2::new(0.0, 0.0), Point2::new(3.0, 4.0)) - 5.0).abs() < 1e-9);
    }

    #[test]
    fn cancel_requests_read_as_our_type() {
        use super::super::msgs::action_msgs::GoalInfo as OurInfo;
        use super::super::msgs::unique_identifier_msgs::UUID;
        let ours = CancelGoalRequest { goal_info: OurInfo { goal_id: UUID { uuid: [7; 16] }, stamp: builtin_interfaces::Time { sec: 3, nanosec: 5 } } };
        let theirs: ra::CancelGoalRequest = serde_json::from_value(serde_json::to_value(ours).unwrap()).unwrap();
        let back: CancelGoalRequest = serde_json::to_value(&theirs).and_then(serde_json::from_value).unwrap();
        assert_eq!(back, ours);
    }

    #[test]
    fn navigator_aborts_carry_nav2s_codes() {
        assert_eq!(GoalEnd::navigator_abort(Some(AbortReason::GoalUnreachableForCostmap)), GoalEnd::Aborted(208, "the navigator gave up: goal_unreachable_for_costmap".into()));
        assert!(matches!(GoalEnd::navigator_abort(Some(AbortReason::NoProgress)), GoalEnd::Aborted(105, _)));
        assert!(matches!(GoalEnd::navigator_abort(None), GoalEnd::Aborted(9000, _)));
    }
}

#[cfg(test)]
mod dds_tests {
    //! The server against ros2-client's action client over DDS on loopback (a domain of the
    //! test's own in 101..=150).
    use super::*;
    use crate::ros::names::Names;
    use crate::ros2::node::Ros2Config;
    use ros2_client::action::{ActionClient, ActionClientQosPolicies};
    use std::time::{Duration, Instant};

    type Client = ActionClient<NavigateToPoseGoal, NavigateToPoseResult, NavigateToPoseFeedback>;

    fn goal(x: f64) -> NavigateToPoseGoal {
        NavigateToPoseGoal { pose: gm::PoseStamped { header: cv::header(1.0, "map"), pose: cv::pose(xhab_types::Pose2::new(x, 0.0, 0.0), 0.0) }, behavior_tree: String::new() }
    }

    /// Polls the server until it yields a request, up to 10 s.
    fn next_request(server: &mut NavigateServer, now: f64) -> Request {
        let t = Instant::now();
        loop {
            if let Some(r) = server.poll(now).unwrap().into_iter().next() {
                return r;
            }
            assert!(t.elapsed() < Duration::from_secs(10), "no request came");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    fn until<T>(what: &str, server: &mut NavigateServer, mut f: impl FnMut() -> Option<T>) -> T {
        let t = Instant::now();
        loop {
            server.poll(9.0).unwrap();
            if let Some(v) = f() {
                return v;
            }
            assert!(t.elapsed() < Duration::from_secs(10), "{what} did not come");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    fn statuses(client: &Client, into: &mut std::collections::HashMap<[u8; 16], GoalStatusEnum>) {
        while let Ok(Some(a)) = client.receive_status() {
            for s in a.status_list {
                into.insert(*s.goal_info.goal_id.uuid.as_bytes(), s.status);
            }
        }
    }

    #[test]
    fn goals_preempt_end_and_cancel_as_nav2s_do() {
        let config = Ros2Config { domain_id: 101 + (std::process::id() % 50) as u16, localhost_only: true };
        let mut srv_node = Ros2Node::new(Names::plain("navigate_server_test"), config).unwrap();
        let mut server = NavigateServer::new(&mut srv_node, "navigate_to_pose").unwrap();
        let mut cli_node = Ros2Node::new(Names::plain("navigate_client_test"), config).unwrap();
        let qos = ActionClientQosPolicies { goal_service: reliable_qos(10), result_service: reliable_qos(10), cancel_service: reliable_qos(10), feedback_subscription: reliable_qos(10), status_subscription: reliable_qos(50) };
        let client: Client = cli_node.node.create_action_client(ServiceMapping::Enhanced, &Name::parse("/navigate_to_pose").unwrap(), &ActionTypeName::new("nav2_msgs", "NavigateToPose"), qos).unwrap();
        // Discovery first: requests sent before the server's reader is matched are lost.
        let p = cli_node.participant();
        let t = Instant::now();
        while !p.discovered_readers().iter().any(|r| r.subscription_topic_data.topic_name == "rq/navigate_to_pose/_action/send_goalRequest") {
            assert!(t.elapsed() < Duration::from_secs(10), "the server was not discovered");
            std::thread::sleep(Duration::from_millis(20));
        }
        std::thread::sleep(Duration::from_millis(300));

        // A goal is accepted and executing; feedback reaches the client.
        let (r1, id1) = client.send_goal(goal(1.0)).unwrap();
        assert_eq!(next_request(&mut server, 2.0), Request::Goal(goal(1.0).pose));
        assert!(until("the goal response", &mut server, || client.receive_goal_response(r1).unwrap()).accepted);
        server.feedback(2.5, cv::pose(xhab_types::Pose2::new(0.5, 0.0, 0.0), 0.0), 0.5, 0.2, 1).unwrap();
        let f = until("feedback", &mut server, || client.receive_feedback(id1).unwrap());
        assert!((f.distance_remaining - 0.5).abs() < 1e-6 && f.number_of_recoveries == 1 && f.navigation_time.nanosec == 500_000_000, "{f:?}");

        // A second goal preempts the first (ABORTED), and ends as the navigator says.
        let (r2, id2) = client.send_goal(goal(2.0)).unwrap();
        assert_eq!(next_request(&mut server, 3.0), Request::Goal(goal(2.0).pose));
        assert!(until("the second goal response", &mut server, || client.receive_goal_response(r2).unwrap()).accepted);
        server.finish(GoalEnd::navigator_abort(Some(AbortReason::NoProgress))).unwrap();
        let req = client.request_result(id2).unwrap();
        let res = until("the result", &mut server, || client.receive_result(req).unwrap());
        assert_eq!((res.0, res.1.error_code), (GoalStatusEnum::Aborted, NavigateToPoseResult::FAILED_TO_MAKE_PROGRESS), "{res:?}");
        let mut seen = std::collections::HashMap::new();
        until("both goals' states", &mut server, || {
            statuses(&client, &mut seen);
            (seen.get(id1.uuid.as_bytes()) == Some(&GoalStatusEnum::Aborted) && seen.get(id2.uuid.as_bytes()) == Some(&GoalStatusEnum::Aborted)).then_some(())
        });

        // A third goal is cancelled: CANCELED, and the navigator is told to stop.
        let (_, id3) = client.send_goal(goal(3.0)).unwrap();
        assert_eq!(next_request(&mut server, 4.0), Request::Goal(goal(3.0).pose));
        client.cancel_goal(id3).unwrap();
        assert_eq!(next_request(&mut server, 4.5), Request::Cancel);
        assert_eq!(server.current_goal(), None);
        until("the cancelled state", &mut server, || {
            statuses(&client, &mut seen);
            (seen.get(id3.uuid.as_bytes()) == Some(&GoalStatusEnum::Canceled)).then_some(())
        });
    }
}
