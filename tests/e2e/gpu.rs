//! Acceptance of the wgpu depth camera on real scenes: it agrees with the ray caster. Without a
//! Vulkan adapter it prints SKIPPED and passes, unless `XHAB_REQUIRE_GPU=1`.

use crate::common::data_dir;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::{load, LoadOptions};
use xhab_sim::sensors::{render_depth, CameraParams, GpuRenderer, RayScene};
use xhab_sim::world::World;
use xhab_types::Pose2;

#[test]
fn gpu_depth_agrees_with_the_ray_cast_on_real_scenes() {
    let test = "gpu_depth_agrees_with_the_ray_cast_on_real_scenes";
    let Some(data) = data_dir(test) else { return };
    for name in ["turtlebot3_house.glb", "aws_small_house.glb"] {
        let scene = load(&data.join("scenes").join(name), &LoadOptions::default()).unwrap();
        let g = match GpuRenderer::new(&scene) {
            Ok(g) => g,
            Err(e) if std::env::var("XHAB_REQUIRE_GPU").as_deref() == Ok("1") => {
                panic!("{test}: XHAB_REQUIRE_GPU=1 but the GPU renderer is unavailable: {e}")
            }
            Err(e) => {
                crate::common::skipped(test, &format!("no GPU renderer ({e})"));
                return;
            }
        };
        let ray = RayScene::new(&scene).unwrap();
        let world = World::new(scene, AgentParams::default());
        let grid = world.grid(world.default_floor().unwrap()).unwrap();
        let cells = grid.cells_on_islands(0.0);
        let mut rng = ChaCha8Rng::seed_from_u64(42);
        let cam = CameraParams::default();
        let views: Vec<(Pose2, f64)> = (0..100).map(|_| (grid.sample_pose(&cells, &mut rng).unwrap(), grid.floor_z)).collect();
        let (mut ok, mut hit, mut all) = (0usize, 0usize, 0usize);
        for (chunk, imgs) in views.chunks(16).map(|c| (c, g.render_depth_batch(c, &cam).unwrap())) {
            for (&(pose, fz), a) in chunk.iter().zip(&imgs) {
                let b = render_depth(&ray, pose, fz, &cam);
                ok += a.data.iter().zip(&b.data).filter(|(x, y)| (**x - **y).abs() < 0.01).count();
                hit += b.data.iter().filter(|d| **d > 0.0).count();
                all += a.data.len();
            }
        }
        let frac = ok as f64 / all as f64;
        eprintln!("{name}: gpu depth ({}) within 1 cm of the ray cast on {:.4}% of {all} pixels ({hit} hit)", g.adapter_info(), 100.0 * frac);
        assert!(frac >= 0.99, "{name}: {frac}");
        assert!(hit as f64 > 0.3 * all as f64, "{name}: only {hit} of {all} pixels hit");
    }
}
