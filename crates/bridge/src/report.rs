//! The benchmark report: the document `xhab bench --out` writes and `xhab.evaluate` returns.
//! Field names are a contract: add fields, never rename.

use crate::nav_agent::Localization;
use crate::runner::{Aggregate, EpisodeRun, Failures, InvalidRun, Outcome, RunConfig};
use serde::{Deserialize, Serialize};
use xhab_sim::env::TaskConfig;

/// Version of the bench JSON layout.
pub const SCHEMA_VERSION: u32 = 1;

/// `xhab bench --out` document.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BenchReport {
    /// Layout version.
    pub schema_version: u32,
    /// The SCENE argument.
    pub scene: String,
    /// The episodes file.
    pub episodes_file: String,
    /// The agent's name.
    pub agent: String,
    /// Worker threads.
    pub threads: usize,
    /// Task settings.
    pub task: TaskConfig,
    /// Physics settings and robot (physics runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub physics: Option<serde_json::Value>,
    /// The camera every observation carries (`--sensors` runs only): images, renderer,
    /// intrinsics and mount, depth noise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub camera: Option<serde_json::Value>,
    /// The nav agent's setup (nav runs only): localisation, scan source, the map AMCL
    /// localises on, and the parameters in effect (ROS names: files layered over defaults,
    /// costmaps sized to the robot).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nav: Option<serde_json::Value>,
    /// Means over valid episodes.
    pub aggregate: Aggregate,
    /// Episodes left out because their start or goal is not navigable for the agent.
    pub invalid: InvalidReport,
    /// One entry per valid episode, in file order.
    pub episodes: Vec<EpisodeReport>,
    /// Whether the agent and the simulator ran as ROS nodes (`--ros`, `--compare-ros`).
    pub ros: bool,
    /// How the ROS run compares with the in-process run (`--compare-ros` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ros_check: Option<RosCheck>,
}

impl BenchReport {
    /// The report of a run: `outcomes` in dataset order, `wall_s` the run's elapsed time (s),
    /// `agent` the agent's name, `scene` and `episodes_file` as given, `ros` whether it ran
    /// over ROS. Invalid episodes are listed in `invalid`, in dataset order.
    pub fn new(outcomes: &[Outcome], wall_s: f64, cfg: &RunConfig, agent: &str, scene: &str, episodes_file: &str, ros: bool) -> BenchReport {
        let mut runs: Vec<&EpisodeRun> = Vec::new();
        let mut invalid = Vec::new();
        for o in outcomes {
            match o {
                Outcome::Ran(r) => runs.push(r),
                Outcome::Invalid(i) => invalid.push(i.clone()),
            }
        }
        let episodes: Vec<EpisodeReport> = runs.iter().map(|r| EpisodeReport::from(*r)).collect();
        BenchReport {
            schema_version: SCHEMA_VERSION,
            scene: scene.to_string(),
            episodes_file: episodes_file.to_string(),
            agent: agent.to_string(),
            threads: cfg.threads,
            task: cfg.task.clone(),
            physics: cfg.physics.as_ref().map(|p| serde_json::json!({"robot": p.profile, "config": p.config, "seed": cfg.seed})),
            camera: cfg.sensors.as_ref().map(|r| {
                let images: Vec<&str> = if r.rgb { vec!["depth", "rgb"] } else { vec!["depth"] };
                serde_json::json!({"sensors": images, "renderer": r.renderer.name(), "params": r.params, "noise": r.noise})
            }),
            nav: cfg.nav.as_ref().map(|n| {
                // No nulls: "none" where there is no scan source or no AMCL map, and no
                // scan height without scans.
                let mut v = serde_json::json!({
                    "localization": n.localization,
                    "scan_source": n.scan.as_ref().map_or("none", |s| s.name()),
                    "amcl_map": if n.localization != Localization::Amcl { "none" } else if n.scan_plane_localization() { "scan_plane" } else { "map" },
                    "params": n.params,
                });
                if let Some(s) = n.scan.as_ref() {
                    v["scan_height_m"] = serde_json::json!(s.height());
                }
                v
            }),
            invalid: InvalidReport::new(invalid),
            aggregate: aggregate(&episodes, wall_s),
            episodes,
            ros,
            ros_check: None,
        }
    }

    /// The report as `xhab bench --out` writes it: pretty-printed JSON and a newline.
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        Ok(serde_json::to_string_pretty(self)? + "\n")
    }
}

/// Agreement of a run over ROS with the same run in-process.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RosCheck {
    /// Same episodes, same steps, collisions and stop calls, metrics within 1e-9.
    pub identical: bool,
    /// Largest absolute difference of success, spl, soft_spl, distance_to_goal, path_length.
    pub max_metric_diff: f64,
    /// Episodes whose step or collision count or stop call differ.
    pub episodes_with_other_steps: usize,
}

/// Invalid episodes.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct InvalidReport {
    /// How many.
    pub count: usize,
    /// Their ids.
    pub episode_ids: Vec<String>,
    /// Why each one is invalid.
    pub reasons: Vec<InvalidRun>,
}

impl InvalidReport {
    /// The report of these invalid episodes, in the order given.
    pub fn new(reasons: Vec<InvalidRun>) -> Self {
        InvalidReport { count: reasons.len(), episode_ids: reasons.iter().map(|i| i.episode_id.clone()).collect(), reasons }
    }
}

/// Metrics of one episode.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EpisodeReport {
    /// The episode's id.
    pub episode_id: String,
    /// 1 on success, else 0.
    pub success: f64,
    /// SPL.
    pub spl: f64,
    /// Soft SPL.
    pub soft_spl: f64,
    /// Final geodesic distance to the goal (m).
    pub distance_to_goal: f64,
    /// Actions taken.
    pub steps: u32,
    /// Blocked or deflected moves.
    pub collisions: u32,
    /// Wall time (s).
    pub wall_s: f64,
    /// Actions per second of wall time.
    pub steps_per_s: f64,
    /// Path length travelled (m).
    pub path_length: f64,
    /// Geodesic start-goal distance at reset (m).
    pub start_distance: f64,
    /// Whether the agent called stop.
    pub called_stop: bool,
    /// Simulated time (s), physics runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sim_s: Option<f64>,
    /// sim_s / wall_s, physics runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub real_time_factor: Option<f64>,
    /// Whether the robot got stuck, physics runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stuck: Option<bool>,
    /// Why it got stuck, when a step higher than its profile's `step_height` held it ("a step
    /// 0.17 m high ahead, above the robot's step_height 0 m (turtlebot3_burger)").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stuck_cause: Option<String>,
    /// Whether the agent gave up (the nav agent's navigator aborted).
    pub aborted: bool,
    /// Why it gave up: `goal_unreachable_for_costmap`, `start_blocked`, `controller_failed`,
    /// `no_progress`, or `unknown` (over ROS).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub abort_reason: Option<String>,
    /// Why the episode failed (failed episodes only): `stuck`, `goal_unreachable_for_costmap`,
    /// `aborted`, `stopped_outside` or `step_limit`, as the aggregate's `failures` count them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
    /// Whether the agent ended off its navigable region: `distance_to_goal` is then the
    /// geodesic from the nearest navigable point plus `off_navigable_m`.
    pub off_navigable: bool,
    /// Distance from the final position to the nearest navigable point (m), when off it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub off_navigable_m: Option<f64>,
    /// Localisation position error at the filter's last update (m), AMCL runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub final_localization_error_m: Option<f64>,
    /// The filter's position spread at its last update (m, one standard deviation), AMCL runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub final_localization_spread_m: Option<f64>,
    /// Mean localisation position error (m), AMCL runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub localization_error_m: Option<f64>,
    /// Mean localisation heading error (degrees), AMCL runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub localization_error_deg: Option<f64>,
    /// Camera frames rendered (`--sensors` runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frames: Option<u64>,
    /// Wall time spent rendering them (s) (`--sensors` runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub render_s: Option<f64>,
    /// The goal's terminal action state: SUCCEEDED, ABORTED, PREEMPTED, ... (`--agent ros`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ros_status: Option<String>,
    /// Why the episode ended: terminal_state, timeout, stuck, step_limit (`--agent ros`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ros_end: Option<String>,
    /// Clock ticks after which the stack's cmd_vel did not come within the grace (`--agent ros`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cmd_vel_missed: Option<u64>,
    /// Wall time spent waiting for the stack (s) (`--agent ros`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stack_wait_s: Option<f64>,
    /// Simulated time from sending the goal to the stack's acknowledgement (s) (`--agent ros`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub goal_ack_s: Option<f64>,
}

impl From<&EpisodeRun> for EpisodeReport {
    fn from(r: &EpisodeRun) -> Self {
        let m = &r.metrics;
        EpisodeReport {
            episode_id: r.episode_id.clone(),
            success: m.success,
            spl: m.spl,
            soft_spl: m.soft_spl,
            distance_to_goal: m.distance_to_goal,
            steps: m.steps,
            collisions: m.collisions,
            wall_s: r.wall_s,
            steps_per_s: if r.wall_s > 0.0 { m.steps as f64 / r.wall_s } else { 0.0 },
            path_length: m.path_length,
            start_distance: m.start_distance,
            called_stop: m.called_stop,
            sim_s: r.sim_s,
            real_time_factor: r.sim_s.map(|s| if r.wall_s > 0.0 { s / r.wall_s } else { 0.0 }),
            stuck: r.stuck,
            stuck_cause: r.stuck_cause.clone(),
            aborted: r.abort_reason.is_some(),
            abort_reason: r.abort_reason.clone(),
            failure: crate::runner::failure_cause(r).map(str::to_string),
            off_navigable: m.off_navigable_m.is_some(),
            off_navigable_m: m.off_navigable_m,
            final_localization_error_m: r.final_localization.map(|f| f[0]),
            final_localization_spread_m: r.final_localization.map(|f| f[1]),
            localization_error_m: r.localization_error.map(|e| e[0]),
            localization_error_deg: r.localization_error.map(|e| e[1].to_degrees()),
            frames: r.render.map(|r| r.0),
            render_s: r.render.map(|r| r.1),
            ros_status: r.ros.as_ref().map(|x| x.ros_status.clone()),
            ros_end: r.ros.as_ref().map(|x| x.end.clone()),
            cmd_vel_missed: r.ros.as_ref().map(|x| x.cmd_vel_missed),
            stack_wait_s: r.ros.as_ref().map(|x| x.stack_wait_s),
            goal_ack_s: r.ros.as_ref().and_then(|x| x.goal_ack_s),
        }
    }
}

/// Means and totals over a run's episodes (in the report's order; `wall_s` the run's elapsed
/// time, s). Everything but the timing figures depends on the episodes alone, so a run split
/// into parts and merged aggregates to the same numbers.
pub fn aggregate(eps: &[EpisodeReport], wall_s: f64) -> Aggregate {
    let n = eps.len().max(1) as f64;
    // Folded from +0.0 (`sum` starts at -0.0, which an empty run would print as "-0.000").
    let mean = |f: &dyn Fn(&EpisodeReport) -> f64| eps.iter().fold(0.0, |a, e| a + f(e)) / n;
    let total_steps: f64 = eps.iter().map(|e| e.steps as f64).sum();
    let physics = eps.iter().any(|e| e.sim_s.is_some());
    let sim_s: f64 = eps.iter().filter_map(|e| e.sim_s).sum();
    let mut failures = Failures::default();
    for e in eps {
        match e.failure.as_deref() {
            Some("stuck") => failures.stuck += 1,
            Some("goal_unreachable_for_costmap") => failures.goal_unreachable_for_costmap += 1,
            Some("aborted") => failures.aborted += 1,
            Some("stopped_outside") => failures.stopped_outside += 1,
            Some(_) => failures.step_limit += 1,
            None => {}
        }
    }
    let loc: Vec<[f64; 2]> = eps.iter().filter_map(|e| Some([e.localization_error_m?, e.localization_error_deg?])).collect();
    let render: Vec<(u64, f64)> = eps.iter().filter_map(|e| Some((e.frames?, e.render_s?))).collect();
    let (frames, render_s) = render.iter().fold((0u64, 0.0), |a, r| (a.0 + r.0, a.1 + r.1));
    let rendered = !render.is_empty();
    let loc_mean = |k: usize| (!loc.is_empty()).then(|| loc.iter().map(|e| e[k]).sum::<f64>() / loc.len() as f64);
    Aggregate {
        localization_error_m: loc_mean(0),
        localization_error_deg: loc_mean(1),
        ros_overhead: None,
        frames: rendered.then_some(frames),
        render_s: rendered.then_some(render_s),
        render_frames_per_s: rendered.then(|| if render_s > 0.0 { frames as f64 / render_s } else { 0.0 }),
        sim_s: physics.then_some(sim_s),
        real_time_factor: physics.then(|| if wall_s > 0.0 { sim_s / wall_s } else { 0.0 }),
        stuck: physics.then(|| eps.iter().filter(|e| e.stuck == Some(true)).count() as f64 / n),
        failures,
        episodes: eps.len(),
        success: mean(&|e| e.success),
        spl: mean(&|e| e.spl),
        soft_spl: mean(&|e| e.soft_spl),
        distance_to_goal: mean(&|e| e.distance_to_goal),
        steps: mean(&|e| e.steps as f64),
        collisions: mean(&|e| e.collisions as f64),
        wall_s,
        steps_per_s: if wall_s > 0.0 { total_steps / wall_s } else { 0.0 },
    }
}

/// CSV of per-episode results (header + one line per episode).
pub fn episodes_csv(eps: &[EpisodeReport]) -> String {
    let mut s = String::from("episode_id,success,spl,soft_spl,distance_to_goal,steps,collisions,path_length,start_distance,called_stop,wall_s\n");
    for e in eps {
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{}\n",
            e.episode_id, e.success, e.spl, e.soft_spl, e.distance_to_goal, e.steps, e.collisions, e.path_length, e.start_distance, e.called_stop, e.wall_s
        ));
    }
    s
}
