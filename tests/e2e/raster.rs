//! Acceptance of the rasterised depth camera on real scenes: it agrees with the ray caster.

use crate::common::data_dir;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::{load, LoadOptions};
use xhab_sim::sensors::{render_depth, CameraParams, RasterScene, RayScene};
use xhab_sim::world::World;

#[test]
fn raster_depth_agrees_with_the_ray_cast_on_real_scenes() {
    let Some(data) = data_dir("raster_depth_agrees_with_the_ray_cast_on_real_scenes") else { return };
    for name in ["turtlebot3_house.glb", "aws_small_house.glb"] {
        let scene = load(&data.join("scenes").join(name), &LoadOptions::default()).unwrap();
        let rs = RasterScene::new(&scene).unwrap();
        let ray = RayScene::new(&scene).unwrap();
        let world = World::new(scene, AgentParams::default());
        let grid = world.grid(world.default_floor().unwrap()).unwrap();
        let cells = grid.cells_on_islands(0.0);
        let mut rng = ChaCha8Rng::seed_from_u64(42);
        let cam = CameraParams::default();
        let (mut ok, mut hit, mut all) = (0usize, 0usize, 0usize);
        for _ in 0..100 {
            let pose = grid.sample_pose(&cells, &mut rng).unwrap();
            let a = rs.render_depth(pose, grid.floor_z, &cam);
            let b = render_depth(&ray, pose, grid.floor_z, &cam);
            ok += a.data.iter().zip(&b.data).filter(|(x, y)| (**x - **y).abs() < 0.01).count();
            hit += b.data.iter().filter(|d| **d > 0.0).count();
            all += a.data.len();
        }
        let frac = ok as f64 / all as f64;
        eprintln!("{name}: raster depth within 1 cm of the ray cast on {:.4}% of {all} pixels ({hit} hit)", 100.0 * frac);
        assert!(frac >= 0.99, "{name}: {frac}");
        assert!(hit as f64 > 0.3 * all as f64, "{name}: only {hit} of {all} pixels hit");
    }
}
