//! Buildings with storeys from the command line: the storeys a scene lists, cross-floor
//! episodes, the oracle across storeys with and without physics, one map per storey.

use crate::common::xhab;
use std::path::{Path, PathBuf};

fn run(args: &[&str]) -> std::process::Output {
    let out = xhab().args(args).output().expect("xhab runs");
    assert!(out.status.success(), "xhab {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    out
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("xhab-storeys-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

#[test]
fn scene_info_lists_the_storeys_and_the_flight_between_them() {
    let out = run(&["scene", "info", "procedural:2", "--storeys", "2", "-q"]);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let floors = j["floors"].as_array().unwrap();
    assert_eq!(floors.len(), 2, "{j}");
    assert_eq!(floors[0]["stairs_to"], serde_json::json!([1]));
    assert_eq!(floors[1]["stairs_to"], serde_json::json!([0]));
    assert!(floors[1]["height_m"].as_f64().unwrap() > 2.5);
    assert_eq!(j["storeys_joined"], serde_json::json!([[0, 1]]));
    // A bad storey count is an error naming the flag.
    let bad = xhab().args(["scene", "info", "procedural", "--storeys", "0"]).output().unwrap();
    assert!(!bad.status.success() && String::from_utf8_lossy(&bad.stderr).contains("--storeys 0"));
}

#[test]
fn cross_floor_episodes_are_run_by_the_oracle_with_and_without_physics() {
    let d = tmp("xf");
    let eps = d.join("xf.json.gz");
    let e = eps.to_str().unwrap();
    run(&["episodes", "stair_building", "--cross-floor", "--count", "8", "--seed", "3", "--out", e]);
    let ds = xhab_sim::episode::read_dataset(&eps).unwrap();
    assert_eq!(ds.episodes.len(), 8);
    for ep in &ds.episodes {
        // Start and goal on different floors (0 and 2.8 m).
        assert!((ep.start_position.z - ep.goals[0].position.z).abs() > 2.0, "{ep:?}");
    }
    let bench = |extra: &[&str], name: &str| {
        let out = d.join(name);
        let mut args = vec!["bench", "--scene", "stair_building", "--episodes", e, "--agent", "oracle", "-q", "--out", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        run(&args);
        json(&out)
    };
    let plain = bench(&[], "plain.json");
    assert!(plain["aggregate"]["success"].as_f64().unwrap() >= 0.97, "{}", plain["aggregate"]);
    assert!(plain["aggregate"]["spl"].as_f64().unwrap() >= 0.95, "{}", plain["aggregate"]);
    // Habitat's agent as a rigid body climbs the flight (step_height 0.2).
    let habitat = bench(&["--physics", "--robot", "habitat"], "habitat.json");
    assert!(habitat["aggregate"]["success"].as_f64().unwrap() >= 0.87, "{}", habitat["aggregate"]);
    // A TurtleBot cannot: every episode ends stuck at a step or drop, the cause named.
    let burger = bench(&["--physics", "--robot", "turtlebot3_burger"], "burger.json");
    assert_eq!(burger["aggregate"]["success"].as_f64().unwrap(), 0.0, "{}", burger["aggregate"]);
    let stuck: Vec<&serde_json::Value> = burger["episodes"].as_array().unwrap().iter().filter(|e| e["stuck"] == true).collect();
    assert!(stuck.len() >= 6, "{} of 8 stuck", stuck.len());
    for e in stuck {
        let cause = e["stuck_cause"].as_str().unwrap_or_default();
        assert!(cause.contains("turtlebot3_burger") && (cause.contains("a step") || cause.contains("a drop")), "{e}");
    }
}

#[test]
fn map_floor_all_writes_one_map_per_storey_and_a_picture_of_them_side_by_side() {
    let d = tmp("maps");
    let out = d.join("house");
    run(&["map", "procedural", "--storeys", "2", "--floor", "all", "--out", out.to_str().unwrap()]);
    for k in 0..2 {
        for ext in ["yaml", "pgm", "png"] {
            assert!(d.join(format!("house_floor{k}.{ext}")).is_file(), "house_floor{k}.{ext}");
        }
    }
    let side = image::open(d.join("house.png")).unwrap();
    let one = image::open(d.join("house_floor0.png")).unwrap();
    assert!(side.width() > 2 * one.width() - 1, "{} vs {}", side.width(), one.width());
    // `--floor 1` is the upper storey's map, the same as in `all`.
    let single = d.join("upper");
    run(&["map", "procedural", "--storeys", "2", "--floor", "1", "--out", single.to_str().unwrap()]);
    assert_eq!(std::fs::read(d.join("upper.pgm")).unwrap(), std::fs::read(d.join("house_floor1.pgm")).unwrap());
}
