//! Benchmarking an external navigation stack through standard interfaces, whatever the
//! transport (`xhab bench --agent ros` over ROS 1, `--agent ros2` over ROS 2): the simulator
//! runs in-process as a node under physics; per episode it places the robot at the start,
//! publishes `initialpose`, sends the goal and advances `/clock` in ticks of one controller
//! period, until the goal reaches a terminal state (SUCCEEDED counts as Habitat's stop), the
//! episode times out (the goal is cancelled), or the robot is stuck.
//!
//! [`options`]: how to run the stack; [`interfaces`]: what the loop needs of a transport (the
//! simulator node's extra topics, the goal's client); [`launch`]: `--launch`; [`episodes`]:
//! the loop, written once.

pub mod episodes;
pub mod interfaces;
pub mod launch;
pub mod options;

pub use episodes::run_episodes;
pub use interfaces::{GoalClient, GoalState, StackSim};
pub use options::{ExternalOptions, GoalInterface, MapOdom, Pace, RosEpisode};
