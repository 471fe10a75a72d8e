//! ROS 1 interop over TCPROS (roslibrust's ros1 backend): the simulator, the native stack and
//! discrete agents as ROS nodes, with a lock-step mode whose results equal in-process runs.

pub mod convert;
pub mod foreground;
pub mod master;
pub mod msgs;
pub mod names;
pub mod node;
pub mod tf_buffer;
pub mod move_base_server;
pub mod sim_node;
pub mod agent_node;
pub mod nav_node;
pub mod bench;
pub mod standalone_sim;
pub mod external;
pub mod move_base_client;
pub mod wire;
