//! `xhab ros2 sim|nav`: the simulator and the native stack as ROS 2 nodes. Parses the flags
//! into the library's specs (as `xhab ros sim|nav` do) and the DDS configuration from the
//! environment, then runs the node.

use crate::cli::{Ros2Command, Ros2Opts};
use anyhow::Result;
use std::process::ExitCode;
use std::time::Duration;
use xhab_bridge::ros::names::Names;
use xhab_bridge::ros2::live::run_live;
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
            run_live(sim.grid.clone(), &sim.options, config)?;
        }
        Ros2Command::Nav(a) => {
            if a.ros2.lockstep {
                anyhow::bail!("--lockstep: xhab ros2 nav runs free (lock-step over ROS 2 is not built yet)");
            }
            let config = Ros2Config::from_env(|k| std::env::var(k).ok())?;
            let node = super::ros::build_nav(&a.nav, false, Duration::from_secs_f64(a.ros2.ros_timeout.max(0.1)))?;
            nav_node::serve(names(&a.ros2, "xhab_nav")?, config, node)?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
