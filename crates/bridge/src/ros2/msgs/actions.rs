//! The message types of ROS 2 actions (action_msgs, unique_identifier_msgs) and of Nav2's
//! `navigate_to_pose` action (nav2_msgs/action/NavigateToPose as Kilted defines it), field
//! for field in their definitions' order.

use super::{builtin_interfaces, geometry_msgs, RosType};
use serde::{Deserialize, Serialize};

/// unique_identifier_msgs: the UUID naming a goal.
pub mod unique_identifier_msgs {
    use super::*;

    /// unique_identifier_msgs/UUID: 16 bytes (`uint8[16]`).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
    pub struct UUID {
        /// The bytes.
        pub uuid: [u8; 16],
    }
    ros_type!("unique_identifier_msgs", UUID);
}

/// action_msgs: goal ids, states and cancel requests, as every action uses them.
pub mod action_msgs {
    use super::*;

    /// action_msgs/GoalInfo: a goal's id and when it was accepted.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct GoalInfo {
        /// The goal's id.
        pub goal_id: unique_identifier_msgs::UUID,
        /// When the server accepted it.
        pub stamp: builtin_interfaces::Time,
    }

    /// action_msgs/GoalStatus: a goal and its state (one of the `STATUS_` constants).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct GoalStatus {
        /// The goal.
        pub goal_info: GoalInfo,
        /// Its state.
        pub status: i8,
    }

    impl GoalStatus {
        /// Not known (also: not processed yet).
        pub const STATUS_UNKNOWN: i8 = 0;
        /// Accepted, waiting to execute.
        pub const STATUS_ACCEPTED: i8 = 1;
        /// Being executed.
        pub const STATUS_EXECUTING: i8 = 2;
        /// A cancel was requested and is being acted upon.
        pub const STATUS_CANCELING: i8 = 3;
        /// Reached.
        pub const STATUS_SUCCEEDED: i8 = 4;
        /// Cancelled on request.
        pub const STATUS_CANCELED: i8 = 5;
        /// The server gave up without a request.
        pub const STATUS_ABORTED: i8 = 6;

        /// Whether `s` is terminal (the goal is over).
        pub fn is_terminal(s: i8) -> bool {
            matches!(s, Self::STATUS_SUCCEEDED | Self::STATUS_CANCELED | Self::STATUS_ABORTED)
        }

        /// The name of a state, as action_msgs spells it (without `STATUS_`).
        pub fn name(s: i8) -> &'static str {
            match s {
                Self::STATUS_ACCEPTED => "ACCEPTED",
                Self::STATUS_EXECUTING => "EXECUTING",
                Self::STATUS_CANCELING => "CANCELING",
                Self::STATUS_SUCCEEDED => "SUCCEEDED",
                Self::STATUS_CANCELED => "CANCELED",
                Self::STATUS_ABORTED => "ABORTED",
                _ => "UNKNOWN",
            }
        }
    }

    /// action_msgs/GoalStatusArray: the states of a server's goals, on `<action>/_action/status`.
    #[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct GoalStatusArray {
        /// One entry per goal the server knows.
        pub status_list: Vec<GoalStatus>,
    }

    /// action_msgs/CancelGoal request: a zero id cancels every goal accepted at or before
    /// `stamp` (all of them when the stamp is zero too); a non-zero id cancels that goal (and
    /// those accepted at or before a non-zero stamp).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct CancelGoalRequest {
        /// Which goals.
        pub goal_info: GoalInfo,
    }

    /// action_msgs/CancelGoal response: a return code (the `ERROR_` constants) and the goals
    /// now cancelling.
    #[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct CancelGoalResponse {
        /// What became of the request.
        pub return_code: i8,
        /// The goals that moved to CANCELING.
        pub goals_canceling: Vec<GoalInfo>,
    }

    impl CancelGoalResponse {
        /// Accepted: the goals in `goals_canceling` are cancelling.
        pub const ERROR_NONE: i8 = 0;
        /// Refused.
        pub const ERROR_REJECTED: i8 = 1;
        /// No goal with that id.
        pub const ERROR_UNKNOWN_GOAL_ID: i8 = 2;
        /// The goal is over already.
        pub const ERROR_GOAL_TERMINATED: i8 = 3;
    }
    ros_type!("action_msgs", GoalInfo, GoalStatus, GoalStatusArray);
}

/// nav2_msgs: the `navigate_to_pose` action (nav2_msgs/action/NavigateToPose, Kilted).
pub mod nav2_msgs {
    use super::*;

    /// NavigateToPose goal: where to go, and the behaviour tree to go there with (empty: the
    /// server's default; xhab's navigator has none and ignores it).
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct NavigateToPoseGoal {
        /// The goal pose, in its frame.
        pub pose: geometry_msgs::PoseStamped,
        /// A behaviour tree's file or XML.
        pub behavior_tree: String,
    }

    /// NavigateToPose result: an error code (the constants here, or the failing task's
    /// codes, as Nav2's bt_navigator forwards them) and a message.
    #[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct NavigateToPoseResult {
        /// 0 when reached.
        pub error_code: u16,
        /// What went wrong, for people.
        pub error_msg: String,
    }

    impl NavigateToPoseResult {
        /// No error.
        pub const NONE: u16 = 0;
        /// An error without a code of its own.
        pub const UNKNOWN: u16 = 9000;
        /// The behaviour tree did not load.
        pub const FAILED_TO_LOAD_BEHAVIOR_TREE: u16 = 9001;
        /// A transform was missing (e.g. the goal's frame to `map`).
        pub const TF_ERROR: u16 = 9002;
        /// Navigation took too long.
        pub const TIMEOUT: u16 = 9003;
        /// ComputePathToPose's START_OCCUPIED (bt_navigator forwards the planner's codes).
        pub const START_OCCUPIED: u16 = 205;
        /// ComputePathToPose's NO_VALID_PATH.
        pub const NO_VALID_PATH: u16 = 208;
        /// FollowPath's FAILED_TO_MAKE_PROGRESS (bt_navigator forwards the controller's codes).
        pub const FAILED_TO_MAKE_PROGRESS: u16 = 105;
        /// FollowPath's NO_VALID_CONTROL.
        pub const NO_VALID_CONTROL: u16 = 106;
    }

    /// NavigateToPose feedback: where the robot is and how far it has left.
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct NavigateToPoseFeedback {
        /// The robot's pose (map frame).
        pub current_pose: geometry_msgs::PoseStamped,
        /// Time since the goal was accepted.
        pub navigation_time: builtin_interfaces::Duration,
        /// Distance remaining over the current speed.
        pub estimated_time_remaining: builtin_interfaces::Duration,
        /// Recoveries run so far.
        pub number_of_recoveries: i16,
        /// Length of the rest of the plan (m).
        pub distance_remaining: f32,
    }

    impl ros2_client::Message for NavigateToPoseGoal {}
    impl ros2_client::Message for NavigateToPoseResult {}
    impl ros2_client::Message for NavigateToPoseFeedback {}
}

#[cfg(test)]
mod tests {
    //! Wire-format checks against bytes rclpy (Kilted) serialized, as in the parent's tests.
    use super::action_msgs::*;
    use super::unique_identifier_msgs::UUID;
    use super::*;
    use byteorder::LittleEndian;
    use ros2_client::dds::rustdds::cdr_encoding;

    fn hex(s: &str) -> Vec<u8> {
        (0..s.len()).step_by(2).map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap()).collect()
    }

    fn check<T: Serialize + for<'de> Deserialize<'de> + PartialEq + std::fmt::Debug>(recorded: &str, want: T) {
        let b = hex(recorded);
        let (got, n) = cdr_encoding::from_bytes::<T, LittleEndian>(&b[4..]).unwrap();
        assert_eq!(got, want);
        assert_eq!(n, b.len() - 4, "all bytes read");
        let ours = cdr_encoding::to_vec::<T, LittleEndian>(&want).unwrap();
        assert_eq!(ours.len(), b.len() - 4, "same length as rclpy's");
    }

    fn info(id: [u8; 16], sec: i32, nanosec: u32) -> GoalInfo {
        GoalInfo { goal_id: UUID { uuid: id }, stamp: builtin_interfaces::Time { sec, nanosec } }
    }

    #[test]
    fn goal_status_array_and_cancel_goal_match_rclpy() {
        check(
            "0001000002000000010101010101010101010101010101010300000005000000020202020202020202020202020202020259f5d0030000000500000004",
            GoalStatusArray { status_list: vec![GoalStatus { goal_info: info([1; 16], 3, 5), status: 2 }, GoalStatus { goal_info: info([2; 16], 3, 5), status: 4 }] },
        );
        let ids: [u8; 16] = std::array::from_fn(|i| i as u8);
        check("00010000000102030405060708090a0b0c0d0e0f0700000000000000", CancelGoalRequest { goal_info: info(ids, 7, 0) });
        check("000100000255000000000000", CancelGoalResponse { return_code: 2, goals_canceling: vec![] });
    }

    #[test]
    fn our_uuid_reads_ros2_clients_goal_id() {
        // ros2-client's action server speaks its own types; ours must be the same bytes.
        let theirs = ros2_client::action::GoalId::new_random();
        let b = cdr_encoding::to_vec::<_, LittleEndian>(&theirs).unwrap();
        let (ours, _) = cdr_encoding::from_bytes::<UUID, LittleEndian>(&b).unwrap();
        assert_eq!(&ours.uuid, theirs.uuid.as_bytes());
    }
}
