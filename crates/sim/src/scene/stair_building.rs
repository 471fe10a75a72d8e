//! A two-storey test building with one straight staircase, all axis-aligned boxes, whose
//! geodesics between storeys are known in closed form (tests and `xhab scene generate
//! --building stairs`).
//!
//! The building spans `[0, length] x [0, width]` (m). The ground floor's top is at z = 0, the
//! upper floor's at `storey_height`. The staircase runs along +x against the south wall, from
//! `stair_x` to `stair_x + steps * tread`, over `y` in `[wall, wall + stair_width]`; step `k`
//! (1-based) is a solid box whose top is at `k * storey_height / (steps + 1)`, so the last
//! riser reaches the upper floor, with a rail panel 5 cm wide on its open (north) side. The
//! upper floor has the stairwell open above the whole flight and a balustrade along the
//! opening's north and west edges.

use super::Scene;
use serde::{Deserialize, Serialize};

/// Shape of the stair building.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StairBuildingParams {
    /// Outer length along x (m, default 10).
    pub length: f64,
    /// Outer width along y (m, default 4).
    pub width: f64,
    /// Height of the upper floor's top above the ground floor's (m, default 2.8).
    pub storey_height: f64,
    /// Number of steps below the upper floor (default 15: 16 risers of 0.175 m).
    pub steps: usize,
    /// Tread depth (m, default 0.28).
    pub tread: f64,
    /// Stair width (m, default 1.0).
    pub stair_width: f64,
    /// x of the first riser (m, default 3).
    pub stair_x: f64,
    /// Wall thickness (m, default 0.1; walls are centred on the outline, so the inside
    /// starts at half of it).
    pub wall_thickness: f64,
    /// Build the staircase (default true); without it no walkable path joins the storeys.
    pub stairs: bool,
    /// A partition on the ground floor at x = `partition_x` from y = `partition_from` to the
    /// north wall, leaving a gap against the south wall (m; `None`: no partition).
    pub partition: Option<Partition>,
}

/// A ground-floor partition wall along y (m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Partition {
    /// Centre line x (m).
    pub x: f64,
    /// The wall's south end (m); it runs north to the outer wall.
    pub from_y: f64,
    /// Thickness (m).
    pub thickness: f64,
}

impl Default for StairBuildingParams {
    fn default() -> Self {
        Self {
            length: 10.0,
            width: 4.0,
            storey_height: 2.8,
            steps: 15,
            tread: 0.28,
            stair_width: 1.0,
            stair_x: 3.0,
            wall_thickness: 0.1,
            stairs: true,
            partition: None,
        }
    }
}

const FLOOR: [f32; 4] = [0.76, 0.70, 0.60, 1.0];
const WALL: [f32; 4] = [0.92, 0.91, 0.88, 1.0];
const STAIR: [f32; 4] = [0.55, 0.38, 0.22, 1.0];
/// Thickness of the upper floor's slab (m).
pub const SLAB: f64 = 0.2;
/// Height of the upper floor's balustrade (m).
const RAIL: f64 = 1.0;

impl StairBuildingParams {
    /// Rise of one step (m).
    pub fn riser(&self) -> f64 {
        self.storey_height / (self.steps + 1) as f64
    }
    /// The inner face of the walls (m from the outline).
    pub fn inner(&self) -> f64 {
        self.wall_thickness / 2.0
    }
    /// x where the flight ends and the upper floor begins (m).
    pub fn stair_end(&self) -> f64 {
        self.stair_x + self.steps as f64 * self.tread
    }
    /// The stair's span across y (m).
    pub fn stair_y(&self) -> (f64, f64) {
        (self.inner(), self.inner() + self.stair_width)
    }
}

/// Builds the stair building.
pub fn stair_building(p: &StairBuildingParams) -> Scene {
    let f = |v: [f64; 3]| v.map(|x| x as f32);
    let mut s = Scene::default();
    let (l, w, h, t) = (p.length, p.width, p.storey_height, p.inner());
    let top = 2.0 * h;
    s.add_box("ground_floor", f([-t, -t, -0.05]), f([l + t, w + t, 0.0]), FLOOR);
    s.add_box("wall_south", f([-t, -t, 0.0]), f([l + t, t, top]), WALL);
    s.add_box("wall_north", f([-t, w - t, 0.0]), f([l + t, w + t, top]), WALL);
    s.add_box("wall_west", f([-t, t, 0.0]), f([t, w - t, top]), WALL);
    s.add_box("wall_east", f([l - t, t, 0.0]), f([l + t, w - t, top]), WALL);
    let (y0, y1) = p.stair_y();
    let (x0, x1) = (p.stair_x, p.stair_end());
    // The upper floor: everything inside the walls but the stairwell.
    let (zs0, zs1) = (h - SLAB, h);
    s.add_box("upper_floor_west", f([t, t, zs0]), f([x0, w - t, zs1]), FLOOR);
    s.add_box("upper_floor_east", f([x1, t, zs0]), f([l - t, w - t, zs1]), FLOOR);
    s.add_box("upper_floor_north", f([x0, y1, zs0]), f([x1, w - t, zs1]), FLOOR);
    if p.stairs {
        for k in 1..=p.steps {
            let xa = x0 + (k - 1) as f64 * p.tread;
            s.add_box(&format!("step_{k}"), f([xa, y0, 0.0]), f([xa + p.tread, y1, k as f64 * p.riser()]), STAIR);
            // The handrail's balusters along the open side, one panel per step.
            s.add_box(&format!("stair_rail_{k}"), f([xa, y1, k as f64 * p.riser()]), f([xa + p.tread, y1 + 0.05, k as f64 * p.riser() + RAIL]), WALL);
        }
        // The balustrade around the stairwell on the upper floor.
        s.add_box("balustrade_north", f([x0 - 0.05, y1, h]), f([x1, y1 + 0.05, h + RAIL]), WALL);
        s.add_box("balustrade_west", f([x0 - 0.05, y0, h]), f([x0, y1, h + RAIL]), WALL);
    } else {
        s.add_box("upper_floor_stairwell", f([x0, y0, zs0]), f([x1, y1, zs1]), FLOOR);
    }
    if let Some(q) = p.partition {
        let ht = q.thickness / 2.0;
        s.add_box("partition", f([q.x - ht, q.from_y, 0.0]), f([q.x + ht, w - t, h - SLAB]), WALL);
    }
    s
}
