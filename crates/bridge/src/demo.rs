//! The whole pipeline on the built-in procedural house, no files needed (`xhab demo`): the
//! house, its map, Habitat-style episodes, the oracle on every episode, the report and a
//! picture of every trajectory, written into one folder.

use crate::agents::AgentKind;
use crate::benchmark::{bench_loaded, BenchError, BenchProgress};
use crate::map_picture::{MapPicture, PictureError};
use crate::report::BenchReport;
use crate::runner::{Outcome, RunConfig};
use crate::setup::{self, SceneOptions, SetupError, WriteMapError};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use xhab_sim::env::TaskConfig;
use xhab_sim::episode::{write_dataset, DatasetError};
use xhab_types::Point2;

/// What the demo does, as `xhab demo`'s flags give it.
#[derive(Debug, Clone)]
pub struct DemoOptions {
    /// Seed of the house and of the episodes.
    pub seed: u64,
    /// Number of episodes.
    pub episodes: usize,
    /// Folder for the map, episodes, results and pictures (created).
    pub out: PathBuf,
    /// Worker threads; `None`: all cores.
    pub threads: Option<usize>,
}

/// What the demo made and where it wrote it.
#[derive(Debug)]
pub struct DemoRun {
    /// The SCENE argument of the house, `procedural:SEED`.
    pub scene: String,
    /// Triangles of the house.
    pub triangles: usize,
    /// Navigable area of its floor (m²).
    pub navigable_area_m2: f64,
    /// The map_server map (`OUT/house.yaml`, with `house.pgm` and `house.png`).
    pub map_yaml: PathBuf,
    /// The episodes file (`OUT/episodes.json.gz`).
    pub episodes_file: PathBuf,
    /// Episodes generated.
    pub episodes: usize,
    /// The report as JSON (`OUT/results.json`).
    pub results: PathBuf,
    /// The picture of every trajectory (`OUT/trajectories.png`).
    pub trajectories: PathBuf,
    /// The oracle's report.
    pub report: BenchReport,
}

/// Why the demo could not run. Messages name the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DemoError {
    /// The output folder could not be created.
    #[error("creating {}", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The house, its grid or its episodes could not be made.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The map could not be written.
    #[error(transparent)]
    Map(#[from] WriteMapError),
    /// The episodes could not be written.
    #[error("writing {}", path.display())]
    Episodes {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: DatasetError,
    },
    /// The benchmark failed.
    #[error(transparent)]
    Bench(#[from] BenchError),
    /// The results could not be written.
    #[error("writing {}", path.display())]
    Results {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The report could not be turned into JSON.
    #[error("writing the results as JSON")]
    Json(#[from] serde_json::Error),
    /// The picture could not be written.
    #[error(transparent)]
    Picture(#[from] PictureError),
}

/// Runs the demo `o` describes; `progress` is called once per finished episode with
/// `(episodes finished, episodes in all)`.
pub fn run_demo(o: &DemoOptions, progress: &BenchProgress<'_>) -> Result<DemoRun, DemoError> {
    std::fs::create_dir_all(&o.out).map_err(|source| DemoError::Folder { path: o.out.clone(), source })?;
    let scene = format!("procedural:{}", o.seed);
    let world = setup::load_world(&scene, &SceneOptions::default())?;
    let floor = setup::floor_index(&world, "auto")?;
    let grid = world.grid(floor).map_err(SetupError::Grid)?;
    let map = grid.occupancy_grid();
    let (map_yaml, _) = setup::write_map(&map, &o.out.join("house"))?;
    let ds = setup::generate(&world, &scene, "auto", o.episodes, o.seed, &scene)?;
    let episodes_file = o.out.join("episodes.json.gz");
    write_dataset(&ds, &episodes_file).map_err(|source| DemoError::Episodes { path: episodes_file.clone(), source })?;
    let threads = o.threads.unwrap_or_else(|| std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1));
    let cfg = RunConfig { agent: AgentKind::Oracle, task: TaskConfig::default(), threads, record_trajectories: true, sensors: None, physics: None, seed: o.seed, nav: None, episode_indices: None };
    let (triangles, navigable_area_m2) = (world.scene.triangle_count(), grid.navigable_cells() as f64 * grid.resolution().powi(2));
    let world = Arc::new(world);
    let total = ds.episodes.len();
    let finished = AtomicUsize::new(0);
    let tick = || progress(finished.fetch_add(1, Ordering::Relaxed) + 1, total);
    let (report, outcomes) = bench_loaded(&world, &ds, &cfg, &scene, &episodes_file.display().to_string(), &AtomicBool::new(false), &tick)?;
    let results = o.out.join("results.json");
    let json = serde_json::to_string_pretty(&report)?;
    std::fs::write(&results, json + "\n").map_err(|source| DemoError::Results { path: results.clone(), source })?;
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
    let trajectories = o.out.join("trajectories.png");
    pic.save(&trajectories)?;
    Ok(DemoRun { scene, triangles, navigable_area_m2, map_yaml, episodes_file, episodes: ds.episodes.len(), results, trajectories, report })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demo_writes_its_files_and_the_oracle_succeeds() {
        let out = std::env::temp_dir().join(format!("xhab-demo-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&out);
        let calls = AtomicUsize::new(0);
        let run = run_demo(&DemoOptions { seed: 2, episodes: 4, out: out.clone(), threads: Some(2) }, &|done, total| {
            assert!(done <= total && total == 4);
            calls.fetch_add(1, Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(calls.load(Ordering::Relaxed), 4);
        assert_eq!((run.scene.as_str(), run.episodes), ("procedural:2", 4));
        assert!(run.triangles > 0 && run.navigable_area_m2 > 0.0);
        for f in ["house.yaml", "house.pgm", "house.png", "episodes.json.gz", "results.json", "trajectories.png"] {
            assert!(out.join(f).is_file(), "missing {f}");
        }
        assert_eq!(run.map_yaml, out.join("house.yaml"));
        assert_eq!(run.report.aggregate.episodes, 4);
        assert!(run.report.aggregate.success > 0.7, "{:?}", run.report.aggregate);
        let written: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&run.results).unwrap()).unwrap();
        assert_eq!(written["aggregate"]["episodes"], 4);
        // The folder is a file: an error naming it.
        let file = out.join("house.yaml");
        let e = run_demo(&DemoOptions { seed: 2, episodes: 1, out: file.clone(), threads: Some(1) }, &|_, _| {}).unwrap_err();
        assert!(e.to_string().starts_with(&format!("creating {}", file.display())), "{e}");
        std::fs::remove_dir_all(&out).ok();
    }
}
