//! Depth image to LaserScan, with the semantics of ROS depthimage_to_laserscan.

use serde::{Deserialize, Serialize};
use xhab_types::{DepthImage, Intrinsics, LaserScan};

/// Parameters (depthimage_to_laserscan names and defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DepthToScanParams {
    /// Rows around the optical centre row whose minimum is taken (default 1).
    pub scan_height: usize,
    /// Shortest valid range (m, default 0.45).
    pub range_min: f64,
    /// Longest valid range (m, default 10).
    pub range_max: f64,
}

impl Default for DepthToScanParams {
    fn default() -> Self {
        Self { scan_height: 1, range_min: 0.45, range_max: 10.0 }
    }
}

/// Index of the beam that a ray at angle `th` (rad) falls in, truncated as ROS does.
pub fn beam_index(th: f64, angle_min: f64, inc: f64, n: usize) -> Option<usize> {
    if inc <= 0.0 {
        return (n > 0).then_some(0);
    }
    let f = ((th - angle_min) / inc + 1e-9).floor();
    (f >= 0.0 && (f as usize) < n).then_some(f as usize)
}

/// One range per column: beam angle from the intrinsics (`-atan((u - cx) / fx)`, CCW positive,
/// so the image's left is positive), range `hypot((u - cx) z / fx, z)`, the minimum over
/// `scan_height` rows around `cy`, NaN where no depth lies in [range_min, range_max].
pub fn depth_to_scan(img: &DepthImage, k: &Intrinsics, p: &DepthToScanParams) -> LaserScan {
    let w = img.width;
    let angle = |u: f64| -((u - k.cx) / k.fx).atan();
    let angle_max = angle(0.0);
    let angle_min = angle((w.max(1) - 1) as f64);
    let inc = if w > 1 { (angle_max - angle_min) / (w - 1) as f64 } else { 0.0 };
    let mut ranges = vec![f32::NAN; w];
    let h = p.scan_height.max(1);
    let first = (k.cy.round() as isize - (h / 2) as isize).max(0) as usize;
    for v in first..(first + h).min(img.height) {
        for u in 0..w {
            let z = img.data[v * w + u] as f64;
            if !(z.is_finite() && z > 0.0) {
                continue;
            }
            let x = (u as f64 - k.cx) * z / k.fx;
            let r = x.hypot(z);
            if r < p.range_min || r > p.range_max {
                continue;
            }
            // As ROS: the beam index comes from the column's own angle (beams run from
            // angle_min, the rightmost column, to angle_max, the leftmost).
            let Some(i) = beam_index(angle(u as f64), angle_min, inc, w) else { continue };
            if ranges[i].is_nan() || (r as f32) < ranges[i] {
                ranges[i] = r as f32;
            }
        }
    }
    LaserScan { angle_min, angle_max, angle_increment: inc, range_min: p.range_min, range_max: p.range_max, ranges }
}
