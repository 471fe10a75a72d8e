//! Sensors: camera conventions, depth to scan against the planar lidar, determinism.

use xhab_nav::depth_to_scan::{beam_index, depth_to_scan, DepthToScanParams};
use xhab_sim::scene::Scene;
use xhab_sim::sensors::{render_depth, CameraParams, Lidar, LidarParams, RayScene};
use xhab_types::Pose2;

const GREY: [f32; 4] = [0.5, 0.5, 0.5, 1.0];

/// A 6 x 4 m room (x in [0, 6], y in [0, 4]) with a pillar.
fn room() -> Scene {
    let mut s = Scene::default();
    s.add_box("floor", [0.0, 0.0, -0.05], [6.0, 4.0, 0.0], GREY);
    s.add_box("wall_e", [6.0, 0.0, 0.0], [6.1, 4.0, 2.5], GREY);
    s.add_box("wall_w", [-0.1, 0.0, 0.0], [0.0, 4.0, 2.5], GREY);
    s.add_box("wall_n", [0.0, 4.0, 0.0], [6.0, 4.1, 2.5], GREY);
    s.add_box("wall_s", [0.0, -0.1, 0.0], [6.0, 0.0, 2.5], GREY);
    s.add_box("pillar", [3.5, 2.3, 0.0], [3.8, 2.6, 2.5], GREY);
    s
}

#[test]
fn a_wall_ahead_is_at_the_image_centre_with_its_depth() {
    let rs = RayScene::new(&room()).unwrap();
    let cam = CameraParams::default();
    let img = render_depth(&rs, Pose2::new(4.0, 1.0, 0.0), 0.0, &cam);
    let c = img.data[128 * 256 + 128];
    assert!((c - 2.0).abs() < 1e-4, "{c}");
    // Depth is along the optical axis: the same 2.0 across the wall, not the ray length.
    let side = img.data[128 * 256 + 20];
    assert!((side - 2.0).abs() < 1e-4, "{side}");
    // Looking up the floor is below: the bottom rows see the floor closer than the top rows see the ceiling (none).
    assert!(img.data[255 * 256 + 128] > 0.0 && img.data[255 * 256 + 128] < 2.0);
    // The top row looks 45 degrees up at the wall 2 m ahead: it hits 2 m ahead (depth 2) unless
    // above the 2.5 m wall top (1.25 + 2 = 3.25 m): then nothing, depth 0.
    assert_eq!(img.data[128], 0.0);
}

#[test]
fn scan_from_depth_equals_the_planar_ray_cast_beam_for_beam() {
    let scene = room();
    let rs = RayScene::new(&scene).unwrap();
    let cam = CameraParams { mount_height: 0.6, ..Default::default() };
    let k = cam.intrinsics();
    for pose in [Pose2::new(1.0, 1.0, 0.3), Pose2::new(5.0, 3.0, 2.5), Pose2::new(2.0, 2.4, -0.1)] {
        let img = render_depth(&rs, pose, 0.0, &cam);
        let scan = depth_to_scan(&img, &k, &DepthToScanParams::default());
        // The planar ray cast at the camera's height, for each column's own angle.
        let mut expected = vec![f64::NAN; scan.ranges.len()];
        for u in 0..img.width {
            let th = -((u as f64 - k.cx) / k.fx).atan();
            let Some(i) = beam_index(th, scan.angle_min, scan.angle_increment, scan.ranges.len()) else { continue };
            let a = pose.yaw + th;
            if let Some(r) = rs.cast([pose.x, pose.y, cam.mount_height], [a.cos(), a.sin(), 0.0], 20.0) {
                if (0.45..=10.0).contains(&r) && (expected[i].is_nan() || r < expected[i]) {
                    expected[i] = r;
                }
            }
        }
        let mut compared = 0;
        for (i, (&got, &want)) in scan.ranges.iter().zip(&expected).enumerate() {
            assert_eq!(got.is_nan(), want.is_nan(), "beam {i}: {got} vs {want}");
            if !want.is_nan() {
                assert!((got as f64 - want).abs() < 0.01, "beam {i}: {got} vs {want}");
                compared += 1;
            }
        }
        assert!(compared > 200, "{compared}");
    }
}

#[test]
fn lidar_sees_walls_at_known_distances_and_noise_is_seeded() {
    let rs = RayScene::new(&room()).unwrap();
    let mut l = Lidar::new(LidarParams { range_max: 10.0, ..Default::default() }, 1);
    let s = l.scan(&rs, Pose2::new(1.0, 1.0, 0.0), 0.0);
    // Beam 180 points at angle 0 (ahead, +x): the pillar is not in the way at y = 1.
    let ahead = s.ranges[180] as f64;
    assert!((s.angle(180)).abs() < 1e-12 && (ahead - 5.0).abs() < 1e-4, "{ahead}");
    let behind = s.ranges[0] as f64;
    assert!((behind - 1.0).abs() < 1e-4, "{behind}");
    let noisy = |seed| Lidar::new(LidarParams { noise_std: 0.01, ..Default::default() }, seed).scan(&rs, Pose2::new(1.0, 1.0, 0.0), 0.0).ranges;
    let (a, b) = (noisy(4), noisy(4));
    assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert!(a.iter().zip(&noisy(5)).any(|(x, y)| x != y));
}
