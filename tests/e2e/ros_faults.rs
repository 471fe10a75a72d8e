//! ROS 1 faults against real ROS (Debian's rosmaster and rospy): peers with a wrong md5sum
//! (as publisher and as subscriber), malformed TCPROS frames, a publisher that disconnects in
//! the middle of a message, and the master dying in the middle of a run. Each must end in a
//! clear error or a recovery: never a panic, a hang or a wrong result.

use crate::common::xhab;
use crate::ros_interop::{ros_available, rospy_script, Killed};
use std::process::Stdio;
use std::time::{Duration, Instant};
use xhab_bridge::ros::master::Master;

#[test]
fn faulty_peers_neither_crash_nor_stall_the_simulator() {
    if !ros_available("faulty_peers_neither_crash_nor_stall_the_simulator") {
        return;
    }
    let master = Master::start().expect("rosmaster starts");
    let log = std::env::temp_dir().join(format!("xhab_ros_faults_{}.log", std::process::id()));
    let sim = xhab()
        .args(["ros", "sim", "procedural:3", "--physics", "--rate", "1", "--duration", "120", "--ros-master", &master.uri])
        .env("ROS_IP", "127.0.0.1")
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let mut sim = Killed(sim);
    let (ok, stdout) = rospy_script("faulty_peers.py", &master.uri);
    let alive = sim.0.try_wait().unwrap().is_none();
    drop(sim);
    let err = std::fs::read_to_string(&log).unwrap();
    eprintln!("{err}");
    assert!(ok && stdout.contains("PASS"), "the faulty peers' script failed");
    assert!(alive, "the simulator died under the faults");
    assert!(!err.contains("panicked"), "a panic under the faults");
    // Each fault is named: the md5sum mismatch both ways, and the frames that do not decode.
    assert!(err.contains("/cmd_vel, but md5sums do not match"), "no error for the wrong md5sum of a cmd_vel publisher");
    assert!(err.contains("/odom, but md5sums do not match"), "no warning for the wrong md5sum of an odom subscriber");
    assert!(err.contains("/cmd_vel: dropped a message"), "no warning for the malformed cmd_vel frames");
}

#[test]
fn the_master_dying_mid_run_leaves_the_run_and_its_results_intact() {
    if !ros_available("the_master_dying_mid_run_leaves_the_run_and_its_results_intact") {
        return;
    }
    let dir = std::env::temp_dir().join(format!("xhab_test_master_dies_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let eps = dir.join("eps.json.gz");
    assert!(xhab().args(["episodes", "procedural:5", "--count", "16", "--seed", "4", "--out"]).arg(&eps).status().unwrap().success());
    let in_process = dir.join("in_process.json");
    assert!(xhab().args(["bench", "--scene", "procedural:5", "--agent", "nav", "--quiet", "--episodes"]).arg(&eps).arg("--out").arg(&in_process).status().unwrap().success());

    let master = Master::start().expect("rosmaster starts");
    let over_ros = dir.join("over_ros.json");
    let log = dir.join("bench.log");
    let bench = xhab()
        .args(["bench", "--scene", "procedural:5", "--agent", "nav", "--quiet", "--ros", "--ros-master", &master.uri, "--episodes"])
        .arg(&eps)
        .arg("--out")
        .arg(&over_ros)
        .env("ROS_IP", "127.0.0.1")
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let mut bench = Killed(bench);
    // Let the nodes connect and a few episodes run, then the master goes (SIGKILL).
    std::thread::sleep(Duration::from_secs(3));
    assert!(bench.0.try_wait().unwrap().is_none(), "the run ended before the master died: nothing was tested");
    drop(master);
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = bench.0.try_wait().unwrap() {
            break s;
        }
        assert!(t0.elapsed() < Duration::from_secs(180), "the run hangs after the master died");
        std::thread::sleep(Duration::from_millis(100));
    };
    let err = std::fs::read_to_string(&log).unwrap();
    assert!(!err.contains("panicked"), "{err}");
    // ROS 1 nodes keep their peer connections when the master goes: the lock-step run finishes,
    // and its episodes are the in-process run's.
    assert!(status.success(), "the run failed after the master died: {err}");
    let read = |p: &std::path::Path| -> serde_json::Value { serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap() };
    let (a, b) = (read(&in_process), read(&over_ros));
    let episodes = |v: &serde_json::Value| -> Vec<(String, String, String)> {
        v["episodes"].as_array().unwrap().iter().map(|e| (e["success"].to_string(), e["spl"].to_string(), e["steps"].to_string())).collect()
    };
    assert_eq!(episodes(&a), episodes(&b), "over ROS with the master gone, the episodes differ from the in-process run");
    assert_eq!(episodes(&a).len(), 16);
    assert!(a["episodes"].as_array().unwrap().iter().all(|e| e["spl"].is_f64() && e["steps"].is_u64()), "the report lacks per-episode spl or steps");
}
