//! `xhab bench --agent ros2`: benchmarks an external ROS 2 stack (Nav2, or any node offering
//! `navigate_to_pose`; `xhab ros2 nav`) with the loop of [`crate::external_stack`] over DDS:
//! the simulator node [`SimNode2`] (scan, odom, tf, map transient local, `/clock`) and the
//! goal through the action or `goal_pose` ([`NavigateClient`]).

use super::navigate_client::NavigateClient;
use super::node::Ros2Config;
use super::sim_node::SimNode2;
use crate::external_stack::episodes::{check, mounts};
use crate::external_stack::launch::launch;
use crate::external_stack::{run_episodes, ExternalOptions};
use crate::ros::node::RosError;
use crate::runner::{Outcome, RunConfig};
use std::sync::Arc;
use xhab_sim::episode::Dataset;
use xhab_sim::world::World;

/// Runs every episode of `ds` against the external ROS 2 stack in the DDS domain of
/// `config`, one at a time (`opts.master` is not used; a `--launch` command inherits the
/// environment, its domain included). `progress` is called once per finished episode.
pub fn run_dataset_external(world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &ExternalOptions, config: Ros2Config, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    check(cfg, opts, "ros2")?;
    let _stack = opts.launch.as_deref().map(|c| launch(c, &[])).transpose()?;
    let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().map_err(|e| RosError::Node(format!("tokio runtime: {e}")))?;
    rt.block_on(async {
        let mounts = mounts(cfg, opts);
        let mut sim = SimNode2::new(opts.names.clone(), config, &mounts.laser_frame, opts.timeout)?;
        let mut client = NavigateClient::new(&mut sim.node, "navigate_to_pose", opts.goal_interface)?;
        run_episodes(&mut sim, &mut client, &mounts, world, ds, cfg, opts, progress).await
    })
}
