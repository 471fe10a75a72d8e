//! Frames per second of the wgpu depth and colour camera (Vulkan; llvmpipe without a GPU)
//! against the CPU rasteriser, on scene files.
//!
//! `cargo run --release -p xhab-sim --example gpu_bench -- [SCENE.glb ...] [--seconds S]`
//! (default: the two house scenes of the shared data, `$XHAB_DATA` or `../shared`). Poses are
//! 100 seeded navigable points with random headings; prints the adapter, agreement with the
//! ray caster (|diff| < 1 cm) and 256x256 frames/s (readback included): depth single view and
//! batches of 16 views in one submission, RGB single view, depth+RGB single view from one pass
//! and from two (a depth render and an RGB render), and depth+RGB batches of 16.

/// The shared data's lookup, as the tests do it.
#[path = "../../../tests/support/data.rs"]
mod data;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::time::Instant;
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::{load, LoadOptions};
use xhab_sim::sensors::{render_depth, CameraParams, GpuRenderer, RasterScene, RayScene};
use xhab_sim::world::World;
use xhab_types::Pose2;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut seconds = 3.0;
    if let Some(i) = args.iter().position(|a| a == "--seconds") {
        seconds = args[i + 1].parse().expect("--seconds S");
        args.drain(i..i + 2);
    }
    if args.is_empty() {
        let Some(data) = data::data_dir("gpu_bench") else {
            eprintln!("gpu_bench: no shared data: name the scene files");
            std::process::exit(2)
        };
        args = ["turtlebot3_house.glb", "aws_small_house.glb"].iter().map(|s| data.join("scenes").join(s).display().to_string()).collect();
    }
    println!("rayon threads: {}", rayon::current_num_threads());
    for path in &args {
        let scene = load(Path::new(path), &LoadOptions::default()).expect("scene");
        let t = Instant::now();
        let gpu = match GpuRenderer::new(&scene) {
            Ok(g) => g,
            Err(e) => {
                eprintln!("{path}: no GPU renderer: {e}");
                std::process::exit(1);
            }
        };
        let build = t.elapsed().as_secs_f64();
        let rs = RasterScene::new(&scene).expect("triangles");
        let ray = RayScene::new(&scene).expect("triangles");
        let world = World::new(scene, AgentParams::default());
        let grid = world.grid(world.default_floor().expect("floor")).expect("grid");
        let cells = grid.cells_on_islands(1.5);
        let cells = if cells.is_empty() { grid.cells_on_islands(0.0) } else { cells };
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let views: Vec<(Pose2, f64)> = (0..100).map(|_| (grid.sample_pose(&cells, &mut rng).expect("navigable point"), grid.floor_z)).collect();
        let cam = CameraParams::default();
        let (mut ok, mut all) = (0usize, 0usize);
        for &(pose, fz) in &views {
            let a = gpu.render_depth(pose, fz, &cam).expect("render");
            let b = render_depth(&ray, pose, fz, &cam);
            ok += a.data.iter().zip(&b.data).filter(|(x, y)| (**x - **y).abs() < 0.01).count();
            all += a.data.len();
        }
        println!(
            "{path}: {} triangles, adapter {}, setup {:.0} ms, agreement {:.4}% of {all} px",
            gpu.triangle_count(),
            gpu.adapter_info(),
            build * 1e3,
            100.0 * ok as f64 / all as f64
        );
        let time = |f: &mut dyn FnMut(usize) -> usize| {
            let t = Instant::now();
            let (mut frames, mut i) = (0, 0);
            while t.elapsed().as_secs_f64() < seconds {
                frames += f(i);
                i += 1;
            }
            frames as f64 / t.elapsed().as_secs_f64()
        };
        let batch16 = |i: usize| -> Vec<(Pose2, f64)> { (0..16).map(|j| views[(i * 16 + j) % views.len()]).collect() };
        let mut sink = 0.0f32;
        let single = time(&mut |i| {
            let (p, fz) = views[i % views.len()];
            sink += gpu.render_depth(p, fz, &cam).expect("render").data[1000];
            1
        });
        let batch = time(&mut |i| {
            sink += gpu.render_depth_batch(&batch16(i), &cam).expect("render").iter().map(|d| d.data[1000]).sum::<f32>();
            16
        });
        let rgb = time(&mut |i| {
            let (p, fz) = views[i % views.len()];
            sink += gpu.render_rgb(p, fz, &cam).expect("render")[3000] as f32;
            1
        });
        let depth_rgb = time(&mut |i| {
            let (p, fz) = views[i % views.len()];
            let (d, c) = gpu.render_depth_rgb(p, fz, &cam).expect("render");
            sink += d.data[1000] + c[3000] as f32;
            1
        });
        let two_passes = time(&mut |i| {
            let (p, fz) = views[i % views.len()];
            sink += gpu.render_depth(p, fz, &cam).expect("render").data[1000] + gpu.render_rgb(p, fz, &cam).expect("render")[3000] as f32;
            1
        });
        let depth_rgb_batch = time(&mut |i| {
            sink += gpu.render_depth_rgb_batch(&batch16(i), &cam).expect("render").iter().map(|(d, c)| d.data[1000] + c[3000] as f32).sum::<f32>();
            16
        });
        let raster_batch = time(&mut |i| {
            sink += rs.render_depth_batch(&batch16(i), &cam).iter().map(|d| d.data[1000]).sum::<f32>();
            16
        });
        println!(
            "{path}: 256x256 frames/s: gpu depth single {single:.0}, gpu depth batch-16 {batch:.0}, gpu rgb single {rgb:.0}, gpu depth+rgb single {depth_rgb:.0} (two passes {two_passes:.0}), gpu depth+rgb batch-16 {depth_rgb_batch:.0}, cpu raster depth batch-16 {raster_batch:.0} (checksum {sink})"
        );
    }
}
