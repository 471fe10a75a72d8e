//! The numbers the report shows, computed once from `results.json`: per configuration (and
//! agent), per scene, timing and failures. Figures and the page only lay them out.

use super::stats::{self, Estimate};
use crate::results::Results;
use xhab_bridge::runner::Failures;

/// Failure causes in the order the aggregate counts them, with their names on the page.
pub const CAUSES: [(&str, &str); 5] = [
    ("stuck", "stuck"),
    ("goal_unreachable_for_costmap", "goal unreachable in costmap"),
    ("aborted", "navigator aborted"),
    ("stopped_outside", "stopped outside radius"),
    ("step_limit", "step limit"),
];

/// A failure tally's counts in [`CAUSES`] order.
pub fn cause_counts(f: &Failures) -> [usize; 5] {
    [f.stuck, f.goal_unreachable_for_costmap, f.aborted, f.stopped_outside, f.step_limit]
}

/// Success, SPL and soft SPL over a group of episodes.
#[derive(Debug, Clone)]
pub struct Group {
    /// The configuration.
    pub configuration: String,
    /// The agent, in per-agent rows.
    pub agent: Option<String>,
    /// Runs in the group.
    pub runs: usize,
    /// Episodes left out as invalid.
    pub invalid: usize,
    /// Success rate (Wilson interval).
    pub success: Estimate,
    /// SPL (t interval).
    pub spl: Estimate,
    /// Soft SPL (t interval).
    pub soft_spl: Estimate,
}

/// Timing of a configuration's runs.
#[derive(Debug, Clone)]
pub struct Timing {
    /// The configuration.
    pub configuration: String,
    /// Episodes run.
    pub episodes: usize,
    /// Wall time of its runs, summed (s).
    pub wall_s: f64,
    /// Actions per wall-clock second.
    pub steps_per_s: f64,
    /// Simulated seconds per wall second over the runs that report simulated time.
    pub real_time_factor: Option<f64>,
}

/// A scene × configuration cell of the per-scene table.
#[derive(Debug, Clone, Copy)]
pub struct Cell {
    /// Episodes.
    pub episodes: usize,
    /// Mean success.
    pub success: f64,
    /// Mean SPL.
    pub spl: f64,
}

/// Everything the report's tables and charts show.
#[derive(Debug, Clone)]
pub struct Summary {
    /// Configurations with runs, in the study's order.
    pub configurations: Vec<String>,
    /// Agents, in order of appearance.
    pub agents: Vec<String>,
    /// Scenes, in order of appearance.
    pub scenes: Vec<String>,
    /// Seeds, in order of appearance.
    pub seeds: Vec<u64>,
    /// One group per configuration.
    pub by_configuration: Vec<Group>,
    /// One group per configuration × agent (configuration-major), when there are several agents.
    pub by_agent: Vec<Group>,
    /// `[scene][configuration]`, `None` where nothing ran.
    pub by_scene: Vec<Vec<Option<Cell>>>,
    /// One per configuration.
    pub timing: Vec<Timing>,
    /// Failures by cause ([`CAUSES`] order), one per configuration.
    pub failures: Vec<[usize; 5]>,
    /// Each configuration's episode SPLs.
    pub spl: Vec<Vec<f64>>,
}

fn push_new<T: PartialEq + Clone>(v: &mut Vec<T>, x: &T) {
    if !v.contains(x) {
        v.push(x.clone());
    }
}

impl Summary {
    /// Summarises `r`; `order` names configurations in the study's order (others follow in
    /// order of appearance).
    pub fn new(r: &Results, order: &[String]) -> Summary {
        let mut configurations: Vec<String> = order.iter().filter(|c| r.runs.iter().any(|x| &x.configuration == *c)).cloned().collect();
        let (mut agents, mut scenes, mut seeds) = (Vec::new(), Vec::new(), Vec::new());
        for run in &r.runs {
            push_new(&mut configurations, &run.configuration);
            push_new(&mut agents, &run.agent);
            push_new(&mut scenes, &run.scene);
            push_new(&mut seeds, &run.seed);
        }
        let group = |c: &str, agent: Option<&str>| {
            let keep = |conf: &str, a: &str| conf == c && agent.is_none_or(|x| x == a);
            let rows: Vec<_> = r.episodes.iter().filter(|e| keep(&e.configuration, &e.agent)).map(|e| &e.metrics).collect();
            let runs: Vec<_> = r.runs.iter().filter(|x| keep(&x.configuration, &x.agent)).collect();
            let col = |f: fn(&xhab_bridge::report::EpisodeReport) -> f64| rows.iter().map(|m| f(m)).collect::<Vec<f64>>();
            Group {
                configuration: c.to_string(),
                agent: agent.map(str::to_string),
                runs: runs.len(),
                invalid: runs.iter().map(|x| x.invalid).sum(),
                success: stats::success_rate(&col(|m| m.success)),
                spl: stats::t_interval(&col(|m| m.spl)),
                soft_spl: stats::t_interval(&col(|m| m.soft_spl)),
            }
        };
        let by_configuration = configurations.iter().map(|c| group(c, None)).collect();
        let by_agent = if agents.len() > 1 {
            configurations.iter().flat_map(|c| agents.iter().map(move |a| (c, a))).map(|(c, a)| group(c, Some(a))).filter(|g| g.runs > 0).collect()
        } else {
            Vec::new()
        };
        let by_scene = scenes
            .iter()
            .map(|s| {
                configurations
                    .iter()
                    .map(|c| {
                        let rows: Vec<_> = r.episodes.iter().filter(|e| &e.scene == s && &e.configuration == c).map(|e| &e.metrics).collect();
                        let n = rows.len();
                        (n > 0).then(|| Cell {
                            episodes: n,
                            success: rows.iter().map(|m| m.success).sum::<f64>() / n as f64,
                            spl: rows.iter().map(|m| m.spl).sum::<f64>() / n as f64,
                        })
                    })
                    .collect()
            })
            .collect();
        let timing = configurations
            .iter()
            .map(|c| {
                let runs: Vec<_> = r.runs.iter().filter(|x| &x.configuration == c).map(|x| &x.aggregate).collect();
                let wall_s: f64 = runs.iter().map(|a| a.wall_s).sum();
                let steps: f64 = runs.iter().map(|a| a.steps * a.episodes as f64).sum();
                let sim: Vec<(f64, f64)> = runs.iter().filter_map(|a| Some((a.sim_s?, a.wall_s))).collect();
                let sim_wall: f64 = sim.iter().map(|s| s.1).sum();
                Timing {
                    configuration: c.clone(),
                    episodes: runs.iter().map(|a| a.episodes).sum(),
                    wall_s,
                    steps_per_s: if wall_s > 0.0 { steps / wall_s } else { 0.0 },
                    real_time_factor: (!sim.is_empty() && sim_wall > 0.0).then(|| sim.iter().map(|s| s.0).sum::<f64>() / sim_wall),
                }
            })
            .collect();
        let failures = configurations
            .iter()
            .map(|c| {
                r.runs.iter().filter(|x| &x.configuration == c).fold([0; 5], |mut acc, x| {
                    for (a, n) in acc.iter_mut().zip(cause_counts(&x.aggregate.failures)) {
                        *a += n;
                    }
                    acc
                })
            })
            .collect();
        let spl = configurations.iter().map(|c| r.episodes.iter().filter(|e| &e.configuration == c).map(|e| e.metrics.spl).collect()).collect();
        Summary { configurations, agents, scenes, seeds, by_configuration, by_agent, by_scene, timing, failures, spl }
    }

    /// Episodes over all runs.
    pub fn episodes(&self) -> usize {
        self.by_configuration.iter().map(|g| g.success.n).sum()
    }
}
