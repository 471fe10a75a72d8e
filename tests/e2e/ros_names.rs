//! ROS names as rosrun hands them over: two simulated robots side by side in their own
//! namespaces (`__ns:=`, `$ROS_NAMESPACE`), a remapped topic and a renamed node.

use crate::common::xhab;
use crate::ros_interop::{ros_available, rospy_script, Killed};
use std::process::Stdio;
use xhab_bridge::ros::master::Master;

#[test]
fn two_robots_run_side_by_side_in_their_namespaces() {
    if !ros_available("two_robots_run_side_by_side_in_their_namespaces") {
        return;
    }
    let master = Master::start().expect("rosmaster starts");
    let sim = |args: &[&str], ns: Option<&str>| {
        let mut c = xhab();
        c.args(["ros", "sim", "procedural:3", "--physics", "--rate", "2", "--duration", "120", "--ros-master", &master.uri]).args(args).env("ROS_IP", "127.0.0.1").env_remove("ROS_NAMESPACE");
        if let Some(ns) = ns {
            c.env("ROS_NAMESPACE", ns);
        }
        Killed(c.stdout(Stdio::null()).stderr(Stdio::inherit()).spawn().unwrap())
    };
    let _r1 = sim(&["--seed", "1", "__ns:=r1"], None);
    let _r2 = sim(&["--seed", "2", "scan:=base_scan", "__name:=sim2"], Some("r2"));
    let (ok, stdout) = rospy_script("two_robots.py", &master.uri);
    assert!(ok && stdout.contains("PASS"), "two-robot check failed");
}

#[test]
fn a_bad_remapping_argument_is_a_clear_error() {
    let out = xhab().args(["ros", "sim", "procedural:3", "scan=base_scan"]).output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("scan=base_scan") && err.contains("FROM:=TO"), "{err}");
}
