//! `xhab bench`: an agent on every episode of a dataset; metrics as JSON, CSV and a table.
//! Parses the flags into the library's [`BenchOptions`], calls [`run_bench`], prints.

use crate::cli::{AgentArg, BenchArgs, GoalInterfaceArg, LocalizationArg, MapOdomArg, PaceArg, PhysicsOpts, ScanSourceArg};
use crate::scene_arg::scene_options;
use anyhow::{Context, Result};
use std::process::ExitCode;
use std::time::Duration;
use xhab_bridge::agents::AgentKind;
use xhab_bridge::benchmark::{run_bench, BenchOptions, BenchRun, ExternalSpec, NavOptions, ScanKind, Transport as BenchTransport};
use xhab_bridge::map_picture::draw_trajectories;
use xhab_bridge::nav_agent::Localization;
use xhab_bridge::report::{episodes_csv, BenchReport};
use xhab_bridge::ros::external::MapOdom;
use xhab_bridge::ros::move_base_client::GoalInterface;
use xhab_bridge::runner::Aggregate;
use xhab_bridge::setup::{EnvOptions, PhysicsOptions};
use xhab_sim::env::TaskConfig;

pub fn run(a: &BenchArgs, quiet: bool) -> Result<ExitCode> {
    let o = bench_options(a)?;
    if !matches!(o.transport, BenchTransport::InProcess) && o.threads > 1 {
        eprintln!("xhab: note: over ROS episodes run one at a time (lock-step); --threads applies to the in-process run only");
    }
    let pb = super::progress(0, quiet, o.agent.name());
    let run = run_bench(&o, &|done, total| {
        pb.set_length(total as u64);
        pb.set_position(done as u64);
        if a.rss_every > 0 && done % a.rss_every == 0 {
            match resident_kib() {
                Some(kib) => eprintln!("xhab: rss after episode {done}: {kib} KiB"),
                None => eprintln!("xhab: rss after episode {done}: unknown (no /proc/self/status)"),
            }
        }
    })?;
    pb.finish_and_clear();
    if let Some(note) = &run.renderer_note {
        eprintln!("xhab: renderer {note}");
    }
    for w in &run.warnings {
        eprintln!("xhab: warning: {w}");
    }
    let r = &run.report;
    if let (Some(check), Some(overhead)) = (&r.ros_check, r.aggregate.ros_overhead) {
        eprintln!(
            "xhab: over {} {:.2} s, in-process {:.2} s (overhead {:.2}x); results {} (max metric difference {:.1e}, {} episodes with other steps)",
            if a.compare_ros2 { "ROS 2" } else { "ROS" },
            r.aggregate.wall_s, r.aggregate.wall_s / overhead.max(1e-9), overhead,
            if check.identical { "identical" } else { "DIFFER" }, check.max_metric_diff, check.episodes_with_other_steps
        );
    }
    let differ = r.ros_check.as_ref().is_some_and(|c| !c.identical);
    let none_valid = r.aggregate.episodes == 0;
    finish(a, &run)?;
    if none_valid {
        anyhow::bail!("no valid episode in {} ({} invalid, see the warnings above): every metric is undefined", a.episodes.display(), run.report.invalid.count);
    }
    if differ {
        let flag = if a.compare_ros2 { "--compare-ros2" } else { "--compare-ros" };
        let over = if a.compare_ros2 { "ROS 2" } else { "ROS" };
        anyhow::bail!("{flag}: the run over {over} differs from the in-process run (see ros_check in the JSON)");
    }
    Ok(ExitCode::SUCCESS)
}

/// The process's resident memory in KiB (`VmRSS` of /proc/self/status; Linux only).
fn resident_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// The library's benchmark options from `xhab bench`'s flags.
fn bench_options(a: &BenchArgs) -> Result<BenchOptions> {
    if !(a.ros_timeout > 0.0 && a.ros_timeout.is_finite()) {
        anyhow::bail!("--ros-timeout must be a positive number of seconds");
    }
    let agent = match a.agent {
        AgentArg::Oracle => AgentKind::Oracle,
        AgentArg::Nav => AgentKind::Nav,
        AgentArg::Ros => AgentKind::Ros,
        AgentArg::Ros2 => AgentKind::Ros2,
    };
    let ros_args = match (a.agent, &a.ros2_args) {
        (AgentArg::Ros2, _) if !a.ros_args.is_empty() => anyhow::bail!("--agent ros2 takes ROS 2 arguments: --ros-args -r FROM:=TO ... (last on the line), not --ros-arg"),
        (AgentArg::Ros2, r) => r.clone().unwrap_or_default(),
        (_, Some(_)) => anyhow::bail!("--ros-args is for --agent ros2 (ROS 1's stack takes --ros-arg FROM:=TO)"),
        (_, None) => a.ros_args.clone(),
    };
    let mut env = EnvOptions::new(a.scene.clone());
    env.scene_options = scene_options(&a.scene_opts);
    // The nav and ros agents drive with velocities: under physics, with --robot.
    env.physics = (a.physics.physics || matches!(a.agent, AgentArg::Nav | AgentArg::Ros | AgentArg::Ros2)).then(|| physics_options(&a.physics));
    env.sensors = a.sensors.clone();
    env.camera = super::render::camera_options(&a.camera);
    env.depth_noise = a.depth_noise;
    env.edge_dropout = a.edge_dropout;
    env.task = TaskConfig { success_distance: a.success_distance, max_episode_steps: a.max_steps, ..Default::default() };
    Ok(BenchOptions {
        env,
        episodes: a.episodes.clone(),
        episode_indices: None,
        agent,
        threads: a.threads.max(1),
        seed: a.seed,
        record_trajectories: a.trajectories.is_some(),
        nav: NavOptions {
            localization: match a.localization {
                LocalizationArg::GroundTruth => Localization::GroundTruth,
                LocalizationArg::Odom => Localization::Odom,
                LocalizationArg::Amcl => Localization::Amcl,
            },
            map: a.map.clone(),
            params: a.nav_params.clone(),
            scans: match (a.no_scans, a.scan_source) {
                (true, _) => None,
                (false, ScanSourceArg::Lidar) => Some(ScanKind::Lidar),
                (false, ScanSourceArg::Depth) => Some(ScanKind::Depth),
            },
        },
        transport: match (a.ros, a.compare_ros, a.ros2, a.compare_ros2) {
            (_, _, _, true) => BenchTransport::CompareRos2,
            (_, _, true, false) => BenchTransport::Ros2,
            (_, true, false, false) => BenchTransport::CompareRos,
            (true, false, false, false) => BenchTransport::Ros,
            (false, false, false, false) => BenchTransport::InProcess,
        },
        ros_master: a.ros_master.clone(),
        ros_timeout: Duration::from_secs_f64(a.ros_timeout.max(0.1)),
        external: ExternalSpec {
            master: a.ros_master.clone(),
            ros_args,
            goal_interface: match a.goal_interface {
                GoalInterfaceArg::Action => GoalInterface::Action,
                GoalInterfaceArg::Simple => GoalInterface::Simple,
            },
            episode_timeout: a.episode_timeout,
            map_odom: match a.map_odom {
                MapOdomArg::Stack => MapOdom::Stack,
                MapOdomArg::GroundTruth => MapOdom::GroundTruth,
            },
            realtime: a.pace == PaceArg::Realtime,
            rate: a.rate,
            cmd_vel_grace: a.cmd_vel_grace,
            controller_frequency: a.controller_frequency,
            launch: a.launch.clone(),
        },
    })
}

/// The library's physics options from the `Physics` flags.
pub fn physics_options(o: &PhysicsOpts) -> PhysicsOptions {
    PhysicsOptions { robot: o.robot.clone(), control_period: o.control_period, steps_per_sec: o.steps_per_sec }
}

/// Writes the trajectories, JSON and CSV a run asked for, and prints its table.
fn finish(a: &BenchArgs, run: &BenchRun) -> Result<()> {
    if let Some(dir) = &a.trajectories {
        draw_trajectories(&run.world, &run.dataset, &run.outcomes, dir)?;
    }
    if let Some(out) = &a.out {
        super::ensure_parent(out)?;
        let json = serde_json::to_string_pretty(&run.report)?;
        std::fs::write(out, json + "\n").with_context(|| format!("writing {}", out.display()))?;
    }
    if let Some(csv) = &a.csv {
        super::ensure_parent(csv)?;
        std::fs::write(csv, episodes_csv(&run.report.episodes)).with_context(|| format!("writing {}", csv.display()))?;
    }
    print_table(&run.report.aggregate, run.report.invalid.count, &run.report.agent);
    print_ros_ends(&run.report);
    Ok(())
}

/// How an external stack's episodes ended (`--agent ros`, `ros2`): terminal action states and why
/// each episode stopped (the failures line above counts them by Habitat's causes only).
fn print_ros_ends(report: &BenchReport) {
    let mut states: std::collections::BTreeMap<&str, usize> = Default::default();
    let mut ends: std::collections::BTreeMap<&str, usize> = Default::default();
    for e in &report.episodes {
        if let (Some(s), Some(end)) = (e.ros_status.as_deref(), e.ros_end.as_deref()) {
            *states.entry(s).or_default() += 1;
            *ends.entry(end).or_default() += 1;
        }
    }
    if states.is_empty() {
        return;
    }
    let list = |m: &std::collections::BTreeMap<&str, usize>| m.iter().map(|(k, n)| format!("{n} {k}")).collect::<Vec<_>>().join(", ");
    println!("ros: goals ended {}; episodes ended by {}", list(&states), list(&ends));
}

/// Prints the summary table on stdout.
pub fn print_table(a: &Aggregate, invalid: usize, agent: &str) {
    println!("{:<8} {:>8} {:>8} {:>8} {:>8} {:>10} {:>8} {:>10} {:>8} {:>12}", "agent", "episodes", "success", "spl", "soft_spl", "dtg_m", "steps", "collisions", "wall_s", "steps_per_s");
    println!(
        "{:<8} {:>8} {:>8.3} {:>8.3} {:>8.3} {:>10.3} {:>8.1} {:>10.1} {:>8.2} {:>12.0}",
        agent, a.episodes, a.success, a.spl, a.soft_spl, a.distance_to_goal, a.steps, a.collisions, a.wall_s, a.steps_per_s
    );
    if let (Some(sim), Some(rtf), Some(stuck)) = (a.sim_s, a.real_time_factor, a.stuck) {
        println!("physics: {sim:.0} s simulated, {rtf:.0}x real time, stuck in {:.1}% of episodes", stuck * 100.0);
    }
    let f = &a.failures;
    if f.stuck + f.stopped_outside + f.step_limit + f.goal_unreachable_for_costmap + f.aborted > 0 {
        println!(
            "failures: {} stuck, {} stopped outside the goal, {} ran out of steps, {} aborted (goal unreachable for the costmap), {} aborted (other)",
            f.stuck, f.stopped_outside, f.step_limit, f.goal_unreachable_for_costmap, f.aborted
        );
    }
    if invalid > 0 {
        println!("({invalid} invalid episodes left out)");
    }
}
