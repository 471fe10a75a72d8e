//! Headings along a path, as ROS global_planner's `orientation_mode`: 0 none (yaw 0),
//! 1 forward, 2 interpolate from the start's yaw to the goal's, 3 forward then interpolate over
//! the last straight leg, 4 backward, 5 leftward, 6 rightward. The last pose always carries
//! the goal's yaw, as in ROS.

use xhab_types::{normalize_angle, Point2, Pose2};

/// Forward heading at point `i` (rad): from the point `window` before it to the one `window`
/// after it.
fn forward_yaw(pts: &[Point2], i: usize, window: usize) -> f64 {
    let n = pts.len();
    let (a, b) = (pts[i.saturating_sub(window)], pts[(i + window).min(n - 1)]);
    if a.dist(b) < 1e-12 {
        return 0.0;
    }
    (b.y - a.y).atan2(b.x - a.x)
}

/// Poses at `pts` with headings by `mode` (see the module doc), `start_yaw` and `goal_yaw`
/// (rad); `window` >= 1 points on each side for forward headings.
pub fn orient(
    pts: &[Point2],
    start_yaw: f64,
    goal_yaw: f64,
    mode: i32,
    window: usize,
) -> Vec<Pose2> {
    let n = pts.len();
    let window = window.max(1);
    let lerp = |a: f64, b: f64, t: f64| normalize_angle(a + t * normalize_angle(b - a));
    let mut yaws: Vec<f64> = (0..n)
        .map(|i| match mode {
            0 => 0.0,
            2 => lerp(
                start_yaw,
                goal_yaw,
                if n > 1 {
                    i as f64 / (n - 1) as f64
                } else {
                    1.0
                },
            ),
            4 => normalize_angle(forward_yaw(pts, i, window) + std::f64::consts::PI),
            5 => normalize_angle(forward_yaw(pts, i, window) + std::f64::consts::FRAC_PI_2),
            6 => normalize_angle(forward_yaw(pts, i, window) - std::f64::consts::FRAC_PI_2),
            _ => forward_yaw(pts, i, window),
        })
        .collect();
    if mode == 3 && n > 2 {
        // The last straight leg: points whose heading matches the final segment's.
        let last = yaws[n - 2];
        let mut k = n - 2;
        while k > 0 && normalize_angle(yaws[k - 1] - last).abs() < 1e-3 {
            k -= 1;
        }
        let span = (n - 1 - k) as f64;
        for (j, y) in yaws.iter_mut().enumerate().take(n - 1).skip(k) {
            *y = lerp(last, goal_yaw, (j - k) as f64 / span);
        }
    }
    if let Some(y) = yaws.last_mut() {
        *y = goal_yaw;
    }
    pts.iter()
        .zip(yaws)
        .map(|(p, yaw)| Pose2::new(p.x, p.y, yaw))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forward_headings_follow_the_path_and_end_at_the_goal_yaw() {
        let pts = [
            Point2::new(0.0, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(1.0, 1.0),
            Point2::new(1.0, 2.0),
        ];
        let p = orient(&pts, 0.3, -1.0, 1, 1);
        assert!((p[0].yaw - 0.0).abs() < 1e-12);
        assert!((p[1].yaw - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
        assert!((p[2].yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert_eq!(p[3].yaw, -1.0);
        let q = orient(&pts, 0.3, -1.0, 2, 1);
        assert!((q[0].yaw - 0.3).abs() < 1e-12 && q[3].yaw == -1.0);
        let b = orient(&pts, 0.0, 0.0, 4, 1);
        assert!((b[0].yaw.abs() - std::f64::consts::PI).abs() < 1e-12);
    }
}
