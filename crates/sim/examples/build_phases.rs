//! Time the three phases of a floor's map build on scene files: floor detection, the
//! navigation grid and the corner graph (`xhab perf`'s `map_build_s` is their sum, best of
//! three; this splits it).
//!
//! `cargo run --release -p xhab-sim --example build_phases -- [SCENE.glb ...] [--runs N]
//! [--pairs M] [--dump FILE] [--each]` (default: the two house scenes of the shared data, `$XHAB_DATA` or
//! `../shared`, 5 runs, no pairs). Prints each phase's best time over the runs (ms), with the
//! grid's size, the graph's nodes and legs, and a hash of the grid's cells, then the best
//! time of each step of the grid's build ([`NavGrid::build_laps`]); with `--pairs`,
//! also the rate of M cold pair queries between seeded random navigable points (this thread)
//! and a hash of their distances' bits (with `--dump`, the pairs and their distances, one per
//! line, `x0 y0 x1 y1 distance` in m, in `FILE.<scene name>`); with `--each`, every run's times (the first run of a
//! process is the cold one a user waits for). The hashes tell whether a change to the build changed
//! the grid or any answer.

/// The shared data's lookup, as the tests do it.
#[path = "../../../tests/support/data.rs"]
mod data;

use rand::SeedableRng;
use std::path::Path;
use std::time::Instant;
use xhab_sim::navgrid::{AgentParams, NavGrid};
use xhab_sim::scene::{load, LoadOptions};
use xhab_sim::world::World;
use xhab_types::Point2;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut flag = |name: &str, default: usize| match args.iter().position(|a| a == name) {
        Some(i) => {
            let Some(v) = args.get(i + 1).and_then(|v| v.parse().ok()) else {
                eprintln!("build_phases: {name} wants a whole number");
                std::process::exit(2);
            };
            args.drain(i..i + 2);
            v
        }
        None => default,
    };
    let runs = flag("--runs", 5);
    let pairs = flag("--pairs", 0);
    // Where to write the pair queries and their distances, to compare two builds.
    let dump = match args.iter().position(|a| a == "--dump") {
        Some(i) if i + 1 < args.len() => Some(args.drain(i..i + 2).nth(1).unwrap_or_default()),
        Some(_) => {
            eprintln!("build_phases: --dump wants a file");
            std::process::exit(2);
        }
        None => None,
    };
    let each = match args.iter().position(|a| a == "--each") {
        Some(i) => {
            args.remove(i);
            true
        }
        None => false,
    };
    if args.is_empty() {
        let Some(data) = data::data_dir("build_phases") else {
            eprintln!("build_phases: no shared data: name the scene files");
            std::process::exit(2)
        };
        args = ["turtlebot3_house.glb", "aws_small_house.glb"].iter().map(|s| data.join("scenes").join(s).display().to_string()).collect();
    }
    println!("rayon threads: {}", rayon::current_num_threads());
    for path in &args {
        let scene = match load(Path::new(path), &LoadOptions::default()) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("build_phases: {e}");
                std::process::exit(1);
            }
        };
        let mut best = [f64::INFINITY; 3];
        // The best time of each step of the grid's build, in the order they ran.
        let mut steps: Vec<(&'static str, f64)> = Vec::new();
        let mut sizes = String::new();
        let mut pair_line = String::new();
        for run in 0..runs.max(1) {
            let copy = scene.clone();
            let t = Instant::now();
            let world = World::new(copy, AgentParams::default());
            let Some(floor) = world.default_floor() else {
                eprintln!("build_phases: {path}: no walkable floor");
                std::process::exit(1);
            };
            let t1 = t.elapsed().as_secs_f64();
            let grid = match world.grid(floor) {
                Ok(g) => g,
                Err(e) => {
                    eprintln!("build_phases: {path}: {e}");
                    std::process::exit(1);
                }
            };
            let t2 = t.elapsed().as_secs_f64();
            let graph = grid.corner_graph();
            let t3 = t.elapsed().as_secs_f64();
            if each {
                println!("  run {}: floors {:.1} ms, grid {:.1} ms, corner graph {:.1} ms, total {:.1} ms", run + 1, t1 * 1e3, (t2 - t1) * 1e3, (t3 - t2) * 1e3, t3 * 1e3);
            }
            for (b, v) in best.iter_mut().zip([t1, t2 - t1, t3 - t2]) {
                *b = b.min(v);
            }
            for &(name, s) in grid.build_laps().laps() {
                match steps.iter_mut().find(|l| l.0 == name) {
                    Some(l) => l.1 = l.1.min(s),
                    None => steps.push((name, s)),
                }
            }
            sizes = format!("grid {:?} cells, graph {} nodes / {} legs, grid hash {:016x}", grid.size(), graph.len(), graph.leg_count(), grid_hash(&grid));
            if run + 1 == runs.max(1) && pairs > 0 {
                // On the last run's grid and graph.
                pair_line = pair_queries(&grid, pairs, dump.as_deref().map(|d| format!("{d}.{}", Path::new(path).file_stem().unwrap_or_default().to_string_lossy())));
            }
        }
        println!("{path}: floors {:.1} ms, grid {:.1} ms, corner graph {:.1} ms ({sizes})", best[0] * 1e3, best[1] * 1e3, best[2] * 1e3);
        let steps: Vec<String> = steps.iter().map(|(name, s)| format!("{name} {:.1}", s * 1e3)).collect();
        println!("  grid steps (best of each, ms): {}", steps.join(", "));
        if !pair_line.is_empty() {
            println!("{pair_line}");
        }
    }
}

/// A hash of every cell's clearance bits and island (as `clearance_at` and `island_at` read
/// them at the cell's centre), to tell whether a change to the build changed the grid.
fn grid_hash(grid: &NavGrid) -> u64 {
    let ((w, h), res, o) = (grid.size(), grid.resolution(), grid.origin());
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    for r in 0..h {
        for c in 0..w {
            let p = Point2::new(o.x + (c as f64 + 0.5) * res, o.y + (r as f64 + 0.5) * res);
            for v in [grid.clearance_at(p).to_bits(), grid.island_at(p).map_or(u64::MAX, |i| i as u64)] {
                hash = (hash ^ v).wrapping_mul(0x0100_0000_01b3);
            }
        }
    }
    hash
}

/// `pairs` cold pair queries between seeded random navigable points of `grid`, on this thread:
/// their rate and a hash of their distances' bits.
fn pair_queries(grid: &NavGrid, pairs: usize, dump: Option<String>) -> String {
    let graph = grid.corner_graph();
    let cells = grid.cells_on_islands(0.0);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let ends: Vec<(Point2, Point2)> = (0..pairs)
        .filter_map(|_| {
            let a = grid.sample_navigable_point(&cells, &mut rng)?;
            let b = grid.sample_navigable_point(&cells, &mut rng)?;
            Some((Point2::new(a.x, a.y), Point2::new(b.x, b.y)))
        })
        .collect();
    let t = Instant::now();
    let dist: Vec<f64> = ends.iter().map(|&(a, b)| graph.distance(grid, a, b)).collect();
    let rate = ends.len() as f64 / t.elapsed().as_secs_f64();
    let hash = dist.iter().fold(0u64, |h, d| h.wrapping_mul(1_000_003).wrapping_add(d.to_bits()));
    if let Some(file) = dump {
        let text: String = ends.iter().zip(&dist).map(|(&(a, b), d)| format!("{} {} {} {} {d}\n", a.x, a.y, b.x, b.y)).collect();
        if let Err(e) = std::fs::write(&file, text) {
            eprintln!("build_phases: {file}: {e}");
            std::process::exit(1);
        }
    }
    format!("  {} pair queries: {rate:.0} per s, distance hash {hash:016x}", ends.len())
}
