//! ROS 1 message types generated at build time from `ros_msgs/` (std, geometry, sensor, nav,
//! tf2, rosgraph and actionlib msgs), with their real md5sums.
#![allow(missing_docs, clippy::all, non_snake_case, non_camel_case_types, unused_imports)]

include!(concat!(env!("OUT_DIR"), "/ros_msgs.rs"));
