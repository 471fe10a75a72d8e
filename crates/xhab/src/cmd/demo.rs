//! `xhab demo`: the whole pipeline on the built-in procedural house, no files needed.

use crate::cli::DemoArgs;
use xhab_bridge::map_picture::MapPicture;
use anyhow::{Context, Result};
use std::process::ExitCode;
use std::time::Instant;
use xhab_bridge::agents::AgentKind;
use xhab_bridge::runner::{Outcome, RunConfig};
use xhab_sim::env::TaskConfig;
use xhab_sim::episode::{generate_episodes, write_dataset, GeneratorParams};
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::house::{generate_house, HouseParams};
use xhab_sim::world::World;
use xhab_types::Point2;

pub fn run(a: &DemoArgs, quiet: bool) -> Result<ExitCode> {
    let t0 = Instant::now();
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let scene = generate_house(a.seed, &HouseParams::default());
    let tris = scene.triangle_count();
    let world = World::new(scene, AgentParams::default());
    let floor = world.default_floor().context("the procedural house has no floor")?;
    let grid = world.grid(floor)?;
    let map = grid.occupancy_grid();
    let (yaml, _) = super::map::write_map(&map, &a.out.join("house"))?;
    eprintln!(
        "xhab: procedural house (seed {}): {} triangles, {:.1} m^2 navigable; map {}",
        a.seed,
        tris,
        grid.navigable_cells() as f64 * grid.resolution().powi(2),
        yaml.display()
    );
    let scene_id = format!("procedural:{}", a.seed);
    let ds = generate_episodes(&grid, &scene_id, a.episodes, a.seed, &GeneratorParams::default())?;
    let eps_path = a.out.join("episodes.json.gz");
    write_dataset(&ds, &eps_path).with_context(|| format!("writing {}", eps_path.display()))?;
    eprintln!("xhab: {} episodes in {}", ds.episodes.len(), eps_path.display());
    let threads = a.threads.unwrap_or_else(|| std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1));
    let cfg = RunConfig { agent: AgentKind::Oracle, task: TaskConfig::default(), threads, record_trajectories: true, sensors: None, physics: None, seed: a.seed, nav: None, episode_indices: None };
    let world = std::sync::Arc::new(world);
    let (report, outcomes) = super::bench::bench_loaded(&world, &ds, &cfg, &scene_id, &eps_path.display().to_string(), quiet)?;
    let results = a.out.join("results.json");
    std::fs::write(&results, serde_json::to_string_pretty(&report)? + "\n").with_context(|| format!("writing {}", results.display()))?;
    // One picture with every trajectory.
    let mut pic = MapPicture::new(&map);
    for (ep, o) in ds.episodes.iter().zip(&outcomes) {
        if let Outcome::Ran(r) = o {
            if let Some(t) = &r.trajectory {
                let pts: Vec<Point2> = t.iter().map(|p| p.position()).collect();
                pic.polyline(&pts, [230, 120, 0]);
            }
            pic.dot(ep.start_position.xy(), 3, [0, 170, 0]);
            pic.dot(ep.goals[0].position.xy(), 3, [220, 0, 0]);
        }
    }
    let overview = a.out.join("trajectories.png");
    pic.save(&overview)?;
    eprintln!("xhab: results {}, trajectories {}", results.display(), overview.display());
    super::bench::print_table(&report.aggregate, report.invalid.count, "oracle");
    eprintln!("xhab: demo done in {:.2} s", t0.elapsed().as_secs_f64());
    Ok(ExitCode::SUCCESS)
}
