//! Time the three phases of a floor's map build on scene files: floor detection, the
//! navigation grid and the corner graph (`xhab perf`'s `map_build_s` is their sum, best of
//! three; this splits it).
//!
//! `cargo run --release -p xhab-sim --example build_phases -- [SCENE.glb ...] [--runs N]`
//! (default: the two shared house scenes, 5 runs). Prints each phase's best time over the
//! runs (ms), with the grid's size and the graph's nodes and legs.

use std::path::Path;
use std::time::Instant;
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::{load, LoadOptions};
use xhab_sim::world::World;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut runs = 5;
    if let Some(i) = args.iter().position(|a| a == "--runs") {
        runs = args[i + 1].parse().expect("--runs N");
        args.drain(i..i + 2);
    }
    if args.is_empty() {
        args = ["turtlebot3_house.glb", "aws_small_house.glb"].iter().map(|s| format!("/work/shared/scenes/{s}")).collect();
    }
    println!("rayon threads: {}", rayon::current_num_threads());
    for path in &args {
        let scene = load(Path::new(path), &LoadOptions::default()).expect("scene");
        let mut best = [f64::INFINITY; 3];
        let mut sizes = String::new();
        for _ in 0..runs {
            let t = Instant::now();
            let world = World::new(scene.clone(), AgentParams::default());
            let floor = world.default_floor().expect("a floor");
            let t1 = t.elapsed().as_secs_f64();
            let grid = world.grid(floor).expect("a grid");
            let t2 = t.elapsed().as_secs_f64();
            let graph = grid.corner_graph();
            let t3 = t.elapsed().as_secs_f64();
            for (b, v) in best.iter_mut().zip([t1, t2 - t1, t3 - t2]) {
                *b = b.min(v);
            }
            sizes = format!("grid {:?} cells, graph {} nodes / {} legs", grid.size(), graph.len(), graph.leg_count());
        }
        println!("{path}: floors {:.1} ms, grid {:.1} ms, corner graph {:.1} ms ({sizes})", best[0] * 1e3, best[1] * 1e3, best[2] * 1e3);
    }
}
