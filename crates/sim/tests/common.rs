//! Scenes and episodes shared by the integration tests.

use xhab_sim::episode::{Episode, Goal};
use xhab_sim::scene::Scene;
use xhab_types::Point3;

/// Grey, for test geometry.
pub const GREY: [f32; 4] = [0.5, 0.5, 0.5, 1.0];

/// A 6 x 6 m room split by a wall at y = 3 with a door at x in [2.5, 3.4].
pub fn room_with_door() -> Scene {
    let mut s = Scene::default();
    s.add_box("floor", [0.0, 0.0, -0.05], [6.0, 6.0, 0.0], GREY);
    s.add_box("wall_s", [0.0, -0.1, 0.0], [6.0, 0.0, 2.5], GREY);
    s.add_box("wall_n", [0.0, 6.0, 0.0], [6.0, 6.1, 2.5], GREY);
    s.add_box("wall_w", [-0.1, 0.0, 0.0], [0.0, 6.0, 2.5], GREY);
    s.add_box("wall_e", [6.0, 0.0, 0.0], [6.1, 6.0, 2.5], GREY);
    s.add_box("wall_mid_a", [0.0, 2.95, 0.0], [2.5, 3.05, 2.5], GREY);
    s.add_box("wall_mid_b", [3.4, 2.95, 0.0], [6.0, 3.05, 2.5], GREY);
    s
}

/// A one-goal episode on the floor at z = 0 (m, rad).
pub fn episode(sx: f64, sy: f64, yaw: f64, gx: f64, gy: f64) -> Episode {
    Episode {
        episode_id: "t".into(),
        scene_id: "test".into(),
        start_position: Point3::new(sx, sy, 0.0),
        start_yaw: yaw,
        goals: vec![Goal { position: Point3::new(gx, gy, 0.0), radius: 0.2 }],
        geodesic_distance: None,
        info: serde_json::Value::Null,
    }
}
