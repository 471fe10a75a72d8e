//! [`DistanceGrid`]: distance (m) from every reachable cell of the local costmap to a set of
//! target cells (the local path, or the local goal), through cells the robot's centre may
//! occupy, as base_local_planner's MapGrid; 8-connected with exact diagonals where ROS counts
//! 4-connected steps.

use crate::costmap_2d::{traverse_segment, Costmap2D, INSCRIBED, LETHAL};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use xhab_types::{Point2, Pose2};

/// Distances over a costmap's cells; `f64::INFINITY` for obstacles and unreachable cells.
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceGrid {
    dist: Vec<f64>,
}

impl DistanceGrid {
    /// Distances from `targets` (cell indices of `costmap`); a target may lie in the inscribed
    /// zone, but distances spread only through cells below INSCRIBED.
    pub fn from_cells(costmap: &Costmap2D, targets: &[usize]) -> Self {
        let (sx, sy) = (costmap.size_x(), costmap.size_y());
        let costs = costmap.costs();
        let mut dist = vec![f64::INFINITY; sx * sy];
        let mut heap = BinaryHeap::new();
        for &t in targets {
            if costs[t] < LETHAL && dist[t] > 0.0 {
                dist[t] = 0.0;
                heap.push(Reverse((0f64.to_bits(), t as u32)));
            }
        }
        let res = costmap.resolution();
        let diag = res * std::f64::consts::SQRT_2;
        while let Some(Reverse((d, m))) = heap.pop() {
            let (d, m) = (f64::from_bits(d), m as usize);
            if d > dist[m] {
                continue;
            }
            let (x, y) = ((m % sx) as isize, (m / sx) as isize);
            for (dx, dy) in [
                (1, 0),
                (-1, 0),
                (0, 1),
                (0, -1),
                (1, 1),
                (1, -1),
                (-1, 1),
                (-1, -1),
            ] {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= sx as isize || ny >= sy as isize {
                    continue;
                }
                let k = ny as usize * sx + nx as usize;
                if costs[k] >= INSCRIBED {
                    continue;
                }
                let nd = d + if dx != 0 && dy != 0 { diag } else { res };
                if nd < dist[k] {
                    dist[k] = nd;
                    heap.push(Reverse((nd.to_bits(), k as u32)));
                }
            }
        }
        Self { dist }
    }

    /// Distances from the cells the polyline `path` (world frame) crosses inside `costmap`.
    pub fn from_path(costmap: &Costmap2D, path: &[Pose2]) -> Self {
        Self::from_cells(costmap, &path_cells(costmap, path))
    }

    /// Distance (m) at world point `p`; `None` outside the map, in an obstacle or unreachable.
    pub fn at(&self, costmap: &Costmap2D, p: Point2) -> Option<f64> {
        let (x, y) = costmap.world_to_map(p)?;
        let d = self.dist[costmap.index(x, y)];
        d.is_finite().then_some(d)
    }
}

/// The cells of `costmap` that the polyline `path` crosses (in order, inside the map only).
pub fn path_cells(costmap: &Costmap2D, path: &[Pose2]) -> Vec<usize> {
    let (sx, sy) = (costmap.size_x() as i64, costmap.size_y() as i64);
    let mut out = Vec::new();
    let mut push = |x: i64, y: i64| {
        if x >= 0 && y >= 0 && x < sx && y < sy {
            out.push((y * sx + x) as usize);
        }
        true
    };
    if path.len() == 1 {
        let (x, y) = costmap.world_to_map_unbounded(path[0].position());
        push(x, y);
    }
    for w in path.windows(2) {
        let (x0, y0) = costmap.world_to_map_continuous(w[0].position());
        let (x1, y1) = costmap.world_to_map_continuous(w[1].position());
        traverse_segment(x0, y0, x1, y1, &mut push);
    }
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::costmap_2d::FREE;

    #[test]
    fn distances_go_around_obstacles() {
        let mut m = Costmap2D::new(20, 10, 0.1, Point2::default(), FREE);
        for y in 0..8 {
            m.set_cost(10, y, LETHAL);
        }
        let g = DistanceGrid::from_cells(&m, &[m.index(5, 2)]);
        assert_eq!(g.at(&m, Point2::new(0.55, 0.25)), Some(0.0));
        assert!((g.at(&m, Point2::new(0.85, 0.25)).unwrap() - 0.3).abs() < 1e-12);
        assert_eq!(g.at(&m, Point2::new(1.05, 0.25)), None);
        // Around the wall's end at row 8: much more than the straight 1 m.
        assert!(g.at(&m, Point2::new(1.55, 0.25)).unwrap() > 1.5);
        let p = DistanceGrid::from_path(
            &m,
            &[Pose2::new(0.05, 0.95, 0.0), Pose2::new(1.95, 0.95, 0.0)],
        );
        assert!((p.at(&m, Point2::new(1.55, 0.55)).unwrap() - 0.4).abs() < 1e-12);
    }
}
