//! ROS 2 interop against real rclpy from PyPI (`ros-kilted-rclpy[fastrtps]` and the message
//! packages, installed into `.venv-ros2` by scripts/test.sh): an rclpy node on Fast DDS
//! receives what `xhab ros2 sim` publishes over RustDDS, and its `cmd_vel` moves the robot.
//! The values are checked against the simulator built in this process from the same options.

use crate::common::{repo_root, xhab};
use crate::ros_interop::Killed;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use xhab_bridge::ros::standalone_sim::{StandaloneSim, SimSpec};
use xhab_bridge::setup::{CameraOptions, PhysicsOptions};
use xhab_sim::sensors::{Lidar, RendererKind};
use xhab_types::Pose2;

/// The python of the ROS 2 virtual environment (`$XHAB_ROS2_PYTHON`, else
/// `.venv-ros2/bin/python`) when it imports rclpy and the message packages; `None` with a
/// loud message otherwise, a panic when `XHAB_REQUIRE_ROS2=1` demands it.
pub fn ros2_python(test: &str) -> Option<PathBuf> {
    let py = std::env::var_os("XHAB_ROS2_PYTHON").map(PathBuf::from).unwrap_or_else(|| repo_root().join(".venv-ros2/bin/python"));
    let ok = py.exists()
        && Command::new(&py)
            .args(["-c", "import rclpy, sensor_msgs.msg, nav_msgs.msg, geometry_msgs.msg, rosgraph_msgs.msg"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
    if ok {
        return Some(py);
    }
    if std::env::var("XHAB_REQUIRE_ROS2").as_deref() == Ok("1") {
        panic!("{test}: XHAB_REQUIRE_ROS2=1 but {} cannot import rclpy (run scripts/test.sh, which installs ros-kilted-rclpy[fastrtps] there)", py.display());
    }
    crate::common::skipped(test, &format!("no rclpy at {} (scripts/test.sh installs it; or set XHAB_ROS2_PYTHON)", py.display()));
    None
}

/// A DDS domain of its own for a test (`salt` tells a process's tests apart), so that
/// concurrent runs do not see each other: 1..=100.
pub fn domain_id(salt: u32) -> String {
    (1 + (std::process::id().wrapping_mul(7).wrapping_add(salt * 31)) % 100).to_string()
}

/// The environment of a test's xhab ROS 2 nodes: its domain, loopback only.
pub fn xhab_ros2_env(cmd: &mut Command, domain: &str) {
    cmd.env("ROS_DOMAIN_ID", domain).env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST").env_remove("ROS_LOCALHOST_ONLY");
}

/// The environment of a test's rclpy nodes: its domain, and Fast DDS on loopback alone with
/// socket buffers that hold a camera frame (tests/e2e/ros2/fastdds_loopback.xml says why
/// `ROS_AUTOMATIC_DISCOVERY_RANGE` stays unset).
pub fn rclpy_env(cmd: &mut Command, domain: &str) {
    cmd.env("ROS_DOMAIN_ID", domain)
        .env_remove("ROS_AUTOMATIC_DISCOVERY_RANGE")
        .env_remove("ROS_LOCALHOST_ONLY")
        .env_remove("ROS_STATIC_PEERS")
        .env("FASTDDS_DEFAULT_PROFILES_FILE", repo_root().join("tests/e2e/ros2/fastdds_loopback.xml"))
        .env("ROS_LOG_DIR", std::env::temp_dir().join("xhab_ros2_log"));
}

const START: Pose2 = Pose2 { x: 0.0, y: 0.0, yaw: 0.0 };

fn spec(start: Pose2) -> SimSpec {
    SimSpec {
        physics: Some(PhysicsOptions { robot: "turtlebot3_burger".into(), ..Default::default() }),
        start: Some(start),
        publish_camera: true,
        rgb: true,
        camera: CameraOptions { renderer: Some(RendererKind::Raster), ..Default::default() },
        ..SimSpec::new("procedural:3")
    }
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

fn pose(v: &serde_json::Value) -> Pose2 {
    Pose2::new(f(&v["x"]), f(&v["y"]), f(&v["yaw"]))
}

#[test]
fn rclpy_receives_our_topics_and_drives_the_robot_over_ros2() {
    let name = "rclpy_receives_our_topics_and_drives_the_robot_over_ros2";
    let Some(py) = ros2_python(name) else { return };
    // A start in the open, from the simulator's own sampling, passed on the command line.
    let probe = StandaloneSim::build(&SimSpec { start: None, ..spec(START) }).expect("simulator builds");
    let start = probe.options.start;
    let sim = StandaloneSim::build(&spec(start)).expect("simulator builds");
    let o = &sim.options;
    let domain = domain_id(1);
    let mut cmd = xhab();
    cmd.args(["ros2", "sim", "procedural:3", "--physics", "--robot", "turtlebot3_burger", "--camera", "--rgb", "--renderer", "raster", "--rate", "1", "--duration", "300"])
        .arg("--start")
        .arg(format!("{},{},{}", start.x, start.y, start.yaw))
        .stdout(Stdio::null())
        .stderr(Stdio::inherit());
    xhab_ros2_env(&mut cmd, &domain);
    let _sim = Killed(cmd.spawn().unwrap());
    let out_json = std::env::temp_dir().join(format!("xhab_ros2_interop_{}.json", std::process::id()));
    let mut check = Command::new(&py);
    check.arg(repo_root().join("tests/e2e/ros2/interop.py")).arg(&out_json);
    rclpy_env(&mut check, &domain);
    let out = check.output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && stdout.contains("PASS"), "the rclpy check failed");
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out_json).unwrap()).unwrap();
    let _ = std::fs::remove_file(&out_json);

    // Clock: advancing sim time.
    assert!(f(&v["clock"][1]) > f(&v["clock"][0]), "clock {}", v["clock"]);

    // Map: the scene's own map, cell for cell.
    let map = o.map.as_ref().unwrap();
    let m = &v["map"];
    assert_eq!(m["frame_id"], "map");
    assert_eq!((m["width"].as_u64().unwrap() as usize, m["height"].as_u64().unwrap() as usize), (map.width, map.height));
    assert!((f(&m["resolution"]) - map.resolution).abs() < 1e-6, "resolution {}", m["resolution"]);
    let origin = pose(&m["origin"]);
    assert!((origin.x - map.origin.x).abs() < 1e-9 && (origin.y - map.origin.y).abs() < 1e-9);
    let data: Vec<i8> = m["data"].as_array().unwrap().iter().map(|x| x.as_i64().unwrap() as i8).collect();
    assert!(data == map.data, "map data differs");

    // Scan: in the laser's frame, with the simulator's ranges from the pose it was taken at.
    let s = &v["scan"];
    let (rays, lidar) = o.lidar.as_ref().unwrap();
    assert_eq!(s["frame_id"], o.mounts.laser_frame.as_str());
    assert_eq!(o.mounts.laser_frame, "base_scan");
    let at = pose(&v["scan_truth"]);
    let want = Lidar::new(lidar.clone(), 0).scan(rays, at, sim.grid.floor_z);
    let got = s["ranges"].as_array().unwrap();
    assert_eq!(got.len(), want.ranges.len());
    assert!((f(&s["angle_min"]) - want.angle_min).abs() < 1e-6 && (f(&s["angle_increment"]) - want.angle_increment).abs() < 1e-6);
    let tol = 0.03 + 3.0 * lidar.noise_std;
    let (mut close, mut valid) = (0, 0);
    let mut bad = Vec::new();
    for (i, (g, w)) in got.iter().zip(&want.ranges).enumerate() {
        if bad.len() < 12 && !matches!((g.as_f64(), w.is_nan()), (None, true)) && !g.as_f64().is_some_and(|g| (g - *w as f64).abs() < tol) {
            bad.push(format!("{i}: got {g}, want {w}"));
        }
        match (g.as_f64(), w.is_nan()) {
            (None, true) => close += 1,
            (Some(g), false) => {
                valid += 1;
                if (g - *w as f64).abs() < tol {
                    close += 1;
                }
            }
            _ => {}
        }
    }
    assert!(valid > got.len() / 4, "too few valid ranges: {valid} of {}", got.len());
    assert!(close as f64 >= 0.95 * got.len() as f64, "scan: only {close} of {} ranges match the simulator's within {tol} m at {at:?}: {bad:?}", got.len());

    // Camera: encodings, frames, calibration, and depth equal to the simulator's render.
    let (renderer, cam, _) = o.camera.as_ref().unwrap();
    let k = cam.intrinsics();
    for (key, frame) in [("depth_info", "camera_depth_optical_frame"), ("rgb_info", "camera_rgb_optical_frame")] {
        let i = &v[key];
        assert_eq!(i["frame_id"], frame);
        assert_eq!((i["width"].as_u64(), i["height"].as_u64()), (Some(cam.width as u64), Some(cam.height as u64)));
        assert_eq!(i["distortion_model"], "plumb_bob");
        let kk: Vec<f64> = i["k"].as_array().unwrap().iter().map(f).collect();
        assert_eq!(kk, vec![k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0], "{key}");
        assert_eq!(i["p"].as_array().unwrap().len(), 12);
    }
    assert!((k.fx - 128.0).abs() < 1e-9 && (k.cx - 127.5).abs() < 1e-9, "hfov 90 at 256 px");
    let d = &v["depth"];
    assert_eq!((d["encoding"].as_str(), d["frame_id"].as_str(), d["is_bigendian"].as_u64()), (Some("32FC1"), Some("camera_depth_optical_frame"), Some(0)));
    let at = pose(&v["depth_truth"]);
    let want = renderer.depth(at, sim.grid.floor_z, cam).unwrap();
    let got = d["values"].as_array().unwrap();
    assert_eq!(got.len(), want.data.len());
    let close = got.iter().zip(&want.data).filter(|(g, w)| match g.as_f64() { None => **w <= 0.0, Some(g) => **w > 0.0 && (g - **w as f64).abs() < 0.03 }).count();
    assert!(close as f64 >= 0.95 * got.len() as f64, "depth: only {close} of {} pixels match the simulator's render", got.len());
    let r = &v["rgb"];
    assert_eq!((r["encoding"].as_str(), r["frame_id"].as_str()), (Some("rgb8"), Some("camera_rgb_optical_frame")));
    assert_eq!(r["bytes"].as_u64(), Some(3 * cam.width as u64 * cam.height as u64));
    assert!(r["distinct"].as_u64().unwrap() > 10, "rgb image looks blank");

    // Odometry and ground truth: frames, covariance, the start pose.
    assert_eq!((v["odom"]["frame_id"].as_str(), v["odom"]["child_frame_id"].as_str()), (Some("odom"), Some("base_link")));
    assert_eq!(f(&v["odom"]["covariance"][0]), 1e-3);
    assert_eq!(v["truth"]["frame_id"], "map");
    let t0 = pose(&v["truth"]["pose"]);
    assert!(t0.position().dist(start.position()) < 0.05, "ground truth {t0:?} is not near the start {start:?}");

    // cmd_vel: 0.2 m/s for 2.5 s moved the robot forward, as odom and ground truth show.
    let (o0, o1) = (pose(&v["odom"]["pose"]), pose(&v["odom_after"]));
    let moved = o0.position().dist(o1.position());
    assert!(moved > 0.25 && moved < 0.7, "odom moved {moved:.3} m under 0.2 m/s for 2.5 s");
    let t1 = pose(&v["truth_after"]);
    let along = (t1.x - t0.x) * t0.yaw.cos() + (t1.y - t0.y) * t0.yaw.sin();
    assert!(along > 0.25, "the robot moved {along:.3} m forward");
    eprintln!("ros2 interop: depth {}x{}, map {}x{}, cmd_vel moved the robot {moved:.3} m", cam.width, cam.height, map.width, map.height);
}

#[test]
fn ros2_names_remapping_and_qos_are_what_rclpy_sees() {
    let name = "ros2_names_remapping_and_qos_are_what_rclpy_sees";
    let Some(py) = ros2_python(name) else { return };
    let domain = domain_id(2);
    let mut cmd = xhab();
    cmd.args(["ros2", "sim", "procedural:3", "--camera", "--resolution", "32", "--renderer", "raster", "--rate", "1", "--duration", "300"])
        .args(["--ros-args", "-r", "__ns:=/robot1", "-r", "__node:=simx", "-r", "scan:=base_scan", "-p", "use_sim_time:=true"])
        .stdout(Stdio::null())
        .stderr(Stdio::inherit());
    xhab_ros2_env(&mut cmd, &domain);
    let _sim = Killed(cmd.spawn().unwrap());
    // rclpy joins a few seconds late: the map must still arrive (transient local).
    std::thread::sleep(std::time::Duration::from_secs(3));
    let mut check = Command::new(&py);
    check.arg(repo_root().join("tests/e2e/ros2/graph.py"));
    rclpy_env(&mut check, &domain);
    let out = check.output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && stdout.contains("PASS"), "the rclpy graph check failed");
}

/// A goal about `dist` m from `start` in the open: the first of 16 headings whose straight
/// segment, and a margin past its end, stays on navigable cells.
pub fn goal_in_the_open(grid: &xhab_sim::navgrid::NavGrid, start: Pose2, dist: f64) -> Option<xhab_types::Point2> {
    (0..16).find_map(|k| {
        let a = start.yaw + k as f64 * std::f64::consts::TAU / 16.0;
        let clear = (0..=((dist + 0.3) / 0.05) as usize).all(|i| {
            let r = i as f64 * 0.05;
            grid.is_navigable(xhab_types::Point2::new(start.x + r * a.cos(), start.y + r * a.sin()))
        });
        clear.then(|| xhab_types::Point2::new(start.x + dist * a.cos(), start.y + dist * a.sin()))
    })
}

#[test]
fn rclpy_goal_pose_sends_xhab_ros2_nav_to_a_goal_it_reaches() {
    let name = "rclpy_goal_pose_sends_xhab_ros2_nav_to_a_goal_it_reaches";
    let Some(py) = ros2_python(name) else { return };
    let probe = StandaloneSim::build(&SimSpec { start: None, publish_camera: false, rgb: false, ..spec(START) }).expect("simulator builds");
    let start = probe.options.start;
    let goal = goal_in_the_open(&probe.grid, start, 1.2).expect("an open direction from the start");
    let domain = domain_id(3);
    let mut sim = xhab();
    sim.args(["ros2", "sim", "procedural:3", "--physics", "--robot", "turtlebot3_burger", "--rate", "1", "--duration", "600"])
        .arg("--start")
        .arg(format!("{},{},{}", start.x, start.y, start.yaw))
        .stdout(Stdio::null())
        .stderr(Stdio::inherit());
    xhab_ros2_env(&mut sim, &domain);
    let _sim = Killed(sim.spawn().unwrap());
    let mut nav = xhab();
    nav.args(["ros2", "nav", "--robot", "turtlebot3_burger", "--localization", "amcl"]).stdout(Stdio::null()).stderr(Stdio::inherit());
    xhab_ros2_env(&mut nav, &domain);
    let _nav = Killed(nav.spawn().unwrap());
    let mut check = Command::new(&py);
    check.arg(repo_root().join("tests/e2e/ros2/nav.py")).args([start.x, start.y, start.yaw, goal.x, goal.y, 0.25].map(|v| v.to_string()));
    rclpy_env(&mut check, &domain);
    let out = check.output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && stdout.contains("PASS"), "xhab ros2 nav did not bring the robot to rclpy's goal_pose");
}
