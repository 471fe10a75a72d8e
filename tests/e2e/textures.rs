//! Textured RGB on real scenes: the shared scenes' textures load, and the three renderers
//! (ray cast, raster, wgpu) give the same colours, texture detail included. Without a Vulkan
//! adapter the wgpu comparison prints SKIPPED, unless `XHAB_REQUIRE_GPU=1`.

use crate::common::data_dir;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::{load, LoadOptions};
use xhab_sim::sensors::{render_rgb, CameraParams, GpuRenderer, RasterScene, RayScene};
use xhab_sim::world::World;

/// Per-channel tolerance (bytes) of two renderers' colours for one pixel.
const TOL: u8 = 2;

/// Pixels of `a` and `b` within [`TOL`] on every channel.
fn agree(a: &[u8], b: &[u8]) -> usize {
    assert_eq!(a.len(), b.len());
    a.chunks(3).zip(b.chunks(3)).filter(|(x, y)| x.iter().zip(y.iter()).all(|(p, q)| p.abs_diff(*q) <= TOL)).count()
}

/// Pixels of `a` that differ from their right neighbour by more than 8 on some channel: a flat
/// colour per triangle gives few, a texture many.
fn detail(a: &[u8], w: usize) -> usize {
    a.chunks(3 * w)
        .map(|row| row.chunks(3).zip(row.chunks(3).skip(1)).filter(|(x, y)| x.iter().zip(y.iter()).any(|(p, q)| p.abs_diff(*q) > 8)).count())
        .sum()
}

#[test]
fn textured_rgb_agrees_between_the_renderers_on_real_scenes() {
    let test = "textured_rgb_agrees_between_the_renderers_on_real_scenes";
    let Some(data) = data_dir(test) else { return };
    // (scene, textures it holds, whether they cover much of what the camera sees).
    for (name, textures, covering) in [("turtlebot3_house.glb", 1, false), ("aws_small_house.glb", 46, true)] {
        let scene = load(&data.join("scenes").join(name), &LoadOptions::default()).unwrap();
        assert_eq!(scene.textures.len(), textures, "{name}");
        let textured = scene.meshes.iter().filter(|m| scene.texture_of(m).is_some()).count();
        assert!(textured > 0, "{name}: no textured mesh");
        let ray = RayScene::new(&scene).unwrap();
        let rs = RasterScene::new(&scene).unwrap();
        // The same scene without textures, to show that they add detail.
        let mut plain = scene.clone();
        plain.textures.clear();
        let flat = RasterScene::new(&plain).unwrap();
        let gpu = match GpuRenderer::new(&scene) {
            Ok(g) => Some(g),
            Err(e) if std::env::var("XHAB_REQUIRE_GPU").as_deref() == Ok("1") => {
                panic!("{test}: XHAB_REQUIRE_GPU=1 but the GPU renderer is unavailable: {e}")
            }
            Err(e) => {
                crate::common::skipped(&format!("{test} (wgpu part)"), &format!("no GPU renderer ({e})"));
                None
            }
        };
        let world = World::new(scene, AgentParams::default());
        let grid = world.grid(world.default_floor().unwrap()).unwrap();
        let cells = grid.cells_on_islands(0.0);
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let cam = CameraParams::default();
        let (mut ray_raster, mut gpu_raster, mut gpu_ray, mut lit, mut all) = (0, 0, 0, 0, 0);
        let (mut textured_detail, mut flat_detail) = (0, 0);
        for _ in 0..30 {
            let pose = grid.sample_pose(&cells, &mut rng).unwrap();
            let a = render_rgb(&ray, pose, grid.floor_z, &cam);
            let b = rs.render_rgb(pose, grid.floor_z, &cam);
            ray_raster += agree(&a, &b);
            if let Some(g) = &gpu {
                let c = g.render_rgb(pose, grid.floor_z, &cam).unwrap();
                gpu_raster += agree(&c, &b);
                gpu_ray += agree(&c, &a);
            }
            lit += a.chunks(3).filter(|x| x.iter().any(|c| *c > 0)).count();
            textured_detail += detail(&b, cam.width);
            flat_detail += detail(&flat.render_rgb(pose, grid.floor_z, &cam), cam.width);
            all += cam.width * cam.height;
        }
        let pc = |n: usize| 100.0 * n as f64 / all as f64;
        eprintln!(
            "{name}: within {TOL} per channel: raster/raycast {:.3}%, wgpu/raster {:.3}%, wgpu/raycast {:.3}% of {all} pixels ({:.1}% lit; {:.2}% of pixels differ from their neighbour, {:.2}% without textures)",
            pc(ray_raster),
            pc(gpu_raster),
            pc(gpu_ray),
            pc(lit),
            pc(textured_detail),
            pc(flat_detail)
        );
        assert!(!covering || textured_detail > flat_detail + all / 50, "{name}: textures add no detail ({textured_detail} vs {flat_detail} pixels)");
        assert!(pc(lit) > 40.0, "{name}: only {:.1}% of pixels lit: the comparison would be vacuous", pc(lit));
        assert!(pc(ray_raster) >= 99.5, "{name}: raster/raycast {:.3}%", pc(ray_raster));
        if gpu.is_some() {
            assert!(pc(gpu_raster) >= 99.5, "{name}: wgpu/raster {:.3}%", pc(gpu_raster));
            assert!(pc(gpu_ray) >= 99.5, "{name}: wgpu/raycast {:.3}%", pc(gpu_ray));
        }
    }
}
