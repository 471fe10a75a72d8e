//! From the layered files to [`NavParams`]: every key is checked against the registry, the
//! implemented ones are read with ROS's lookup rules, and the rest come back as warnings.
//!
//! The files are read as move_base's private namespace: move_base's own names at the top,
//! `global_costmap/`, `local_costmap/`, the local planner's (`DWAPlannerROS/`, or
//! `TrajectoryPlannerROS/` when `base_local_planner` names it) and the global planner's
//! (`GlobalPlanner/` or `NavfnROS/`). A leading `move_base/` is the same namespace. amcl's names
//! go under `amcl/`, or at the top (they do not clash with move_base's).
//!
//! Lookup rules follow ROS: `footprint` and `robot_radius` are searched from the costmap's
//! namespace up to move_base's (a valid `footprint` wins and `robot_radius` is then unread);
//! a name at a costmap's top wins over the same name in its layer; an observation source's
//! `obstacle_range`/`raytrace_range` win over the layer's; the local planner's
//! `controller_frequency` is found by searching up to move_base's.
//!
//! Where xhab has one value for what ROS keeps per costmap (one obstacle layer for both
//! costmaps, one control period), the local costmap's (move_base's) value is taken and a
//! disagreement is a warning.

use super::error::ParamError;
use super::nav2::{is_nav2, translate};
use super::layout::{old_layers, parse_plugins, parse_sources, LayerKind, Layout, Source};
use super::registry::{names, spec, Effect, ParamSpec, RosNode};
use super::suggest::nearest;
use super::tree::{Leaf, ParamSource, ParamTree};
use super::value::{as_bool, as_f64, as_footprint, as_i64, as_str, check, show};
use crate::amcl::{LaserModelType, OdomModelType};
use crate::navigator::NavParams;
use std::collections::{BTreeMap, HashSet};

const COSTMAPS: [&str; 2] = ["global_costmap", "local_costmap"];
const NAMESPACES: [&str; 7] = ["global_costmap", "local_costmap", "DWAPlannerROS", "TrajectoryPlannerROS", "GlobalPlanner", "NavfnROS", "amcl"];
const DEFAULT_RECOVERIES: [&str; 3] = ["conservative_reset", "rotate_recovery", "aggressive_reset"];

/// Navigation parameters read from ROS parameter files, and what the files said that xhab did
/// not take.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedParams {
    /// The parameters: xhab's defaults where the files say nothing.
    pub params: NavParams,
    /// One line each: unknown keys (with the nearest known name), old names read in place of
    /// new ones, disagreements xhab had to settle, and one line listing every known key
    /// without effect. Meant for stderr.
    pub warnings: Vec<String>,
    /// The files gave the global costmap a `footprint` or `robot_radius`.
    pub global_shape_given: bool,
    /// The files gave the local costmap a `footprint` or `robot_radius`.
    pub local_shape_given: bool,
}

impl LoadedParams {
    /// Gives each costmap whose shape the files did not give the robot's: `radius` (m) and
    /// `footprint` (m, base frame; `None` for a round robot).
    pub fn size_to_robot(&mut self, radius: f64, footprint: Option<&[[f64; 2]]>) {
        let p = &mut self.params;
        for (given, c) in [(self.global_shape_given, &mut p.global_costmap), (self.local_shape_given, &mut p.local_costmap)] {
            if !given {
                c.robot_radius = radius;
                c.footprint = footprint.map(<[_]>::to_vec).unwrap_or_default();
            }
        }
    }
}

/// Reads navigation parameters from ROS parameter files' texts, layered in order as
/// roslaunch's `<rosparam file ns>` loads them (no files: the defaults).
///
/// Errors (naming the file and key) for YAML that does not parse, values of the wrong type
/// and values out of range; warnings for everything else.
///
/// # Example
/// ```
/// use xhab_nav::ros_params::{nav_params_from_sources, ParamSource};
/// let src = |text: &str, ns: &str| ParamSource { name: format!("{ns}.yaml"), text: text.into(), namespace: ns.into() };
/// let loaded = nav_params_from_sources(&[
///     src("inflation_radius: 0.3\nfootprint: [[-0.1, -0.1], [-0.1, 0.1], [0.1, 0.1], [0.1, -0.1]]\n", "global_costmap"),
///     src("DWAPlannerROS: {max_vel_x: 0.22, max_vel_xx: 1}\nshutdown_costmaps: false\n", ""),
/// ])
/// .unwrap();
/// assert_eq!(loaded.params.global_costmap.inflation_radius, 0.3);
/// assert_eq!(loaded.params.dwa.max_vel_x, 0.22);
/// assert!(loaded.global_shape_given && !loaded.local_shape_given);
/// assert!(loaded.warnings[0].contains("did you mean `max_vel_x`"));
/// assert!(loaded.warnings[1].contains("shutdown_costmaps"));
/// ```
///
/// A Nav2 (ROS 2) file, one whose top-level values hold `ros__parameters`, is read by Nav2's
/// names and layered in its place (see [`super::nav2`]); its namespace, if any, keeps only the
/// nodes under it. Warnings and errors then name its keys as Nav2 writes them.
pub fn nav_params_from_sources(sources: &[ParamSource]) -> Result<LoadedParams, ParamError> {
    let mut ros1 = Vec::with_capacity(sources.len());
    let mut nav2_warnings = Vec::new();
    let mut idle = Vec::new();
    let mut keys = BTreeMap::new();
    for s in sources {
        if is_nav2(&s.text) {
            let t = translate(&s.name, &s.text, &s.namespace)?;
            nav2_warnings.extend(t.warnings);
            idle.extend(t.idle);
            keys.extend(t.keys.into_iter().map(|(k, v)| (k, (s.name.clone(), v))));
            ros1.push(t.source);
        } else {
            ros1.push(s.clone());
        }
    }
    let tree = ParamTree::build(&ros1)?;
    let mut loaded = Loader::new(&tree).run().map_err(|e| match e {
        ParamError::Value { file, key, message } => {
            let key = keys.get(&key).filter(|(f, _)| *f == file).map(|(_, k)| k.clone()).unwrap_or(key);
            ParamError::Value { file, key, message }
        }
        other => other,
    })?;
    if keys.is_empty() && idle.is_empty() && nav2_warnings.is_empty() {
        return Ok(loaded);
    }
    let mut warnings = nav2_warnings;
    for w in std::mem::take(&mut loaded.warnings) {
        if let Some((_, list)) = w.split_once(IDLE_MARK) {
            idle.extend(list.split(", ").map(|k| keys.get(k).map(|(_, n)| n.clone()).unwrap_or_else(|| k.to_string())));
            continue;
        }
        // `FILE: KEY: message` with a translated KEY names the Nav2 key.
        let renamed = keys.iter().find_map(|(k, (file, n))| w.strip_prefix(&format!("{file}: {k}: ")).map(|rest| format!("{file}: {n}: {rest}")));
        warnings.push(renamed.unwrap_or(w));
    }
    if !idle.is_empty() {
        warnings.push(idle_line(&idle));
    }
    loaded.warnings = warnings;
    Ok(loaded)
}

/// What the line listing keys without effect says before the keys.
const IDLE_MARK: &str = " ROS parameter(s) without effect in xhab (not implemented, or overridden): ";

fn idle_line<S: AsRef<str>>(keys: &[S]) -> String {
    format!("{}{IDLE_MARK}{}", keys.len(), keys.iter().map(AsRef::as_ref).collect::<Vec<_>>().join(", "))
}

/// How a key was classified.
enum Class {
    Known(&'static ParamSpec),
    Unknown(Option<String>),
    Foreign,
}

struct Loader<'a> {
    tree: &'a ParamTree,
    /// Each parameter by its name in move_base's namespace: the key as placed, and its leaf.
    by_name: BTreeMap<String, (&'a str, &'a Leaf)>,
    /// Keys that another spelling of the same name overrode (`move_base/x` and `x`).
    shadowed: Vec<(&'a str, &'a Leaf)>,
    used: HashSet<String>,
    warnings: Vec<String>,
    layouts: [Layout; 2],
    local_ns: &'static str,
    global_ns: &'static str,
    recoveries: Vec<String>,
}

/// The name of the key `key` inside move_base's namespace (amcl's names under `amcl/`).
fn name_of(key: &str) -> String {
    let k = key.strip_prefix("move_base/").unwrap_or(key);
    if !k.contains('/') && spec(RosNode::MoveBase, k).is_none() && spec(RosNode::Amcl, k).is_some() {
        format!("amcl/{k}")
    } else {
        k.to_string()
    }
}

impl<'a> Loader<'a> {
    fn new(tree: &'a ParamTree) -> Self {
        let mut by_name: BTreeMap<String, (&'a str, &'a Leaf)> = BTreeMap::new();
        let mut shadowed = Vec::new();
        for (key, leaf) in &tree.leaves {
            let name = name_of(key);
            match by_name.get(&name) {
                Some(&(_, l0)) if l0.seq > leaf.seq => shadowed.push((key.as_str(), leaf)),
                Some(&(k0, l0)) => {
                    shadowed.push((k0, l0));
                    by_name.insert(name, (key.as_str(), leaf));
                }
                None => {
                    by_name.insert(name, (key.as_str(), leaf));
                }
            }
        }
        Loader { tree, by_name, shadowed, used: HashSet::new(), warnings: Vec::new(), layouts: Default::default(), local_ns: "DWAPlannerROS", global_ns: "GlobalPlanner", recoveries: Vec::new() }
    }

    fn run(mut self) -> Result<LoadedParams, ParamError> {
        self.structure()?;
        // Check every key; unknown ones are warned about in the order they were loaded.
        let mut entries: Vec<(&String, &(&str, &Leaf))> = self.by_name.iter().collect();
        entries.sort_by_key(|e| e.1 .1.seq);
        let mut unknown = Vec::new();
        let mut renamed = Vec::new();
        for (name, &(key, leaf)) in entries {
            match self.classify(name) {
                Class::Known(s) => {
                    check(&leaf.value, s.ty).map_err(|m| self.err(key, leaf, m))?;
                    if let Effect::Renamed(new) = s.effect {
                        renamed.push((name.clone(), key, leaf, new));
                    }
                }
                Class::Unknown(hint) => {
                    let hint = hint.map(|h| format!(" (did you mean `{h}`?)")).unwrap_or_default();
                    unknown.push(format!("{}: {key}: unknown parameter, ignored{hint}", self.tree.file_of(leaf)));
                }
                Class::Foreign => {}
            }
        }
        let mut p = NavParams::default();
        let mut shape_given = [false; 2];
        self.move_base(&mut p)?;
        for (i, given) in shape_given.iter_mut().enumerate() {
            *given = self.costmap(i, &mut p)?;
        }
        self.obstacles(&mut p)?;
        self.local_planner(&mut p)?;
        self.global_planner(&mut p)?;
        self.amcl(&mut p)?;
        self.cross_checks(&p)?;
        let mut warnings = unknown;
        for (name, key, leaf, new) in renamed {
            if self.used.contains(&name) {
                warnings.push(format!("{}: {key}: old name of `{new}` (noetic warns and no longer reads it), read as `{new}`", self.tree.file_of(leaf)));
            }
        }
        warnings.append(&mut self.warnings);
        let mut idle: Vec<(&str, &Leaf)> = self.by_name.iter().filter(|(n, _)| !self.used.contains(*n)).filter(|(n, _)| !matches!(self.classify(n), Class::Unknown(_))).map(|(_, &e)| e).collect();
        idle.extend(self.shadowed.iter().copied());
        idle.sort_by_key(|e| e.1.seq);
        if !idle.is_empty() {
            let keys: Vec<&str> = idle.iter().map(|e| e.0).collect();
            warnings.push(idle_line(&keys));
        }
        Ok(LoadedParams { params: p, warnings, global_shape_given: shape_given[0], local_shape_given: shape_given[1] })
    }

    fn err(&self, key: &str, leaf: &Leaf, message: String) -> ParamError {
        ParamError::Value { file: self.tree.file_of(leaf).to_string(), key: key.to_string(), message }
    }

    fn warn(&mut self, key: &str, leaf: &Leaf, message: String) {
        self.warnings.push(format!("{}: {key}: {message}", self.tree.file_of(leaf)));
    }

    fn has_namespace(&self, ns: &str) -> bool {
        let prefix = format!("{ns}/");
        self.by_name.keys().any(|k| k.starts_with(&prefix))
    }

    /// The first of `names` present, marked as used.
    fn first<S: AsRef<str>>(&mut self, names: &[S]) -> Option<(&'a str, &'a Leaf)> {
        let (name, hit) = names.iter().find_map(|n| self.by_name.get(n.as_ref()).map(|&h| (n.as_ref(), h)))?;
        self.used.insert(name.to_string());
        Some(hit)
    }

    fn read<S: AsRef<str>, T>(&mut self, names: &[S], conv: impl Fn(&serde_yaml::Value) -> Result<T, String>) -> Result<Option<T>, ParamError> {
        match self.first(names) {
            Some((key, leaf)) => conv(&leaf.value).map(Some).map_err(|m| self.err(key, leaf, m)),
            None => Ok(None),
        }
    }

    fn f64<S: AsRef<str>>(&mut self, names: &[S]) -> Result<Option<f64>, ParamError> {
        self.read(names, as_f64)
    }

    fn set_f64<S: AsRef<str>>(&mut self, to: &mut f64, names: &[S]) -> Result<(), ParamError> {
        if let Some(v) = self.f64(names)? {
            *to = v;
        }
        Ok(())
    }

    fn set_bool<S: AsRef<str>>(&mut self, to: &mut bool, names: &[S]) -> Result<(), ParamError> {
        if let Some(v) = self.read(names, as_bool)? {
            *to = v;
        }
        Ok(())
    }

    fn set_int<S: AsRef<str>, T: TryFrom<i64>>(&mut self, to: &mut T, names: &[S]) -> Result<(), ParamError> {
        let conv = |v: &serde_yaml::Value| as_i64(v).and_then(|i| T::try_from(i).map_err(|_| format!("out of range, got {i}")));
        if let Some(v) = self.read(names, conv)? {
            *to = v;
        }
        Ok(())
    }

    /// Layouts of the costmaps, the planners move_base runs, the recovery behaviours' names.
    fn structure(&mut self) -> Result<(), ParamError> {
        for (i, cm) in COSTMAPS.iter().enumerate() {
            let mut lay = Layout::default();
            let plugins_key = format!("{cm}/plugins");
            if let Some((key, leaf)) = self.first(&[&plugins_key]) {
                lay.plugins = true;
                lay.layers = parse_plugins(&leaf.value, self.tree.file_of(leaf), key)?;
                for l in &lay.layers {
                    if let LayerKind::Other(ty) = &l.kind {
                        self.warn(key, leaf, format!("`{}` ({ty}) is not a layer xhab runs: its parameters have no effect", l.name));
                    }
                }
                let obstacle_layers: Vec<String> = lay.layers.iter().filter(|l| matches!(l.kind, LayerKind::Obstacle | LayerKind::Voxel)).map(|l| l.name.clone()).collect();
                for l in obstacle_layers {
                    if let Some((key, leaf)) = self.first(&[format!("{cm}/{l}/observation_sources")]) {
                        for s in parse_sources(&leaf.value, self.tree.file_of(leaf), key)? {
                            lay.sources.push(Source { prefixes: vec![format!("{l}/{s}")], name: s });
                        }
                    }
                }
            } else {
                let voxel = self.by_name.get(&format!("{cm}/map_type")).is_some_and(|(_, l)| l.value.as_str() == Some("voxel"));
                lay.layers = old_layers(voxel);
                if let Some((key, leaf)) = self.first(&[format!("{cm}/observation_sources"), format!("{cm}/obstacle_layer/observation_sources")]) {
                    for s in parse_sources(&leaf.value, self.tree.file_of(leaf), key)? {
                        lay.sources.push(Source { prefixes: vec![s.clone(), format!("obstacle_layer/{s}")], name: s });
                    }
                }
            }
            self.layouts[i] = lay;
        }
        let planner = |me: &mut Self, key: &str, known: [(&str, &'static str); 2], fallback: &'static str| -> Result<Option<&'static str>, ParamError> {
            let Some((k, leaf)) = me.first(&[key]) else { return Ok(None) };
            let v = as_str(&leaf.value).map_err(|m| me.err(k, leaf, m))?;
            if let Some((_, ns)) = known.iter().find(|(plugin, _)| *plugin == v) {
                return Ok(Some(*ns));
            }
            me.warn(k, leaf, format!("xhab runs its own planner in place of `{v}`, with `{fallback}/` parameters"));
            Ok(Some(fallback))
        };
        let local = planner(self, "base_local_planner", [("dwa_local_planner/DWAPlannerROS", "DWAPlannerROS"), ("base_local_planner/TrajectoryPlannerROS", "TrajectoryPlannerROS")], "DWAPlannerROS")?;
        self.local_ns = local.unwrap_or(if self.has_namespace("DWAPlannerROS") || !self.has_namespace("TrajectoryPlannerROS") { "DWAPlannerROS" } else { "TrajectoryPlannerROS" });
        let global = planner(self, "base_global_planner", [("global_planner/GlobalPlanner", "GlobalPlanner"), ("navfn/NavfnROS", "NavfnROS")], "GlobalPlanner")?;
        self.global_ns = global.unwrap_or(if self.has_namespace("GlobalPlanner") || !self.has_namespace("NavfnROS") { "GlobalPlanner" } else { "NavfnROS" });
        self.recoveries = match self.by_name.get("recovery_behaviors") {
            Some((_, leaf)) => leaf.value.as_sequence().into_iter().flatten().filter_map(|b| b.get("name").and_then(|n| n.as_str()).map(str::to_string)).collect(),
            None => DEFAULT_RECOVERIES.iter().map(|s| s.to_string()).collect(),
        };
        Ok(())
    }

    fn classify(&self, name: &str) -> Class {
        let in_node = |node: RosNode, n: &str| match spec(node, n) {
            Some(s) => Class::Known(s),
            None => Class::Unknown(nearest(n, names(node)).map(str::to_string)),
        };
        let parts: Vec<&str> = name.split('/').collect();
        match parts.as_slice() {
            [n] => match spec(RosNode::MoveBase, n) {
                Some(s) => Class::Known(s),
                None => Class::Unknown(nearest(n, names(RosNode::MoveBase).chain(names(RosNode::Amcl)).chain(NAMESPACES)).map(str::to_string)),
            },
            ["amcl", n] => in_node(RosNode::Amcl, n),
            [cm, rest @ ..] if COSTMAPS.contains(cm) => self.classify_costmap(&self.layouts[usize::from(*cm == COSTMAPS[1])], rest),
            ["DWAPlannerROS", n] => in_node(RosNode::Dwa, n),
            ["TrajectoryPlannerROS", rest @ ..] => in_node(RosNode::TrajectoryPlanner, &rest.join("/")),
            ["GlobalPlanner", n] => in_node(RosNode::GlobalPlanner, n),
            ["NavfnROS", n] => in_node(RosNode::Navfn, n),
            [ns, ..] if self.recoveries.iter().any(|r| r == ns) => Class::Foreign,
            [ns, rest @ ..] => Class::Unknown(nearest(ns, NAMESPACES.iter().copied().chain(self.recoveries.iter().map(String::as_str))).map(|s| format!("{s}/{}", rest.join("/")))),
            [] => Class::Unknown(None),
        }
    }

    fn classify_costmap(&self, lay: &Layout, rest: &[&str]) -> Class {
        let in_node = |node: RosNode, n: &str| match spec(node, n) {
            Some(s) => Class::Known(s),
            None => Class::Unknown(nearest(n, names(node)).map(str::to_string)),
        };
        match rest {
            [] => Class::Unknown(None),
            [n] => in_node(RosNode::Costmap, n),
            [head @ .., n] => {
                if lay.source_at(&head.join("/")).is_some() {
                    return in_node(RosNode::ObservationSource, n);
                }
                match (head, lay.kind_of(head[0])) {
                    ([_], Some(LayerKind::Static)) => in_node(RosNode::StaticLayer, n),
                    ([_], Some(LayerKind::Obstacle)) => in_node(RosNode::ObstacleLayer, n),
                    ([_], Some(LayerKind::Voxel)) => in_node(RosNode::VoxelLayer, n),
                    ([_], Some(LayerKind::Inflation)) => in_node(RosNode::InflationLayer, n),
                    (_, Some(LayerKind::Other(_))) => Class::Foreign,
                    _ => {
                        let known = lay.layers.iter().map(|l| l.name.as_str()).chain(lay.sources.iter().map(|s| s.name.as_str()));
                        Class::Unknown(nearest(head[0], known).map(|s| format!("{s}/{}", rest[1..].join("/"))))
                    }
                }
            }
        }
    }

    fn move_base(&mut self, p: &mut NavParams) -> Result<(), ParamError> {
        let mb = &mut p.move_base;
        self.set_f64(&mut mb.planner_frequency, &["planner_frequency"])?;
        self.set_f64(&mut mb.planner_patience, &["planner_patience"])?;
        self.set_f64(&mut mb.controller_patience, &["controller_patience"])?;
        self.set_f64(&mut mb.oscillation_timeout, &["oscillation_timeout"])?;
        self.set_f64(&mut mb.oscillation_distance, &["oscillation_distance"])?;
        self.set_int(&mut mb.max_planning_retries, &["max_planning_retries"])?;
        self.set_bool(&mut mb.recovery_behavior_enabled, &["recovery_behavior_enabled"])?;
        self.set_bool(&mut mb.clearing_rotation_allowed, &["clearing_rotation_allowed"])?;
        self.set_int(&mut mb.max_recoveries, &["max_recoveries"])?;
        self.set_f64(&mut mb.recovery_rotation_speed, &["recovery_rotation_speed"])?;
        // One control period in xhab: move_base's rate, which the local planner's own
        // `controller_frequency` (found first by its searchParam) stands in for when alone.
        let own = self.f64(&["controller_frequency"])?;
        let planner_key = format!("{}/controller_frequency", self.local_ns);
        let planner = self.f64(&[&planner_key])?;
        if let (Some(a), Some(b)) = (own, planner) {
            if let Some(&(key, leaf)) = self.by_name.get(&planner_key).filter(|_| a != b) {
                self.warn(key, leaf, format!("{b} Hz differs from move_base's controller_frequency {a} Hz: xhab's controller runs at one rate, move_base's"));
            }
        }
        if let Some(f) = own.or(planner) {
            p.dwa.controller_period = 1.0 / f;
        }
        Ok(())
    }

    /// One costmap's shape and inflation; true when the files gave its shape.
    fn costmap(&mut self, i: usize, p: &mut NavParams) -> Result<bool, ParamError> {
        let cm = COSTMAPS[i];
        let lay = self.layouts[i].clone();
        let c = if i == 0 { &mut p.global_costmap } else { &mut p.local_costmap };
        let mut given = false;
        if let Some(Some(poly)) = self.read(&[format!("{cm}/footprint"), "footprint".into()], as_footprint)? {
            c.footprint = poly;
            given = true;
        } else if let Some(r) = self.f64(&[format!("{cm}/robot_radius"), "robot_radius".into()])? {
            c.robot_radius = r;
            c.footprint.clear();
            given = true;
        }
        self.set_f64(&mut c.footprint_padding, &[format!("{cm}/footprint_padding")])?;
        match lay.layer(|k| *k == LayerKind::Inflation) {
            Some(l) => {
                self.set_f64(&mut c.inflation_radius, &[format!("{cm}/inflation_radius"), format!("{cm}/{l}/inflation_radius")])?;
                self.set_f64(&mut c.cost_scaling_factor, &[format!("{cm}/cost_scaling_factor"), format!("{cm}/{l}/cost_scaling_factor")])?;
            }
            None => {
                if let Some(&(key, leaf)) = self.by_name.get(&format!("{cm}/plugins")) {
                    self.warn(key, leaf, format!("no costmap_2d::InflationLayer: xhab inflates anyway (inflation_radius {} m)", c.inflation_radius));
                }
            }
        }
        if i == 0 {
            // The static layer exists only in the global costmap (the local one is cut from it).
            let st: Vec<String> = lay.layer(|k| *k == LayerKind::Static).map(|l| format!("{cm}/{l}/")).into_iter().collect();
            let keys = |n: &str| std::iter::once(format!("{cm}/{n}")).chain(st.iter().map(|s| format!("{s}{n}"))).collect::<Vec<_>>();
            self.set_int(&mut c.lethal_cost_threshold, &keys("lethal_cost_threshold"))?;
            self.set_bool(&mut c.track_unknown_space, &keys("track_unknown_space"))?;
        }
        Ok(given)
    }

    /// What one costmap says of its obstacle layer (for the scans xhab feeds it).
    fn obstacle_reading(&mut self, i: usize) -> Result<ObstacleReading, ParamError> {
        let cm = COSTMAPS[i];
        let lay = self.layouts[i].clone();
        let Some(layer) = lay.layer(|k| matches!(k, LayerKind::Obstacle | LayerKind::Voxel)) else { return Ok(ObstacleReading::default()) };
        let mut chosen: Option<&Source> = None;
        for s in &lay.sources {
            let keys: Vec<String> = s.prefixes.iter().map(|pre| format!("{cm}/{pre}/data_type")).collect();
            // No data_type is PointCloud, costmap_2d's default.
            if let Some((key, leaf)) = self.first(&keys) {
                match as_str(&leaf.value).map_err(|m| self.err(key, leaf, m))? {
                    "LaserScan" => chosen = chosen.or(Some(s)),
                    "PointCloud" | "PointCloud2" => {}
                    other => return Err(self.err(key, leaf, format!("must be LaserScan, PointCloud or PointCloud2, got {other:?}"))),
                }
            }
        }
        if chosen.is_none() && !lay.sources.is_empty() {
            self.warnings.push(format!("{cm}: no observation source has data_type LaserScan; xhab's laser scans mark and clear with the layer's ranges"));
        }
        let src = |n: &str| chosen.map(|s| s.prefixes.iter().map(|pre| format!("{cm}/{pre}/{n}")).collect::<Vec<_>>()).unwrap_or_default();
        let ranged = |n: &str| {
            let mut keys = src(n);
            keys.push(format!("{cm}/{n}"));
            keys.push(format!("{cm}/{layer}/{n}"));
            keys
        };
        let mut r = ObstacleReading { obstacle_range: self.f64(&ranged("obstacle_range"))?, raytrace_range: self.f64(&ranged("raytrace_range"))?, ..Default::default() };
        if chosen.is_some() {
            // costmap_2d's per-source defaults.
            r.marking = Some(self.read(&src("marking"), as_bool)?.unwrap_or(true));
            r.clearing = Some(self.read(&src("clearing"), as_bool)?.unwrap_or(false));
            r.inf_is_valid = Some(self.read(&src("inf_is_valid"), as_bool)?.unwrap_or(false));
        }
        Ok(r)
    }

    /// xhab's one obstacle layer, from the local costmap's settings, else the global's.
    fn obstacles(&mut self, p: &mut NavParams) -> Result<(), ParamError> {
        let (local, global) = (self.obstacle_reading(1)?, self.obstacle_reading(0)?);
        let o = &mut p.obstacle_layer;
        let mut disagree = Vec::new();
        settle("obstacle_range", local.obstacle_range, global.obstacle_range, &mut o.obstacle_range, &mut disagree);
        settle("raytrace_range", local.raytrace_range, global.raytrace_range, &mut o.raytrace_range, &mut disagree);
        settle("marking", local.marking, global.marking, &mut o.marking, &mut disagree);
        settle("clearing", local.clearing, global.clearing, &mut o.clearing, &mut disagree);
        settle("inf_is_valid", local.inf_is_valid, global.inf_is_valid, &mut o.clear_on_max_range, &mut disagree);
        if !disagree.is_empty() {
            self.warnings.push(format!("local_costmap and global_costmap disagree on their obstacle layers' {}: xhab's one obstacle layer takes local_costmap's", disagree.join(", ")));
        }
        let (w, h) = (self.f64(&["local_costmap/width"])?, self.f64(&["local_costmap/height"])?);
        if let (Some(a), Some(b)) = (w, h) {
            if a != b {
                self.warnings.push(format!("local_costmap: width {a} m and height {b} m differ: xhab's rolling window is a square of the larger side"));
            }
        }
        if let Some(side) = w.into_iter().chain(h).reduce(f64::max) {
            o.local_window = side;
        }
        Ok(())
    }

    fn local_planner(&mut self, p: &mut NavParams) -> Result<(), ParamError> {
        let ns = self.local_ns;
        let k = |n: &str| format!("{ns}/{n}");
        let d = &mut p.dwa;
        self.set_f64(&mut d.max_vel_x, &[k("max_vel_x")])?;
        self.set_f64(&mut d.min_vel_x, &[k("min_vel_x")])?;
        self.set_f64(&mut d.acc_lim_x, &[k("acc_lim_x")])?;
        self.set_f64(&mut d.acc_lim_theta, &[k("acc_lim_theta")])?;
        self.set_f64(&mut d.sim_time, &[k("sim_time")])?;
        self.set_f64(&mut d.sim_granularity, &[k("sim_granularity")])?;
        self.set_int(&mut d.vx_samples, &[k("vx_samples")])?;
        self.set_f64(&mut d.xy_goal_tolerance, &[k("xy_goal_tolerance")])?;
        if ns == "DWAPlannerROS" {
            self.set_f64(&mut d.max_vel_trans, &[k("max_vel_trans"), k("max_trans_vel")])?;
            self.set_f64(&mut d.min_vel_trans, &[k("min_vel_trans"), k("min_trans_vel")])?;
            self.set_f64(&mut d.max_vel_theta, &[k("max_vel_theta"), k("max_rot_vel")])?;
            self.set_f64(&mut d.min_vel_theta, &[k("min_vel_theta"), k("min_rot_vel")])?;
            self.set_int(&mut d.vth_samples, &[k("vth_samples")])?;
            self.set_f64(&mut d.path_distance_bias, &[k("path_distance_bias")])?;
            self.set_f64(&mut d.goal_distance_bias, &[k("goal_distance_bias")])?;
            self.set_f64(&mut d.occdist_scale, &[k("occdist_scale")])?;
            self.set_f64(&mut d.forward_point_distance, &[k("forward_point_distance")])?;
            self.set_f64(&mut d.rotate_first_angle, &[k("rotate_first_angle")])?;
            self.set_f64(&mut d.local_goal_distance, &[k("local_goal_distance")])?;
        } else {
            // TrajectoryPlannerROS: its limits mean what DWA's do; its scores weigh other terms.
            self.set_f64(&mut d.max_vel_theta, &[k("max_vel_theta"), k("max_rotational_vel")])?;
            self.set_int(&mut d.vth_samples, &[k("vtheta_samples")])?;
        }
        Ok(())
    }

    fn global_planner(&mut self, p: &mut NavParams) -> Result<(), ParamError> {
        let ns = self.global_ns;
        let k = |n: &str| format!("{ns}/{n}");
        let g = &mut p.planner;
        self.set_f64(&mut g.default_tolerance, &[k("default_tolerance")])?;
        self.set_int(&mut g.smooth_max_cost, &[k("smooth_max_cost")])?;
        if ns == "GlobalPlanner" {
            if let Some(dijkstra) = self.read(&[k("use_dijkstra")], as_bool)? {
                g.use_astar = !dijkstra;
            }
            if let Some(c) = self.read(&[k("neutral_cost")], as_i64)? {
                g.neutral_cost = c as f64;
            }
            self.set_f64(&mut g.cost_factor, &[k("cost_factor")])?;
        }
        Ok(())
    }

    fn amcl(&mut self, p: &mut NavParams) -> Result<(), ParamError> {
        let k = |n: &str| [format!("amcl/{n}")];
        let a = &mut p.amcl;
        self.set_int(&mut a.min_particles, &k("min_particles"))?;
        self.set_int(&mut a.max_particles, &k("max_particles"))?;
        self.set_int(&mut a.resample_interval, &k("resample_interval"))?;
        self.set_int(&mut a.laser_max_beams, &k("laser_max_beams"))?;
        self.set_bool(&mut a.do_beamskip, &k("do_beamskip"))?;
        for (name, to) in [
            ("kld_err", &mut a.kld_err),
            ("kld_z", &mut a.kld_z),
            ("update_min_d", &mut a.update_min_d),
            ("update_min_a", &mut a.update_min_a),
            ("recovery_alpha_slow", &mut a.recovery_alpha_slow),
            ("recovery_alpha_fast", &mut a.recovery_alpha_fast),
            ("odom_alpha1", &mut a.odom_alpha1),
            ("odom_alpha2", &mut a.odom_alpha2),
            ("odom_alpha3", &mut a.odom_alpha3),
            ("odom_alpha4", &mut a.odom_alpha4),
            ("laser_z_hit", &mut a.laser_z_hit),
            ("laser_z_short", &mut a.laser_z_short),
            ("laser_z_max", &mut a.laser_z_max),
            ("laser_z_rand", &mut a.laser_z_rand),
            ("laser_sigma_hit", &mut a.laser_sigma_hit),
            ("laser_lambda_short", &mut a.laser_lambda_short),
            ("laser_likelihood_max_dist", &mut a.laser_likelihood_max_dist),
            ("laser_no_return_likelihood", &mut a.laser_no_return_likelihood),
            ("beam_skip_distance", &mut a.beam_skip_distance),
            ("beam_skip_threshold", &mut a.beam_skip_threshold),
            ("beam_skip_error_threshold", &mut a.beam_skip_error_threshold),
        ] {
            self.set_f64(to, &k(name))?;
        }
        let laser = |v: &serde_yaml::Value| match as_str(v)? {
            "likelihood_field" => Ok(LaserModelType::LikelihoodField),
            "likelihood_field_prob" => Ok(LaserModelType::LikelihoodFieldProb),
            "beam" => Ok(LaserModelType::Beam),
            _ => Err(format!("must be beam, likelihood_field or likelihood_field_prob, got {}", show(v))),
        };
        if let Some(m) = self.read(&k("laser_model_type"), laser)? {
            a.laser_model_type = m;
        }
        let odom = |v: &serde_yaml::Value| match as_str(v)? {
            "diff" => Ok(OdomModelType::Diff),
            "diff-corrected" => Ok(OdomModelType::DiffCorrected),
            "omni" | "omni-corrected" => Err(format!("xhab's robots are differential drives: diff or diff-corrected, got {}", show(v))),
            _ => Err(format!("must be diff, diff-corrected, omni or omni-corrected, got {}", show(v))),
        };
        if let Some(m) = self.read(&k("odom_model_type"), odom)? {
            a.odom_model_type = m;
        }
        Ok(())
    }

    /// Checks that involve two parameters; the error names the one set last.
    fn cross_checks(&self, p: &NavParams) -> Result<(), ParamError> {
        let blame = |names: [String; 2], message: String| -> ParamError {
            let hits = names.iter().filter_map(|n| self.by_name.get(n)).max_by_key(|h| h.1.seq);
            match hits {
                Some(&(key, leaf)) => self.err(key, leaf, message),
                None => ParamError::Value { file: "(defaults)".into(), key: names[0].clone(), message },
            }
        };
        let d = &p.dwa;
        if d.min_vel_x > d.max_vel_x {
            let ns = self.local_ns;
            return Err(blame([format!("{ns}/max_vel_x"), format!("{ns}/min_vel_x")], format!("min_vel_x ({}) must be <= max_vel_x ({})", d.min_vel_x, d.max_vel_x)));
        }
        let a = &p.amcl;
        if a.min_particles > a.max_particles {
            return Err(blame(["amcl/max_particles".into(), "amcl/min_particles".into()], format!("min_particles ({}) must be <= max_particles ({})", a.min_particles, a.max_particles)));
        }
        Ok(())
    }
}

/// Sets `to` from the local costmap's value, else the global's; notes when both differ.
fn settle<T: PartialEq + std::fmt::Display + Copy>(what: &str, local: Option<T>, global: Option<T>, to: &mut T, disagree: &mut Vec<String>) {
    if let (Some(a), Some(b)) = (local, global) {
        if a != b {
            disagree.push(format!("{what} (local {a}, global {b})"));
        }
    }
    if let Some(v) = local.or(global) {
        *to = v;
    }
}

/// What one costmap's obstacle layer says, where it says it.
#[derive(Debug, Clone, Copy, Default)]
struct ObstacleReading {
    obstacle_range: Option<f64>,
    raytrace_range: Option<f64>,
    marking: Option<bool>,
    clearing: Option<bool>,
    inf_is_valid: Option<bool>,
}
