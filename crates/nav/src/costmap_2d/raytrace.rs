//! Grid traversal of a segment (Amanatides and Woo): every cell the segment passes through, in
//! order, with no gaps at diagonal steps (ROS's Bresenham lines may skip corner cells).

/// Calls `visit(cx, cy)` for each cell crossed by the segment from `(x0, y0)` to `(x1, y1)`
/// (continuous map coordinates, cells), start and end cells included, until `visit` returns
/// false.
pub fn traverse_segment(
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
    mut visit: impl FnMut(i64, i64) -> bool,
) {
    let (mut cx, mut cy) = (x0.floor() as i64, y0.floor() as i64);
    let (ex, ey) = (x1.floor() as i64, y1.floor() as i64);
    let (dx, dy) = (x1 - x0, y1 - y0);
    let step_x: i64 = if dx > 0.0 { 1 } else { -1 };
    let step_y: i64 = if dy > 0.0 { 1 } else { -1 };
    let t_delta_x = if dx != 0.0 {
        (1.0 / dx).abs()
    } else {
        f64::INFINITY
    };
    let t_delta_y = if dy != 0.0 {
        (1.0 / dy).abs()
    } else {
        f64::INFINITY
    };
    let first_boundary = |p: f64, c: i64, s: i64| {
        if s > 0 {
            (c + 1) as f64 - p
        } else {
            p - c as f64
        }
    };
    let mut t_max_x = if dx != 0.0 {
        first_boundary(x0, cx, step_x) * t_delta_x
    } else {
        f64::INFINITY
    };
    let mut t_max_y = if dy != 0.0 {
        first_boundary(y0, cy, step_y) * t_delta_y
    } else {
        f64::INFINITY
    };
    let max_steps = (ex - cx).unsigned_abs() + (ey - cy).unsigned_abs();
    if !visit(cx, cy) {
        return;
    }
    for _ in 0..max_steps {
        if t_max_x < t_max_y {
            cx += step_x;
            t_max_x += t_delta_x;
        } else {
            cy += step_y;
            t_max_y += t_delta_y;
        }
        if !visit(cx, cy) {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cells(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<(i64, i64)> {
        let mut v = Vec::new();
        traverse_segment(x0, y0, x1, y1, |x, y| {
            v.push((x, y));
            true
        });
        v
    }

    #[test]
    fn visits_every_crossed_cell_in_order() {
        assert_eq!(
            cells(0.5, 0.5, 3.5, 0.5),
            vec![(0, 0), (1, 0), (2, 0), (3, 0)]
        );
        assert_eq!(cells(0.5, 0.5, 0.5, -1.5), vec![(0, 0), (0, -1), (0, -2)]);
        let d = cells(0.2, 0.5, 2.2, 1.5);
        assert_eq!(d.first(), Some(&(0, 0)));
        assert_eq!(d.last(), Some(&(2, 1)));
        // 4-connected: consecutive cells share an edge.
        assert!(
            d.windows(2)
                .all(|w| (w[0].0 - w[1].0).abs() + (w[0].1 - w[1].1).abs() == 1),
            "{d:?}"
        );
        assert_eq!(cells(1.5, 1.5, 1.7, 1.2), vec![(1, 1)]);
    }
}
