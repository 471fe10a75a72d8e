//! The fuzz targets' bodies: each feeds its input to a parser the way xhab reads that format
//! and asserts what callers rely on: an error names the input, a success is usable.
//! `fuzz_targets/*.rs` call them under libFuzzer (nightly); the stable e2e test
//! `fuzz_regressions` (tests/e2e/fuzz_regressions.rs) includes this file and runs every input
//! of `fuzz/regressions/TARGET/` through the same function, so it uses no libFuzzer items.

use std::path::{Path, PathBuf};
use xhab_bridge::ros::convert as cv;
use xhab_bridge::ros::msgs::{actionlib_msgs as al, geometry_msgs as gm, move_base_msgs as mb, nav_msgs, sensor_msgs, std_msgs, tf2_msgs, xhab_msgs};
use xhab_bridge::ros::tf_buffer::TfBuffer;
use xhab_bridge::ros::wire;
use xhab_nav::map_server::{decode_map_image, parse_map_yaml, MapMetadata, MapMode, MAX_RESOLUTION, MIN_RESOLUTION};
use xhab_nav::ros_params::{nav_params_from_sources, ParamFile, ParamSource};
use xhab_sim::episode::parse_dataset;
use xhab_sim::robot::RobotProfile;
use xhab_sim::scene::{parse, LoadOptions, Scene, SceneFormat, UpAxis};

/// The targets, as `scripts/fuzz.sh` and `fuzz/regressions/` name them.
pub const TARGETS: [&str; 9] = ["gltf", "obj", "ply", "map_yaml", "map_image", "episodes", "robot_profile", "nav_params", "ros_msgs"];

/// Runs target `name` on `data`; panics (as libFuzzer wants) when an invariant fails.
pub fn run(name: &str, data: &[u8]) {
    match name {
        "gltf" => gltf(data),
        "obj" => obj(data),
        "ply" => ply(data),
        "map_yaml" => map_yaml(data),
        "map_image" => map_image(data),
        "episodes" => episodes(data),
        "robot_profile" => robot_profile(data),
        "nav_params" => nav_params(data),
        "ros_msgs" => ros_msgs(data),
        _ => panic!("no fuzz target {name}"),
    }
}

/// Asserts that an error message names the file `path`.
pub fn names_file(msg: &str, path: &Path) {
    let p = path.display().to_string();
    assert!(msg.contains(&p), "the error does not name the file {p}: {msg}");
}

/// A loaded scene: finite vertices, indices in range, triangles present, texture coordinates
/// only with a texture that exists.
pub fn scene(s: &Scene) {
    assert!(s.triangle_count() > 0);
    for m in &s.meshes {
        assert!(m.positions.iter().flatten().all(|c| c.is_finite()));
        assert!(m.indices.iter().flatten().all(|&i| (i as usize) < m.positions.len()));
        if let Some(t) = m.texture {
            let t = &s.textures[t as usize];
            assert!(t.is_consistent());
            assert_eq!(m.uvs.len(), m.positions.len());
        }
    }
    assert!(!s.bounds().is_empty());
}

fn not_found() -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::NotFound, "fuzzing: no such file")
}

/// glTF 2.0 scenes: a GLB file, or a .gltf JSON file whose external buffers and images are all
/// the bytes after its first NUL byte.
pub fn gltf(data: &[u8]) {
    let (path, doc, files) = if data.starts_with(b"glTF") {
        (Path::new("/fuzz/scene.glb"), data, None)
    } else {
        match data.iter().position(|&b| b == 0) {
            Some(i) => (Path::new("/fuzz/scene.gltf"), &data[..i], Some(&data[i + 1..])),
            None => (Path::new("/fuzz/scene.gltf"), data, None),
        }
    };
    let read = |_: &Path| files.map(<[u8]>::to_vec).ok_or_else(not_found);
    // (With and without textures, as for OBJ below.)
    match parse(doc, SceneFormat::Gltf, path, &LoadOptions { textures: doc.len() % 3 != 0, ..LoadOptions::default() }, &read) {
        Ok(s) => scene(&s),
        Err(e) => names_file(&e.to_string(), path),
    }
}

/// Wavefront OBJ scenes with their material library: the OBJ text, a NUL byte, then the MTL
/// text every `mtllib` reads (`map_Kd` images are missing).
pub fn obj(data: &[u8]) {
    let (obj, mtl) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &[][..]),
    };
    let read = |p: &Path| if p.extension().is_some_and(|e| e == "mtl") { Ok(mtl.to_vec()) } else { Err(not_found()) };
    let path = Path::new("/fuzz/scene.obj");
    // (Both with and without textures: the loader must hold up either way.)
    let opts = LoadOptions { up_axis: if obj.len() % 2 == 0 { UpAxis::Y } else { UpAxis::Z }, drop_ceilings: true, textures: obj.len() % 3 != 0 };
    match parse(obj, SceneFormat::Obj, path, &opts, &read) {
        Ok(s) => scene(&s),
        Err(e) => names_file(&e.to_string(), path),
    }
}

/// PLY scenes, ascii and binary (little and big endian).
pub fn ply(data: &[u8]) {
    let path = Path::new("/fuzz/scene.ply");
    let read = |_: &Path| Err(not_found());
    match parse(data, SceneFormat::Ply, path, &LoadOptions::default(), &read) {
        Ok(s) => scene(&s),
        Err(e) => names_file(&e.to_string(), path),
    }
}

/// map_server map YAML (the metadata): a success holds values the grid code can use.
pub fn map_yaml(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let path = Path::new("/fuzz/map.yaml");
    match parse_map_yaml(text, path) {
        Ok(m) => {
            assert!((MIN_RESOLUTION..=MAX_RESOLUTION).contains(&m.resolution));
            assert!(m.origin.iter().all(|v| v.is_finite()));
            assert!(0.0 <= m.free_thresh && m.free_thresh < m.occupied_thresh && m.occupied_thresh <= 1.0);
            let _ = m.image_path(path);
        }
        Err(e) => names_file(&e.to_string(), path),
    }
}

/// map_server map images (PGM P5/P2, 8 and 16 bit, and PNG): the first byte picks the mode
/// (trinary, scale, raw) and negate, the rest is the image. A grid has one cell per pixel,
/// with ROS's values.
pub fn map_image(data: &[u8]) {
    let Some((&sel, bytes)) = data.split_first() else { return };
    let mode = [MapMode::Trinary, MapMode::Scale, MapMode::Raw][(sel % 3) as usize];
    let meta = MapMetadata {
        image: PathBuf::from("map.pgm"),
        resolution: 0.05,
        origin: [-1.0, 2.0, 0.5],
        negate: sel & 4 != 0,
        occupied_thresh: 0.65,
        free_thresh: 0.196,
        mode,
    };
    let path = Path::new("/fuzz/map.pgm");
    match decode_map_image(bytes, path, &meta) {
        Ok(g) => {
            assert_eq!(g.data.len(), g.width * g.height);
            assert!(g.width > 0 && g.height > 0);
            if mode != MapMode::Raw {
                assert!(g.data.iter().all(|&v| v == -1 || (0..=100).contains(&v)));
            }
        }
        Err(e) => names_file(&e.to_string(), path),
    }
}

/// Habitat PointNav episode files, plain JSON or gzipped (told by the first bytes): episodes
/// must be what the runner can use (finite, with goals).
pub fn episodes(data: &[u8]) {
    let path = Path::new("/fuzz/episodes.json.gz");
    match parse_dataset(data, path) {
        Ok(ds) => {
            for e in &ds.episodes {
                assert!(e.start_position.x.is_finite() && e.start_position.y.is_finite() && e.start_position.z.is_finite());
                assert!(e.start_yaw.is_finite());
                assert!(!e.goals.is_empty());
                assert!(e.goals.iter().all(|g| g.radius.is_finite()
                    && g.radius > 0.0
                    && g.position.x.is_finite()
                    && g.position.y.is_finite()
                    && g.position.z.is_finite()));
            }
        }
        Err(e) => names_file(&e.to_string(), path),
    }
}

/// Robot profile YAML: a profile passes its own range checks.
pub fn robot_profile(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let path = Path::new("/fuzz/robot.yaml");
    match RobotProfile::parse(text, path) {
        Ok(p) => {
            assert!(p.validate().is_ok());
            let _ = p.laser.lidar();
        }
        Err(e) => names_file(&e.to_string(), path),
    }
}

/// ROS navigation parameter files (move_base, costmap_2d, DWA, global_planner, amcl), layered:
/// up to four files split at NUL bytes; a file whose first line is `@NAMESPACE` is loaded under
/// that namespace (parsed as the `FILE@NAMESPACE` argument). Errors name a file or the argument.
pub fn nav_params(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let mut sources = Vec::new();
    for (i, part) in text.split('\0').take(4).enumerate() {
        let name = format!("/fuzz/params{i}.yaml");
        let (namespace, body) = match part.strip_prefix('@') {
            Some(rest) => {
                let (ns, body) = rest.split_once('\n').unwrap_or((rest, ""));
                let arg = format!("{name}@{ns}");
                match arg.parse::<ParamFile>() {
                    Ok(f) => (f.namespace, body),
                    Err(e) => {
                        assert!(e.to_string().contains(&arg), "{e}");
                        return;
                    }
                }
            }
            None => (String::new(), part),
        };
        sources.push(ParamSource { name, text: body.to_string(), namespace });
    }
    match nav_params_from_sources(&sources) {
        Ok(mut loaded) => {
            loaded.size_to_robot(0.2, None);
            loaded.size_to_robot(0.2, Some(&[[0.1, 0.1], [-0.1, 0.1], [-0.1, -0.1]]));
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with("/fuzz/params"), "the error does not name a file: {msg}");
        }
    }
}

/// Decodes `frame` as `$t`; on success runs `$use` on it and checks that the re-encoding
/// decodes to the same encoding. An error names the type.
macro_rules! case {
    ($frame:expr, $t:ty, |$m:ident| $use:expr) => {{
        match wire::decode::<$t>($frame) {
            Ok($m) => {
                let bytes = wire::encode(&$m);
                match wire::decode::<$t>(&bytes) {
                    Ok(again) => assert_eq!(wire::encode(&again), bytes),
                    Err(e) => panic!("a re-encoded message does not decode: {e}"),
                }
                let _ = $use;
            }
            Err(e) => {
                let ty = std::any::type_name::<$t>().rsplit("::").next().unwrap_or_default();
                assert!(e.to_string().contains(ty), "{e}");
            }
        }
    }};
}

/// ROS 1 messages of every type xhab's nodes subscribe to, decoded as roslibrust's subscriber
/// decodes what arrives (a body behind its length prefix), then converted as the nodes convert
/// them. The first byte picks the type, the rest is the body.
pub fn ros_msgs(data: &[u8]) {
    let Some((&sel, body)) = data.split_first() else { return };
    let f = &wire::frame(body)[..];
    match sel % 15 {
        0 => case!(f, gm::Twist, |m| cv::twist2(&m)),
        1 => case!(f, nav_msgs::Odometry, |m| (cv::pose2(&m.pose.pose), cv::twist2(&m.twist.twist), cv::seconds(&m.header.stamp))),
        2 => case!(f, sensor_msgs::LaserScan, |m| {
            let s = cv::scan_from_msg(&m);
            assert_eq!(s.ranges.len(), m.ranges.len());
        }),
        3 => case!(f, gm::PoseWithCovarianceStamped, |m| cv::pose2(&m.pose.pose)),
        4 => case!(f, mb::MoveBaseActionGoal, |m| (cv::pose2(&m.goal.target_pose.pose), cv::seconds(&m.goal_id.stamp))),
        5 => case!(f, al::GoalID, |m| cv::seconds(&m.stamp)),
        6 => case!(f, al::GoalStatusArray, |m| m.status_list.len()),
        7 => case!(f, mb::MoveBaseActionResult, |m| m.status.status),
        8 => case!(f, gm::PoseStamped, |m| cv::pose2(&m.pose)),
        9 => case!(f, nav_msgs::OccupancyGrid, |m| {
            if let Ok(g) = cv::grid_from_msg(&m) {
                assert_eq!(g.data.len(), g.width * g.height);
            }
        }),
        10 => case!(f, tf2_msgs::TFMessage, |m| {
            let mut b = TfBuffer::new();
            b.insert(&m);
            for t in &m.transforms {
                let _ = b.lookup("map", &t.child_frame_id);
                let _ = b.lookup(&t.header.frame_id, "base_link");
            }
        }),
        11 => case!(f, std_msgs::Int16, |m| m.data),
        12 => case!(f, xhab_msgs::Episode, |m| (cv::pose2(&m.goal.pose), cv::pose2(&m.initial_pose.pose.pose), cv::seconds(&m.start))),
        13 => case!(f, xhab_msgs::Step, |m| cv::seconds(&m.stamp)),
        _ => case!(f, xhab_msgs::StepReply, |m| cv::twist2(&m.twist)),
    }
}
