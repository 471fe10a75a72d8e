//! The benchmark over ROS: the simulator and the agent as separate nodes talking through a real
//! rosmaster, in lock-step, so that every step and metric equals the in-process run.

use super::master::Master;
use super::names::Names;
use super::node::RosError;
use super::sim_node::SimNode;
use crate::agents::AgentKind;
use crate::robot_io::{finish_lockstep_run, mounts, run_lockstep_dataset};
use crate::runner::{make_env, Outcome, RunConfig};
use std::sync::Arc;
use std::time::{Duration, Instant};
use xhab_sim::episode::Dataset;
use xhab_sim::world::World;

/// Where the ROS run finds its master, and how patient it is.
#[derive(Debug, Clone)]
pub struct RosOptions {
    /// `http://host:port` of a running master; `None` starts `rosmaster` for the run.
    pub master: Option<String>,
    /// How long to wait for a peer before failing (s).
    pub timeout: Duration,
}

impl Default for RosOptions {
    fn default() -> Self {
        Self { master: None, timeout: Duration::from_secs(30) }
    }
}

/// Runs every episode of `ds` over ROS, one at a time (lock-step is sequential by nature).
/// `progress` is called once per finished episode.
pub fn run_dataset_ros(world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &RosOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    let master = Master::connect_or_start(opts.master.as_deref())?;
    // One thread for both nodes: lock-step hands the turn back and forth, and a wake-up on the
    // same thread costs a fraction of one across threads.
    let rt = tokio::runtime::Builder::new_current_thread().enable_all().build().map_err(|e| RosError::Node(format!("tokio runtime: {e}")))?;
    rt.block_on(run_all(&master.uri, world, ds, cfg, opts, progress))
}

async fn run_all(uri: &str, world: Arc<World>, ds: &Dataset, cfg: &RunConfig, opts: &RosOptions, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, RosError> {
    let (stop_tx, stop_rx) = tokio::sync::watch::channel(false);
    let (stats_tx, mut stats_rx) = tokio::sync::mpsc::unbounded_channel();
    let agent = match (cfg.agent, &cfg.nav) {
        (AgentKind::Nav, Some(setup)) => {
            let o = super::nav_node::NavNodeOptions { setup: setup.scored(cfg.task.success_distance), lockstep: true, seed: cfg.seed, timeout: opts.timeout };
            let uri = uri.to_string();
            tokio::spawn(async move { super::nav_node::run(&uri, Names::plain("xhab_nav"), o, None, None, stop_rx, Some(stats_tx)).await })
        }
        (AgentKind::Nav, None) => return Err(RosError::Protocol("the nav agent needs its navigation setup".into())),
        (kind, _) => {
            let (uri, world, task, timeout) = (uri.to_string(), world.clone(), cfg.task.clone(), opts.timeout);
            tokio::spawn(async move { super::agent_node::run(&uri, Names::plain("xhab_agent"), world, kind, task, timeout, true, stop_rx).await })
        }
    };
    let t_start = Instant::now();
    // The first episode's environment (its geodesic field) is built on another thread while
    // the nodes register and connect, which is mostly waiting on the master.
    let first = ds.episodes.first().map(|ep| {
        let (w, ep, c) = (world.clone(), ep.clone(), cfg.clone());
        tokio::task::spawn_blocking(move || make_env(&w, &ep, c.episode_index(0), &c))
    });
    let mounts = mounts(cfg);
    let mut sim = SimNode::new(uri, Names::plain("xhab_sim"), &mounts.laser_frame, opts.timeout).await?;
    tracing::debug!("ros bench: nodes up in {:.3} s", t_start.elapsed().as_secs_f64());
    let run = run_lockstep_dataset(&mut sim, &world, ds, cfg, first, "ROS", progress).await;
    tracing::debug!("ros bench: episodes done at {:.3} s", t_start.elapsed().as_secs_f64());
    let outcomes = finish_lockstep_run(run, stop_tx, agent, &mut stats_rx, cfg).await?;
    tracing::debug!("ros bench: agent stopped at {:.3} s", t_start.elapsed().as_secs_f64());
    Ok(outcomes)
}
