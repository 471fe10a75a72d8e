//! Top-down trajectory maps of chosen episodes: the spec's named episodes and each run's
//! `worst` lowest-SPL ones, drawn over their floor's map as `xhab bench --trajectories` does.

use super::ReportError;
use crate::part::Trajectory;
use crate::results::{ResultRow, Results, RunResult};
use crate::spec::TrajectorySpec;
use std::collections::HashMap;
use std::path::Path;
use xhab_bridge::map_picture::MapPicture;
use xhab_types::{OccupancyGrid, Point2};

/// The shortest path's colour.
pub const SHORTEST: [u8; 3] = [60, 160, 255];
/// The robot's path's colour.
pub const ROBOT: [u8; 3] = [230, 120, 0];
/// The start's colour.
pub const START: [u8; 3] = [0, 170, 0];
/// The goals' colour.
pub const GOAL: [u8; 3] = [220, 0, 0];

/// Why an episode is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Why {
    /// The spec names it.
    Chosen,
    /// The run's `k`th lowest SPL (1-based).
    Worst(usize),
}

/// One drawn episode.
#[derive(Debug, Clone)]
pub struct Picture {
    /// The PNG, relative to the report folder.
    pub file: String,
    /// The episode's id.
    pub episode_id: String,
    /// Its index in the set.
    pub index: usize,
    /// Why it is drawn.
    pub why: Why,
    /// Its results row, when it has one.
    pub row: Option<ResultRow>,
}

/// A run's pictures.
#[derive(Debug, Clone)]
pub struct RunPictures {
    /// The run.
    pub run: RunResult,
    /// Its pictures, chosen first, then worst first.
    pub pictures: Vec<Picture>,
    /// Why the run has none, when it has none to show.
    pub note: Option<String>,
}

/// The episodes of a run to draw: trajectories named in `spec` (in the spec's order), then
/// the `spec.worst` lowest-SPL rows (ties: lower episode index first) not already named.
/// Returns indices into `trajs` with the reason.
pub fn pick(rows: &[&ResultRow], trajs: &[Trajectory], spec: &TrajectorySpec) -> Vec<(usize, Why)> {
    let mut out: Vec<(usize, Why)> = Vec::new();
    for id in &spec.episodes {
        if let Some(t) = trajs.iter().position(|t| &t.episode_id == id) {
            if !out.iter().any(|o| o.0 == t) {
                out.push((t, Why::Chosen));
            }
        }
    }
    let mut ranked: Vec<&&ResultRow> = rows.iter().collect();
    ranked.sort_by(|a, b| a.metrics.spl.total_cmp(&b.metrics.spl).then(a.episode_index.cmp(&b.episode_index)).then(a.metrics.episode_id.cmp(&b.metrics.episode_id)));
    let mut k = 0;
    for r in ranked {
        if k == spec.worst {
            break;
        }
        let Some(t) = trajs.iter().position(|t| t.index == r.episode_index) else { continue };
        if out.iter().any(|o| o.0 == t) {
            continue;
        }
        k += 1;
        out.push((t, Why::Worst(k)));
    }
    out
}

/// A file-name-safe form of `s`.
fn file_safe(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.' { c } else { '_' }).collect()
}

/// Reads `DIR/runs/RUN/trajectories.json`; `None` when the run has none.
fn read_trajectories(dir: &Path, run: &str) -> Result<Option<Vec<Trajectory>>, ReportError> {
    let path = dir.join("runs").join(run).join("trajectories.json");
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => return Err(ReportError::Io { path, source }),
    };
    serde_json::from_str(&text).map(Some).map_err(|e| ReportError::Format { path, message: e.to_string() })
}

/// Draws the picked episodes of every run of `r` (study folder `dir`) into
/// `out/trajectories/RUN-INDEX.png`.
pub fn draw(dir: &Path, out: &Path, r: &Results, spec: &TrajectorySpec) -> Result<Vec<RunPictures>, ReportError> {
    let folder = out.join("trajectories");
    std::fs::create_dir_all(&folder).map_err(|source| ReportError::Io { path: folder.clone(), source })?;
    let mut maps: HashMap<String, OccupancyGrid> = HashMap::new();
    let mut all = Vec::new();
    for run in &r.runs {
        let mut pictures = Vec::new();
        let Some(trajs) = read_trajectories(dir, &run.id)? else {
            all.push(RunPictures { run: run.clone(), pictures, note: Some("no trajectories recorded (runs/RUN/trajectories.json is missing)".into()) });
            continue;
        };
        let rows: Vec<&ResultRow> = r.episodes.iter().filter(|e| e.run == run.id).collect();
        for (t, why) in pick(&rows, &trajs, spec) {
            let t = &trajs[t];
            if !maps.contains_key(&t.map) {
                let (grid, _) = xhab_nav::map_server::load_map(&dir.join(&t.map))?;
                maps.insert(t.map.clone(), grid);
            }
            let mut pic = MapPicture::new(&maps[&t.map]);
            let pts = |v: &[[f64; 2]]| v.iter().map(|p| Point2::new(p[0], p[1])).collect::<Vec<_>>();
            pic.polyline(&pts(&t.shortest_path), SHORTEST);
            pic.polyline(&pts(&t.path), ROBOT);
            pic.dot(Point2::new(t.start[0], t.start[1]), 4, START);
            for g in &t.goals {
                pic.dot(Point2::new(g[0], g[1]), 4, GOAL);
            }
            let file = format!("trajectories/{}-{}.png", file_safe(&run.id), t.index);
            pic.save(&out.join(&file))?;
            let row = rows.iter().find(|x| x.episode_index == t.index).map(|x| (*x).clone());
            pictures.push(Picture { file, episode_id: t.episode_id.clone(), index: t.index, why, row });
        }
        let note = pictures.is_empty().then(|| "no episode to draw".to_string());
        all.push(RunPictures { run: run.clone(), pictures, note });
    }
    Ok(all)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(index: usize, spl: f64) -> ResultRow {
        let metrics = serde_json::from_value(serde_json::json!({
            "episode_id": format!("e{index}"), "success": 0.0, "spl": spl, "soft_spl": spl, "distance_to_goal": 1.0,
            "steps": 10, "collisions": 0, "wall_s": 0.1, "steps_per_s": 100.0, "path_length": 2.0,
            "start_distance": 1.0, "called_stop": false, "aborted": false, "off_navigable": false
        }))
        .unwrap();
        ResultRow { run: "r".into(), scene: "s".into(), agent: "a".into(), configuration: "c".into(), physics: false, ros: false, ros2: false, seed: 0, episode_index: index, metrics }
    }

    fn traj(index: usize) -> Trajectory {
        Trajectory { episode_id: format!("e{index}"), index, map: "maps/m.yaml".into(), path: vec![], shortest_path: vec![], start: [0.0; 2], goals: vec![] }
    }

    #[test]
    fn picks_named_then_lowest_spl_with_ties_by_index() {
        let rows = [row(0, 0.5), row(1, 0.0), row(2, 0.9), row(3, 0.0), row(4, 0.2)];
        let rows: Vec<&ResultRow> = rows.iter().collect();
        let trajs: Vec<Trajectory> = (0..5).map(traj).collect();
        let spec = TrajectorySpec { worst: 3, episodes: vec!["e3".into(), "missing".into()] };
        // e3 is named; worst: e1 (0.0, index 1), then e4 (0.2), then e0 (0.5).
        assert_eq!(pick(&rows, &trajs, &spec), vec![(3, Why::Chosen), (1, Why::Worst(1)), (4, Why::Worst(2)), (0, Why::Worst(3))]);
        assert!(pick(&rows, &trajs, &TrajectorySpec { worst: 0, episodes: vec![] }).is_empty());
        assert_eq!(file_safe("a b/c<d>.e"), "a_b_c_d_.e");
    }
}
