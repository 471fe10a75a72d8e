//! Rollouts of constant velocity commands and their collision checks against a costmap.

use crate::costmap_2d::{traverse_segment, Costmap2D, Footprint, INSCRIBED, LETHAL, UNKNOWN};
use xhab_types::{normalize_angle, Pose2};

/// The pose after driving at `v` (m/s) and `w` (rad/s) for `dt` (s) from `p` (exact arc).
pub fn advance(p: Pose2, v: f64, w: f64, dt: f64) -> Pose2 {
    let th = p.yaw + w * dt;
    if w.abs() < 1e-9 {
        Pose2::new(
            p.x + v * dt * p.yaw.cos(),
            p.y + v * dt * p.yaw.sin(),
            normalize_angle(th),
        )
    } else {
        let r = v / w;
        Pose2::new(
            p.x + r * (th.sin() - p.yaw.sin()),
            p.y - r * (th.cos() - p.yaw.cos()),
            normalize_angle(th),
        )
    }
}

/// A simulated constant-velocity trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct Rollout {
    /// Forward speed (m/s).
    pub v: f64,
    /// Turn rate (rad/s).
    pub w: f64,
    /// Poses after each step up to the horizon (the start excluded).
    pub poses: Vec<Pose2>,
    /// Highest cell cost met within the horizon.
    pub max_cost: u8,
    /// Sum of the cell costs met within the horizon.
    pub sum_cost: f64,
}

/// Checks poses of a footprint against a costmap.
#[derive(Debug, Clone, Copy)]
pub struct CollisionChecker<'a> {
    /// The costmap.
    pub costmap: &'a Costmap2D,
    /// The robot's footprint.
    pub footprint: &'a Footprint,
}

impl CollisionChecker<'_> {
    /// The cost of the cell under the robot at `pose`, or `None` when the robot collides there:
    /// its centre's cell is off the map, unknown, lethal or (unless `allow_inscribed`)
    /// inscribed, or an edge of a polygonal footprint crosses a lethal or unknown cell.
    pub fn pose_cost(&self, pose: Pose2, allow_inscribed: bool) -> Option<u8> {
        let c = self.costmap.cost_at(pose.position())?;
        let limit = if allow_inscribed { LETHAL } else { INSCRIBED };
        if c >= limit {
            return None;
        }
        if !self.footprint.is_circle() && !self.outline_clear(pose) {
            return None;
        }
        Some(c)
    }

    fn outline_clear(&self, pose: Pose2) -> bool {
        let outline = self.footprint.outline_at(pose);
        let n = outline.len();
        let (sx, sy) = (self.costmap.size_x() as i64, self.costmap.size_y() as i64);
        let costs = self.costmap.costs();
        (0..n).all(|i| {
            let (x0, y0) = self.costmap.world_to_map_continuous(outline[i]);
            let (x1, y1) = self.costmap.world_to_map_continuous(outline[(i + 1) % n]);
            let mut clear = true;
            traverse_segment(x0, y0, x1, y1, |x, y| {
                clear = x >= 0 && y >= 0 && x < sx && y < sy && {
                    let c = costs[(y * sx + x) as usize];
                    c != LETHAL && c != UNKNOWN
                };
                clear
            });
            clear
        })
    }

    /// Rolls `(v, w)` out from `start` per `spec`. A rollout that collides is cut at its last
    /// free pose if the robot could still stop before the collision (braking at the
    /// acceleration limits, plus `stop_time_buffer`), and dropped (`None`) otherwise. From a
    /// start inside the inscribed zone, inscribed cells may be crossed provided the rollout
    /// ends outside it.
    pub fn rollout(&self, start: Pose2, v: f64, w: f64, spec: &RolloutSpec) -> Option<Rollout> {
        let steps = ((v.abs() * spec.sim_time / spec.granularity)
            .max(w.abs() * spec.sim_time / spec.angular_granularity))
        .ceil()
        .max(1.0) as usize;
        let dt = spec.sim_time / steps as f64;
        let escaping = self
            .costmap
            .cost_at(start.position())
            .is_some_and(|c| c >= INSCRIBED);
        let mut poses = Vec::with_capacity(steps);
        let (mut max_cost, mut sum_cost) = (0u8, 0.0);
        let mut p = start;
        for _ in 0..steps {
            p = advance(p, v, w, dt);
            let Some(c) = self.pose_cost(p, escaping) else {
                let stop_time = (v.abs() / (2.0 * spec.acc_lim_x))
                    .max(w.abs() / (2.0 * spec.acc_lim_theta))
                    + spec.stop_time_buffer;
                if poses.is_empty() || (poses.len() as f64) * dt < stop_time {
                    return None;
                }
                break;
            };
            poses.push(p);
            max_cost = max_cost.max(c);
            sum_cost += c as f64;
        }
        if escaping
            && poses
                .last()
                .is_some_and(|q| self.pose_cost(*q, false).is_none())
        {
            return None;
        }
        Some(Rollout {
            v,
            w,
            poses,
            max_cost,
            sum_cost,
        })
    }
}

/// How rollouts are simulated and checked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RolloutSpec {
    /// Horizon (s).
    pub sim_time: f64,
    /// Largest step along the path (m).
    pub granularity: f64,
    /// Largest step of the heading (rad).
    pub angular_granularity: f64,
    /// Time the robot must be able to stop before a collision, beyond braking (s).
    pub stop_time_buffer: f64,
    /// Braking deceleration (m/s^2).
    pub acc_lim_x: f64,
    /// Angular braking deceleration (rad/s^2).
    pub acc_lim_theta: f64,
}

impl RolloutSpec {
    /// The spec of DWA parameters `p`.
    pub fn from_params(p: &super::DwaParams) -> Self {
        Self {
            sim_time: p.sim_time,
            granularity: p.sim_granularity,
            angular_granularity: p.angular_sim_granularity,
            stop_time_buffer: p.stop_time_buffer,
            acc_lim_x: p.acc_lim_x.max(1e-6),
            acc_lim_theta: p.acc_lim_theta.max(1e-6),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::costmap_2d::FREE;
    use xhab_types::Point2;

    #[test]
    fn arcs_are_exact() {
        let p = advance(
            Pose2::new(0.0, 0.0, 0.0),
            1.0,
            std::f64::consts::FRAC_PI_2,
            1.0,
        );
        let r = 2.0 / std::f64::consts::PI;
        assert!(
            (p.x - r).abs() < 1e-12
                && (p.y - r).abs() < 1e-12
                && (p.yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12
        );
    }

    #[test]
    fn rollouts_stop_at_walls_and_polygon_edges() {
        let mut m = Costmap2D::new(40, 40, 0.05, Point2::default(), FREE);
        for y in 0..40 {
            m.set_cost(30, y, LETHAL);
            m.set_cost(28, y, INSCRIBED);
            m.set_cost(29, y, INSCRIBED);
        }
        let round = Footprint::circle(0.1);
        let c = CollisionChecker {
            costmap: &m,
            footprint: &round,
        };
        let spec = RolloutSpec {
            sim_time: 1.0,
            granularity: 0.025,
            angular_granularity: 0.1,
            stop_time_buffer: 0.2,
            acc_lim_x: 2.5,
            acc_lim_theta: 3.2,
        };
        let start = Pose2::new(0.5, 1.0, 0.0);
        let r = c.rollout(start, 0.5, 0.0, &spec).unwrap();
        assert!(
            (r.poses.last().unwrap().x - 1.0).abs() < 1e-9,
            "free all the way"
        );
        // 1.5 m/s hits the inscribed zone at 1.4 m after 0.6 s but could stop (0.3 + 0.2 s): cut.
        let r = c.rollout(start, 1.5, 0.0, &spec).unwrap();
        assert!(r.poses.last().unwrap().x < 1.4 && r.poses.last().unwrap().x > 1.35);
        // Starting 0.1 m from the inscribed zone at 1 m/s: 0.1 s to the collision, 0.4 s to stop.
        assert!(c
            .rollout(Pose2::new(1.3, 1.0, 0.0), 1.0, 0.0, &spec)
            .is_none());
        // A long box: its nose reaches the wall while its centre is far from it.
        let long = Footprint::polygon(&[[-0.1, -0.1], [0.6, -0.1], [0.6, 0.1], [-0.1, 0.1]], 0.0);
        let c = CollisionChecker {
            costmap: &m,
            footprint: &long,
        };
        let r = c.rollout(start, 0.5, 0.0, &spec).unwrap();
        assert!(
            r.poses.last().unwrap().x + 0.6 < 1.5,
            "cut before the nose meets the wall"
        );
        // From inside the inscribed zone, backing out is allowed, going deeper is not.
        let c = CollisionChecker {
            costmap: &m,
            footprint: &round,
        };
        let stuck = Pose2::new(1.43, 1.0, 0.0);
        assert!(c.rollout(stuck, -0.2, 0.0, &spec).is_some());
        assert!(c.rollout(stuck, 0.1, 0.0, &spec).is_none());
    }
}
