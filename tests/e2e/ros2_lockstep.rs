//! Lock-step over ROS 2 between xhab's own nodes (`xhab bench --compare-ros2`): the oracle and
//! the nav agent give the same steps, metrics and abort reasons over DDS as in-process; a
//! simulator whose agent never appears fails with a clear error, not a hang. No rclpy needed
//! there: both ends are xhab's (RustDDS). `xhab ros2 agent` beside `xhab ros2 sim --lockstep`,
//! as separate processes, brings the robot to rclpy's `goal_pose`.

use crate::common::{repo_root, xhab};
use crate::ros2_interop::{domain_id, goal_in_the_open, rclpy_env, ros2_python, xhab_ros2_env};
use crate::ros_interop::Killed;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use xhab_bridge::ros::standalone_sim::{StandaloneSim, SimSpec};

fn tempdir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("xhab_test_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `xhab bench --compare-ros2` with `extra` flags in DDS domain `domain`: the report's JSON.
fn compare_ros2(dir: &std::path::Path, eps: &std::path::Path, domain: &str, extra: &[&str]) -> serde_json::Value {
    let out = dir.join("r.json");
    let mut cmd = xhab();
    cmd.args(["bench", "--scene", "procedural:5", "--episodes"]).arg(eps).args(["--compare-ros2", "--ros-timeout", "20", "--quiet", "--out"]).arg(&out).args(extra);
    xhab_ros2_env(&mut cmd, domain);
    let st = cmd.status().unwrap();
    assert!(st.success(), "bench --compare-ros2 {extra:?} failed");
    serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap()
}

#[test]
fn bench_over_ros2_equals_the_in_process_run() {
    let dir = tempdir("ros2_bench");
    let eps = dir.join("eps.json.gz");
    assert!(xhab().args(["episodes", "procedural:5", "--count", "3", "--seed", "2", "--out"]).arg(&eps).status().unwrap().success());
    for (i, extra) in [&[][..], &["--agent", "nav", "--localization", "amcl"][..]].into_iter().enumerate() {
        let v = compare_ros2(&dir, &eps, &domain_id(40 + i as u32), extra);
        assert_eq!(v["ros"], true);
        assert_eq!(v["ros_check"]["identical"], true, "{extra:?}: {}", v["ros_check"]);
        assert_eq!(v["ros_check"]["episodes_with_other_steps"], 0, "{extra:?}");
        assert!(v["aggregate"]["ros_overhead"].as_f64().unwrap() > 0.0);
        assert_eq!(v["aggregate"]["episodes"].as_u64().unwrap(), 3, "{extra:?}");
        assert!(v["aggregate"]["success"].as_f64().unwrap() > 0.6, "{extra:?}: {}", v["aggregate"]);
    }
}

#[test]
fn a_nav_abort_over_ros2_carries_the_navigators_reason() {
    let dir = tempdir("ros2_abort");
    let eps = dir.join("eps.json.gz");
    assert!(xhab().args(["episodes", "procedural:5", "--count", "2", "--seed", "3", "--out"]).arg(&eps).status().unwrap().success());
    // A 1.6 m square footprint: the house has no room for it, so the navigator gives up, for
    // the same reason in-process and over ROS 2 (ros_check compares the reasons).
    let params = dir.join("huge.yaml");
    let square = "[[-0.8, -0.8], [-0.8, 0.8], [0.8, 0.8], [0.8, -0.8]]";
    std::fs::write(&params, format!("global_costmap:\n  footprint: {square}\nlocal_costmap:\n  footprint: {square}\n")).unwrap();
    let v = compare_ros2(&dir, &eps, &domain_id(43), &["--agent", "nav", "--nav-params", params.to_str().unwrap()]);
    assert_eq!(v["ros_check"]["identical"], true, "{}", v["ros_check"]);
    let episodes = v["episodes"].as_array().unwrap();
    assert!(!episodes.is_empty());
    for e in episodes {
        let reason = e["abort_reason"].as_str().unwrap_or_default();
        assert!(["start_blocked", "goal_unreachable_for_costmap"].contains(&reason), "{e}");
        assert_eq!(e["aborted"], true, "{e}");
    }
}

#[test]
fn a_ros2_simulator_in_lockstep_without_its_agent_is_a_clear_error_not_a_hang() {
    let t0 = Instant::now();
    let mut cmd = xhab();
    cmd.args(["ros2", "sim", "procedural:5", "--lockstep", "--ros-timeout", "2", "--rate", "0"]);
    xhab_ros2_env(&mut cmd, &domain_id(44));
    let out = cmd.output().unwrap();
    assert!(!out.status.success());
    assert!(t0.elapsed() < Duration::from_secs(20), "{:?}", t0.elapsed());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("within 2 s (lock-step)"), "{err}");
}

#[test]
fn xhab_ros2_agent_beside_the_lockstep_simulator_reaches_rclpys_goal() {
    let name = "xhab_ros2_agent_beside_the_lockstep_simulator_reaches_rclpys_goal";
    let Some(py) = ros2_python(name) else { return };
    // The discrete simulator's start, from its own sampling (seed 0), and a goal in the open.
    let spec = SimSpec { lockstep: true, ..SimSpec::new("procedural:5") };
    let probe = StandaloneSim::build(&spec).expect("simulator builds");
    let goal = goal_in_the_open(&probe.grid, probe.options.start, 1.5).expect("an open direction from the start");
    let domain = domain_id(45);
    let mut sim = xhab();
    sim.args(["ros2", "sim", "procedural:5", "--lockstep", "--ros-timeout", "120", "--duration", "600"]).stdout(Stdio::null()).stderr(Stdio::inherit());
    xhab_ros2_env(&mut sim, &domain);
    let _sim = Killed(sim.spawn().unwrap());
    let mut agent = xhab();
    agent.args(["ros2", "agent", "procedural:5", "--ros-args", "-r", "__node:=oracle"]).stdout(Stdio::null()).stderr(Stdio::inherit());
    xhab_ros2_env(&mut agent, &domain);
    let _agent = Killed(agent.spawn().unwrap());
    let mut check = Command::new(&py);
    check.arg(repo_root().join("tests/e2e/ros2/goal.py")).args([goal.x, goal.y, 0.3].map(|v| v.to_string()));
    rclpy_env(&mut check, &domain);
    let out = check.output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && stdout.contains("PASS"), "xhab ros2 agent did not bring the lock-step simulator's robot to rclpy's goal_pose");
}

#[test]
fn a_study_with_ros2_true_runs_each_episode_as_bench_ros2_does() {
    let dir = tempdir("ros2_study");
    let study = dir.join("study.yaml");
    std::fs::write(
        &study,
        "name: over ROS 2\nscenes: [{scene: 'procedural:3', generate: {count: 2, seed: 1}}]\nagents: [{agent: oracle}]\nconfigurations: [{physics: false, ros2: true}]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let domain = domain_id(46);
    let mut cmd = xhab();
    cmd.args(["-q", "experiment"]).arg(&study).arg("--out").arg(&out);
    xhab_ros2_env(&mut cmd, &domain);
    assert!(cmd.status().unwrap().success(), "xhab experiment over ROS 2 failed");
    let results: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let run = &results["runs"][0];
    assert_eq!(run["id"], "procedural_3.oracle.nophysics_ros2.s0");
    assert_eq!(run["configuration"], "-physics +ROS 2");
    assert_eq!((run["ros"].as_bool(), run["ros2"].as_bool()), (Some(false), Some(true)));
    let bench: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("runs").join(run["id"].as_str().unwrap()).join("bench.json")).unwrap()).unwrap();
    assert_eq!(bench["ros"], true, "the study's run went over ROS 2");
    // The same episodes through `xhab bench --ros2` give the same steps and metrics.
    let alone = dir.join("alone.json");
    let mut cmd = xhab();
    cmd.args(["-q", "bench", "--scene", "procedural:3", "--ros2", "--episodes"]).arg(out.join("episodes/procedural_3.json.gz")).arg("--out").arg(&alone);
    xhab_ros2_env(&mut cmd, &domain);
    assert!(cmd.status().unwrap().success(), "xhab bench --ros2 failed");
    let alone: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&alone).unwrap()).unwrap();
    let key = |v: &serde_json::Value| -> Vec<(String, u64, String)> {
        v["episodes"].as_array().unwrap().iter().map(|e| (e["episode_id"].to_string(), e["steps"].as_u64().unwrap(), format!("{:.6}", e["spl"].as_f64().unwrap()))).collect()
    };
    assert_eq!(key(&bench), key(&alone));
    assert_eq!(key(&bench).len(), 2);
    std::fs::remove_dir_all(&dir).ok();
}
