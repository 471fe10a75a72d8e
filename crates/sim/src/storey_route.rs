//! An episode's way across storeys: on each storey from the start's to the goals', a goal
//! field towards the next flight's portal (each portal point carrying the way on from it) or,
//! on the goals' storey, towards the goals. The distance any of these fields gives is the
//! planar length still to go, so they compare across storeys, and an agent on a flight counts
//! on the storey whose field says it is nearer.

use crate::goal_field::GoalField;
use crate::navgrid::NavGrid;
use crate::world::World;
use std::sync::Arc;
use xhab_types::Point2;

/// The storeys of one episode's way, with their grids and goal fields.
#[derive(Debug)]
pub struct StoreyRoute {
    /// Per storey of the world: its grid and field when on the way.
    legs: Vec<Option<(Arc<NavGrid>, Arc<GoalField>)>>,
    /// Per lower storey of a flight on the way: the height of its portal tread (m).
    portal_z: Vec<Option<f64>>,
    /// The goals' storey.
    pub goal_storey: usize,
}

impl StoreyRoute {
    /// The way from storey `start` to the goals on storey `goal_storey`, or `None` when a
    /// storey on it cannot be built or no flight joins two storeys on it.
    pub fn new(world: &World, start: usize, goal_storey: usize, goals: &[Point2]) -> Option<StoreyRoute> {
        let mut legs: Vec<Option<(Arc<NavGrid>, Arc<GoalField>)>> = vec![None; world.floors.len()];
        let mut portal_z = vec![None; world.floors.len()];
        let g = world.grid(goal_storey).ok()?;
        let f = g.field(goals);
        legs[goal_storey] = Some((g, f));
        let portals = world.portals();
        let start_above = start > goal_storey;
        let mut k = goal_storey;
        while k != start {
            let next = if start_above { k + 1 } else { k - 1 };
            let lower = k.min(next);
            let (gk, fk) = legs[k].clone()?;
            let grid = world.grid(next).ok()?;
            let (mut pts, mut off) = (Vec::new(), Vec::new());
            for p in portals.iter().filter(|p| p.lower == lower) {
                portal_z[lower] = p.points.first().map(|q| q.z);
                for q in &p.points {
                    let t = Point2::new(q.x, q.y);
                    let d = fk.distance(&gk, t);
                    if d.is_finite() {
                        pts.push(t);
                        off.push(d);
                    }
                }
            }
            if pts.is_empty() {
                return None;
            }
            let field = Arc::new(GoalField::with_offsets(&grid, &pts, &off));
            legs[next] = Some((grid, field));
            k = next;
        }
        Some(StoreyRoute { legs, portal_z, goal_storey })
    }

    /// The grid and field of storey `k`, when it is on the way.
    pub fn leg(&self, k: usize) -> Option<&(Arc<NavGrid>, Arc<GoalField>)> {
        self.legs.get(k).and_then(|l| l.as_ref())
    }

    /// The storey an agent at `p` (m, planar) counts on after a move on storey `current`: a
    /// neighbouring storey on the way when `p` is on a flight both storeys share, at the same
    /// height, and the distance still to go is no longer there (the storey nearer the goals'
    /// takes over as soon as the agent steps on the shared part of the flight); else `current`.
    pub fn storey_at(&self, current: usize, p: Point2) -> usize {
        let Some((gc, fc)) = self.leg(current) else { return current };
        if !gc.on_stairs(p) {
            return current;
        }
        let mut best = (fc.distance(gc, p), current);
        for n in [current.wrapping_sub(1), current + 1] {
            let Some((gn, fn_)) = self.leg(n) else { continue };
            let same = match (gc.ground_at(p), gn.ground_at(p)) {
                (Some(a), Some(b)) => (a - b).abs() < 1e-4,
                _ => false,
            };
            // Only around the flight's portal tread, in the middle of the part both storeys
            // share: where a storey's part of a flight ends, its grid has an edge the agent
            // must not change grid at.
            let near_portal = match (self.portal_z.get(current.min(n)).copied().flatten(), gc.ground_at(p)) {
                (Some(z), Some(g)) => (g - z).abs() <= 1.5 * gc.params.max_climb,
                _ => false,
            };
            if !same || !near_portal || !gn.on_stairs(p) || !gn.is_navigable(p) {
                continue;
            }
            // Towards the goals' storey a tie is enough (on a shared flight the next storey's
            // way is never longer), away from it only a clearly shorter way.
            let towards = n.abs_diff(self.goal_storey) < current.abs_diff(self.goal_storey);
            let d = fn_.distance(gn, p);
            if (towards && d <= best.0 + 1e-9) || d < best.0 - 1e-6 {
                best = (d, n);
            }
        }
        best.1
    }
}
