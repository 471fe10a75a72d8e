//! A depth image projected onto the floor plan: the points that stand in the robot's body
//! band (obstacles it would hit, table tops included, which a planar lidar misses) and the
//! points on the floor (space seen to be free), as a height-band voxel layer flattens a
//! point cloud.

use serde::{Deserialize, Serialize};
use xhab_types::{DepthImage, Intrinsics, Point2, Pose2};

/// Which heights count as what (m above the floor).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ProjectionParams {
    /// Points higher than this are obstacles (m, default 0.2: the highest step climbed).
    pub min_obstacle_height: f64,
    /// Points up to this height are obstacles (m, default 1.5: the robot's height).
    pub max_obstacle_height: f64,
    /// Points within this of the floor are floor (m, default 0.05).
    pub floor_tolerance: f64,
    /// Points farther than this are ignored (m, default 4).
    pub max_range: f64,
    /// Every `stride`-th pixel in both directions is used (default 1).
    pub stride: usize,
}

impl Default for ProjectionParams {
    fn default() -> Self {
        Self { min_obstacle_height: 0.2, max_obstacle_height: 1.5, floor_tolerance: 0.05, max_range: 4.0, stride: 1 }
    }
}

/// Floor-plan points of one depth image (world frame, m).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BandPoints {
    /// Points in the obstacle band.
    pub obstacles: Vec<Point2>,
    /// Points on the floor.
    pub floor: Vec<Point2>,
}

/// Projects `depth` (optical-axis depth, m; 0 = no return) taken by a level camera with
/// intrinsics `k` at planar pose `camera` (looking along its yaw) `camera_height` m above the
/// floor.
pub fn project_depth(depth: &DepthImage, k: &Intrinsics, camera: Pose2, camera_height: f64, p: &ProjectionParams) -> BandPoints {
    let (s, c) = camera.yaw.sin_cos();
    let stride = p.stride.max(1);
    let mut out = BandPoints::default();
    // The previous used row's obstacle point (floor plan, height) per column.
    let mut above: Vec<Option<(Point2, f64)>> = vec![None; depth.width];
    for v in (0..depth.height).step_by(stride) {
        let y = (v as f64 - k.cy) / k.fy;
        for u in (0..depth.width).step_by(stride) {
            let z = depth.data[v * depth.width + u] as f64;
            let prev = above[u].take();
            if !(z > 0.0 && z.is_finite()) {
                continue;
            }
            let x = (u as f64 - k.cx) / k.fx * z;
            if z * z + x * x > p.max_range * p.max_range {
                continue;
            }
            // Optical x is to the right of the heading, y down.
            let q = Point2::new(camera.x + z * c + x * s, camera.y + z * s - x * c);
            let h = camera_height - y * z;
            if h.abs() <= p.floor_tolerance {
                out.floor.push(q);
            } else if h > p.min_obstacle_height && h <= p.max_obstacle_height {
                // A surface seen at a grazing angle (a table top from afar) puts consecutive
                // rows far apart on the plan: fill the gap when both rows lie on one surface.
                if let Some((a, ha)) = prev {
                    let d = a.dist(q);
                    if (ha - h).abs() < FILL_MAX_DH && d < FILL_MAX_GAP && d > FILL_STEP {
                        let n = (d / FILL_STEP).ceil() as usize;
                        out.obstacles.extend((1..n).map(|i| {
                            let t = i as f64 / n as f64;
                            Point2::new(a.x + t * (q.x - a.x), a.y + t * (q.y - a.y))
                        }));
                    }
                }
                out.obstacles.push(q);
                above[u] = Some((q, h));
            }
        }
    }
    out
}

/// Gaps between rows on one surface are filled at this spacing (m).
const FILL_STEP: f64 = 0.02;
/// Rows whose points are farther apart than this (m) are not joined.
const FILL_MAX_GAP: f64 = 0.5;
/// Rows whose heights differ more than this (m) are not on one surface.
const FILL_MAX_DH: f64 = 0.05;

#[cfg(test)]
mod tests {
    use super::*;

    /// A level camera 1 m up facing +x at a wall 2 m away: pixels above the horizon hit the
    /// wall, those below it the floor up to the wall.
    #[test]
    fn a_wall_and_the_floor_in_front_of_it() {
        let (w, h) = (64, 64);
        let k = Intrinsics::from_hfov(w, h, 90f64.to_radians());
        let cam_h = 1.0;
        let mut data = vec![0f32; w * h];
        for v in 0..h {
            let y = (v as f64 - k.cy) / k.fy;
            // Floor at depth cam_h / y where that is nearer than the wall.
            data[v * w..(v + 1) * w].iter_mut().for_each(|d| *d = if y > 0.0 && cam_h / y < 2.0 { (cam_h / y) as f32 } else { 2.0 });
        }
        let img = DepthImage { width: w, height: h, data };
        let p = ProjectionParams { stride: 1, ..Default::default() };
        let b = project_depth(&img, &k, Pose2::new(1.0, 0.0, 0.0), cam_h, &p);
        assert!(!b.obstacles.is_empty() && !b.floor.is_empty());
        assert!(b.obstacles.iter().all(|q| (q.x - 3.0).abs() < 1e-9 && q.y.abs() <= 2.0 + 1e-9), "wall points at x = 3");
        assert!(b.floor.iter().all(|q| q.x > 1.0 && q.x <= 3.0 + 1e-9));
        // Facing +y instead, the wall is at y = 2.
        let b = project_depth(&img, &k, Pose2::new(0.0, 0.0, std::f64::consts::FRAC_PI_2), cam_h, &p);
        assert!(b.obstacles.iter().all(|q| (q.y - 2.0).abs() < 1e-9));
        // A pixel right of centre lands to the right of the heading (+x when facing +y).
        let right = project_depth(&DepthImage { width: w, height: h, data: (0..w * h).map(|i| if i % w == w - 1 && i / w == h / 2 { 2.0 } else { 0.0 }).collect() }, &k, Pose2::new(0.0, 0.0, std::f64::consts::FRAC_PI_2), cam_h, &p);
        assert!(right.obstacles.len() == 1 && right.obstacles[0].x > 1.5, "{:?}", right.obstacles);
    }

    /// A table top 0.5 m below the camera, 3..4 m ahead: seen at a grazing angle its rows land
    /// far apart on the plan, and the gaps between them are filled.
    #[test]
    fn a_table_top_seen_from_afar_is_filled_in() {
        let (w, h) = (512, 512);
        let k = Intrinsics::from_hfov(w, h, 90f64.to_radians());
        let mut data = vec![0f32; w * h];
        for v in 0..h {
            let y = (v as f64 - k.cy) / k.fy;
            // The top's plane is 0.5 m below the camera: depth 0.5 / y, kept between 3 and 4 m.
            if y > 0.0 && (3.0..=4.0).contains(&(0.5 / y)) {
                data[v * w..(v + 1) * w].iter_mut().for_each(|d| *d = (0.5 / y) as f32);
            }
        }
        let img = DepthImage { width: w, height: h, data };
        let b = project_depth(&img, &k, Pose2::default(), 1.25, &ProjectionParams { stride: 1, ..Default::default() });
        // Along the two centre columns the points cover 3..4 m without a gap over 0.05 m.
        let mut xs: Vec<f64> = b.obstacles.iter().filter(|q| q.y.abs() < 0.01).map(|q| q.x).collect();
        xs.sort_by(f64::total_cmp);
        assert!(xs.len() > 40 && xs[0] < 3.1 && *xs.last().unwrap() > 3.9, "{xs:?}");
        assert!(xs.windows(2).all(|p| p[1] - p[0] <= 0.05), "gaps: {xs:?}");
    }
}
