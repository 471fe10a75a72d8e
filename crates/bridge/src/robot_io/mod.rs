//! What the simulated robot publishes and takes over ROS, whatever the transport (ROS 1's
//! TCPROS in [`crate::ros`], ROS 2's DDS in `crate::ros2`): the robot's state at an instant,
//! the sensor mounts, the commands, the numbers every message carries (time split into
//! seconds and nanoseconds, quaternions, covariances, camera matrices, depth bytes), the
//! simulator node's main loop, generic over a [`SimTransport`], and the benchmark's lock-step
//! episodes, generic over a [`LockstepTransport`].

mod standalone_loop;
mod lockstep;
mod lockstep_run;
mod state;
pub mod wire;

pub use standalone_loop::{render_frame, run_sim, SimTransport};
pub use lockstep::{EpisodeStart, LockstepTransport, StepAnswer};
pub(crate) use lockstep_run::{mounts, run_lockstep_dataset, finish_lockstep_run};
pub use state::{Command, Mounts, RobotState, DEPTH_OPTICAL_FRAME, OPTICAL_ROTATION, RGB_OPTICAL_FRAME};
