//! `xhab bench --agent ros`: benchmarks an external ROS navigation stack (move_base + amcl with
//! the user's YAML, a rospy node, `xhab ros nav`) through standard interfaces only, with the
//! loop of [`crate::external_stack`] on ROS 1: the simulator node, the `move_base` action or
//! `move_base_simple/goal` (goal's fate read from `move_base/status`), a master with
//! `/use_sim_time`.

use super::master::Master;
use super::move_base_client::MoveBaseClient;
use super::node::RosError;
use super::sim_node::SimNode;
use crate::external_stack::episodes::{check, mounts};
use crate::external_stack::launch::launch;
use crate::external_stack::{run_episodes, StackSim};
use crate::runner::{Outcome, RunConfig};
use std::sync::Arc;
use std::time::Duration;
use xhab_sim::episode::Dataset;
use xhab_sim::world::World;
use xhab_types::{Pose2, Twist};

pub use crate::external_stack::{ExternalOptions, MapOdom, Pace, RosEpisode};

/// Runs every episode of `ds` against the external stack, one at a time. `progress` is
/// called once per finished episode.
pub fn run_dataset_external(world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &ExternalOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    check(cfg, opts, "ros")?;
    let master = Master::connect_or_start(opts.master.as_deref())?;
    // The stack runs on simulated time: set before it starts (nodes read it once).
    master.set_param_bool("/use_sim_time", true)?;
    let _stack = opts.launch.as_deref().map(|c| launch(c, &[("ROS_MASTER_URI", &master.uri)])).transpose()?;
    let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().map_err(|e| RosError::Node(format!("tokio runtime: {e}")))?;
    rt.block_on(async {
        let mounts = mounts(cfg, opts);
        let mut sim = SimNode::new(&master.uri, opts.names.clone(), &mounts.laser_frame, opts.timeout).await?;
        let mut client = MoveBaseClient::new(&sim.node, opts.goal_interface).await?;
        run_episodes(&mut sim, &mut client, &mounts, world, ds, cfg, opts, progress).await
    })
}

impl StackSim for SimNode {
    async fn publish_clock(&self, stamp: f64) -> Result<(), RosError> {
        SimNode::publish_clock(self, stamp).await
    }

    async fn publish_initialpose(&self, stamp: f64, p: Pose2, xy_std: f64, yaw_std: f64) -> Result<(), RosError> {
        SimNode::publish_initialpose(self, stamp, p, xy_std, yaw_std).await
    }

    async fn cmd_vel_within(&mut self, grace: Duration) -> Option<Twist> {
        SimNode::cmd_vel_within(self, grace).await
    }

    async fn republish_latched(&mut self) -> Result<(), RosError> {
        SimNode::republish_latched(self).await
    }
}
