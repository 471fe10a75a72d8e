//! `xhab ros sim|nav|agent`: the simulator, the native stack and a discrete agent as ROS 1
//! nodes. Parses the flags into the library's options ([`SimSpec`], [`NavNodeSpec`],
//! [`AgentNodeOptions`]), builds and runs the node there, prints.

use crate::cli::{LocalizationArg, MapOdomArg, NavNodeArgs, RosCommand, RosOpts, SimNodeArgs};
use crate::scene_arg::scene_options;
use anyhow::{bail, Result};
use std::process::ExitCode;
use std::time::Duration;
use xhab_bridge::nav_agent::Localization;
use xhab_bridge::ros::agent_node::{self, AgentNodeOptions};
use xhab_bridge::ros::standalone_sim::{run_standalone, StandaloneSim, SimSpec};
use xhab_bridge::ros::names::Names;
use xhab_bridge::ros::nav_node::{self, NavNodeSetup, NavNodeSpec};
use xhab_types::Pose2;

/// The master: --ros-master, else $ROS_MASTER_URI, else `None` (start one).
fn master_uri(o: &RosOpts) -> Option<String> {
    o.ros_master.clone().or_else(|| std::env::var("ROS_MASTER_URI").ok().filter(|s| !s.is_empty()))
}

/// The node's names: `--name` (else `default`), then the ROS arguments and `$ROS_NAMESPACE`.
fn names(o: &RosOpts, default: &str) -> Result<Names> {
    let ns = std::env::var("ROS_NAMESPACE").ok().filter(|s| !s.is_empty());
    Ok(Names::from_args(o.name.as_deref().unwrap_or(default), &o.ros_args, ns.as_deref())?)
}

/// How long to wait for a peer: `--ros-timeout`, at least 0.1 s.
fn timeout(o: &RosOpts) -> Duration {
    Duration::from_secs_f64(o.ros_timeout.max(0.1))
}

/// `--start X,Y,YAW`.
pub(crate) fn start_pose(s: &str) -> Result<Pose2> {
    let v: Vec<f64> = s.split(',').map(|t| t.trim().parse::<f64>()).collect::<std::result::Result<_, _>>().map_err(|_| anyhow::anyhow!("bad --start '{s}': expected X,Y,YAW"))?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        bail!("bad --start '{s}': expected three finite numbers X,Y,YAW");
    }
    Ok(Pose2::new(v[0], v[1], v[2]))
}

/// The simulator's spec from `xhab ros sim`'s or `xhab ros2 sim`'s flags and the node's
/// transport options.
pub(crate) fn sim_spec(a: &SimNodeArgs, master: Option<String>, names: Names, lockstep: bool, timeout: Duration) -> Result<SimSpec> {
    Ok(SimSpec {
        scene: a.scene.clone(),
        scene_options: scene_options(&a.scene_opts),
        physics: a.physics.physics.then(|| super::bench::physics_options(&a.physics)),
        map: a.map.clone(),
        amcl_map: a.amcl_map.clone(),
        start: a.start.as_deref().map(start_pose).transpose()?,
        publish_camera: a.camera,
        rgb: a.rgb,
        camera: super::render::camera_options(&a.cam),
        depth_noise: a.depth_noise,
        edge_dropout: a.edge_dropout,
        rate: a.rate,
        period: a.period,
        duration: a.duration,
        seed: a.seed,
        map_odom_ground_truth: a.map_odom == MapOdomArg::GroundTruth,
        master,
        names,
        lockstep,
        timeout,
    })
}

/// Builds the simulator of `spec` and says on stderr what runs (renderer, start, commands).
pub(crate) fn build_sim(a: &SimNodeArgs, spec: &SimSpec) -> Result<StandaloneSim> {
    let sim = StandaloneSim::build(spec)?;
    if let Some(note) = &sim.renderer_note {
        super::render::print_renderer_note(note);
    }
    let (start, o) = (sim.options.start, &sim.options);
    eprintln!("xhab: simulating {} from ({:.2}, {:.2}, yaw {:.2}){}", a.scene, start.x, start.y, start.yaw, if o.physics.is_some() { " under physics (cmd_vel)" } else { " with discrete actions (action)" });
    Ok(sim)
}

/// The nav node of `xhab ros nav`'s or `xhab ros2 nav`'s flags, its warnings printed.
pub(crate) fn build_nav(a: &NavNodeArgs, lockstep: bool, timeout: Duration) -> Result<NavNodeSetup> {
    let spec = NavNodeSpec {
        map: a.map.clone(),
        amcl_map: a.amcl_map.clone(),
        localization: match a.localization {
            LocalizationArg::GroundTruth => Localization::GroundTruth,
            LocalizationArg::Odom => Localization::Odom,
            LocalizationArg::Amcl => Localization::Amcl,
        },
        nav_params: a.nav_params.clone(),
        robot: a.robot.clone(),
        seed: a.seed,
        lockstep,
        timeout,
    };
    let node = NavNodeSetup::build(&spec)?;
    for w in &node.warnings {
        eprintln!("xhab: warning: {w}");
    }
    Ok(node)
}

pub fn run(c: &RosCommand) -> Result<ExitCode> {
    match c {
        RosCommand::Sim(a) => {
            let spec = sim_spec(&a.sim, master_uri(&a.ros), names(&a.ros, "xhab_sim")?, a.ros.lockstep, timeout(&a.ros))?;
            let sim = build_sim(&a.sim, &spec)?;
            run_standalone(sim.grid.clone(), &sim.options)?;
        }
        RosCommand::Nav(a) => {
            let node = build_nav(&a.nav, a.ros.lockstep, timeout(&a.ros))?;
            nav_node::serve(master_uri(&a.ros).as_deref(), names(&a.ros, "xhab_nav")?, node)?;
        }
        RosCommand::Agent(a) => {
            let o = AgentNodeOptions { scene: a.scene.clone(), scene_options: scene_options(&a.scene_opts), master: master_uri(&a.ros), names: names(&a.ros, "xhab_agent")?, timeout: timeout(&a.ros) };
            agent_node::serve(&o)?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
