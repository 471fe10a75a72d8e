//! Scene loading: real scenes, round trips, bad files, and the procedural house.

use std::path::{Path, PathBuf};
use xhab_sim::navgrid::{AgentParams, NavGrid};
use xhab_sim::scene::house::{generate_house, HouseParams};
use xhab_sim::scene::{load, to_glb_bytes, LoadOptions, Scene, UpAxis};

use crate::data::data_dir;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("xhab-scenes-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

#[test]
fn every_shared_scene_loads_upright() {
    let Some(data) = data_dir("every_shared_scene_loads_upright") else { return };
    let mut n = 0;
    for e in std::fs::read_dir(data.join("scenes")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "glb") {
            continue;
        }
        let s = load(&p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let b = s.bounds();
        eprintln!("{}: {} triangles, bounds {:?} .. {:?}", p.display(), s.triangle_count(), b.min, b.max);
        // z up: floors near 0, walls going up a few metres, not sideways.
        assert!(b.min[2] >= -1.5 && b.max[2] < 10.0 && b.max[2] > 0.5, "{}: {b:?}", p.display());
        n += 1;
    }
    assert!(n >= 7);
}

#[test]
fn turtlebot3_house_keeps_its_gazebo_coordinates() {
    let Some(data) = data_dir("turtlebot3_house_keeps_its_gazebo_coordinates") else { return };
    let s = load(&data.join("scenes/turtlebot3_house.glb"), &LoadOptions::default()).unwrap();
    let b = s.bounds();
    // The Gazebo world spans about x in [-7.5, 8.5], y in [-5.5, 6] (ROS frame).
    assert!(b.min[0] < -6.0 && b.max[0] > 7.0 && b.min[1] < -4.0 && b.max[1] > 4.5, "{b:?}");
}

#[test]
fn glb_round_trip_is_exact_and_deterministic() {
    let house = generate_house(4, &HouseParams::default());
    let bytes = to_glb_bytes(&house);
    assert_eq!(bytes, to_glb_bytes(&house));
    let p = tmp("house.glb");
    std::fs::write(&p, &bytes).unwrap();
    let back = load(&p, &LoadOptions::default()).unwrap();
    assert_eq!(back.meshes.len(), house.meshes.len());
    for (a, b) in house.meshes.iter().zip(&back.meshes) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.indices, b.indices);
        for (p, q) in a.positions.iter().zip(&b.positions) {
            assert!((0..3).all(|i| (p[i] - q[i]).abs() < 1e-6), "{p:?} {q:?}");
        }
    }
}

fn err_of(path: &Path) -> String {
    load(path, &LoadOptions::default()).expect_err("must fail").to_string()
}

#[test]
fn bad_files_give_errors_naming_the_file() {
    let glb = to_glb_bytes(&generate_house(1, &HouseParams::default()));
    for (name, bytes) in [
        ("truncated.glb", glb[..1000].to_vec()),
        ("half.glb", glb[..glb.len() / 2].to_vec()),
        ("garbage.glb", b"this is not a glb file at all".to_vec()),
        ("empty.glb", vec![]),
    ] {
        let p = tmp(name);
        std::fs::write(&p, bytes).unwrap();
        let e = err_of(&p);
        assert!(e.contains(name), "{e}");
    }
    let obj = |name: &str, text: &str| {
        let p = tmp(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let e = err_of(&obj("nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n"));
    assert!(e.contains("nan.obj") && e.contains("non-finite"), "{e}");
    let e = err_of(&obj("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"));
    assert!(e.contains("index.obj"), "{e}");
    let e = err_of(&obj("empty.obj", "# nothing\n"));
    assert!(e.contains("empty.obj") && e.contains("no triangles"), "{e}");
    let e = err_of(Path::new("/nonexistent/x.glb"));
    assert!(e.contains("/nonexistent/x.glb"), "{e}");
    let p = tmp("scene.xyz");
    std::fs::write(&p, "x").unwrap();
    assert!(err_of(&p).contains("unknown scene format"));
    let p = tmp("bad.ply");
    std::fs::write(&p, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n").unwrap();
    let e = err_of(&p);
    assert!(e.contains("bad.ply") && e.contains("out of range"), "{e}");
}

#[test]
fn obj_and_ply_honour_the_up_axis() {
    let obj = tmp("tri.obj");
    std::fs::write(&obj, "o floor\nv 0 0 0\nv 1 0 0\nv 0 0 -1\nf 1 2 3\n").unwrap();
    let s = load(&obj, &LoadOptions::default()).unwrap();
    // y-up file: (0, 0, -1) is 1 m along our +y.
    assert_eq!(s.meshes[0].positions[2], [0.0, 1.0, 0.0]);
    let ply = tmp("tri.ply");
    std::fs::write(&ply, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 2\n3 0 1 2\n").unwrap();
    let s = load(&ply, &LoadOptions { up_axis: UpAxis::Z, drop_ceilings: true, ..Default::default() }).unwrap();
    assert_eq!(s.meshes[0].positions[2], [0.0, 1.0, 2.0]);
}

#[test]
fn ceilings_are_dropped_by_name() {
    let mut s = Scene::default();
    s.add_box("floor", [0.0, 0.0, -0.1], [5.0, 5.0, 0.0], [1.0; 4]);
    s.add_box("Living_Ceiling_01", [0.0, 0.0, 2.5], [5.0, 5.0, 2.6], [1.0; 4]);
    let p = tmp("ceil.glb");
    std::fs::write(&p, to_glb_bytes(&s)).unwrap();
    assert_eq!(load(&p, &LoadOptions::default()).unwrap().meshes.len(), 1);
    assert_eq!(load(&p, &LoadOptions { drop_ceilings: false, ..Default::default() }).unwrap().meshes.len(), 2);
}

#[test]
fn procedural_houses_are_seeded_and_connected() {
    let p = HouseParams::default();
    assert_eq!(generate_house(3, &p), generate_house(3, &p));
    assert_ne!(generate_house(3, &p), generate_house(4, &p));
    for seed in 0..8 {
        let s = generate_house(seed, &p);
        let g = NavGrid::build(&s, &AgentParams::default(), 0.0).unwrap();
        // One island holds nearly all the navigable floor: rooms connect through doors.
        let total: usize = g.islands.iter().map(|i| i.cells).sum();
        let largest = g.islands.iter().map(|i| i.cells).max().unwrap();
        assert!(largest as f64 >= 0.95 * total as f64, "seed {seed}: {largest} of {total} cells connected");
        assert!(largest as f64 * 0.0025 > 50.0, "seed {seed}: only {} m^2", largest as f64 * 0.0025);
    }
}
