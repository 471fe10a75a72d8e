//! When the navigator may stop at a goal: its estimate within `xy_goal_tolerance` (ROS's
//! meaning, unchanged) *and* sure enough of that estimate that the true position lies within
//! the success radius a benchmark scores against; otherwise it refines with a short final
//! approach. It also drives that final approach, on the robot's footprint alone, to goals the
//! inflated costmap blocks but the robot fits (the plan then ends short of the goal, at the
//! planner's `default_tolerance`).

use crate::costmap::{Costmap, LETHAL};
use serde::{Deserialize, Serialize};
use xhab_types::{normalize_angle, Point2, Pose2, Twist};

/// Goal-approach settings (xhab's own; move_base stops on the estimate alone).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GoalApproachParams {
    /// Radius around the goal within which the robot must truly end (m, default 0: off, stop
    /// on the estimate alone as move_base). A PointNav benchmark sets its success distance.
    pub success_radius: f64,
    /// Standard deviations of the localisation spread a stop allows for (default 2).
    pub confidence_sigmas: f64,
    /// Distance to the goal the refining approach drives down to (m, default 0.03).
    pub refine_distance: f64,
    /// Forward speed of the final approach (m/s, default 0.1).
    pub approach_speed: f64,
    /// Longest time spent refining before stopping on the estimate anyway (s, default 15).
    pub max_refine_time: f64,
}

impl Default for GoalApproachParams {
    fn default() -> Self {
        Self { success_radius: 0.0, confidence_sigmas: 2.0, refine_distance: 0.03, approach_speed: 0.1, max_refine_time: 15.0 }
    }
}

/// What the goal check says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GoalCheck {
    /// Not within tolerance yet.
    Outside,
    /// Within tolerance and confident: stop.
    Reached,
    /// Within tolerance by the estimate, but the spread leaves the true position possibly
    /// outside the success radius: refine.
    Unsure,
}

/// The stopping rule: `dist` the estimated distance to the goal (m), `tolerance` the
/// `xy_goal_tolerance` (m), `spread` the localisation's position standard deviation (m; 0
/// for ground truth). Confident when `dist + confidence_sigmas * spread < success_radius`,
/// i.e. the spread is below `(success_radius - dist) / confidence_sigmas`.
pub fn goal_check(dist: f64, tolerance: f64, spread: f64, p: &GoalApproachParams) -> GoalCheck {
    if !(dist <= tolerance) {
        return GoalCheck::Outside;
    }
    let spread = if spread.is_nan() { f64::INFINITY } else { spread.max(0.0) };
    if !(p.success_radius > 0.0) || dist + p.confidence_sigmas * spread < p.success_radius {
        GoalCheck::Reached
    } else {
        GoalCheck::Unsure
    }
}

/// Points of a round footprint of `radius` (m) about the base origin, as costmap_2d's
/// `makeFootprintFromRadius` (16 points).
pub fn round_footprint(radius: f64) -> Vec<[f64; 2]> {
    (0..16).map(|k| {
        let a = k as f64 * std::f64::consts::TAU / 16.0;
        [radius * a.cos(), radius * a.sin()]
    })
    .collect()
}

/// Whether the footprint at `q` fits between the lethal cells, however close the inflation
/// says they are: its centre and its outline, drawn half a cell in (an occupied cell holds an
/// obstacle somewhere within it, not all over), sampled every half cell, touch no lethal cell.
pub fn footprint_free(cm: &Costmap, q: Pose2, footprint: &[[f64; 2]]) -> bool {
    if cm.cost_at(q.position()) >= LETHAL {
        return false;
    }
    let (s, c) = q.yaw.sin_cos();
    let half = 0.5 * cm.resolution;
    let world = |v: [f64; 2]| {
        let l = v[0].hypot(v[1]);
        let k = if l > half { (l - half) / l } else { 0.0 };
        let v = [v[0] * k, v[1] * k];
        Point2::new(q.x + c * v[0] - s * v[1], q.y + s * v[0] + c * v[1])
    };
    let n = footprint.len();
    (0..n).all(|i| {
        let (a, b) = (world(footprint[i]), world(footprint[(i + 1) % n]));
        let k = (a.dist(b) / (cm.resolution * 0.5)).ceil().max(1.0) as usize;
        (0..=k).all(|j| {
            let t = j as f64 / k as f64;
            cm.cost_at(Point2::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y))) < LETHAL
        })
    })
}

/// One command of the straight final approach from `pose` to `goal` (turn towards it, then
/// drive at `speed` slowing down near it), or `None` when the footprint would touch a lethal
/// cell over the next `horizon` seconds of that command.
pub fn approach_command(cm: &Costmap, pose: Pose2, goal: Point2, footprint: &[[f64; 2]], speed: f64, max_turn: f64, horizon: f64) -> Option<Twist> {
    let d = pose.position().dist(goal);
    let err = normalize_angle((goal.y - pose.y).atan2(goal.x - pose.x) - pose.yaw);
    let turn = (1.5 * err).clamp(-max_turn, max_turn);
    if err.abs() > 0.35 {
        return Some(Twist { linear: 0.0, angular: turn });
    }
    let v = speed.min(d / horizon.max(1e-3)).max(0.0);
    let steps = 5;
    let free = (1..=steps).all(|k| {
        let t = horizon * k as f64 / steps as f64;
        let yaw = pose.yaw + turn * t;
        let q = Pose2::new(pose.x + v * t * yaw.cos(), pose.y + v * t * yaw.sin(), yaw);
        footprint_free(cm, q, footprint)
    });
    free.then_some(Twist { linear: v, angular: turn })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::costmap::CostmapParams;
    use xhab_types::OccupancyGrid;

    #[test]
    fn stops_only_when_sure_enough() {
        let p = GoalApproachParams { success_radius: 0.2, ..Default::default() };
        assert_eq!(goal_check(0.15, 0.1, 0.0, &p), GoalCheck::Outside);
        assert_eq!(goal_check(0.08, 0.1, 0.0, &p), GoalCheck::Reached, "ground truth: the estimate is the truth");
        assert_eq!(goal_check(0.08, 0.1, 0.05, &p), GoalCheck::Reached, "0.08 + 2 * 0.05 < 0.2");
        assert_eq!(goal_check(0.08, 0.1, 0.07, &p), GoalCheck::Unsure, "0.08 + 2 * 0.07 >= 0.2");
        assert_eq!(goal_check(0.01, 0.1, 0.07, &p), GoalCheck::Reached, "closer in, the same spread is enough");
        assert_eq!(goal_check(0.01, 0.1, 0.2, &p), GoalCheck::Unsure);
        // Off: move_base's rule, the estimate alone; tolerance keeps its meaning.
        let off = GoalApproachParams::default();
        assert_eq!(goal_check(0.1, 0.1, 5.0, &off), GoalCheck::Reached);
        assert_eq!(goal_check(0.11, 0.1, 0.0, &off), GoalCheck::Outside);
        assert_eq!(goal_check(f64::NAN, 0.1, 0.0, &p), GoalCheck::Outside);
        assert_eq!(goal_check(0.05, 0.1, f64::NAN, &p), GoalCheck::Unsure);
    }

    /// A gap of four free cells (0.2 m) in a wall at x = 2: the inflated costmap blocks it, a
    /// robot of radius 0.1 m fits.
    fn gap() -> Costmap {
        let mut m = OccupancyGrid::new(80, 80, 0.05, Pose2::default(), 0);
        for r in 0..80 {
            for c in 0..80 {
                if (c == 40 || c == 41) && !(36..40).contains(&r) {
                    m.set(c, r, 100);
                }
            }
        }
        Costmap::from_map(&m, &CostmapParams::default())
    }

    #[test]
    fn the_final_approach_fits_where_the_inflation_blocks() {
        let cm = gap();
        let fp = round_footprint(0.1);
        let goal = Point2::new(2.06, 1.9);
        assert!(cm.cost_at(goal) >= crate::costmap::INSCRIBED, "the goal is in the inscribed zone");
        assert!(footprint_free(&cm, Pose2::new(goal.x, goal.y, 0.0), &fp));
        // Against a wall the footprint does not fit.
        assert!(!footprint_free(&cm, Pose2::new(2.0, 1.0, 0.0), &fp));
        // Drive in from the approach side.
        let mut pose = Pose2::new(1.7, 1.9, 0.5);
        for _ in 0..400 {
            let Some(t) = approach_command(&cm, pose, goal, &fp, 0.1, 1.0, 0.5) else { panic!("blocked at {pose:?}") };
            pose = Pose2::new(pose.x + t.linear * pose.yaw.cos() * 0.05, pose.y + t.linear * pose.yaw.sin() * 0.05, pose.yaw + t.angular * 0.05);
        }
        assert!(pose.position().dist(goal) < 0.03, "{pose:?}");
        // A goal inside the wall: the approach stops short of it.
        let mut pose = Pose2::new(1.7, 1.0, 0.0);
        let mut blocked = false;
        for _ in 0..400 {
            let Some(t) = approach_command(&cm, pose, Point2::new(2.05, 1.0), &fp, 0.1, 1.0, 0.5) else {
                blocked = true;
                break;
            };
            pose = Pose2::new(pose.x + t.linear * pose.yaw.cos() * 0.05, pose.y + t.linear * pose.yaw.sin() * 0.05, pose.yaw + t.angular * 0.05);
        }
        assert!(blocked && pose.x < 2.0 - 0.07 && pose.x > 1.8, "{pose:?}");
    }
}
