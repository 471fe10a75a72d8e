//! ROS 1 message types generated at build time from `ros_msgs/` (std, geometry, sensor, nav,
//! tf2, rosgraph, actionlib, move_base msgs, std_srvs, and xhab's own xhab_msgs), with their
//! real md5sums.
#![allow(missing_docs, clippy::all, non_snake_case, non_camel_case_types, unused_imports)]

include!(concat!(env!("OUT_DIR"), "/ros_msgs.rs"));

#[cfg(test)]
mod tests {
    use roslibrust::RosMessageType;

    /// The md5sums real ROS 1 (Debian's rospy) reports for the types we exchange.
    #[test]
    fn md5sums_match_real_ros() {
        let cases: [(&str, &str); 17] = [
            (super::move_base_msgs::MoveBaseActionGoal::DESCRIPTION.md5sum, "660d6895a1b9a16dce51fbdd9a64a56b"),
            (super::move_base_msgs::MoveBaseActionResult::DESCRIPTION.md5sum, "1eb06eeff08fa7ea874431638cb52332"),
            (super::move_base_msgs::MoveBaseActionFeedback::DESCRIPTION.md5sum, "7d1870ff6e0decea702b943b5af0b42e"),
            (super::actionlib_msgs::GoalStatusArray::DESCRIPTION.md5sum, "8b2b82f13216d0a8ea88bd3af735e619"),
            (super::actionlib_msgs::GoalID::DESCRIPTION.md5sum, "302881f31927c1df708a2dbab0e80ee8"),
            (<super::std_srvs::Empty as roslibrust::RosServiceType>::MD5SUM, "d41d8cd98f00b204e9800998ecf8427e"),
            (super::sensor_msgs::LaserScan::DESCRIPTION.md5sum, "90c7ef2dc6895d81024acba2ac42f369"),
            (super::sensor_msgs::Image::DESCRIPTION.md5sum, "060021388200f6f0f447d0fcd9c64743"),
            (super::sensor_msgs::CameraInfo::DESCRIPTION.md5sum, "c9a58c1b0b154e0e6da7578cb991d214"),
            (super::nav_msgs::Odometry::DESCRIPTION.md5sum, "cd5e73d190d741a2f92e81eda573aca7"),
            (super::nav_msgs::OccupancyGrid::DESCRIPTION.md5sum, "3381f2d731d4076ec5c71b0759edbe4e"),
            (super::tf2_msgs::TFMessage::DESCRIPTION.md5sum, "94810edda583a504dfda3829e70d7eec"),
            (super::rosgraph_msgs::Clock::DESCRIPTION.md5sum, "a9c97c1d230cfc112e270351a944ee47"),
            (super::geometry_msgs::Twist::DESCRIPTION.md5sum, "9f195f881246fdfa2798d1d3eebca84a"),
            (super::geometry_msgs::PoseStamped::DESCRIPTION.md5sum, "d3812c3cbc69362b77dc0b19b345f8f5"),
            (super::std_msgs::Int16::DESCRIPTION.md5sum, "8524586e34fbd7cb1c08c5f5f1ca0e57"),
            (super::sensor_msgs::LaserScan::DESCRIPTION.ros_type_name, "sensor_msgs/LaserScan"),
        ];
        for (got, want) in cases {
            assert_eq!(got, want);
        }
    }
}
