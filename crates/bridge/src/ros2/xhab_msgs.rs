//! xhab's own lock-step messages for ROS 2 (package `xhab_msgs`, DDS type names such as
//! `xhab_msgs::msg::dds_::Step_`): the same fields, in the same order, as the ROS 1 definitions
//! in `ros_msgs/xhab_msgs/msg/` (Episode, Step, StepReply), with ROS 2's builtin time.

use super::msgs::{builtin_interfaces::Time, geometry_msgs as gm, RosType};
use serde::{Deserialize, Serialize};

/// The start of one lock-step episode, from the simulator on `xhab/episode` (transient
/// local): what the agent side needs that has no standard topic.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Episode {
    /// The episode's index in the run (0, 1, ...).
    pub index: u32,
    /// Its id in the dataset.
    pub episode_id: String,
    /// Stamp of the episode's first step.
    pub start: Time,
    /// The PointNav goal (frame map).
    pub goal: gm::PoseStamped,
    /// The start pose and its spread (frame map).
    pub initial_pose: gm::PoseWithCovarianceStamped,
    /// header.stamp of its message on `map` (0: none).
    pub map_stamp: Time,
    /// header.stamp of its message on `amcl/map` (0: none).
    pub amcl_map_stamp: Time,
}

/// One lock-step step, from the simulator on `xhab/step`, published after the step's
/// standard messages (clock, tf, scan, odom, ground_truth/pose, camera), which all carry `stamp`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Step {
    /// Episode.index.
    pub episode: u32,
    /// 0, 1, ... within the episode.
    pub step: u32,
    /// header.stamp of every standard message of this step.
    pub stamp: Time,
    /// Whether a scan with this stamp was published on `scan`.
    pub scan: bool,
}

/// The agent's answer to one Step, on `xhab/step_reply`; the simulator advances on it.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StepReply {
    /// Step.episode answered.
    pub episode: u32,
    /// Step.step answered.
    pub step: u32,
    /// One of [`StepReply::DRIVE`], [`StepReply::ACTION`], [`StepReply::STOP`], [`StepReply::ABORT`].
    pub kind: u8,
    /// The velocity of a DRIVE reply (the same twist is on `cmd_vel`).
    pub twist: gm::Twist,
    /// The discrete action of an ACTION reply (Habitat's numbering: 0 stop, 1 forward, 2 left, 3 right).
    pub action: i16,
    /// Kind ABORT: why the navigator gave up; else empty.
    pub abort_reason: String,
}

impl StepReply {
    /// Drive with `twist` for one controller period.
    pub const DRIVE: u8 = 0;
    /// Take the discrete `action`.
    pub const ACTION: u8 = 1;
    /// The goal is reached: call Habitat's stop.
    pub const STOP: u8 = 2;
    /// The agent gave up.
    pub const ABORT: u8 = 3;
}

macro_rules! xhab_type {
    ($($t:ident),+) => {$(
        impl RosType for $t {
            const PACKAGE: &'static str = "xhab_msgs";
            const NAME: &'static str = stringify!($t);
        }
    )+};
}
xhab_type!(Episode, Step, StepReply);

#[cfg(test)]
mod tests {
    use super::*;
    use ros2_client::MessageTypeName;

    #[test]
    fn the_dds_type_names_are_under_xhabs_package() {
        let n = MessageTypeName::new(Step::PACKAGE, Step::NAME);
        assert_eq!(n.dds_msg_type(), "xhab_msgs::msg::dds_::Step_");
        assert_eq!(MessageTypeName::new(StepReply::PACKAGE, StepReply::NAME).dds_msg_type(), "xhab_msgs::msg::dds_::StepReply_");
        assert_eq!(MessageTypeName::new(Episode::PACKAGE, Episode::NAME).dds_msg_type(), "xhab_msgs::msg::dds_::Episode_");
    }
}
