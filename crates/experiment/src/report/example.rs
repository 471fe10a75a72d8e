//! A small synthetic study folder, made without simulating anything: two scenes with their
//! maps, two agents, the four configurations, made-up but self-consistent episodes, written as
//! parts and merged as a real study is. What the report's tests (and anyone trying the report
//! out) draw.

use crate::part::{Part, Trajectory};
use crate::plan::{Plan, RunPlan, SkippedRun};
use crate::results::{merge, ExperimentRecord, Results, ResultsError};
use crate::spec::ExperimentSpec;
use std::path::{Path, PathBuf};
use xhab_bridge::report::{aggregate, BenchReport, EpisodeReport, InvalidReport, SCHEMA_VERSION};
use xhab_bridge::runner::InvalidRun;
use xhab_types::{OccupancyGrid, Pose2, GRID_FREE, GRID_OCCUPIED};

/// The example study's spec: names with HTML's special characters, so escaping shows.
pub const SPEC: &str = "name: Synthetic study <oracle & nav>
description: Made-up episodes on two rooms split by a wall with a door, to show the report.
scenes:
  - {name: rooms-top-door, scene: 'procedural:1', generate: {count: 12}}
  - {name: rooms-bottom-door & co, scene: 'procedural:2', generate: {count: 12}}
agents:
  - {agent: oracle}
  - {agent: nav, name: 'nav <stack>'}
trajectories: {worst: 2, episodes: [ep-3]}
";

/// Episodes per run.
pub const EPISODES: usize = 12;

/// splitmix64: a deterministic stream of numbers in [0, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// The door's centre (y, m) of scene `s`: the wall at x = 0 has a 1.6 m gap there.
fn door(s: usize) -> f64 {
    if s == 0 {
        1.8
    } else {
        -1.8
    }
}

/// An 8 × 6 m floor (5 cm cells) walled round, split at x = 0 but for the door.
fn floor(s: usize) -> OccupancyGrid {
    let mut g = OccupancyGrid::new(160, 120, 0.05, Pose2 { x: -4.0, y: -3.0, yaw: 0.0 }, GRID_FREE);
    for row in 0..g.height {
        for col in 0..g.width {
            let (x, y) = (-4.0 + (col as f64 + 0.5) * 0.05, -3.0 + (row as f64 + 0.5) * 0.05);
            let border = col < 2 || row < 2 || col >= g.width - 2 || row >= g.height - 2;
            let wall = x.abs() < 0.1 && (y - door(s)).abs() > 0.8;
            if border || wall {
                g.set(col, row, GRID_OCCUPIED);
            }
        }
    }
    g
}

fn length(p: &[[f64; 2]]) -> f64 {
    p.windows(2).map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1])).sum()
}

/// The first `f` (0..1) of polyline `p`, densified to 10 cm steps, with a sideways wobble.
fn follow(p: &[[f64; 2]], f: f64, wobble: f64, rng: &mut Rng) -> Vec<[f64; 2]> {
    let total = length(p) * f;
    let mut out = vec![p[0]];
    let mut travelled = 0.0;
    let phase = rng.range(0.0, std::f64::consts::TAU);
    for w in p.windows(2) {
        let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
        let l = dx.hypot(dy);
        let n = (l / 0.1).ceil().max(1.0) as usize;
        for k in 1..=n {
            if travelled + l * k as f64 / n as f64 > total {
                return out;
            }
            let t = k as f64 / n as f64;
            let side = wobble * (phase + 7.0 * (travelled + l * t)).sin() * (std::f64::consts::PI * t).sin();
            out.push([w[0][0] + dx * t - dy / l * side, w[0][1] + dy * t + dx / l * side]);
        }
        travelled += l;
    }
    out
}

/// Episode `i` of scene `s` run by agent `a` under configuration `c` (index into the
/// default four: -physics -ROS, +physics -ROS, -physics +ROS, +physics +ROS).
fn episode(s: usize, a: usize, c: usize, i: usize) -> (EpisodeReport, Trajectory) {
    let (physics, ros) = (c % 2 == 1, c >= 2);
    let mut place = Rng(((s * 1000 + i) as u64) << 8);
    let start = [place.range(-3.3, -0.8), place.range(-2.4, 2.4)];
    let goal = [place.range(0.8, 3.3), place.range(-2.4, 2.4)];
    let shortest = vec![start, [0.0, door(s)], goal];
    let geodesic = length(&shortest);
    let mut rng = Rng(((s * 1000 + i) as u64) << 20 | (a * 10 + c) as u64);
    let p_success = [0.92, 0.75][a] - if physics { 0.12 } else { 0.0 } - if ros { 0.03 } else { 0.0 };
    let success = rng.next() < p_success;
    let reach = if success { 1.0 } else { rng.range(0.2, 0.85) };
    let path = follow(&shortest, reach, rng.range(0.02, 0.25), &mut rng);
    let travelled = length(&path).max(1e-9);
    let remaining = (geodesic * (1.0 - reach)).max(if success { 0.05 } else { 0.3 });
    let ratio = geodesic / travelled.max(geodesic);
    let failure = (!success).then(|| match (physics, a) {
        (true, _) if rng.next() < 0.5 => "stuck",
        (_, 1) if rng.next() < 0.5 => "goal_unreachable_for_costmap",
        (_, 1) => "aborted",
        (true, _) => "step_limit",
        _ => "stopped_outside",
    });
    let steps = (travelled / 0.25 * 2.2).round() as u32 + 4;
    let wall_s = steps as f64 * if physics { 0.012 } else { 0.0015 } * if ros { 1.6 } else { 1.0 } * rng.range(0.9, 1.1);
    let sim_s = physics.then_some(steps as f64 * 0.1);
    let json = serde_json::json!({
        "episode_id": format!("ep-{i}"),
        "success": if success { 1.0 } else { 0.0 },
        "spl": if success { ratio } else { 0.0 },
        "soft_spl": (1.0 - remaining / geodesic).max(0.0) * ratio,
        "distance_to_goal": remaining,
        "steps": steps,
        "collisions": (rng.next() * 4.0) as u32,
        "wall_s": wall_s,
        "steps_per_s": steps as f64 / wall_s,
        "path_length": travelled,
        "start_distance": geodesic,
        "called_stop": success || failure == Some("stopped_outside"),
        "sim_s": sim_s,
        "real_time_factor": sim_s.map(|x| x / wall_s),
        "stuck": physics.then_some(failure == Some("stuck")),
        "aborted": matches!(failure, Some("goal_unreachable_for_costmap" | "aborted")),
        "failure": failure,
        "off_navigable": false,
    });
    let report: EpisodeReport = serde_json::from_value(json).expect("the example's episode is an EpisodeReport");
    let map = format!("maps/floor{s}.yaml");
    (report, Trajectory { episode_id: format!("ep-{i}"), index: i, map, path, shortest_path: shortest, start, goals: vec![goal] })
}

/// Writes the example study into `dir` (maps, `experiment.json`, parts) and merges it into
/// `results.json`; returns the results.
pub fn write_example(dir: &Path) -> Result<Results, ResultsError> {
    let spec = ExperimentSpec::parse(SPEC, Path::new("example.yaml")).map_err(|e| ResultsError::Format { path: "example.yaml".into(), message: e.to_string() })?;
    for s in 0..spec.scenes.len() {
        let path = dir.join("maps").join(format!("floor{s}.yaml"));
        std::fs::create_dir_all(dir.join("maps")).map_err(|source| ResultsError::Io { path: dir.join("maps"), source })?;
        xhab_nav::map_server::save_map(&floor(s), &path).map_err(|e| ResultsError::Format { path, message: e.to_string() })?;
    }
    let mut plan = Plan { runs: Vec::new(), skipped: Vec::new() };
    let slug = crate::plan::slug;
    for (s, scene) in spec.scenes.iter().enumerate() {
        for (a, agent) in spec.agents.iter().enumerate() {
            for (c, conf) in spec.configurations.iter().enumerate() {
                if a == 1 && !conf.physics {
                    let reason = "the nav agent drives with velocities: it runs under physics only".into();
                    plan.skipped.push(SkippedRun { scene: scene.label(), agent: agent.label(), configuration: conf.label(), reason });
                    continue;
                }
                // As the plan names runs: `+physics -ROS` is `physics_noros`.
                let c_slug = crate::plan::config_slug(conf);
                let id = format!("{}.{}.{c_slug}.s0", slug(&scene.label()), slug(&agent.label()));
                let label = format!("episodes/{}.json.gz", slug(&scene.label()));
                plan.runs.push(RunPlan { id, scene: s, agent: a, configuration: c, seed: 0, episodes_file: PathBuf::from(&label), episodes_label: label, episodes: EPISODES });
            }
        }
    }
    let record = ExperimentRecord { spec, plan };
    let path = ExperimentRecord::path(dir);
    std::fs::write(&path, serde_json::to_string_pretty(&record).unwrap_or_default()).map_err(|source| ResultsError::Io { path, source })?;
    for (k, run) in record.plan.runs.iter().enumerate() {
        let conf = &record.spec.configurations[run.configuration];
        let (mut episodes, mut trajectories, mut indices, mut invalid, mut invalid_indices) = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for i in 0..run.episodes {
            // The first run's last episode is invalid, as a start off the navigable area is.
            if k == 0 && i + 1 == run.episodes {
                invalid.push(InvalidRun { episode_id: format!("ep-{i}"), reason: "start is not navigable".into() });
                invalid_indices.push(i);
                continue;
            }
            let (e, t) = episode(run.scene, run.agent, run.configuration, i);
            episodes.push(e);
            trajectories.push(t);
            indices.push(i);
        }
        let wall_s = episodes.iter().map(|e| e.wall_s).sum();
        let report = BenchReport {
            schema_version: SCHEMA_VERSION,
            scene: record.spec.scenes[run.scene].scene.clone(),
            episodes_file: run.episodes_label.clone(),
            agent: record.spec.agents[run.agent].label(),
            threads: 1,
            task: record.spec.task.clone(),
            physics: conf.physics.then(|| serde_json::json!({"robot": "habitat"})),
            camera: None,
            nav: None,
            aggregate: aggregate(&episodes, wall_s),
            invalid: InvalidReport::new(invalid),
            episodes,
            ros: conf.ros,
            ros_check: None,
        };
        let part = Part { run: run.id.clone(), first: 0, end: run.episodes, report, indices, invalid_indices, trajectories };
        part.write(dir)?;
    }
    merge(&[dir.to_path_buf()], dir)
}
