//! An experiment expanded into runs (scene × agent × configuration × seed) and each run into
//! the [`BenchOptions`] that `xhab bench` would build from the same settings.

use crate::spec::{AgentKindSpec, AgentSpec, Configuration, ExperimentSpec, ScansSpec, SceneSpec};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use xhab_bridge::agents::AgentKind;
use xhab_bridge::benchmark::{BenchOptions, ExternalSpec, NavOptions, ParamFile, ScanKind, Transport};
use xhab_bridge::ros::external::MapOdom;
use xhab_bridge::ros::move_base_client::GoalInterface;
use xhab_bridge::setup::{self, EnvOptions, PhysicsOptions, SetupError};

/// One run of a study: an agent on a scene's episodes under one configuration and seed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunPlan {
    /// `SCENE.AGENT.CONFIGURATION.sSEED`, file-name safe; names the run's folders.
    pub id: String,
    /// Index into the spec's scenes.
    pub scene: usize,
    /// Index into the spec's agents.
    pub agent: usize,
    /// Index into the spec's configurations.
    pub configuration: usize,
    /// The seed.
    pub seed: u64,
    /// The episodes file the run reads (generated sets: under the experiment's folder).
    pub episodes_file: PathBuf,
    /// How the report names the episodes file (generated sets: relative to the folder).
    pub episodes_label: String,
    /// Episodes the run has (the set's first `limit`).
    pub episodes: usize,
}

/// A scene × agent × configuration the study leaves out, and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SkippedRun {
    /// The scene's name.
    pub scene: String,
    /// The agent's name.
    pub agent: String,
    /// The configuration's name.
    pub configuration: String,
    /// Why it does not run.
    pub reason: String,
}

/// The study's runs, in spec order (scenes, then agents, configurations, seeds).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// Runs.
    pub runs: Vec<RunPlan>,
    /// Combinations left out.
    pub skipped: Vec<SkippedRun>,
}

impl Plan {
    /// Episodes over all runs.
    pub fn episodes(&self) -> usize {
        self.runs.iter().map(|r| r.episodes).sum()
    }
}

/// Why a plan could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// A scene or episode set could not be loaded or generated.
    #[error("scene `{scene}`")]
    Setup {
        /// The scene's name.
        scene: String,
        /// Why.
        #[source]
        source: Box<SetupError>,
    },
    /// A generated episode set could not be written.
    #[error("writing generated episodes {path}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A scene's episode set is shorter than its `limit` or empty.
    #[error("scene `{scene}`: {message}")]
    Episodes {
        /// The scene's name.
        scene: String,
        /// What is wrong.
        message: String,
    },
}

/// Expands `spec` into runs; generated episode sets are written under `dir/episodes` (once:
/// an existing file is reused, so shards running at once agree).
pub fn plan(spec: &ExperimentSpec, dir: &Path) -> Result<Plan, PlanError> {
    let mut runs = Vec::new();
    let mut skipped = Vec::new();
    for (si, scene) in spec.scenes.iter().enumerate() {
        let (file, label, available) = episode_set(scene, dir)?;
        let episodes = match scene.limit {
            Some(l) if l > available => return Err(PlanError::Episodes { scene: scene.label(), message: format!("limit {l} but the set has {available} episodes") }),
            Some(l) => l,
            None => available,
        };
        if episodes == 0 {
            return Err(PlanError::Episodes { scene: scene.label(), message: format!("{} has no episodes", file.display()) });
        }
        for (ai, agent) in spec.agents.iter().enumerate() {
            for (ci, c) in spec.configurations.iter().enumerate() {
                if let Some(reason) = not_applicable(agent, c) {
                    skipped.push(SkippedRun { scene: scene.label(), agent: agent.label(), configuration: c.label(), reason: reason.into() });
                    continue;
                }
                for &seed in &spec.seeds {
                    let id = format!("{}.{}.{}.s{seed}", slug(&scene.label()), slug(&agent.label()), config_slug(c));
                    runs.push(RunPlan { id, scene: si, agent: ai, configuration: ci, seed, episodes_file: file.clone(), episodes_label: label.clone(), episodes });
                }
            }
        }
    }
    Ok(Plan { runs, skipped })
}

/// Why `agent` cannot run under `c`, if it cannot.
fn not_applicable(agent: &AgentSpec, c: &Configuration) -> Option<&'static str> {
    match agent.agent {
        AgentKindSpec::Oracle => None,
        AgentKindSpec::Nav if !c.physics => Some("the nav agent drives with velocities: it runs under physics only"),
        AgentKindSpec::Nav => None,
        AgentKindSpec::Ros if !c.physics => Some("an external stack drives with velocities: it runs under physics only"),
        AgentKindSpec::Ros if !c.ros => Some("an external stack runs over ROS only"),
        AgentKindSpec::Ros => None,
        AgentKindSpec::Ros2 if !c.physics => Some("an external stack drives with velocities: it runs under physics only"),
        AgentKindSpec::Ros2 if !c.ros2 => Some("an external ROS 2 stack runs over ROS 2 only"),
        AgentKindSpec::Ros2 => None,
    }
}

/// The scene's episodes file, its name in reports, and how many episodes it holds.
fn episode_set(scene: &SceneSpec, dir: &Path) -> Result<(PathBuf, String, usize), PlanError> {
    let setup_err = |source| PlanError::Setup { scene: scene.label(), source: Box::new(source) };
    if let Some(f) = &scene.episodes {
        let path = PathBuf::from(f);
        let ds = setup::read_episodes(&path).map_err(setup_err)?;
        return Ok((path, f.clone(), ds.episodes.len()));
    }
    let g = scene.generate.as_ref().expect("the spec check guarantees an episode source");
    let label = format!("episodes/{}.json.gz", slug(&scene.label()));
    let path = dir.join(&label);
    if path.exists() {
        let ds = setup::read_episodes(&path).map_err(setup_err)?;
        return Ok((path, label, ds.episodes.len()));
    }
    let opts = setup::SceneOptions { keep_ceilings: scene.keep_ceilings, storeys: scene.storeys, ..Default::default() };
    let world = setup::load_geometry(&scene.scene, &opts).map_err(setup_err)?;
    let ds = if g.cross_floor {
        setup::generate_cross_floor(&world, &scene.scene, g.count, g.seed, &scene.scene)
    } else {
        setup::generate(&world, &scene.scene, "auto", g.count, g.seed, &scene.scene)
    }
    .map_err(setup_err)?;
    let write_err = |source| PlanError::Write { path: path.clone(), source };
    std::fs::create_dir_all(path.parent().unwrap_or(dir)).map_err(write_err)?;
    // Written beside and renamed: a reader never sees half a file.
    let tmp = dir.join(format!("episodes/{}.tmp{}.json.gz", slug(&scene.label()), std::process::id()));
    xhab_sim::episode::write_dataset(&ds, &tmp).map_err(|e| PlanError::Write { path: tmp.clone(), source: std::io::Error::other(e.to_string()) })?;
    std::fs::rename(&tmp, &path).map_err(write_err)?;
    Ok((path, label, ds.episodes.len()))
}

/// The benchmark options of `run`'s episodes `first..end`: what `xhab bench` builds from the
/// same scene, agent, configuration and seed.
pub fn bench_options(spec: &ExperimentSpec, run: &RunPlan, first: usize, end: usize) -> Result<BenchOptions, String> {
    let scene = &spec.scenes[run.scene];
    let agent = &spec.agents[run.agent];
    let c = &spec.configurations[run.configuration];
    let mut env = EnvOptions::new(scene.scene.clone());
    env.scene_options.keep_ceilings = scene.keep_ceilings;
    env.scene_options.storeys = scene.storeys;
    env.physics = c.physics.then(|| PhysicsOptions { robot: agent.robot.clone(), ..Default::default() });
    env.task = spec.task.clone();
    let mut o = BenchOptions::new(scene.scene.clone(), run.episodes_file.clone());
    o.env = env;
    o.episode_indices = Some((first..end).collect());
    o.seed = run.seed;
    o.threads = spec.threads;
    o.agent = match agent.agent {
        AgentKindSpec::Oracle => AgentKind::Oracle,
        AgentKindSpec::Nav => AgentKind::Nav,
        AgentKindSpec::Ros => AgentKind::Ros,
        AgentKindSpec::Ros2 => AgentKind::Ros2,
    };
    // An external stack brings its own transport; xhab's agents go over the one asked for.
    let external = matches!(agent.agent, AgentKindSpec::Ros | AgentKindSpec::Ros2);
    o.transport = match (external, c.ros, c.ros2) {
        (false, true, _) => Transport::Ros,
        (false, _, true) => Transport::Ros2,
        _ => Transport::InProcess,
    };
    o.nav = NavOptions {
        localization: agent.localization,
        map: agent.map.as_ref().map(PathBuf::from),
        params: agent.nav_params.iter().map(|p| p.parse::<ParamFile>().map_err(|e| e.to_string())).collect::<Result<_, _>>()?,
        scans: match agent.scans {
            ScansSpec::Lidar => Some(ScanKind::Lidar),
            ScansSpec::Depth => Some(ScanKind::Depth),
            ScansSpec::None => None,
        },
    };
    if let Some(x) = &agent.external {
        o.external = ExternalSpec {
            launch: x.launch.clone(),
            ros_args: x.ros_args.clone(),
            goal_interface: if x.goal_interface == "simple" { GoalInterface::Simple } else { GoalInterface::Action },
            episode_timeout: x.episode_timeout,
            map_odom: if x.map_odom == "ground_truth" { MapOdom::GroundTruth } else { MapOdom::Stack },
            ..Default::default()
        };
    }
    Ok(o)
}

/// `s` with every character outside `[A-Za-z0-9_-]` replaced by `_`.
pub fn slug(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect()
}

/// A configuration's part of run ids, from what it switches on (`physics_ros`,
/// `nophysics_noros`, `physics_ros2`, ...): names are free text, and the switches tell
/// configurations apart.
pub(crate) fn config_slug(c: &Configuration) -> String {
    let transport = if c.ros2 { "ros2" } else if c.ros { "ros" } else { "noros" };
    format!("{}physics_{transport}", if c.physics { "" } else { "no" })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_expand_in_spec_order_and_skip_what_cannot_run() {
        let dir = std::env::temp_dir().join(format!("xhab-plan-{}", std::process::id()));
        let spec = ExperimentSpec::parse(
            "name: s\nscenes: [{scene: 'procedural:3', generate: {count: 5, seed: 2}, limit: 3}]\nagents: [{agent: oracle}, {agent: nav, name: stack}]\nseeds: [0, 7]\n",
            Path::new("s.yaml"),
        )
        .unwrap();
        let p = plan(&spec, &dir).unwrap();
        let ids: Vec<&str> = p.runs.iter().map(|r| r.id.as_str()).collect();
        assert_eq!(ids[..3], ["procedural_3.oracle.nophysics_noros.s0", "procedural_3.oracle.nophysics_noros.s7", "procedural_3.oracle.physics_noros.s0"]);
        // oracle: 4 configurations x 2 seeds; nav: the 2 physics configurations x 2 seeds.
        assert_eq!(p.runs.len(), 12);
        assert_eq!(p.skipped.len(), 2);
        assert!(p.skipped.iter().all(|s| s.agent == "stack" && s.configuration.starts_with("-physics")));
        assert!(p.runs.iter().all(|r| r.episodes == 3 && r.episodes_label == "episodes/procedural_3.json.gz"));
        assert_eq!(p.episodes(), 36);
        // Planned again, the generated set is read back, not regenerated.
        let again = plan(&spec, &dir).unwrap();
        assert_eq!(again, p);
        let o = bench_options(&spec, &p.runs[11], 1, 3).unwrap();
        assert_eq!(o.agent, AgentKind::Nav);
        assert!(matches!(o.transport, Transport::Ros) && o.env.physics.is_some());
        assert_eq!(o.episode_indices, Some(vec![1, 2]));
        assert_eq!(o.seed, 7);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn ros2_configurations_send_xhabs_agents_over_ros2_and_run_external_ros2_stacks() {
        let dir = std::env::temp_dir().join(format!("xhab-plan-ros2-{}", std::process::id()));
        let spec = ExperimentSpec::parse(
            "name: s\nscenes: [{scene: 'procedural:3', generate: {count: 2}}]\nagents: [{agent: oracle}, {agent: ros}, {agent: ros2, external: {launch: 'true'}}]\nconfigurations: [{physics: true, ros2: true}, {physics: true, ros: true}]\n",
            Path::new("s.yaml"),
        )
        .unwrap();
        assert_eq!(spec.configurations[0].label(), "+physics +ROS 2");
        let p = plan(&spec, &dir).unwrap();
        let ids: Vec<&str> = p.runs.iter().map(|r| r.id.as_str()).collect();
        assert_eq!(ids, ["procedural_3.oracle.physics_ros2.s0", "procedural_3.oracle.physics_ros.s0", "procedural_3.ros.physics_ros.s0", "procedural_3.ros2.physics_ros2.s0"]);
        assert_eq!(p.skipped.len(), 2, "{:?}", p.skipped);
        let transports: Vec<(AgentKind, Transport)> = p.runs.iter().map(|r| {
            let o = bench_options(&spec, r, 0, 2).unwrap();
            (o.agent, o.transport)
        }).collect();
        assert!(matches!(transports[0], (AgentKind::Oracle, Transport::Ros2)));
        assert!(matches!(transports[1], (AgentKind::Oracle, Transport::Ros)));
        assert!(matches!(transports[2], (AgentKind::Ros, Transport::InProcess)));
        assert!(matches!(transports[3], (AgentKind::Ros2, Transport::InProcess)));
        let both = ExperimentSpec::parse("name: s\nscenes: [{scene: x, episodes: a}]\nagents: [{agent: oracle}]\nconfigurations: [{physics: true, ros: true, ros2: true}]\n", Path::new("s.yaml")).unwrap_err().to_string();
        assert!(both.contains("configurations[0]") && both.contains("ros2"), "{both}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_study_on_a_two_storey_house_generates_cross_floor_episodes_and_runs_them_there() {
        let dir = std::env::temp_dir().join(format!("xhab-plan-storeys-{}", std::process::id()));
        let spec = ExperimentSpec::parse(
            "name: s\nscenes: [{scene: 'procedural:1', storeys: 2, generate: {count: 3, seed: 4, cross_floor: true}}]\nagents: [{agent: oracle}]\n",
            Path::new("s.yaml"),
        )
        .unwrap();
        let p = plan(&spec, &dir).unwrap();
        let ds = xhab_sim::episode::read_dataset(&dir.join(&p.runs[0].episodes_label)).unwrap();
        assert_eq!(ds.episodes.len(), 3);
        assert!(ds.episodes.iter().all(|e| (e.start_position.z - e.goals[0].position.z).abs() > 2.0));
        let o = bench_options(&spec, &p.runs[0], 0, 3).unwrap();
        assert_eq!(o.env.scene_options.storeys, 2);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_limit_past_the_set_is_an_error() {
        let dir = std::env::temp_dir().join(format!("xhab-plan-limit-{}", std::process::id()));
        let spec = ExperimentSpec::parse("name: s\nscenes: [{scene: 'procedural:3', generate: {count: 2}, limit: 5}]\nagents: [{agent: oracle}]\n", Path::new("s.yaml")).unwrap();
        let e = plan(&spec, &dir).unwrap_err().to_string();
        assert!(e.contains("procedural_3") && e.contains("limit 5"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
