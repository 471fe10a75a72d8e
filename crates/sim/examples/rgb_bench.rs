//! Depth+RGB frames per second of the CPU rasteriser, with a hash of every colour byte so that
//! a change meant to keep the images can be checked to keep them.
//!
//! `cargo run --release -p xhab-sim --example rgb_bench -- [SCENE.glb ...] [--seconds S]
//! [--frames N]` (default: aws_small_house from the shared data). Poses are 100 seeded
//! navigable points with random headings. Prints the FNV-1a hash of the first 100 views' RGB
//! bytes and depth bits, then frames/s over `--seconds` (3 by default); `--frames N` renders
//! exactly N views instead (a fixed workload for `perf` or callgrind). Each rate is also
//! given as the best over batches of 20 frames (views 0-19, 20-39, ...), steadier on a busy host. `--dump FILE` writes
//! those views' RGB bytes; `--compare FILE` says how far this build's are from a dump's.

/// The shared data's lookup, as the tests do it.
#[path = "../../../tests/support/data.rs"]
mod data;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::time::Instant;
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::{load, LoadOptions};
use xhab_sim::sensors::{CameraParams, RasterScene};
use xhab_sim::world::World;
use xhab_types::Pose2;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut take = |flag: &str| -> Option<String> {
        let i = args.iter().position(|a| a == flag)?;
        let v = args.get(i + 1).cloned().unwrap_or_else(|| fail(&format!("{flag} needs a value")));
        args.drain(i..i + 2);
        Some(v)
    };
    let seconds: f64 = take("--seconds").map(|s| s.parse().unwrap_or_else(|_| fail("--seconds S: a number"))).unwrap_or(3.0);
    let frames: Option<usize> = take("--frames").map(|s| s.parse().unwrap_or_else(|_| fail("--frames N: a whole number")));
    let (dump, compare) = (take("--dump"), take("--compare"));
    if args.is_empty() {
        let Some(data) = data::data_dir("rgb_bench") else {
            eprintln!("rgb_bench: no shared data: name the scene files");
            std::process::exit(2)
        };
        args = ["aws_small_house.glb"].iter().map(|s| data.join("scenes").join(s).display().to_string()).collect();
    }
    println!("rayon threads: {}", rayon::current_num_threads());
    for path in &args {
        let scene = load(Path::new(path), &LoadOptions::default()).unwrap_or_else(|e| fail(&format!("{path}: {e}")));
        let texels: u64 = scene.textures.iter().map(|t| t.width as u64 * t.height as u64).sum();
        println!("{path}: {} textures, {:.1} Mtexels at level 0", scene.textures.len(), texels as f64 / 1e6);
        let rs = RasterScene::new(&scene).unwrap_or_else(|| fail(&format!("{path}: no triangles")));
        let world = World::new(scene, AgentParams::default());
        let Some(grid) = world.default_floor().and_then(|f| world.grid(f).ok()) else { fail(&format!("{path}: no walkable floor")) };
        let cells = grid.cells_on_islands(1.5);
        let cells = if cells.is_empty() { grid.cells_on_islands(0.0) } else { cells };
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let views: Vec<(Pose2, f64)> = (0..100).filter_map(|_| Some((grid.sample_pose(&cells, &mut rng)?, grid.floor_z))).collect();
        if views.is_empty() {
            fail(&format!("{path}: no navigable point"));
        }
        let cam = CameraParams::default();
        let mut hash = 0xcbf29ce484222325u64;
        let mut all_rgb = Vec::new();
        for &(p, fz) in &views {
            let (d, c) = rs.render_depth_rgb(p, fz, &cam);
            all_rgb.extend_from_slice(&c);
            for b in c.iter().copied().chain(d.data.iter().flat_map(|x| x.to_bits().to_le_bytes())) {
                hash = (hash ^ b as u64).wrapping_mul(0x100000001b3);
            }
        }
        println!("{path}: hash of {} views' RGB and depth {hash:016x}", views.len());
        if let Some(f) = &dump {
            std::fs::write(f, &all_rgb).unwrap_or_else(|e| fail(&format!("{f}: {e}")));
        }
        if let Some(f) = &compare {
            let old = std::fs::read(f).unwrap_or_else(|e| fail(&format!("{f}: {e}")));
            if old.len() != all_rgb.len() {
                fail(&format!("{f}: {} bytes, this run has {}", old.len(), all_rgb.len()));
            }
            let px = |k: usize| old[k * 3..k * 3 + 3].iter().zip(&all_rgb[k * 3..k * 3 + 3]).map(|(a, b)| a.abs_diff(*b)).max().unwrap_or(0);
            let n = old.len() / 3;
            let (same, within1) = ((0..n).filter(|&k| px(k) == 0).count(), (0..n).filter(|&k| px(k) <= 1).count());
            let worst = (0..n).map(px).max().unwrap_or(0);
            println!("{path}: against {f}: {:.4}% of pixels identical, {:.4}% within a byte, worst {worst}", 100.0 * same as f64 / n as f64, 100.0 * within1 as f64 / n as f64);
        }
        // Frames/s of one kind of render over the views, for `--seconds` or `--frames`; and the
        // best rate over batches of 20 frames, which a busy host disturbs less than the mean.
        let time = |what: &str, render: &dyn Fn(Pose2, f64)| {
            let t = Instant::now();
            let (mut n, mut best) = (0usize, f64::INFINITY);
            let mut batch = Instant::now();
            while frames.map_or(t.elapsed().as_secs_f64() < seconds, |f| n < f) {
                let (p, fz) = views[n % views.len()];
                render(p, fz);
                n += 1;
                if n % 20 == 0 {
                    best = best.min(batch.elapsed().as_secs_f64() / 20.0);
                    batch = Instant::now();
                }
            }
            println!("{path}: {}x{} {what} frames/s {:.1} ({n} frames), best batch of 20 {:.1}", cam.width, cam.height, n as f64 / t.elapsed().as_secs_f64(), 1.0 / best);
        };
        time("depth+RGB", &|p, fz| drop(std::hint::black_box(rs.render_depth_rgb(p, fz, &cam))));
        time("depth", &|p, fz| drop(std::hint::black_box(rs.render_depth(p, fz, &cam))));
    }
}

fn fail(msg: &str) -> ! {
    eprintln!("rgb_bench: {msg}");
    std::process::exit(2)
}
