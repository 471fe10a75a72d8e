//! A ROS 2 node on RustDDS: the domain (`$ROS_DOMAIN_ID`), loopback-only discovery
//! (`$ROS_LOCALHOST_ONLY=1` or `$ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`), the QoS profiles
//! xhab publishes with, and ROS 2's command-line names (`--ros-args -r from:=to`,
//! `-r __ns:=/ns`, `-r __node:=name`) resolved with [`Names`].

use super::msgs::RosType;
use crate::ros::names::{NameError, Names};
use crate::ros::node::RosError;
use ros2_client::dds::rustdds::DomainParticipantBuilder;
use ros2_client::qos::{Durability, History, Reliability, WhenFull};
use ros2_client::{Context, MessageTypeName, Name, Node, NodeName, NodeOptions, Publisher, QosProfile, Subscription};
use std::net::{IpAddr, Ipv4Addr};

/// Where a node talks: the DDS domain and whether discovery stays on this host.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Ros2Config {
    /// The DDS domain (`$ROS_DOMAIN_ID`, default 0; 0..=232 on Linux).
    pub domain_id: u16,
    /// Discover and talk only over loopback (127.0.0.1).
    pub localhost_only: bool,
}

impl Ros2Config {
    /// The configuration ROS 2 reads from the environment: `ROS_DOMAIN_ID`, and loopback-only
    /// when `ROS_LOCALHOST_ONLY=1` or `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`; `var` looks a
    /// variable up (`std::env::var(..).ok()` in the CLI). An unparsable domain is an error
    /// naming it.
    pub fn from_env(var: impl Fn(&str) -> Option<String>) -> Result<Ros2Config, RosError> {
        let domain_id = match var("ROS_DOMAIN_ID").map(|s| s.trim().to_string()).filter(|s| !s.is_empty()) {
            None => 0,
            Some(s) => match s.parse::<u16>() {
                Ok(d) if d <= 232 => d,
                _ => return Err(RosError::Node(format!("ROS_DOMAIN_ID={s}: expected a domain id in 0..=232"))),
            },
        };
        let localhost_only = var("ROS_LOCALHOST_ONLY").is_some_and(|v| v.trim() == "1") || var("ROS_AUTOMATIC_DISCOVERY_RANGE").is_some_and(|v| v.trim().eq_ignore_ascii_case("LOCALHOST"));
        Ok(Ros2Config { domain_id, localhost_only })
    }
}

/// Sensor data (`rmw_qos_profile_sensor_data`): best effort, volatile, the last 5 samples.
pub fn sensor_data_qos() -> QosProfile {
    QosProfile::subscription_default().reliability(Reliability::BestEffort).durability(Durability::Volatile).history(History::KeepLast { depth: 5 })
}

/// ROS 2's default for topics: reliable, volatile, the last `depth` samples.
pub fn reliable_qos(depth: usize) -> QosProfile {
    QosProfile::publisher_default().reliability(Reliability::Reliable { when_full: WhenFull::DEFAULT }).durability(Durability::Volatile).history(History::KeepLast { depth })
}

/// Latched (`map`, `/tf_static`): reliable, transient local, the last sample, which late
/// subscribers with transient-local durability receive.
pub fn latched_qos() -> QosProfile {
    reliable_qos(1).durability(Durability::TransientLocal)
}

/// What a command subscription accepts: best effort, so that it matches reliable and
/// best-effort publishers alike (teleop, Nav2's controller).
pub fn command_qos() -> QosProfile {
    QosProfile::subscription_default().reliability(Reliability::BestEffort).durability(Durability::Volatile).history(History::KeepLast { depth: 10 })
}

/// The node's names from ROS 2's command line: `args` are what follows `--ros-args`
/// (`-r FROM:=TO` or `--remap FROM:=TO`, `__ns`, `__node` (or `__name`); `NODE:FROM:=TO`
/// applies to the node named NODE only); `-p`/`--param` and `--log-level` with their values
/// are accepted and ignored. `ros_namespace` is `$ROS_NAMESPACE`.
pub fn names_from_ros_args(default_node: &str, args: &[String], ros_namespace: Option<&str>) -> Result<Names, NameError> {
    let mut remaps = Vec::new();
    let mut it = args.iter();
    let mut node = default_node.to_string();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--ros-args" | "--" => {}
            "-r" | "--remap" => {
                let Some(r) = it.next() else {
                    return Err(NameError { arg: a.clone(), why: "expected FROM:=TO after it".into() });
                };
                let Some((from, to)) = r.split_once(":=") else {
                    return Err(NameError { arg: r.clone(), why: "expected FROM:=TO".into() });
                };
                // `NODE:FROM:=TO` is for the node named NODE alone.
                let from = match from.split_once(':') {
                    Some((n, f)) if n == node || n == default_node => f,
                    Some(_) => continue,
                    None => from,
                };
                let from = if from == "__node" { "__name" } else { from };
                if from == "__name" {
                    node = to.to_string();
                }
                remaps.push(format!("{from}:={to}"));
            }
            "-p" | "--param" | "--log-level" | "--params-file" | "-e" | "--enclave" => {
                if it.next().is_none() {
                    return Err(NameError { arg: a.clone(), why: "expected a value after it".into() });
                }
            }
            _ => return Err(NameError { arg: a.clone(), why: "expected -r FROM:=TO (ROS 2 arguments follow --ros-args)".into() }),
        }
    }
    Names::from_args(default_node, &remaps, ros_namespace)
}

fn create_err(what: &str, e: impl std::fmt::Display) -> RosError {
    RosError::Node(format!("{what}: {e}"))
}

/// A ROS 2 node on its own DDS participant, with the names it resolves topics with.
pub struct Ros2Node {
    /// ros2-client's node (kept alive with this).
    pub node: Node,
    /// Namespace, node name and remappings.
    pub names: Names,
    /// The domain and discovery range.
    pub config: Ros2Config,
    _context: Context,
}

impl Ros2Node {
    /// Joins the DDS domain of `config` as the node `names` (RustDDS runs its own threads).
    pub fn new(names: Names, config: Ros2Config) -> Result<Ros2Node, RosError> {
        let mut b = DomainParticipantBuilder::new(config.domain_id);
        if config.localhost_only {
            b = b.with_only_networks([IpAddr::V4(Ipv4Addr::LOCALHOST)]);
        }
        let dp = b.build().map_err(|e| create_err(&format!("joining DDS domain {}", config.domain_id), e))?;
        let context = Context::from_domain_participant(dp).map_err(|e| create_err("ROS 2 context", e))?;
        let full = names.node_name();
        let (ns, base) = match full.rsplit_once('/') {
            Some(("", b)) => ("/".to_string(), b.to_string()),
            Some((n, b)) => (n.to_string(), b.to_string()),
            None => ("/".to_string(), full.clone()),
        };
        let node_name = NodeName::new(&ns, &base).map_err(|e| create_err(&format!("node name {full}"), e))?;
        // No spinner: ros2-client's spinner serves parameters and reads `/clock` as
        // builtin_interfaces/Time (not rosgraph_msgs/Clock), which puts a second type on
        // `/clock` in the ROS graph. The node announces its endpoints without it.
        let node = context.new_node(node_name, NodeOptions::new().enable_rosout(false)).map_err(|e| create_err(&format!("creating node {full}"), e))?;
        Ok(Ros2Node { node, names, config, _context: context })
    }

    fn topic<T: RosType>(&mut self, topic: &str, qos: &QosProfile) -> Result<(String, ros2_client::dds::rustdds::Topic), RosError> {
        let g = self.names.resolve(topic);
        let name = Name::parse(&g).map_err(|e| create_err(&format!("topic name {g}"), e))?;
        let t = self.node.create_topic(&name, MessageTypeName::new(T::PACKAGE, T::NAME), qos).map_err(|e| create_err(&format!("topic {g}"), e))?;
        Ok((g, t))
    }

    /// The node's DDS participant (a handle), to look at what discovery found.
    pub fn participant(&self) -> ros2_client::dds::rustdds::DomainParticipant {
        self._context.domain_participant()
    }

    /// A publisher of `T` on `topic` (resolved with the node's names) with `qos`.
    pub fn publisher<T: RosType>(&mut self, topic: &str, qos: QosProfile) -> Result<Publisher<T>, RosError> {
        let (g, t) = self.topic::<T>(topic, &qos)?;
        self.node.create_publisher(&t, Some(qos)).map_err(|e| create_err(&format!("publishing on {g}"), e))
    }

    /// A subscription to `T` on `topic` (resolved with the node's names) with `qos`.
    pub fn subscription<T: RosType>(&mut self, topic: &str, qos: QosProfile) -> Result<Subscription<T>, RosError> {
        let (g, t) = self.topic::<T>(topic, &qos)?;
        self.node.create_subscription(&t, Some(qos)).map_err(|e| create_err(&format!("subscribing to {g}"), e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn ros_args_remap_namespace_and_node() {
        let n = names_from_ros_args("xhab_sim", &args("--ros-args -r __ns:=/robot1 -r scan:=base_scan --remap __node:=sim -p use_sim_time:=true"), None).unwrap();
        assert_eq!(n.node_name(), "/robot1/sim");
        assert_eq!(n.resolve("scan"), "/robot1/base_scan");
        assert_eq!(n.resolve("odom"), "/robot1/odom");
        assert_eq!(n.resolve("/tf"), "/tf");
        // A remapping for another node is not ours.
        let n = names_from_ros_args("xhab_sim", &args("-r other:scan:=x -r xhab_sim:odom:=wheel_odom"), Some("/r")).unwrap();
        assert_eq!(n.resolve("scan"), "/r/scan");
        assert_eq!(n.resolve("odom"), "/r/wheel_odom");
    }

    #[test]
    fn bad_ros_args_are_errors_naming_the_argument() {
        for (a, bad) in [("-r", "-r"), ("-r scan", "scan"), ("--frobnicate", "--frobnicate"), ("-r __ns:=/a//b", "/a//b")] {
            let e = names_from_ros_args("n", &args(a), None).expect_err(a);
            assert!(e.to_string().contains(bad), "{a}: {e}");
        }
    }

    #[test]
    fn the_environment_gives_domain_and_range() {
        let env = |pairs: &'static [(&'static str, &'static str)]| move |k: &str| pairs.iter().find(|(n, _)| *n == k).map(|(_, v)| v.to_string());
        assert_eq!(Ros2Config::from_env(env(&[])).unwrap(), Ros2Config { domain_id: 0, localhost_only: false });
        assert_eq!(Ros2Config::from_env(env(&[("ROS_DOMAIN_ID", "42"), ("ROS_LOCALHOST_ONLY", "1")])).unwrap(), Ros2Config { domain_id: 42, localhost_only: true });
        assert!(Ros2Config::from_env(env(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "localhost")])).unwrap().localhost_only);
        assert!(Ros2Config::from_env(env(&[("ROS_DOMAIN_ID", "300")])).unwrap_err().to_string().contains("ROS_DOMAIN_ID=300"));
        assert!(Ros2Config::from_env(env(&[("ROS_DOMAIN_ID", "x")])).is_err());
    }
}
