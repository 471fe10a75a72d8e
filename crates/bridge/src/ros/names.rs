//! ROS 1 graph names as roslaunch and rosrun hand them to a node: the namespace (`__ns:=`, else
//! `$ROS_NAMESPACE`), the node name (`__name:=`) and remappings (`from:=to`), resolved to
//! global names before they reach roslibrust (whose relative-name subscriptions never connect
//! to publishers that appear after them).

/// A node's name, namespace and remappings; resolves topic and service names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Names {
    /// The namespace, `/` or `/a/b` (no trailing slash).
    namespace: String,
    /// The node's base name (no slashes).
    node: String,
    /// Remappings, both sides resolved to global names.
    remaps: Vec<(String, String)>,
}

/// A name or remapping argument that ROS would reject.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("bad ROS name argument '{arg}': {why}")]
pub struct NameError {
    /// The argument as given.
    pub arg: String,
    /// What is wrong with it.
    pub why: String,
}

fn valid_base(s: &str) -> bool {
    let mut c = s.chars();
    c.next().is_some_and(|f| f.is_ascii_alphabetic()) && c.all(|x| x.is_ascii_alphanumeric() || x == '_')
}

fn valid_name(s: &str) -> bool {
    let body = s.strip_prefix('/').or_else(|| s.strip_prefix('~')).unwrap_or(s);
    !body.is_empty() && !body.ends_with('/') && body.split('/').all(valid_base)
}

/// `/` joined with `rest` under `ns` (`/` or `/a/b`).
fn join(ns: &str, rest: &str) -> String {
    if ns == "/" { format!("/{rest}") } else { format!("{ns}/{rest}") }
}

fn canonical_ns(ns: &str) -> Result<String, NameError> {
    let t = ns.trim_end_matches('/');
    if t.is_empty() {
        return Ok("/".into());
    }
    let g = if t.starts_with('/') { t.to_string() } else { format!("/{t}") };
    if !valid_name(&g) {
        return Err(NameError { arg: ns.into(), why: "not a valid namespace".into() });
    }
    Ok(g)
}

impl Names {
    /// A node `node` in namespace `/` with no remappings.
    pub fn plain(node: &str) -> Names {
        Names { namespace: "/".into(), node: node.trim_start_matches('/').to_string(), remaps: Vec::new() }
    }

    /// The names of node `default_node` under the process's ROS arguments (`__ns:=NS`,
    /// `__name:=NAME`, `from:=to`; `__log:=` and other special keys are ignored) and
    /// `ros_namespace` (`$ROS_NAMESPACE`, overridden by `__ns:=`).
    pub fn from_args(default_node: &str, args: &[String], ros_namespace: Option<&str>) -> Result<Names, NameError> {
        let mut ns = canonical_ns(ros_namespace.unwrap_or("/"))?;
        let mut node = default_node.trim_start_matches('/').to_string();
        let mut pairs = Vec::new();
        for a in args {
            let Some((from, to)) = a.split_once(":=") else {
                return Err(NameError { arg: a.clone(), why: "expected FROM:=TO".into() });
            };
            match from {
                "__ns" => ns = canonical_ns(to)?,
                "__name" => {
                    if !valid_base(to) {
                        return Err(NameError { arg: a.clone(), why: "a node name is one word of letters, digits and _".into() });
                    }
                    node = to.to_string();
                }
                f if f.starts_with("__") => {}
                f => {
                    if !valid_name(f) || !valid_name(to) {
                        return Err(NameError { arg: a.clone(), why: "not a valid ROS name on each side of :=".into() });
                    }
                    pairs.push((f.to_string(), to.to_string()));
                }
            }
        }
        if !valid_base(&node) {
            return Err(NameError { arg: node, why: "not a valid node name".into() });
        }
        let mut n = Names { namespace: ns, node, remaps: Vec::new() };
        n.remaps = pairs.iter().map(|(f, t)| (n.expand(f), n.expand(t))).collect();
        Ok(n)
    }

    /// The node's global name (`/ns/node`).
    pub fn node_name(&self) -> String {
        join(&self.namespace, &self.node)
    }

    /// The namespace (`/` or `/a/b`).
    pub fn namespace(&self) -> &str {
        &self.namespace
    }

    /// `name` made global without remapping: `/x` stays, `~x` is under the node, `x` under
    /// the namespace.
    fn expand(&self, name: &str) -> String {
        if name.starts_with('/') {
            name.to_string()
        } else if let Some(p) = name.strip_prefix('~') {
            join(&self.node_name(), p.trim_start_matches('/'))
        } else {
            join(&self.namespace, name)
        }
    }

    /// The global name a topic or service `name` resolves to, remappings applied.
    pub fn resolve(&self, name: &str) -> String {
        let g = self.expand(name);
        self.remaps.iter().find(|(f, _)| *f == g).map_or(g, |(_, t)| t.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn names_resolve_as_ros_does() {
        let n = Names::from_args("xhab_sim", &[], None).unwrap();
        assert_eq!(n.resolve("scan"), "/scan");
        assert_eq!(n.resolve("/clock"), "/clock");
        assert_eq!(n.resolve("~status"), "/xhab_sim/status");
        assert_eq!(n.node_name(), "/xhab_sim");
        let n = Names::from_args("xhab_sim", &args(&["__ns:=robot1", "scan:=base_scan", "/tf:=/robot1/tf", "__log:=/tmp/x.log"]), None).unwrap();
        assert_eq!(n.node_name(), "/robot1/xhab_sim");
        assert_eq!(n.resolve("scan"), "/robot1/base_scan");
        assert_eq!(n.resolve("odom"), "/robot1/odom");
        assert_eq!(n.resolve("/tf"), "/robot1/tf");
        assert_eq!(n.resolve("move_base/goal"), "/robot1/move_base/goal");
        let n = Names::from_args("nav", &args(&["__name:=nav2"]), Some("/r2/")).unwrap();
        assert_eq!(n.node_name(), "/r2/nav2");
        assert_eq!(n.resolve("cmd_vel"), "/r2/cmd_vel");
        // __ns beats $ROS_NAMESPACE.
        assert_eq!(Names::from_args("n", &args(&["__ns:=/a"]), Some("b")).unwrap().resolve("x"), "/a/x");
    }

    #[test]
    fn bad_arguments_are_errors_naming_them() {
        for bad in ["scan", "scan:=", "1scan:=x", "__name:=a/b", "__ns:=a b"] {
            let e = Names::from_args("n", &args(&[bad]), None).unwrap_err();
            assert!(bad.contains(&e.arg), "{bad}: {e}");
        }
    }
}
