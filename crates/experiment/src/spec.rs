//! The experiment as data: scenes, episode sets, agents, configurations (±physics, ±ROS)
//! and seeds, read from a YAML (or JSON) file. [`crate::plan`] expands it into runs.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A study: every scene × agent × configuration × seed is one run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentSpec {
    /// The study's name (titles the report).
    pub name: String,
    /// What the study asks (shown in the report).
    #[serde(default)]
    pub description: String,
    /// Scenes and their episode sets.
    pub scenes: Vec<SceneSpec>,
    /// Agents under test.
    pub agents: Vec<AgentSpec>,
    /// Configurations every agent runs under (default: the four ±physics × ±ROS).
    #[serde(default = "four_configurations")]
    pub configurations: Vec<Configuration>,
    /// Seeds; each makes its own runs (default `[0]`).
    #[serde(default = "default_seeds")]
    pub seeds: Vec<u64>,
    /// Worker threads for in-process runs (results do not depend on it; default 1).
    #[serde(default = "one")]
    pub threads: usize,
    /// Task settings: Habitat's names and defaults (`success_distance`, `max_episode_steps`, ...).
    #[serde(default)]
    pub task: xhab_sim::env::TaskConfig,
    /// Trajectory maps in the report.
    #[serde(default)]
    pub trajectories: TrajectorySpec,
}

/// A scene and the episodes run on it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// Short name used in run ids and the report (default: the file stem).
    #[serde(default)]
    pub name: Option<String>,
    /// The SCENE argument: a GLB/OBJ/PLY file or `procedural[:SEED]`.
    pub scene: String,
    /// A Habitat PointNav episodes file (`.json.gz`/`.json`); or use `generate`.
    #[serde(default)]
    pub episodes: Option<String>,
    /// Episodes generated on the scene's default floor instead of read from a file.
    #[serde(default)]
    pub generate: Option<GenerateSpec>,
    /// Only the first `limit` episodes of the set.
    #[serde(default)]
    pub limit: Option<usize>,
    /// Keep meshes named "ceiling" (default false: dropped, as `xhab bench` does).
    #[serde(default)]
    pub keep_ceilings: bool,
    /// Storeys of the procedural house (`xhab --storeys`; default 1).
    #[serde(default = "one_storey")]
    pub storeys: usize,
}

fn one_storey() -> usize {
    1
}

/// Episodes generated as `xhab episodes` does.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GenerateSpec {
    /// How many.
    pub count: usize,
    /// The generator's seed (default 0).
    #[serde(default)]
    pub seed: u64,
    /// Pairs on different storeys joined by stairs, as `xhab episodes --cross-floor`
    /// (default false: the default floor).
    #[serde(default)]
    pub cross_floor: bool,
}

/// Which agent, and how it is set up.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AgentSpec {
    /// Short name used in run ids and the report (default: the agent kind).
    #[serde(default)]
    pub name: Option<String>,
    /// `oracle` (Habitat's ShortestPathFollower), `nav` (the native stack), `ros` (an
    /// external ROS 1 stack, which `launch` starts) or `ros2` (an external ROS 2 stack offering
    /// `navigate_to_pose`, Nav2's, which `launch` starts).
    pub agent: AgentKindSpec,
    /// Robot profile under physics: habitat, locobot, turtlebot3_burger, turtlebot3_waffle or
    /// a .yaml file (default habitat).
    #[serde(default = "default_robot")]
    pub robot: String,
    /// Localisation of the nav agent: ground_truth, odom or amcl (default ground_truth).
    #[serde(default)]
    pub localization: xhab_bridge::nav_agent::Localization,
    /// Laser scans of the nav and ros agents: lidar, depth or none (default lidar).
    #[serde(default)]
    pub scans: ScansSpec,
    /// Static map (map_server YAML) of the nav agent (default: the map of the episode's floor).
    #[serde(default)]
    pub map: Option<String>,
    /// ROS parameter files layered in order, `FILE[@NAMESPACE]` as `--nav-params` takes them.
    #[serde(default)]
    pub nav_params: Vec<String>,
    /// The external stack (`agent: ros` or `agent: ros2`).
    #[serde(default)]
    pub external: Option<ExternalStackSpec>,
}

/// The agent kinds an experiment can run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AgentKindSpec {
    /// Habitat's ShortestPathFollower.
    Oracle,
    /// xhab's native navigation stack.
    Nav,
    /// An external ROS 1 stack.
    Ros,
    /// An external ROS 2 stack (Nav2, or any node offering `navigate_to_pose`).
    Ros2,
}

/// Where the nav and ros agents' scans come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ScansSpec {
    /// The robot's planar lidar.
    #[default]
    Lidar,
    /// The depth camera through depthimage_to_laserscan.
    Depth,
    /// No scans (static map only).
    None,
}

/// How the external stack is started and driven (`xhab bench --agent ros`'s and
/// `--agent ros2`'s flags).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExternalStackSpec {
    /// A command that starts the stack (`sh -c`), stopped at the end of each run.
    #[serde(default)]
    pub launch: Option<String>,
    /// The simulator node's ROS arguments (ROS 1: `from:=to`, `__ns:=NS`; ROS 2: `-r`,
    /// `from:=to`, ...).
    #[serde(default)]
    pub ros_args: Vec<String>,
    /// `action` (move_base's action server, or Nav2's `navigate_to_pose`; default) or `simple`
    /// (move_base_simple/goal, or Nav2's goal_pose).
    #[serde(default = "default_goal_interface")]
    pub goal_interface: String,
    /// Simulated seconds after which an episode's goal is cancelled (s, default 120).
    #[serde(default = "default_episode_timeout")]
    pub episode_timeout: f64,
    /// Who publishes map -> odom: `stack` (default) or `ground_truth`.
    #[serde(default = "default_map_odom")]
    pub map_odom: String,
}

/// One of the study's conditions.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Configuration {
    /// Its name in run ids and the report (default: `±physics ±ROS`, or `±physics +ROS 2`).
    #[serde(default)]
    pub name: Option<String>,
    /// Rigid-body physics (Algorithm 1 under rapier3d) instead of teleport-and-slide.
    pub physics: bool,
    /// Agent and simulator as separate ROS 1 nodes in lock-step (default false).
    #[serde(default)]
    pub ros: bool,
    /// Agent and simulator as separate ROS 2 nodes in lock-step (default false; not with
    /// `ros`).
    #[serde(default)]
    pub ros2: bool,
}

impl Configuration {
    /// The configuration's name: given, or `+physics -ROS` style (`+ROS 2` over ROS 2).
    pub fn label(&self) -> String {
        let physics = if self.physics { "+" } else { "-" };
        if self.ros2 {
            return self.name.clone().unwrap_or_else(|| format!("{physics}physics +ROS 2"));
        }
        self.name.clone().unwrap_or_else(|| format!("{physics}physics {}ROS", if self.ros { "+" } else { "-" }))
    }
}

/// Which episodes get a top-down trajectory map in the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrajectorySpec {
    /// The `worst` lowest-SPL episodes of each run (default 2).
    #[serde(default = "two")]
    pub worst: usize,
    /// These episode ids, in every run that has them.
    #[serde(default)]
    pub episodes: Vec<String>,
}

impl Default for TrajectorySpec {
    fn default() -> Self {
        Self { worst: 2, episodes: Vec::new() }
    }
}

fn four_configurations() -> Vec<Configuration> {
    let c = |physics, ros| Configuration { name: None, physics, ros, ros2: false };
    vec![c(false, false), c(true, false), c(false, true), c(true, true)]
}
fn default_seeds() -> Vec<u64> {
    vec![0]
}
fn one() -> usize {
    1
}
fn two() -> usize {
    2
}
fn default_robot() -> String {
    "habitat".into()
}
fn default_goal_interface() -> String {
    "action".into()
}
fn default_map_odom() -> String {
    "stack".into()
}
fn default_episode_timeout() -> f64 {
    120.0
}

/// Why a spec could not be read.
#[derive(Debug, thiserror::Error)]
pub enum SpecError {
    /// The file could not be read.
    #[error("reading {path}")]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The YAML is malformed or a field is wrong.
    #[error("{path}: field `{field}`: {message}")]
    Field {
        /// The file.
        path: PathBuf,
        /// The field's path (`scenes[0].episodes`).
        field: String,
        /// What is wrong.
        message: String,
    },
}

impl ExperimentSpec {
    /// Reads and checks a spec file (YAML, of which JSON is a subset); `${VAR}` and
    /// `${VAR:-default}` in scene, episode, map and parameter paths expand from the
    /// environment (`${XHAB_DATA:-../shared}`). Relative paths are relative to the
    /// directory the command runs in, as `xhab bench`'s are.
    pub fn read(path: &Path) -> Result<Self, SpecError> {
        let text = std::fs::read_to_string(path).map_err(|source| SpecError::Read { path: path.to_path_buf(), source })?;
        Self::parse(&text, path)
    }

    /// [`read`](Self::read) from text; `path` names the file in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Self, SpecError> {
        let field = |field: String, message: String| SpecError::Field { path: path.to_path_buf(), field, message };
        let de = serde_yaml::Deserializer::from_str(text);
        let mut spec: ExperimentSpec = serde_path_to_error::deserialize(de).map_err(|e| {
            let f = e.path().to_string();
            field(if f == "." { "(top level)".into() } else { f }, e.into_inner().to_string())
        })?;
        spec.expand_env().map_err(|(f, m)| field(f, m))?;
        spec.check().map_err(|(f, m)| field(f, m))?;
        Ok(spec)
    }

    /// Expands `${VAR}` / `${VAR:-default}` in every path.
    fn expand_env(&mut self) -> Result<(), (String, String)> {
        for (i, s) in self.scenes.iter_mut().enumerate() {
            s.scene = expand(&s.scene).map_err(|m| (format!("scenes[{i}].scene"), m))?;
            if let Some(e) = &mut s.episodes {
                *e = expand(e).map_err(|m| (format!("scenes[{i}].episodes"), m))?;
            }
        }
        for (i, a) in self.agents.iter_mut().enumerate() {
            if let Some(m) = &mut a.map {
                *m = expand(m).map_err(|msg| (format!("agents[{i}].map"), msg))?;
            }
            for (j, p) in a.nav_params.iter_mut().enumerate() {
                *p = expand(p).map_err(|m| (format!("agents[{i}].nav_params[{j}]"), m))?;
            }
            if let Some(x) = &mut a.external {
                if let Some(l) = &mut x.launch {
                    *l = expand(l).map_err(|m| (format!("agents[{i}].external.launch"), m))?;
                }
            }
        }
        Ok(())
    }

    /// Checks what serde cannot: non-empty lists, unique names, one episode source per scene.
    fn check(&self) -> Result<(), (String, String)> {
        let nonempty = |n: usize, f: &str| if n == 0 { Err((f.to_string(), "must list at least one".to_string())) } else { Ok(()) };
        nonempty(self.scenes.len(), "scenes")?;
        nonempty(self.agents.len(), "agents")?;
        nonempty(self.configurations.len(), "configurations")?;
        nonempty(self.seeds.len(), "seeds")?;
        if self.threads == 0 {
            return Err(("threads".into(), "must be at least 1".into()));
        }
        for (i, s) in self.scenes.iter().enumerate() {
            match (&s.episodes, &s.generate) {
                (Some(_), Some(_)) => return Err((format!("scenes[{i}]"), "give `episodes` (a file) or `generate`, not both".into())),
                (None, None) => return Err((format!("scenes[{i}]"), "needs `episodes` (a file) or `generate: {count: N}`".into())),
                (None, Some(g)) if g.count == 0 => return Err((format!("scenes[{i}].generate.count"), "must be at least 1".into())),
                _ => {}
            }
            if s.limit == Some(0) {
                return Err((format!("scenes[{i}].limit"), "must be at least 1".into()));
            }
        }
        for (i, a) in self.agents.iter().enumerate() {
            for (j, p) in a.nav_params.iter().enumerate() {
                p.parse::<xhab_bridge::benchmark::ParamFile>().map_err(|e| (format!("agents[{i}].nav_params[{j}]"), e.to_string()))?;
            }
            if a.external.is_some() && !matches!(a.agent, AgentKindSpec::Ros | AgentKindSpec::Ros2) {
                return Err((format!("agents[{i}].external"), "only `agent: ros` and `agent: ros2` drive an external stack".into()));
            }
            if let Some(x) = &a.external {
                if !matches!(x.goal_interface.as_str(), "action" | "simple") {
                    return Err((format!("agents[{i}].external.goal_interface"), format!("`{}`: expected action or simple", x.goal_interface)));
                }
                if !matches!(x.map_odom.as_str(), "stack" | "ground_truth") {
                    return Err((format!("agents[{i}].external.map_odom"), format!("`{}`: expected stack or ground_truth", x.map_odom)));
                }
                if !(x.episode_timeout > 0.0 && x.episode_timeout.is_finite()) {
                    return Err((format!("agents[{i}].external.episode_timeout"), "must be a positive number of seconds".into()));
                }
            }
        }
        if let Some(i) = self.configurations.iter().position(|c| c.ros && c.ros2) {
            return Err((format!("configurations[{i}]"), "ros and ros2 cannot both be true: a run goes over one of them".into()));
        }
        unique(self.scenes.iter().map(|s| s.label()), "scenes", "name")?;
        unique(self.agents.iter().map(|a| a.label()), "agents", "name")?;
        unique(self.configurations.iter().map(|c| c.label()), "configurations", "name")?;
        unique(self.configurations.iter().map(|c| format!("physics: {}, ros: {}, ros2: {}", c.physics, c.ros, c.ros2)), "configurations", "")?;
        unique(self.seeds.iter().map(|s| s.to_string()), "seeds", "")?;
        Ok(())
    }
}

impl SceneSpec {
    /// The scene's name: given, or the scene file's stem (`procedural_3` for `procedural:3`).
    pub fn label(&self) -> String {
        self.name.clone().unwrap_or_else(|| {
            let stem = Path::new(&self.scene).file_stem().map_or_else(|| self.scene.clone(), |s| s.to_string_lossy().into_owned());
            stem.replace(':', "_")
        })
    }
}

impl AgentSpec {
    /// The agent's name: given, or its kind (`oracle`, `nav`, `ros`, `ros2`).
    pub fn label(&self) -> String {
        self.name.clone().unwrap_or_else(|| match self.agent {
            AgentKindSpec::Oracle => "oracle".into(),
            AgentKindSpec::Nav => "nav".into(),
            AgentKindSpec::Ros => "ros".into(),
            AgentKindSpec::Ros2 => "ros2".into(),
        })
    }
}

/// Fails on the first repeated name.
fn unique(names: impl Iterator<Item = String>, list: &str, field: &str) -> Result<(), (String, String)> {
    let mut seen = std::collections::BTreeMap::new();
    for (i, n) in names.enumerate() {
        if let Some(j) = seen.insert(n.clone(), i) {
            let f = if field.is_empty() { format!("{list}[{i}]") } else { format!("{list}[{i}].{field}") };
            return Err((f, format!("`{n}` is also {list}[{j}]'s; names must differ")));
        }
    }
    Ok(())
}

/// Expands `${VAR}` and `${VAR:-default}` from the environment (an unset variable without a
/// default is an error naming it).
pub fn expand(s: &str) -> Result<String, String> {
    let mut out = String::new();
    let mut rest = s;
    while let Some(start) = rest.find("${") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        let end = after.find('}').ok_or_else(|| format!("`{s}`: unclosed `${{`"))?;
        let inner = &after[..end];
        let (name, default) = match inner.split_once(":-") {
            Some((n, d)) => (n, Some(d)),
            None => (inner, None),
        };
        if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(format!("`{s}`: bad variable name `{name}`"));
        }
        match (std::env::var(name).ok().filter(|v| !v.is_empty()), default) {
            (Some(v), _) => out.push_str(&v),
            (None, Some(d)) => out.push_str(d),
            (None, None) => return Err(format!("`{s}`: ${{{name}}} is not set (write ${{{name}:-DEFAULT}} for a default)")),
        }
        rest = &after[end + 1..];
    }
    out.push_str(rest);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(y: &str) -> Result<ExperimentSpec, SpecError> {
        ExperimentSpec::parse(y, Path::new("study.yaml"))
    }

    #[test]
    fn defaults_give_the_four_configurations() {
        let s = parse("name: s\nscenes: [{scene: 'procedural:3', generate: {count: 4}}]\nagents: [{agent: oracle}]\n").unwrap();
        let labels: Vec<String> = s.configurations.iter().map(|c| c.label()).collect();
        assert_eq!(labels, ["-physics -ROS", "+physics -ROS", "-physics +ROS", "+physics +ROS"]);
        assert_eq!(s.seeds, [0]);
        assert_eq!(s.scenes[0].label(), "procedural_3");
        assert_eq!(s.agents[0].label(), "oracle");
        assert_eq!(s.agents[0].robot, "habitat");
    }

    #[test]
    fn errors_name_the_file_and_field() {
        let e = parse("name: s\nscenes: [{scene: x, episodes: e.json, limt: 3}]\nagents: [{agent: oracle}]\n").unwrap_err().to_string();
        assert!(e.contains("study.yaml") && e.contains("scenes[0]") && e.contains("limt"), "{e}");
        let e = parse("name: s\nscenes: [{scene: x, episodes: e.json}]\nagents: [{agent: orcale}]\n").unwrap_err().to_string();
        assert!(e.contains("agents[0].agent") && e.contains("orcale"), "{e}");
        let e = parse("name: s\nscenes: [{scene: x}]\nagents: [{agent: oracle}]\n").unwrap_err().to_string();
        assert!(e.contains("scenes[0]") && e.contains("generate"), "{e}");
        let e = parse("name: s\nscenes: [{scene: x, episodes: a}, {scene: y/x.glb, episodes: b}]\nagents: [{agent: oracle}]\n").unwrap_err().to_string();
        assert!(e.contains("scenes[1].name") && e.contains("`x`"), "{e}");
        let e = parse("name: s\nscenes: [{scene: x, episodes: a}]\nagents: [{agent: nav, nav_params: ['f.yaml@1bad']}]\n").unwrap_err().to_string();
        assert!(e.contains("agents[0].nav_params[0]"), "{e}");
        let e = parse("name: s\nscenes: [{scene: '${XHAB_SURELY_UNSET_VAR}/a.glb', episodes: a}]\nagents: [{agent: oracle}]\n").unwrap_err().to_string();
        assert!(e.contains("scenes[0].scene") && e.contains("XHAB_SURELY_UNSET_VAR"), "{e}");
        let e = parse("name: s\nscenes: [{scene: x, episodes: a}]\nagents: [{agent: oracle}]\nconfigurations: [{physics: true, ros: false}, {name: again, physics: true, ros: false}]\n").unwrap_err().to_string();
        assert!(e.contains("configurations[1]") && e.contains("physics: true, ros: false"), "{e}");
        let e = parse("name: s\nscenes: [{scene: x, episodes: a}]\nagents: [{agent: oracle}]\nthreads: 0\n").unwrap_err().to_string();
        assert!(e.contains("`threads`"), "{e}");
    }

    #[test]
    fn variables_expand_with_defaults() {
        assert_eq!(expand("${XHAB_SURELY_UNSET_VAR:-../shared}/scenes/a.glb").unwrap(), "../shared/scenes/a.glb");
        assert_eq!(expand("plain/path").unwrap(), "plain/path");
        assert!(expand("${UNCLOSED").is_err());
        assert!(expand("${bad-name}").is_err());
    }
}
