//! `xhab ros2 sim|nav|agent`: the simulator, the native stack and the oracle as ROS 2 nodes. Parses the flags
//! into the library's specs (as `xhab ros sim|nav` do) and the DDS configuration from the
//! environment, then runs the node.

use crate::cli::{Ros2Command, Ros2Opts};
use anyhow::Result;
use std::process::ExitCode;
use std::time::Duration;
use xhab_bridge::ros::names::Names;
use crate::scene_arg::scene_options;
use xhab_bridge::ros2::agent_node::{self, Agent2Options};
use xhab_bridge::ros2::standalone_sim::run_standalone;
use xhab_bridge::ros2::nav_node;
use xhab_bridge::ros2::node::{names_from_ros_args, Ros2Config};

/// The node's names: `--name` (else `default`), then `--ros-args` and `$ROS_NAMESPACE`.
fn names(o: &Ros2Opts, default: &str) -> Result<Names> {
    let ns = std::env::var("ROS_NAMESPACE").ok().filter(|s| !s.is_empty());
    Ok(names_from_ros_args(o.name.as_deref().unwrap_or(default), o.ros_args.as_deref().unwrap_or(&[]), ns.as_deref())?)
}

pub fn run(c: &Ros2Command) -> Result<ExitCode> {
    match c {
        Ros2Command::Sim(a) => {
            let config = Ros2Config::from_env(|k| std::env::var(k).ok())?;
            let timeout = Duration::from_secs_f64(a.ros2.ros_timeout.max(0.1));
            let spec = super::ros::sim_spec(&a.sim, None, names(&a.ros2, "xhab_sim")?, a.ros2.lockstep, timeout)?;
            let sim = super::ros::build_sim(&a.sim, &spec)?;
            run_standalone(sim.grid.clone(), &sim.options, config)?;
        }
        Ros2Command::Nav(a) => {
            let config = Ros2Config::from_env(|k| std::env::var(k).ok())?;
            let node = super::ros::build_nav(&a.nav, a.ros2.lockstep, Duration::from_secs_f64(a.ros2.ros_timeout.max(0.1)))?;
            nav_node::serve(names(&a.ros2, "xhab_nav")?, config, node)?;
        }
        Ros2Command::Agent(a) => {
            let config = Ros2Config::from_env(|k| std::env::var(k).ok())?;
            let timeout = Duration::from_secs_f64(a.ros2.ros_timeout.max(0.1));
            let o = Agent2Options { scene: a.scene.clone(), scene_options: scene_options(&a.scene_opts), names: names(&a.ros2, "xhab_agent")?, config, timeout, lockstep: a.ros2.lockstep };
            agent_node::serve(&o)?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
