//! External ROS stacks against real ROS 1 (Debian's rosmaster, rospy, actionlib, tf2_ros,
//! rosbag): `xhab ros nav` and a plain-rospy move_base server benchmarked with
//! `xhab bench --agent ros`, actionlib and move_base_simple clients of `xhab ros nav`, and the
//! standard topics of a lock-step run recorded and checked, with other publishers on them.
//!
//! Every test starts its own rosmaster on a free port and stops what it started.

use crate::common::{data_dir, xhab};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};
use xhab_bridge::ros::master::Master;
use xhab_sim::episode::{read_dataset, write_dataset, Dataset};

const PY: &str = "/usr/bin/python3";

/// Whether rosmaster and the Python modules `modules` are here; panics when
/// `XHAB_REQUIRE_ROS=1` demands them.
fn ros_with(test: &str, modules: &[&str], tools: &[&str]) -> bool {
    let missing: Vec<String> = ["rosmaster"]
        .iter()
        .chain(tools)
        .filter(|t| !Command::new("which").arg(t).stdout(Stdio::null()).status().is_ok_and(|s| s.success()))
        .map(|t| t.to_string())
        .chain(modules.iter().filter(|m| !Command::new(PY).args(["-c", &format!("import {m}")]).env("PYTHONPATH", "").stderr(Stdio::null()).status().is_ok_and(|s| s.success())).map(|m| format!("python {m}")))
        .collect();
    if missing.is_empty() {
        return true;
    }
    if std::env::var("XHAB_REQUIRE_ROS").as_deref() == Ok("1") {
        panic!("{test}: XHAB_REQUIRE_ROS=1 but ROS is incomplete: missing {missing:?} (Debian: python3-rosmaster python3-rospy python3-rosbag rosbag python3-actionlib python3-tf2-ros python3-move-base-msgs)");
    }
    crate::common::skipped(test, &format!("missing {missing:?}"));
    false
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("xhab_test_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Sets the environment a ROS process of the test needs.
fn ros_env<'a>(c: &'a mut Command, master: &Master) -> &'a mut Command {
    c.env("ROS_MASTER_URI", &master.uri)
        .env("ROS_IP", "127.0.0.1")
        .env("ROS_LOG_DIR", std::env::temp_dir().join("xhab_ros_log"))
        .env("PYTHONPATH", "")
        .stdin(Stdio::null())
}

/// A process in its own process group: on drop the group gets SIGINT (rosbag closes its bag,
/// rospy shuts down), then SIGKILL after `grace`.
struct Group {
    child: Child,
    grace: Duration,
}

impl Group {
    fn spawn(c: &mut Command, log: &Path, grace: Duration) -> Group {
        let f = std::fs::File::create(log).unwrap();
        let child = c.stdout(f.try_clone().unwrap()).stderr(f).process_group(0).spawn().unwrap_or_else(|e| panic!("spawning {c:?}: {e}"));
        Group { child, grace }
    }

    fn signal(&self, sig: &str) {
        // `--`: procps kill reads `-INT -1234` as process group -1, every process.
        let _ = Command::new("kill").args(["-s", sig, "--", &format!("-{}", self.child.id())]).stderr(Stdio::null()).status();
    }

    /// Whether the process it started is still running.
    fn running(&mut self) -> bool {
        matches!(self.child.try_wait(), Ok(None))
    }

    /// Whether any process of the group is alive (not a zombie): `rosbag record` leaves its
    /// recorder writing the bag after the wrapper exits.
    fn group_alive(&mut self) -> bool {
        let _ = self.child.try_wait();
        let pgid = self.child.id().to_string();
        std::fs::read_dir("/proc").into_iter().flatten().flatten().any(|d| {
            let stat = std::fs::read_to_string(d.path().join("stat")).unwrap_or_default();
            // pid (comm) state ppid pgrp ...
            let f: Vec<&str> = stat.rsplit(')').next().unwrap_or("").split_whitespace().collect();
            f.len() > 2 && f[2] == pgid && f[0] != "Z" && f[0] != "X"
        })
    }

    /// Stops the group (SIGINT, then SIGKILL after the grace); returns whether it ended on SIGINT.
    fn stop(&mut self) -> bool {
        if !self.group_alive() {
            return true;
        }
        self.signal("INT");
        let t = Instant::now();
        while t.elapsed() < self.grace {
            if !self.group_alive() {
                return true;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        self.signal("KILL");
        let _ = self.child.wait();
        false
    }
}

impl Drop for Group {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Runs `c` (in its own process group, output to `log`) for at most `limit`; on overrun kills
/// the group and panics with the end of the log.
fn run_limited(c: &mut Command, log: &Path, limit: Duration) -> (ExitStatus, String) {
    let mut g = Group::spawn(c, log, Duration::from_secs(5));
    let t0 = Instant::now();
    let status = loop {
        if let Ok(Some(s)) = g.child.try_wait() {
            break s;
        }
        if t0.elapsed() > limit {
            g.signal("KILL");
            let _ = g.child.wait();
            panic!("{c:?} ran past {} s:\n{}", limit.as_secs(), tail(log, 3000));
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    eprintln!("  {:.1} s: {}", t0.elapsed().as_secs_f64(), c.get_args().map(|a| a.to_string_lossy()).collect::<Vec<_>>().join(" "));
    (status, std::fs::read_to_string(log).unwrap_or_default())
}

fn tail(p: &Path, n: usize) -> String {
    let s = std::fs::read_to_string(p).unwrap_or_default();
    s[s.len().saturating_sub(n)..].to_string()
}

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))).unwrap()
}

/// The episodes of `from` whose index `pick` accepts, written to `to`.
fn subset(from: &Path, to: &Path, pick: impl Fn(usize) -> bool) -> Dataset {
    let ds = read_dataset(from).unwrap();
    let ds = Dataset { episodes: ds.episodes.into_iter().enumerate().filter(|(i, _)| pick(*i)).map(|(_, e)| e).collect() };
    write_dataset(&ds, to).unwrap();
    ds
}

const TERMINAL: [&str; 3] = ["SUCCEEDED", "ABORTED", "PREEMPTED"];

/// `xhab ros nav` as a separate process on turtlebot3_house, benchmarked with `--agent ros`,
/// equals the native stack run in-process (same map, same habitat robot, AMCL): success and
/// SPL agree; every episode ends in a terminal action state. Then a second run against the same
/// node (the clock starts over) with `--goal-interface simple`: the stack names the goals on
/// move_base/status and they succeed.
#[test]
fn xhab_ros_nav_benchmarked_as_an_external_stack_matches_the_in_process_nav() {
    let test = "xhab_ros_nav_benchmarked_as_an_external_stack_matches_the_in_process_nav";
    let Some(data) = data_dir(test) else { return };
    if !ros_with(test, &["rospy"], &[]) {
        return;
    }
    let t_test = Instant::now();
    let dir = temp_dir("ros_external_nav");
    let scene = data.join("scenes/turtlebot3_house.glb");
    let scene = scene.to_str().unwrap();
    let (st, out) = run_limited(xhab().arg("map").arg(scene).arg("--out").arg(dir.join("house")), &dir.join("map.log"), Duration::from_secs(60));
    assert!(st.success(), "xhab map: {out}");
    let map = dir.join("house.yaml");
    let eps = dir.join("eps8.json.gz");
    let all = data.join("episodes/turtlebot3_house_pointnav.json.gz");
    let ds = subset(&all, &eps, |i| i < 8);
    assert_eq!(ds.episodes.len(), 8);

    let master = Master::start().expect("rosmaster starts");
    let nav_log = dir.join("nav.log");
    let mut nav = Group::spawn(ros_env(xhab().env("XHAB_LOG", "xhab_bridge=info").args(["ros", "nav", "--localization", "amcl", "--ros-master", &master.uri]).arg("--map").arg(&map), &master), &nav_log, Duration::from_secs(5));
    let ros_json = dir.join("ros.json");
    let (st, out) = run_limited(
        ros_env(xhab().args(["bench", "--scene", scene, "--agent", "ros", "--ros-master", &master.uri, "--ros-timeout", "60", "--quiet"]).arg("--episodes").arg(&eps).arg("--map").arg(&map).arg("--out").arg(&ros_json), &master),
        &dir.join("bench_ros.log"),
        Duration::from_secs(100),
    );
    assert!(nav.running(), "xhab ros nav died during the run:\n{}", tail(&nav_log, 2000));
    assert!(st.success(), "bench --agent ros failed:\n{out}\nros nav:\n{}", tail(&nav_log, 2000));

    let local_json = dir.join("local.json");
    let (st, out) = run_limited(
        xhab().args(["bench", "--scene", scene, "--agent", "nav", "--localization", "amcl", "--quiet"]).arg("--episodes").arg(&eps).arg("--map").arg(&map).arg("--out").arg(&local_json),
        &dir.join("bench_local.log"),
        Duration::from_secs(60),
    );
    assert!(st.success(), "bench --agent nav failed:\n{out}");

    let (ros, local) = (json(&ros_json), json(&local_json));
    let (r, l) = (&ros["aggregate"], &local["aggregate"]);
    eprintln!(
        "turtlebot3_house, 8 episodes: over ROS success {:.3} SPL {:.4}; in-process success {:.3} SPL {:.4}",
        r["success"].as_f64().unwrap(),
        r["spl"].as_f64().unwrap(),
        l["success"].as_f64().unwrap(),
        l["spl"].as_f64().unwrap()
    );
    for (a, b) in ros["episodes"].as_array().unwrap().iter().zip(local["episodes"].as_array().unwrap()) {
        eprintln!(
            "  episode {:>3}: ros {} {:<14} spl {:.3} path {:6.2} m | in-process spl {:.3} path {:6.2} m",
            a["episode_id"].as_str().unwrap(),
            a["ros_status"].as_str().unwrap_or("-"),
            a["ros_end"].as_str().unwrap_or("-"),
            a["spl"].as_f64().unwrap(),
            a["path_length"].as_f64().unwrap(),
            b["spl"].as_f64().unwrap(),
            b["path_length"].as_f64().unwrap()
        );
    }
    assert_eq!(ros["invalid"]["count"], 0, "{}", ros["invalid"]);
    assert_eq!(r["episodes"].as_u64(), Some(8));
    assert_eq!(l["episodes"].as_u64(), Some(8));
    let ids = |v: &serde_json::Value| v["episodes"].as_array().unwrap().iter().map(|e| e["episode_id"].as_str().unwrap().to_string()).collect::<Vec<_>>();
    assert_eq!(ids(&ros), ids(&local));
    for e in ros["episodes"].as_array().unwrap() {
        let s = e["ros_status"].as_str().unwrap_or_else(|| panic!("episode {} has no ros_status", e["episode_id"]));
        assert!(TERMINAL.contains(&s), "episode {}: ros_status {s}", e["episode_id"]);
    }
    assert!(r["success"].as_f64().unwrap() >= 0.95, "success over ROS {}", r["success"]);
    let d_spl = (r["spl"].as_f64().unwrap() - l["spl"].as_f64().unwrap()).abs();
    assert!(d_spl <= 0.05, "SPL over ROS {} vs in-process {}: differ by {d_spl:.3}", r["spl"], l["spl"]);

    // A second run against the same `xhab ros nav` (its clock starts over), with goals on
    // move_base_simple/goal: the stack names them on move_base/status, as move_base does.
    let short = dir.join("eps_short.json.gz");
    let ds = subset(&all, &short, |i| i == 19 || i == 20);
    assert_eq!(ds.episodes.len(), 2);
    let simple_json = dir.join("simple.json");
    let (st, out) = run_limited(
        ros_env(xhab().args(["bench", "--scene", scene, "--agent", "ros", "--goal-interface", "simple", "--ros-master", &master.uri, "--ros-timeout", "60", "--quiet"]).arg("--episodes").arg(&short).arg("--map").arg(&map).arg("--out").arg(&simple_json), &master),
        &dir.join("bench_simple.log"),
        Duration::from_secs(60),
    );
    assert!(st.success(), "bench --goal-interface simple failed:\n{out}\nros nav:\n{}", tail(&nav_log, 2000));
    nav.stop();
    for e in json(&simple_json)["episodes"].as_array().unwrap() {
        assert_eq!(e["ros_status"], "SUCCEEDED", "move_base_simple/goal, episode {}: {e}", e["episode_id"]);
        assert_eq!(e["success"], 1.0, "move_base_simple/goal, episode {}: {e}", e["episode_id"]);
    }
    eprintln!("{test}: {:.0} s", t_test.elapsed().as_secs_f64());
}

/// A move_base server in plain rospy (actionlib, tf2_ros, a sim-time rospy.Rate), started by
/// `bench --launch`, driven through 4 turtlebot3_world episodes with map -> odom from ground
/// truth: every episode ends in the terminal state the node reports (a stalled goal is
/// cancelled at the timeout and ends PREEMPTED, a goal given up on ABORTED), and each
/// episode's path_length is the path the node saw: to 1 mm by ground_truth/pose (the same
/// poses, one per tick), and within the odometry's noise by /odom.
#[test]
fn a_rospy_move_base_server_is_benchmarked_and_its_path_matches_its_odometry() {
    let test = "a_rospy_move_base_server_is_benchmarked_and_its_path_matches_its_odometry";
    let Some(data) = data_dir(test) else { return };
    if !ros_with(test, &["rospy", "actionlib", "tf2_ros", "move_base_msgs.msg"], &[]) {
        return;
    }
    let t_test = Instant::now();
    let dir = temp_dir("ros_external_rospy");
    let scene = data.join("scenes/turtlebot3_world.glb");
    let eps = dir.join("eps.json.gz");
    subset(&data.join("episodes/turtlebot3_world_pointnav.json.gz"), &eps, |i| i < 4);
    let master = Master::start().expect("rosmaster starts");
    let node_json = dir.join("rospy_nav.json");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/e2e/ros/rospy_nav.py");
    // Goal 3 is never driven to (cancelled at the timeout), goal 4 is given up after 2 s.
    let launch = format!("exec {PY} {script} {} --stall 3 --abort 4", node_json.display());
    let out_json = dir.join("ros.json");
    let (st, out) = run_limited(
        ros_env(xhab().args(["bench", "--agent", "ros", "--map-odom", "ground-truth", "--episode-timeout", "30", "--ros-master", &master.uri, "--ros-timeout", "60", "--quiet", "--launch", &launch]).arg("--scene").arg(&scene).arg("--episodes").arg(&eps).arg("--out").arg(&out_json), &master),
        &dir.join("bench.log"),
        Duration::from_secs(120),
    );
    assert!(st.success(), "bench --agent ros with the rospy node failed:\n{out}");
    let report = json(&out_json);
    let node = json(&node_json);
    // bench stopped the node it launched (and nothing else).
    let pid = node["pid"].as_u64().expect("the node's pid");
    let t = Instant::now();
    let alive = |p: u64| std::fs::read_to_string(format!("/proc/{p}/stat")).is_ok_and(|s| !s.rsplit(')').next().unwrap_or("").trim_start().starts_with('Z'));
    while alive(pid) && t.elapsed() < Duration::from_secs(5) {
        std::thread::sleep(Duration::from_millis(50));
    }
    assert!(!alive(pid), "the launched rospy node (pid {pid}) outlived the bench");
    assert_eq!(node["use_sim_time"], true);

    let eps = report["episodes"].as_array().unwrap();
    let goals = node["goals"].as_array().unwrap();
    assert_eq!(eps.len(), 4, "{report}");
    assert_eq!(goals.len(), 4, "the node took {} goals: {node}", goals.len());
    let tick = 1.0 / 20.0; // --controller-frequency 20
    for (k, (e, g)) in eps.iter().zip(goals).enumerate() {
        let id = e["episode_id"].as_str().unwrap();
        let status = e["ros_status"].as_str().expect("ros_status");
        let path = e["path_length"].as_f64().unwrap();
        let sim_s = e["sim_s"].as_f64().unwrap();
        let (odom, turn, truth) = (g["odom_path_length"].as_f64().unwrap(), g["odom_turn"].as_f64().unwrap(), g["truth_path_length"].as_f64().unwrap());
        eprintln!(
            "  episode {id}: {status} ({}), sim {sim_s:.2} s, path_length {path:.4} m; the node saw {:.4} m by ground truth, {odom:.4} m by odometry (turning {turn:.2} rad), {} odometry messages",
            e["ros_end"], truth, g["odom_messages"]
        );
        assert!(TERMINAL.contains(&status), "episode {id}: ros_status {status}");
        assert_eq!(g["result"].as_str(), Some(status), "episode {id}: bench says {status}, the node ended it {}", g["result"]);
        assert_eq!(g["frame_id"], "map");
        match k {
            2 => {
                assert_eq!((status, e["ros_end"].as_str()), ("PREEMPTED", Some("timeout")), "the stalled goal: {e}");
                assert!((sim_s - 30.0).abs() < 0.5 * tick, "cancelled at the 30 s timeout, not {sim_s}");
            }
            3 => assert_eq!((status, e["ros_end"].as_str()), ("ABORTED", Some("terminal_state")), "the goal given up: {e}"),
            _ => assert_eq!(e["ros_end"], "terminal_state", "{e}"),
        }
        assert_eq!(e["called_stop"], status == "SUCCEEDED", "{e}");
        if status == "SUCCEEDED" {
            assert_eq!(e["success"], 1.0, "the node stops within 0.15 m of the goal (success radius 0.2 m): {e}");
        }
        // One message per tick, from the start pose to the last: the node missed none.
        let ticks = (sim_s / tick).round() as u64 + 1;
        assert_eq!(g["odom_messages"].as_u64(), Some(ticks), "episode {id}");
        assert_eq!(g["truth_messages"].as_u64(), Some(ticks), "episode {id}");
        // Ground truth: path_length sums the same per-tick displacements.
        assert!((truth - path).abs() <= 1e-3, "episode {id}: path_length {path} vs {truth} by ground_truth/pose");
        // Odometry (crates/sim/src/robot/odometry.rs, default alpha1..4 = 0.005, 0.005, 0.01,
        // 0.005, per 60 Hz physics step) is noisy: translation error sigma = 0.1 * step (a random
        // walk of about 0.1 L / sqrt(N), under 1 cm here: 3 % of L is ample), and while turning
        // sigma = sqrt(0.005) * dtheta, whose magnitude adds about 0.056 m per rad per physics
        // step, or 0.033 m/rad at the node's 20 Hz (sqrt(3) fewer): allow 0.06 m per rad turned.
        let (lo, hi) = (path - 0.02 - 0.03 * path, path + 0.02 + 0.03 * path + 0.06 * turn);
        assert!(odom >= lo && odom <= hi, "episode {id}: path_length {path:.4} m, by odometry {odom:.4} m (turned {turn:.2} rad): outside [{lo:.4}, {hi:.4}]");
    }
    assert!(eps.iter().any(|e| e["ros_status"] == "SUCCEEDED"), "the rospy node reached none of the short goals: {report}");
    eprintln!("{test}: {:.0} s", t_test.elapsed().as_secs_f64());
}

/// `xhab ros sim` (TurtleBot3 Burger, physics, 5x real time) and `xhab ros nav` (AMCL) with
/// move_base's clients in rospy: an actionlib SimpleActionClient goal SUCCEEDS, a goal on
/// move_base_simple/goal ends SUCCEEDED on move_base/status under a new id,
/// move_base/clear_costmaps answers, and tf2 resolves map -> odom -> base_link -> base_scan
/// with base_scan 32 mm behind the base.
#[test]
fn ros_nav_serves_actionlib_move_base_simple_clear_costmaps_and_tf2() {
    let test = "ros_nav_serves_actionlib_move_base_simple_clear_costmaps_and_tf2";
    let Some(data) = data_dir(test) else { return };
    if !ros_with(test, &["rospy", "actionlib", "tf2_ros", "move_base_msgs.msg", "std_srvs.srv"], &[]) {
        return;
    }
    let t_test = Instant::now();
    let dir = temp_dir("ros_external_clients");
    // Episode 20 of turtlebot3_house: 2.5 m in a straight line; then back to its start.
    let ds = read_dataset(&data.join("episodes/turtlebot3_house_pointnav.json.gz")).unwrap();
    let ep = ds.episodes.iter().find(|e| e.episode_id == "20").expect("episode 20");
    let (s, g) = (ep.start_position, ep.goals[0].position);
    let master = Master::start().expect("rosmaster starts");
    let sim_log = dir.join("sim.log");
    let start = format!("{},{},{}", s.x, s.y, ep.start_yaw);
    let mut sim = Group::spawn(
        ros_env(xhab().args(["ros", "sim"]).arg(data.join("scenes/turtlebot3_house.glb")).args(["--physics", "--robot", "turtlebot3_burger", "--rate", "5", "--start", &start, "--ros-master", &master.uri]), &master),
        &sim_log,
        Duration::from_secs(5),
    );
    let nav_log = dir.join("nav.log");
    let mut nav = Group::spawn(ros_env(xhab().env("XHAB_LOG", "xhab_bridge=info").args(["ros", "nav", "--localization", "amcl", "--ros-master", &master.uri]), &master), &nav_log, Duration::from_secs(5));
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/e2e/ros/move_base_clients.py");
    let (st, out) = run_limited(
        ros_env(Command::new(PY).arg(script).args([g.x, g.y, s.x, s.y].map(|v| v.to_string())).args(["base_scan", "-0.032"]), &master),
        &dir.join("clients.log"),
        Duration::from_secs(150),
    );
    eprintln!("{out}");
    assert!(sim.running(), "xhab ros sim died:\n{}", tail(&sim_log, 2000));
    assert!(nav.running(), "xhab ros nav died:\n{}", tail(&nav_log, 2000));
    assert!(st.success() && out.contains("PASS"), "move_base clients failed\nros nav:\n{}\nros sim:\n{}", tail(&nav_log, 2000), tail(&sim_log, 2000));
    sim.stop();
    nav.stop();
    eprintln!("{test}: {:.0} s", t_test.elapsed().as_secs_f64());
}

/// During a lock-step `bench --ros` (nav agent, AMCL) `rosbag record -a` sees only standard
/// messages on standard topics (check_bag.py: stamps never go back, no `probe` frames, nothing
/// on initialpose or move_base_simple/goal, scans sized and in range, xhab_msgs on /xhab/*
/// only). Then a `--compare-ros` run of the same episodes, while a rospy node spams /odom and
/// /scan with other stamps and `rosbag play` replays the recording, is still identical to
/// the in-process run.
#[test]
fn lockstep_keeps_standard_topics_clean_and_ignores_other_publishers() {
    let test = "lockstep_keeps_standard_topics_clean_and_ignores_other_publishers";
    if !ros_with(test, &["rospy", "rosbag"], &["rosbag"]) {
        return;
    }
    let t_test = Instant::now();
    let dir = temp_dir("ros_external_topics");
    let eps = dir.join("eps.json.gz");
    assert!(xhab().args(["episodes", "procedural:5", "--count", "3", "--seed", "2", "--out"]).arg(&eps).status().unwrap().success());
    let master = Master::start().expect("rosmaster starts");
    let bag = dir.join("rec.bag");
    let mut rec = Group::spawn(ros_env(Command::new("rosbag").args(["record", "-a", "-O"]).arg(&bag), &master), &dir.join("record.log"), Duration::from_secs(10));
    std::thread::sleep(Duration::from_secs(2)); // the recorder registers and polls the master
    let bench = |out: &Path, extra: &[&str], log: &str| {
        run_limited(
            ros_env(xhab().args(["bench", "--scene", "procedural:5", "--agent", "nav", "--localization", "amcl", "--ros-master", &master.uri, "--ros-timeout", "30", "--quiet"]).args(extra).arg("--episodes").arg(&eps).arg("--out").arg(out), &master),
            &dir.join(log),
            Duration::from_secs(90),
        )
    };
    let (st, out) = bench(&dir.join("ros.json"), &["--ros"], "bench_ros.log");
    assert!(st.success(), "bench --ros failed:\n{out}");
    std::thread::sleep(Duration::from_millis(500));
    assert!(rec.stop(), "rosbag record did not stop on SIGINT:\n{}", tail(&dir.join("record.log"), 2000));
    assert!(bag.is_file(), "no bag at {}:\n{}", bag.display(), tail(&dir.join("record.log"), 2000));
    let (st, out) = run_limited(ros_env(Command::new(PY).arg(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/e2e/ros/check_bag.py")).arg(&bag), &master), &dir.join("check.log"), Duration::from_secs(60));
    eprintln!("{out}");
    assert!(st.success() && out.contains("PASS"), "the recorded topics break the rules above");

    // Other publishers on the standard topics while the run pairs messages by stamp.
    let spam_log = dir.join("spam.log");
    let mut spam = Group::spawn(ros_env(Command::new(PY).arg(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/e2e/ros/spam.py")), &master), &spam_log, Duration::from_secs(5));
    let play_log = dir.join("play.log");
    let topics = ["/odom", "/scan", "/tf", "/tf_static", "/clock", "/map", "/amcl/map", "/ground_truth/pose"];
    let mut play = Group::spawn(ros_env(Command::new("rosbag").args(["play", "--loop", "-q"]).arg(&bag).arg("--topics").args(topics), &master), &play_log, Duration::from_secs(5));
    std::thread::sleep(Duration::from_secs(2));
    let cmp = dir.join("compare.json");
    let (st, out) = bench(&cmp, &["--compare-ros"], "bench_compare.log");
    assert!(spam.running(), "the spammer died:\n{}", tail(&spam_log, 2000));
    assert!(play.running(), "rosbag play died:\n{}", tail(&play_log, 2000));
    spam.stop();
    play.stop();
    assert!(tail(&spam_log, 2000).contains("pairs"), "the spammer published nothing:\n{}", tail(&spam_log, 2000));
    assert!(st.success(), "bench --compare-ros with other publishers on /odom and /scan failed:\n{out}");
    let v = json(&cmp);
    assert_eq!(v["ros_check"]["identical"], true, "{}", v["ros_check"]);
    assert_eq!(v["aggregate"]["episodes"], 3);
    eprintln!("{test}: {:.0} s", t_test.elapsed().as_secs_f64());
}
