//! The benchmark over ROS 2 (`xhab bench --ros2`): the simulator and xhab's agent as separate
//! ROS 2 nodes (each its own DDS participant) in lock-step, so that every step and metric
//! equals the in-process run. Both nodes run on one current-thread tokio runtime: lock-step
//! hands the turn back and forth, and a wake-up on the same thread costs less than one across
//! threads.

use super::lockstep::LockstepSim2;
use super::node::Ros2Config;
use crate::agents::AgentKind;
use crate::robot_io::{finish_lockstep_run, mounts, run_lockstep_dataset};
use crate::ros::names::Names;
use crate::ros::node::RosError;
use crate::runner::{make_env, Outcome, RunConfig};
use std::sync::Arc;
use std::time::{Duration, Instant};
use xhab_sim::episode::Dataset;
use xhab_sim::world::World;

/// Where the ROS 2 run talks, and how patient it is.
#[derive(Debug, Clone, Copy)]
pub struct Ros2BenchOptions {
    /// The DDS domain and discovery range of both nodes.
    pub config: Ros2Config,
    /// How long to wait for a peer before failing.
    pub timeout: Duration,
}

/// Runs every episode of `ds` over ROS 2, one at a time (lock-step is sequential by nature).
/// `progress` is called once per finished episode.
pub fn run_dataset_ros2(world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &Ros2BenchOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    let rt = tokio::runtime::Builder::new_current_thread().enable_all().build().map_err(|e| RosError::Node(format!("tokio runtime: {e}")))?;
    rt.block_on(run_all(world, ds, cfg, opts, progress))
}

async fn run_all(world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &Ros2BenchOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    let (stop_tx, stop_rx) = tokio::sync::watch::channel(false);
    let (stats_tx, mut stats_rx) = tokio::sync::mpsc::unbounded_channel();
    let (config, timeout) = (opts.config, opts.timeout);
    let t_start = Instant::now();
    // The first episode's environment (its geodesic field) is built on another thread while
    // the nodes discover each other.
    let first = ds.episodes.first().map(|ep| {
        let (w, ep, c) = (world.clone(), ep.clone(), cfg.clone());
        tokio::task::spawn_blocking(move || make_env(&w, &ep, c.episode_index(0), &c))
    });
    let agent = match (cfg.agent, &cfg.nav) {
        (AgentKind::Nav, Some(setup)) => {
            let o = crate::ros::nav_node::NavNodeOptions { setup: setup.scored(cfg.task.success_distance), lockstep: true, seed: cfg.seed, timeout };
            tokio::spawn(super::nav_lockstep::run(Names::plain("xhab_nav"), config, o, None, None, stop_rx, Some(stats_tx)))
        }
        (AgentKind::Nav, None) => return Err(RosError::Protocol("the nav agent needs its navigation setup".into())),
        (kind, _) => tokio::spawn(super::agent_node::run(Names::plain("xhab_agent"), config, world.clone(), kind, cfg.task.clone(), timeout, true, stop_rx)),
    };
    // Each node has its own participant: RustDDS 0.15 did not deliver between a writer and a
    // reader of one participant (tried: the first step was never answered).
    let mut sim = LockstepSim2::new(Names::plain("xhab_sim"), config, &mounts(cfg).laser_frame, timeout)?;
    tracing::debug!("ros2 bench: nodes up in {:.3} s", t_start.elapsed().as_secs_f64());
    let run = run_lockstep_dataset(&mut sim, &world, ds, cfg, first, "ROS 2", progress).await;
    let t = sim.timing;
    tracing::debug!(steps = t.steps, publish_s = t.publish_s, wait_s = t.wait_s, total_s = t_start.elapsed().as_secs_f64(), "ros2 bench: lock-step timing");
    finish_lockstep_run(run, stop_tx, agent, &mut stats_rx, cfg).await
}
