//! What the simulated robot publishes and takes over ROS, whatever the transport (ROS 1's
//! TCPROS in [`crate::ros`], ROS 2's DDS in `crate::ros2`): the robot's state at an instant,
//! the sensor mounts, the commands, the numbers every message carries (time split into
//! seconds and nanoseconds, quaternions, covariances, camera matrices, depth bytes), and the
//! simulator node's main loop, generic over a [`SimTransport`].

mod live_loop;
mod state;
pub mod wire;

pub use live_loop::{render_frame, run_sim, SimTransport};
pub use state::{Command, Mounts, RobotState, DEPTH_OPTICAL_FRAME, OPTICAL_ROTATION, RGB_OPTICAL_FRAME};
