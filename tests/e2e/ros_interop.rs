//! ROS 1 interop against real ROS from Debian's packages: a rospy node reads our topics and
//! drives our robot, rosbag records them, and `bench --ros` equals the in-process run.

use crate::common::xhab;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use xhab_bridge::ros::master::Master;

/// Whether real ROS is here; panics when `XHAB_REQUIRE_ROS=1` demands it.
pub fn ros_available(test: &str) -> bool {
    let ok = Command::new("which").arg("rosmaster").stdout(Stdio::null()).status().is_ok_and(|s| s.success())
        && Command::new("/usr/bin/python3").args(["-c", "import rospy, rosbag"]).stderr(Stdio::null()).status().is_ok_and(|s| s.success());
    if !ok {
        if std::env::var("XHAB_REQUIRE_ROS").as_deref() == Ok("1") {
            panic!("{test}: XHAB_REQUIRE_ROS=1 but rosmaster/rospy are missing (install python3-rosmaster python3-rospy python3-rosbag)");
        }
        crate::common::skipped(test, "rosmaster or rospy not installed");
    }
    ok
}

pub struct Killed(pub Child);
impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn rospy_reads_our_topics_records_them_and_drives_the_robot() {
    if !ros_available("rospy_reads_our_topics_records_them_and_drives_the_robot") {
        return;
    }
    let master = Master::start().expect("rosmaster starts");
    let sim = xhab()
        .args(["ros", "sim", "procedural:3", "--physics", "--camera", "--rate", "1", "--duration", "120", "--ros-master", &master.uri])
        .env("ROS_IP", "127.0.0.1")
        .stdout(Stdio::null())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    let _sim = Killed(sim);
    let t0 = Instant::now();
    let (ok, stdout) = rospy_script("interop.py", &master.uri);
    assert!(ok && stdout.contains("PASS"), "interop script failed after {:.0} s", t0.elapsed().as_secs_f64());
}

/// Runs `tests/ros/SCRIPT` with Debian's rospy against the master at `uri`; echoes its output
/// and returns whether it exited 0, and its stdout.
pub fn rospy_script(script: &str, uri: &str) -> (bool, String) {
    let out = Command::new("/usr/bin/python3")
        .arg(format!("{}/../../tests/e2e/ros/{script}", env!("CARGO_MANIFEST_DIR")))
        .env("ROS_MASTER_URI", uri)
        .env("ROS_IP", "127.0.0.1")
        .env("ROS_LOG_DIR", std::env::temp_dir().join("xhab_ros_log"))
        .env("PYTHONPATH", "")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    (out.status.success(), stdout)
}

#[test]
fn bench_over_ros_equals_the_in_process_run() {
    if !ros_available("bench_over_ros_equals_the_in_process_run") {
        return;
    }
    let dir = tempfile_dir("ros_bench");
    let eps = dir.join("eps.json.gz");
    let st = xhab().args(["episodes", "procedural:5", "--count", "6", "--seed", "2", "--out"]).arg(&eps).status().unwrap();
    assert!(st.success());
    // Scans flattened from the observed (noisy) depth frames, in-process and over ROS alike.
    let depth = ["--agent", "nav", "--localization", "amcl", "--scan-source", "depth", "--sensors", "depth", "--resolution", "96", "--renderer", "raster", "--depth-noise", "0.005"];
    for extra in [&[][..], &["--physics"][..], &["--agent", "nav", "--localization", "amcl"][..], &depth[..]] {
        let out = dir.join("r.json");
        let st = xhab()
            .args(["bench", "--scene", "procedural:5", "--episodes"])
            .arg(&eps)
            .args(["--compare-ros", "--ros-timeout", "20", "--quiet", "--out"])
            .arg(&out)
            .args(extra)
            .env("ROS_IP", "127.0.0.1")
            .status()
            .unwrap();
        assert!(st.success(), "bench --compare-ros {extra:?} failed");
        let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        assert_eq!(v["ros"], true);
        assert_eq!(v["ros_check"]["identical"], true, "{extra:?}: {}", v["ros_check"]);
        assert!(v["aggregate"]["ros_overhead"].as_f64().unwrap() > 0.0);
        assert!(v["aggregate"]["episodes"].as_u64().unwrap() >= 1);
    }
}

#[test]
fn a_nav_abort_over_ros_carries_the_navigators_reason() {
    if !ros_available("a_nav_abort_over_ros_carries_the_navigators_reason") {
        return;
    }
    let dir = tempfile_dir("ros_abort");
    let eps = dir.join("eps.json.gz");
    assert!(xhab().args(["episodes", "procedural:5", "--count", "2", "--seed", "3", "--out"]).arg(&eps).status().unwrap().success());
    // A 1.6 m square footprint: the house has no room for it, so the navigator gives up
    // (start_blocked or goal_unreachable_for_costmap), for the same reason in-process and over
    // ROS (ros_check compares the reasons); before, every abort over ROS was `unknown`.
    let params = dir.join("huge.yaml");
    let square = "[[-0.8, -0.8], [-0.8, 0.8], [0.8, 0.8], [0.8, -0.8]]";
    std::fs::write(&params, format!("global_costmap:\n  footprint: {square}\nlocal_costmap:\n  footprint: {square}\n")).unwrap();
    let out = dir.join("r.json");
    let st = xhab()
        .args(["bench", "--scene", "procedural:5", "--episodes"])
        .arg(&eps)
        .args(["--agent", "nav", "--compare-ros", "--ros-timeout", "20", "--quiet", "--nav-params"])
        .arg(&params)
        .arg("--out")
        .arg(&out)
        .env("ROS_IP", "127.0.0.1")
        .status()
        .unwrap();
    assert!(st.success(), "bench --compare-ros with a huge footprint failed");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
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
fn a_missing_master_is_a_clear_error_not_a_hang() {
    let dir = tempfile_dir("ros_nomaster");
    let eps = dir.join("eps.json.gz");
    assert!(xhab().args(["episodes", "procedural:5", "--count", "2", "--out"]).arg(&eps).status().unwrap().success());
    let t0 = Instant::now();
    let out = xhab().args(["bench", "--scene", "procedural:5", "--episodes"]).arg(&eps).args(["--ros", "--ros-master", "http://127.0.0.1:9"]).output().unwrap();
    assert!(!out.status.success());
    assert!(t0.elapsed() < Duration::from_secs(20));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("ROS master at http://127.0.0.1:9"), "{err}");
}

fn tempfile_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("xhab_test_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}
