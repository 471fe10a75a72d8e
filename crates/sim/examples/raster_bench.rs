//! Frames per second of the rasterised depth camera against the ray caster, on scene files.
//!
//! `cargo run --release -p xhab-sim --example raster_bench -- [SCENE.glb ...] [--seconds S]
//! [--frames N]` (default: the two house scenes of the shared data, `$XHAB_DATA` or `../shared`). Poses are 100 seeded navigable points
//! with random headings; prints agreement with the ray caster (|diff| < 1 cm) and frames/s,
//! single view (all threads on one image) and batched (16 views, one per task). `--frames N`
//! instead renders exactly N single views per scene and nothing else (no agreement check, no
//! ray casting): a fixed workload for instruction counts (`valgrind --tool=callgrind`).

/// The shared data's lookup, as the tests do it.
#[path = "../../../tests/support/data.rs"]
mod data;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::time::Instant;
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::{load, LoadOptions};
use xhab_sim::sensors::{render_depth, CameraParams, RasterScene, RayScene};
use xhab_sim::world::World;
use xhab_types::Pose2;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut seconds = 3.0;
    if let Some(i) = args.iter().position(|a| a == "--seconds") {
        seconds = args[i + 1].parse().expect("--seconds S");
        args.drain(i..i + 2);
    }
    let mut frames = None;
    if let Some(i) = args.iter().position(|a| a == "--frames") {
        frames = Some(args[i + 1].parse::<usize>().expect("--frames N"));
        args.drain(i..i + 2);
    }
    if args.is_empty() {
        let Some(data) = data::data_dir("raster_bench") else {
            eprintln!("raster_bench: no shared data: name the scene files");
            std::process::exit(2)
        };
        args = ["turtlebot3_house.glb", "aws_small_house.glb"].iter().map(|s| data.join("scenes").join(s).display().to_string()).collect();
    }
    println!("rayon threads: {}", rayon::current_num_threads());
    for path in &args {
        let scene = load(Path::new(path), &LoadOptions::default()).expect("scene");
        let t = Instant::now();
        let rs = RasterScene::new(&scene).expect("triangles");
        let build_rs = t.elapsed().as_secs_f64();
        let ray = RayScene::new(&scene).expect("triangles");
        let world = World::new(scene, AgentParams::default());
        let grid = world.grid(world.default_floor().expect("floor")).expect("grid");
        let cells = grid.cells_on_islands(1.5);
        let cells = if cells.is_empty() { grid.cells_on_islands(0.0) } else { cells };
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let views: Vec<(Pose2, f64)> = (0..100).map(|_| (grid.sample_pose(&cells, &mut rng).expect("navigable point"), grid.floor_z)).collect();
        let cam = CameraParams::default();
        if let Some(n) = frames {
            let t = Instant::now();
            let sink: f32 = (0..n).map(|i| rs.render_depth(views[i % views.len()].0, views[i % views.len()].1, &cam).data[1000]).sum();
            println!("{path}: {n} frames in {:.3} s (checksum {sink})", t.elapsed().as_secs_f64());
            continue;
        }
        let (mut ok, mut all) = (0usize, 0usize);
        for &(pose, fz) in &views {
            let a = rs.render_depth(pose, fz, &cam);
            let b = render_depth(&ray, pose, fz, &cam);
            ok += a.data.iter().zip(&b.data).filter(|(x, y)| (**x - **y).abs() < 0.01).count();
            all += a.data.len();
        }
        println!("{path}: {} triangles, raster build {:.1} ms, agreement {:.4}% of {all} px", rs.triangle_count(), build_rs * 1e3, 100.0 * ok as f64 / all as f64);
        let time = |f: &mut dyn FnMut(usize) -> usize| {
            let t = Instant::now();
            let (mut frames, mut i) = (0, 0);
            while t.elapsed().as_secs_f64() < seconds {
                frames += f(i);
                i += 1;
            }
            frames as f64 / t.elapsed().as_secs_f64()
        };
        let mut sink = 0.0f32;
        let single = time(&mut |i| {
            let (p, fz) = views[i % views.len()];
            sink += rs.render_depth(p, fz, &cam).data[1000];
            1
        });
        let batch = time(&mut |i| {
            let k = (i * 16) % views.len();
            let chunk: Vec<_> = (0..16).map(|j| views[(k + j) % views.len()]).collect();
            sink += rs.render_depth_batch(&chunk, &cam).iter().map(|d| d.data[1000]).sum::<f32>();
            16
        });
        let raycast = time(&mut |i| {
            let (p, fz) = views[i % views.len()];
            sink += render_depth(&ray, p, fz, &cam).data[1000];
            1
        });
        println!("{path}: 256x256 depth frames/s: raster single {single:.0}, raster batch-16 {batch:.0}, raycast {raycast:.0} (checksum {sink})");
    }
}
