//! External ROS 2 stacks benchmarked with `xhab bench --agent ros2` against real rclpy from
//! PyPI and against `xhab ros2 nav`: a small rclpy navigation node that takes `goal_pose` and
//! reports on `navigate_to_pose/_action/status`, and `xhab ros2 nav` through the
//! `navigate_to_pose` action (started with `--launch`) on turtlebot3_house, cancelled at a
//! timeout too.

use crate::common::{data_dir, repo_root, xhab};
use crate::ros2_interop::{domain_id, goal_in_the_open, rclpy_env, ros2_python, xhab_ros2_env};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Instant;
use xhab_sim::episode::{read_dataset, write_dataset, Dataset};
use xhab_sim::geodesic::geodesic_distance;
use xhab_types::{Point2, Point3, Pose2};

/// The ROS 2 python when it also imports action_msgs (ros-kilted-action-msgs); `None` with a
/// loud message otherwise, a panic when `XHAB_REQUIRE_ROS2=1` demands it.
fn ros2_python_with_actions(test: &str) -> Option<PathBuf> {
    let py = ros2_python(test)?;
    if Command::new(&py).args(["-c", "import action_msgs.msg"]).stdout(Stdio::null()).stderr(Stdio::null()).status().is_ok_and(|s| s.success()) {
        return Some(py);
    }
    if std::env::var("XHAB_REQUIRE_ROS2").as_deref() == Ok("1") {
        panic!("{test}: XHAB_REQUIRE_ROS2=1 but {} cannot import action_msgs (scripts/test.sh installs ros-kilted-action-msgs)", py.display());
    }
    eprintln!("SKIPPED {test}: no action_msgs at {} (scripts/test.sh installs ros-kilted-action-msgs)", py.display());
    None
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("xhab_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))).unwrap()
}

fn run(c: &mut Command) -> (Output, String) {
    let out = c.stdin(Stdio::null()).output().unwrap();
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    (out, text)
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// A small rclpy navigation node (tests/e2e/ros2/goto.py: `goal_pose` in, `cmd_vel` out, the
/// goal's fate on `navigate_to_pose/_action/status`) benchmarked with `--agent ros2
/// --goal-interface simple`, started by `--launch`, on three procedural episodes whose
/// shortest path is a straight line: each goal ends SUCCEEDED, the episode succeeds, and the
/// SPL is what a turn-then-go drive gets.
#[test]
fn an_rclpy_navigation_node_is_benchmarked_with_agent_ros2() {
    let test = "an_rclpy_navigation_node_is_benchmarked_with_agent_ros2";
    let Some(py) = ros2_python_with_actions(test) else { return };
    let t0 = Instant::now();
    let dir = temp_dir("ros2_goto");
    let all = dir.join("all.json.gz");
    let (out, text) = run(xhab().args(["episodes", "procedural:5", "--count", "20", "--seed", "3", "--out"]).arg(&all));
    assert!(out.status.success(), "xhab episodes: {text}");
    // Easy episodes (Habitat's generator leaves out straight ones): from the generated
    // starts, a goal 2 m away along an open heading whose shortest path is that line.
    let world = xhab_bridge::setup::load_world("procedural:5", &Default::default()).unwrap();
    let easy: Vec<_> = read_dataset(&all)
        .unwrap()
        .episodes
        .into_iter()
        .filter_map(|mut e| {
            let s = e.start_position;
            let grid = world.grid_at(s.z).ok()?;
            // Off to the side first: the node turns, then goes.
            let goal = goal_in_the_open(&grid, Pose2::new(s.x, s.y, e.start_yaw + 2.0), 2.0)?;
            let d = geodesic_distance(&grid, Point2::new(s.x, s.y), goal);
            (d <= 2.04).then(|| {
                e.goals[0].position = Point3::new(goal.x, goal.y, s.z);
                e.geodesic_distance = Some(d);
                e
            })
        })
        .take(3)
        .collect();
    assert_eq!(easy.len(), 3, "three straight-line episodes from 20 starts");
    let eps = dir.join("easy.json.gz");
    write_dataset(&Dataset { episodes: easy }, &eps).unwrap();
    let domain = domain_id(61);
    let out_json = dir.join("goto.json");
    // rclpy's Fast DDS keeps to loopback by its profile, not by the discovery range (see
    // tests/e2e/ros2/fastdds_loopback.xml).
    let launch = format!("exec env -u ROS_AUTOMATIC_DISCOVERY_RANGE {} {} 0.1", py.display(), repo_root().join("tests/e2e/ros2/goto.py").display());
    let mut bench = xhab();
    bench
        .args(["bench", "--scene", "procedural:5", "--agent", "ros2", "--goal-interface", "simple", "--map-odom", "ground-truth", "--ros-timeout", "60", "--quiet", "--launch", &launch])
        .arg("--episodes")
        .arg(&eps)
        .arg("--out")
        .arg(&out_json);
    // The bench's own node speaks RustDDS on loopback; the launched rclpy node inherits the
    // environment, Fast DDS's loopback profile included.
    rclpy_env(&mut bench, &domain);
    xhab_ros2_env(&mut bench, &domain);
    let (out, text) = run(&mut bench);
    eprintln!("{text}");
    assert!(out.status.success(), "bench --agent ros2 with the rclpy node failed");
    assert!(text.contains("ros: goals ended 3 SUCCEEDED; episodes ended by 3 terminal_state"), "the per-episode terminal states are reported");
    let r = json(&out_json);
    assert_eq!(r["agent"], "ros2");
    for e in r["episodes"].as_array().unwrap() {
        assert_eq!(e["ros_status"], "SUCCEEDED", "episode {}: {e}", e["episode_id"]);
        assert_eq!(e["success"], 1.0, "episode {}: {e}", e["episode_id"]);
    }
    let spl = f(&r["aggregate"]["spl"]);
    assert!(spl > 0.8 && spl <= 1.0, "SPL {spl} of a turn-then-go drive along straight shortest paths");
    eprintln!("{test}: SPL {spl:.3}, {:.0} s", t0.elapsed().as_secs_f64());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `xhab ros2 nav` started by `--launch` on turtlebot3_house and benchmarked through the
/// `navigate_to_pose` action: every goal SUCCEEDED and the episodes succeed. Then one episode
/// with a 3 s timeout: the bench cancels the goal and the server reports it CANCELED.
#[test]
fn xhab_ros2_nav_is_benchmarked_through_navigate_to_pose() {
    let test = "xhab_ros2_nav_is_benchmarked_through_navigate_to_pose";
    let Some(data) = data_dir(test) else { return };
    let t0 = Instant::now();
    let dir = temp_dir("ros2_bench_nav");
    let scene = data.join("scenes/turtlebot3_house.glb");
    let scene = scene.to_str().unwrap();
    let (out, text) = run(xhab().arg("map").arg(scene).arg("--out").arg(dir.join("house")));
    assert!(out.status.success(), "xhab map: {text}");
    let map = dir.join("house.yaml");
    let all = read_dataset(&data.join("episodes/turtlebot3_house_pointnav.json.gz")).unwrap();
    let eps = dir.join("eps.json.gz");
    write_dataset(&Dataset { episodes: all.episodes[..3].to_vec() }, &eps).unwrap();
    let launch = format!("exec {} ros2 nav --localization amcl --map {}", env!("CARGO_BIN_EXE_xhab"), map.display());
    let bench = |extra: &[&str], out_json: &Path, domain: &str| {
        let mut c = xhab();
        c.args(["bench", "--scene", scene, "--agent", "ros2", "--localization", "amcl", "--ros-timeout", "60", "--quiet", "--launch", &launch]).args(extra).arg("--map").arg(&map).arg("--episodes").arg(&eps).arg("--out").arg(out_json);
        xhab_ros2_env(&mut c, domain);
        let (out, text) = run(&mut c);
        eprintln!("{text}");
        assert!(out.status.success(), "bench --agent ros2 against xhab ros2 nav failed");
        text
    };
    let out_json = dir.join("action.json");
    let text = bench(&[], &out_json, &domain_id(62));
    assert!(text.contains("ros: goals ended 3 SUCCEEDED"), "every goal SUCCEEDED");
    let r = json(&out_json);
    for e in r["episodes"].as_array().unwrap() {
        assert_eq!(e["ros_status"], "SUCCEEDED", "episode {}: {e}", e["episode_id"]);
        assert_eq!(e["success"], 1.0, "episode {}: {e}", e["episode_id"]);
    }
    eprintln!("turtlebot3_house, 3 episodes over navigate_to_pose: SPL {:.3}", f(&r["aggregate"]["spl"]));

    write_dataset(&Dataset { episodes: all.episodes[..1].to_vec() }, &eps).unwrap();
    let out_json = dir.join("timeout.json");
    bench(&["--episode-timeout", "3"], &out_json, &domain_id(63));
    let e = &json(&out_json)["episodes"][0];
    assert_eq!((e["ros_end"].as_str(), e["ros_status"].as_str()), (Some("timeout"), Some("CANCELED")), "{e}");
    eprintln!("{test}: {:.0} s", t0.elapsed().as_secs_f64());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Flags that do not go with `--agent ros2` (or only with it) are errors naming them, and a
/// run without any stack in its domain ends with a timeout naming the action's status topic.
#[test]
fn agent_ros2_flag_errors_and_a_missing_stack_are_clear() {
    let dir = temp_dir("ros2_bench_errors");
    let eps = dir.join("eps.json.gz");
    let (out, text) = run(xhab().args(["episodes", "procedural:5", "--count", "1", "--seed", "3", "--out"]).arg(&eps));
    assert!(out.status.success(), "xhab episodes: {text}");
    let base = |agent: &str| {
        let mut c = xhab();
        c.args(["bench", "--scene", "procedural:5", "--agent", agent, "--quiet", "--ros-timeout", "2"]).arg("--episodes").arg(&eps);
        c
    };
    let (out, text) = run(base("ros2").args(["--ros-arg", "scan:=base_scan"]));
    assert!(!out.status.success() && text.contains("--ros-args"), "{text}");
    let (out, text) = run(base("ros").args(["--ros-args", "-r", "scan:=base_scan"]));
    assert!(!out.status.success() && text.contains("--ros-args is for --agent ros2"), "{text}");
    let (out, text) = run(base("ros2").args(["--ros-args", "-r"]));
    assert!(!out.status.success() && text.contains("-r"), "{text}");
    let mut c = base("ros2");
    c.args(["--ros-args", "-r", "__ns:=/robot7"]);
    xhab_ros2_env(&mut c, &domain_id(64));
    let t0 = Instant::now();
    let (out, text) = run(&mut c);
    assert!(!out.status.success() && text.contains("no navigation stack answered on /robot7/navigate_to_pose/_action/status within 2 s"), "{text}");
    assert!(t0.elapsed().as_secs_f64() < 30.0, "the missing stack took {:.0} s to report", t0.elapsed().as_secs_f64());
    let _ = std::fs::remove_dir_all(&dir);
}
