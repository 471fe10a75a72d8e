//! ROS 2 interop over DDS (ros2-client on RustDDS: pure Rust, no ROS installation needed to
//! build or run): the simulator as a ROS 2 node with Nav2's conventions (sensor-data QoS for
//! sensors, transient-local `map` and `/tf_static`, `/clock`), talking to rclpy/rclcpp nodes
//! over Fast DDS or any other RTPS implementation.
//!
//! [`msgs`]: the message types; [`convert`]: xhab's types to and from them; [`node`]: the
//! DDS participant, QoS profiles, names and remapping (`--ros-args -r`); [`sim_node`]: the
//! simulator node; [`standalone_sim`]: `xhab ros2 sim`; [`nav_node`]: `xhab ros2 nav`, with its
//! `navigate_to_pose` server [`navigate_action`]; [`external`]: `xhab bench --agent ros2`,
//! with [`navigate_client`].
//!
//! Lock-step between xhab's own nodes (`xhab bench --ros2`, `--compare-ros2`): [`xhab_msgs`]:
//! xhab's lock-step messages; [`lockstep`]: the simulator's side and the stamp-keyed inbox;
//! [`agent_node`]: `xhab ros2 agent`; [`nav_lockstep`]: `xhab ros2 nav --lockstep`;
//! [`bench`]: the benchmark over ROS 2.

pub mod convert;
pub mod external;
pub mod standalone_sim;
pub mod msgs;
pub mod navigate_action;
pub mod navigate_client;
pub mod nav_node;
pub mod node;
pub mod sim_node;

// Lock-step between xhab's own nodes.
pub mod agent_node;
pub mod bench;
pub mod lockstep;
pub mod nav_lockstep;
pub mod xhab_msgs;
