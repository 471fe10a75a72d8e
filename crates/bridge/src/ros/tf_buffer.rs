//! A small planar tf buffer: the newest transform of every parent -> child edge heard on `/tf`
//! and `/tf_static`, looked up between any two connected frames (enough for a planar base:
//! where the laser sits on base_link, a goal given in `odom` or `map`).

use super::convert as cv;
use super::msgs::tf2_msgs::TFMessage;
use std::collections::HashMap;
use xhab_types::Pose2;

/// The newest transform of each edge, keyed by child frame (tf trees have one parent each).
#[derive(Debug, Clone, Default)]
pub struct TfBuffer {
    edges: HashMap<String, (String, Pose2)>,
}

/// Frame ids compare without a leading slash (tf2 strips it).
fn bare(f: &str) -> &str {
    f.trim_start_matches('/')
}

impl TfBuffer {
    /// An empty buffer.
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes in every transform of a `/tf` or `/tf_static` message (planar part only).
    pub fn insert(&mut self, m: &TFMessage) {
        for t in &m.transforms {
            self.insert_edge(&t.header.frame_id, &t.child_frame_id, cv::pose2_of_transform(&t.transform));
        }
    }

    /// Adds or replaces the transform `parent -> child` (the child's planar pose in the
    /// parent's frame); non-finite ones are ignored.
    pub fn insert_edge(&mut self, parent: &str, child: &str, p: Pose2) {
        if p.x.is_finite() && p.y.is_finite() && p.yaw.is_finite() {
            self.edges.insert(bare(child).to_string(), (bare(parent).to_string(), p));
        }
    }

    fn to_root(&self, frame: &str) -> Vec<(String, Pose2)> {
        let mut out = vec![(bare(frame).to_string(), Pose2::default())];
        let mut cur = bare(frame).to_string();
        // Poses of `frame` in each ancestor, accumulated upward.
        let mut acc = Pose2::default();
        while let Some((parent, p)) = self.edges.get(&cur) {
            if out.iter().any(|(f, _)| f == parent) {
                break; // a loop: tf would reject it, so do we
            }
            acc = p.compose(acc);
            out.push((parent.clone(), acc));
            cur = parent.clone();
        }
        out
    }

    /// The pose of frame `source` in frame `target` (m, rad), if they are connected.
    pub fn lookup(&self, target: &str, source: &str) -> Option<Pose2> {
        let up_s = self.to_root(source);
        let up_t = self.to_root(target);
        for (f, s_in_f) in &up_s {
            if let Some((_, t_in_f)) = up_t.iter().find(|(g, _)| g == f) {
                return Some(t_in_f.inverse().compose(*s_in_f));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ros::msgs::tf2_msgs::TFMessage;

    #[test]
    fn lookups_follow_the_tree_both_ways() {
        let mut b = TfBuffer::new();
        let odom_base = Pose2::new(1.0, 2.0, 0.5);
        let base_laser = Pose2::new(-0.032, 0.0, 0.0);
        let map_odom = Pose2::new(-3.0, 0.5, -0.2);
        b.insert(&TFMessage {
            transforms: vec![
                cv::tf(0.0, "odom", "base_link", cv::transform(odom_base, 0.0)),
                cv::tf(0.0, "base_link", "base_scan", cv::transform(base_laser, 0.172)),
                cv::tf(0.0, "/map", "odom", cv::transform(map_odom, 0.0)),
            ],
        });
        let close = |a: Pose2, b: Pose2| (a.x - b.x).abs() < 1e-12 && (a.y - b.y).abs() < 1e-12 && xhab_types::normalize_angle(a.yaw - b.yaw).abs() < 1e-12;
        assert!(close(b.lookup("base_link", "base_scan").unwrap(), base_laser));
        assert!(close(b.lookup("map", "base_scan").unwrap(), map_odom.compose(odom_base).compose(base_laser)));
        assert!(close(b.lookup("base_scan", "map").unwrap(), map_odom.compose(odom_base).compose(base_laser).inverse()));
        assert!(close(b.lookup("odom", "odom").unwrap(), Pose2::default()));
        assert!(b.lookup("map", "camera_link").is_none());
    }
}
