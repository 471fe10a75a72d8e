//! `xhab ros2 sim`: the simulator as a long-running ROS 2 node (the loop of
//! [`crate::robot_io::run_sim`], the scene and robot as [`crate::ros::standalone_sim::StandaloneSim`] builds
//! them for `xhab ros sim`).

use super::node::Ros2Config;
use super::sim_node::SimNode2;
use crate::robot_io::run_sim;
use crate::ros::standalone_sim::StandaloneOptions;
use crate::ros::node::RosError;
use std::sync::Arc;
use xhab_sim::navgrid::NavGrid;

/// Runs the simulator node (names from `o.names`; `o.master` is not used) in the DDS domain
/// of `config` until `o.duration` passes or the process is interrupted.
pub fn run_standalone(grid: Arc<NavGrid>, o: &StandaloneOptions, config: Ros2Config) -> Result<(), RosError> {
    crate::ros::foreground::run_until_ctrl_c(async move {
        let mut sim = SimNode2::new(o.names.clone(), config, &o.mounts.laser_frame, o.timeout)?;
        eprintln!("xhab: ROS 2 node {} in DDS domain {}{}", o.names.node_name(), config.domain_id, if config.localhost_only { " (localhost only)" } else { "" });
        run_sim(&mut sim, grid, o).await
    })
}
