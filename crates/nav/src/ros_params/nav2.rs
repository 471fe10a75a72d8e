//! Nav2 (ROS 2) parameter files: `NODE: {ros__parameters: {...}}` at the top (node names may
//! sit under namespaces, as `global_costmap: {global_costmap: {ros__parameters: ...}}`).
//!
//! Each node's names are checked against the Nav2 registry ([`super::nav2_registry`]): wrong
//! types and values out of range are errors naming the file and key, unknown names are
//! warnings with a "did you mean", and the names with a ROS 1 counterpart are translated into
//! a ROS 1 parameter text that [`super::load`] then reads by its usual rules. A key is named
//! as `ros2 param` does: the node's full name, `/`, the parameter's `.`-separated name.

use super::error::ParamError;
use super::nav2_registry::{nav2_names, nav2_spec, Nav2Role, OTHER_NODES};
use super::suggest::nearest;
use super::tree::ParamSource;
use super::value::{as_bool, as_str, check, show};
use serde_yaml::{Mapping, Value};
use std::collections::BTreeMap;

const PARAMS: &str = "ros__parameters";
const COSTMAP_NODES: [&str; 2] = ["global_costmap", "local_costmap"];
/// Names that say which plugins run (read above, not translated).
const STRUCTURE: [&str; 7] = ["plugin", "plugins", "controller_plugins", "goal_checker_plugins", "progress_checker_plugin", "progress_checker_plugins", "planner_plugins"];
/// Nav2's layers when a costmap lists no `plugins`.
const DEFAULT_LAYERS: [(&str, &str); 3] = [("static_layer", "nav2_costmap_2d::StaticLayer"), ("obstacle_layer", "nav2_costmap_2d::ObstacleLayer"), ("inflation_layer", "nav2_costmap_2d::InflationLayer")];

/// True when `text` is a Nav2 parameter file: some top-level value holds `ros__parameters`.
pub(crate) fn is_nav2(text: &str) -> bool {
    fn holds(v: &Value, depth: usize) -> bool {
        match v {
            Value::Mapping(m) => m.contains_key(PARAMS) || (depth > 0 && m.values().any(|v| holds(v, depth - 1))),
            _ => false,
        }
    }
    match serde_yaml::from_str::<Value>(text) {
        Ok(Value::Mapping(m)) => m.values().any(|v| holds(v, 3)),
        _ => false,
    }
}

/// A Nav2 file read as ROS 1 parameters.
#[derive(Debug, Clone)]
pub(crate) struct Translated {
    /// ROS 1 parameters (move_base's namespace) with the file's name.
    pub source: ParamSource,
    /// Unknown names, plugins xhab does not run, keys outside any node.
    pub warnings: Vec<String>,
    /// Known keys without a counterpart in xhab, in file order.
    pub idle: Vec<String>,
    /// Each ROS 1 name written, with the Nav2 key it came from.
    pub keys: BTreeMap<String, String>,
}

/// A node's parameters: `.`-joined names and their values, in file order.
type Leaves = Vec<(String, Value)>;

fn flatten(prefix: &str, v: &Value, out: &mut Leaves) {
    match v {
        Value::Mapping(m) => {
            for (k, sub) in m {
                let k = match k {
                    Value::String(s) => s.clone(),
                    other => show(other),
                };
                flatten(&if prefix.is_empty() { k } else { format!("{prefix}.{k}") }, sub, out);
            }
        }
        _ => out.push((prefix.to_string(), v.clone())),
    }
}

/// Translates the Nav2 file `file` (its text `text`); `namespace` (may be empty) keeps only the
/// nodes under it.
pub(crate) fn translate(file: &str, text: &str, namespace: &str) -> Result<Translated, ParamError> {
    let doc: Value = serde_yaml::from_str(text).map_err(|e| ParamError::Yaml { file: file.into(), message: e.to_string() })?;
    let mut t = Tr { file, out: Mapping::new(), warnings: Vec::new(), idle: Vec::new(), keys: BTreeMap::new() };
    let mut nodes = Vec::new();
    find_nodes("", &doc, &mut nodes, &mut t.warnings, file);
    let ns = namespace.trim_matches('/');
    for (path, params) in nodes {
        if !ns.is_empty() && !(path == ns || path.starts_with(&format!("{ns}/"))) {
            continue;
        }
        let mut leaves = Leaves::new();
        flatten("", &params, &mut leaves);
        let node = path.rsplit('/').next().unwrap_or(&path).to_string();
        t.node(&path, &node, &leaves)?;
    }
    let text = serde_yaml::to_string(&Value::Mapping(t.out)).map_err(|e| ParamError::Yaml { file: file.into(), message: e.to_string() })?;
    Ok(Translated { source: ParamSource { name: file.into(), text, namespace: String::new() }, warnings: t.warnings, idle: t.idle, keys: t.keys })
}

fn find_nodes(path: &str, v: &Value, nodes: &mut Vec<(String, Value)>, warnings: &mut Vec<String>, file: &str) {
    let Value::Mapping(m) = v else {
        warnings.push(format!("{file}: {path}: not under a node's {PARAMS}, ignored"));
        return;
    };
    if let Some(p) = m.get(PARAMS) {
        nodes.push((path.to_string(), p.clone()));
        for k in m.keys().filter(|k| k.as_str() != Some(PARAMS)) {
            warnings.push(format!("{file}: {path}/{}: not under {PARAMS}, ignored", show(k).trim_matches('"')));
        }
        return;
    }
    for (k, sub) in m {
        let k = k.as_str().map(str::to_string).unwrap_or_else(|| show(k));
        find_nodes(&if path.is_empty() { k } else { format!("{path}/{k}") }, sub, nodes, warnings, file);
    }
}

/// Where a name goes: its role, its name inside the role, the ROS 1 prefix.
struct Place {
    role: Nav2Role,
    name: String,
    ros1: String,
}

struct Tr<'a> {
    file: &'a str,
    out: Mapping,
    warnings: Vec<String>,
    idle: Vec<String>,
    keys: BTreeMap<String, String>,
}

/// `key`'s string list value (Nav2's plugin lists), or `default`.
fn list(leaves: &Leaves, key: &str, default: &[&str]) -> Vec<String> {
    match leaves.iter().find(|(k, _)| k == key).map(|(_, v)| v) {
        Some(Value::Sequence(s)) => s.iter().filter_map(|v| v.as_str().map(str::to_string)).collect(),
        Some(Value::String(s)) => s.split([' ', ',']).filter(|s| !s.is_empty()).map(str::to_string).collect(),
        _ => default.iter().map(|s| s.to_string()).collect(),
    }
}

fn string(leaves: &Leaves, key: &str) -> Option<String> {
    leaves.iter().find(|(k, _)| k == key).and_then(|(_, v)| v.as_str()).map(str::to_string)
}

impl Tr<'_> {
    fn node(&mut self, path: &str, node: &str, leaves: &Leaves) -> Result<(), ParamError> {
        let display = |k: &str| format!("{path}/{k}");
        // Plugins by name: (name, role, ROS 1 prefix); names of plugins xhab does not run.
        let mut plugins: Vec<(String, Nav2Role, String)> = Vec::new();
        let mut foreign: Vec<String> = Vec::new();
        let own = match node {
            "controller_server" => {
                let mut dwb = false;
                for c in list(leaves, "controller_plugins", &["FollowPath"]) {
                    // No `plugin` (Nav2 would refuse to start): read as DWB's names.
                    let ty = string(leaves, &format!("{c}.plugin")).unwrap_or("dwb_core::DWBLocalPlanner".into());
                    if ty == "dwb_core::DWBLocalPlanner" && !dwb {
                        dwb = true;
                        plugins.push((c, Nav2Role::Dwb, "DWAPlannerROS/".into()));
                    } else {
                        self.warnings.push(format!("{}: {}: `{c}` ({ty}) is not a controller xhab runs (xhab runs one DWA controller, read from a dwb_core::DWBLocalPlanner's parameters): its parameters have no effect", self.file, display("controller_plugins")));
                        foreign.push(c);
                    }
                }
                for g in list(leaves, "goal_checker_plugins", &["goal_checker"]) {
                    plugins.push((g, Nav2Role::GoalChecker, "DWAPlannerROS/".into()));
                }
                let progress = leaves.iter().any(|(k, _)| k == "progress_checker_plugins");
                let progress = if progress { list(leaves, "progress_checker_plugins", &[]) } else { vec![string(leaves, "progress_checker_plugin").unwrap_or("progress_checker".into())] };
                for p in progress {
                    plugins.push((p, Nav2Role::ProgressChecker, String::new()));
                }
                Some((Nav2Role::ControllerServer, String::new()))
            }
            "planner_server" => {
                for p in list(leaves, "planner_plugins", &["GridBased"]) {
                    let ty = string(leaves, &format!("{p}.plugin")).unwrap_or_default();
                    if !ty.starts_with("nav2_navfn_planner") {
                        self.warnings.push(format!("{}: {}: xhab plans with its own grid planner (navfn's Dijkstra or A*) in place of `{p}` ({ty}); its tolerance is read", self.file, display("planner_plugins")));
                    }
                    plugins.push((p, Nav2Role::Planner, "GlobalPlanner/".into()));
                }
                Some((Nav2Role::PlannerServer, String::new()))
            }
            cm if COSTMAP_NODES.contains(&cm) => {
                let names = list(leaves, "plugins", &DEFAULT_LAYERS.map(|l| l.0));
                let mut ros1_layers = Vec::new();
                for l in names {
                    // A default layer's name without `plugin` is taken as that layer.
                    let default_ty = DEFAULT_LAYERS.iter().find(|d| d.0 == l).map(|d| d.1.to_string());
                    let ty = string(leaves, &format!("{l}.plugin")).or(default_ty).unwrap_or_default();
                    let (role, ros1_ty) = match ty.as_str() {
                        "nav2_costmap_2d::StaticLayer" => (Some(Nav2Role::StaticLayer), "costmap_2d::StaticLayer".to_string()),
                        "nav2_costmap_2d::ObstacleLayer" => (Some(Nav2Role::ObstacleLayer), "costmap_2d::ObstacleLayer".into()),
                        "nav2_costmap_2d::VoxelLayer" => (Some(Nav2Role::VoxelLayer), "costmap_2d::VoxelLayer".into()),
                        "nav2_costmap_2d::InflationLayer" => (Some(Nav2Role::InflationLayer), "costmap_2d::InflationLayer".into()),
                        other => (None, other.to_string()),
                    };
                    let mut layer = Mapping::new();
                    layer.insert("name".into(), l.clone().into());
                    layer.insert("type".into(), ros1_ty.into());
                    ros1_layers.push(Value::Mapping(layer));
                    match role {
                        Some(r) => {
                            if matches!(r, Nav2Role::ObstacleLayer | Nav2Role::VoxelLayer) {
                                for s in string(leaves, &format!("{l}.observation_sources")).unwrap_or_default().split_whitespace() {
                                    plugins.push((format!("{l}.{s}"), Nav2Role::ObservationSource, format!("{cm}/{l}/{s}/")));
                                }
                            }
                            plugins.push((l.clone(), r, format!("{cm}/{l}/")));
                        }
                        None => foreign.push(l),
                    }
                }
                let plugins_key = format!("{cm}/plugins");
                self.keys.insert(plugins_key.clone(), display("plugins"));
                self.out.insert(plugins_key.into(), Value::Sequence(ros1_layers));
                Some((Nav2Role::Costmap, format!("{cm}/")))
            }
            "amcl" => Some((Nav2Role::Amcl, "amcl/".into())),
            other if OTHER_NODES.contains(&other) => None,
            other => {
                let known = ["controller_server", "planner_server", "global_costmap", "local_costmap", "amcl"];
                let hint = nearest(other, known.into_iter().chain(OTHER_NODES.iter().copied())).map(|h| format!(" (did you mean `{h}`?)")).unwrap_or_default();
                self.warnings.push(format!("{}: {path}: unknown Nav2 node, ignored{hint}", self.file));
                return Ok(());
            }
        };
        // Longest plugin names first, so `obstacle_layer.scan` wins over `obstacle_layer`.
        plugins.sort_by_key(|p| std::cmp::Reverse(p.0.len()));
        for (key, value) in leaves {
            let shown = display(key);
            let Some((own_role, own_prefix)) = &own else {
                self.idle.push(shown);
                continue;
            };
            if foreign.iter().any(|f| key.starts_with(&format!("{f}."))) {
                self.idle.push(shown);
                continue;
            }
            let place = plugins
                .iter()
                .find_map(|(p, role, ros1)| key.strip_prefix(&format!("{p}.")).map(|rest| Place { role: *role, name: rest.to_string(), ros1: ros1.clone() }))
                .unwrap_or(Place { role: *own_role, name: key.clone(), ros1: own_prefix.clone() });
            let Some(spec) = nav2_spec(place.role, &place.name) else {
                // A layer listed nowhere (Nav2 ignores it too) is without effect, not unknown.
                if COSTMAP_NODES.contains(&node) && key.contains('.') && place.role == Nav2Role::Costmap {
                    self.idle.push(shown);
                    continue;
                }
                let prefix = key.strip_suffix(&place.name).unwrap_or("");
                let mut candidates: Vec<String> = nav2_names(place.role).map(|s| format!("{prefix}{}", s.name)).collect();
                if place.role == *own_role {
                    candidates.extend(plugins.iter().flat_map(|(p, role, _)| nav2_names(*role).map(move |s| format!("{p}.{}", s.name))));
                }
                let hint = nearest(key, candidates.iter().map(String::as_str)).map(|h| format!(" (did you mean `{h}`?)")).unwrap_or_default();
                self.warnings.push(format!("{}: {shown}: unknown parameter, ignored{hint}", self.file));
                continue;
            };
            check(value, spec.ty).map_err(|message| ParamError::Value { file: self.file.into(), key: shown.clone(), message })?;
            // Plugin lists and the types of plugins xhab runs shaped the translation above.
            if STRUCTURE.contains(&place.name.as_str()) && place.role != Nav2Role::ObservationSource {
                continue;
            }
            let Some(ros1) = spec.ros1 else {
                self.idle.push(shown);
                continue;
            };
            let value = match spec.name {
                "use_astar" => Value::Bool(!as_bool(value).unwrap_or(false)),
                "robot_model_type" => Value::String(
                    match as_str(value).unwrap_or_default() {
                        "nav2_amcl::DifferentialMotionModel" | "nav2_amcl::DiffMotionModel" | "differential" => "diff",
                        "nav2_amcl::OmniMotionModel" | "omnidirectional" => "omni",
                        _ => return Err(ParamError::Value { file: self.file.into(), key: shown, message: format!("must be nav2_amcl::DifferentialMotionModel or nav2_amcl::OmniMotionModel, got {}", show(value)) }),
                    }
                    .into(),
                ),
                _ => value.clone(),
            };
            let ros1_key = format!("{}{ros1}", place.ros1);
            self.keys.insert(ros1_key.clone(), shown);
            self.out.insert(ros1_key.into(), value);
        }
        Ok(())
    }
}
