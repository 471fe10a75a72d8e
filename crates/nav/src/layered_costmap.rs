//! costmap_2d's layered costmap on the static map's grid: the static layer with its exact
//! distance field (computed once per map), the obstacle layer's marks, and inflation redone
//! only inside the bounds where marks changed (`updateBounds` then `updateCosts`), for the
//! global costmap and for the rolling local window alike.
//!
//! Every cost equals the one a full rebuild gives ([`Costmap::from_map`] and
//! [`ObstacleLayer::local_costmap`]): distances between cell centres are whole numbers of
//! cells squared, taken exactly, and a cell's cost depends only on obstacles within the
//! inflation's reach, so recomputing the cells within that reach of a change is enough.

use crate::cell_bounds::{CellBounds, DirtyBounds};
use crate::costmap::{Costmap, CostmapParams, LETHAL, UNKNOWN, INSCRIBED};
use crate::distance_field::{squared_edt, stamp_points, FAR};
use crate::inflation_table::InflationTable;
use crate::obstacle_layer::{ObstacleLayer, ObstacleParams};
use xhab_types::{LaserScan, OccupancyGrid, Point2, Pose2, GRID_UNKNOWN};

/// Cells the cached local region extends past the local window on each side, so that the
/// window can follow the robot between scans without a rebuild.
const LOCAL_SLACK_CELLS: isize = 4;

/// The global and local costmaps of one static map, kept up to date with the obstacle marks.
#[derive(Debug, Clone)]
pub struct LayeredCostmap {
    /// The static layer inflated with the global costmap's parameters.
    static_layer: Costmap,
    static_lethal: Vec<bool>,
    /// Squared distance (cells^2) from each cell to the nearest static lethal cell; exact up
    /// to the larger of the two tables' caps.
    static_d2: Vec<u32>,
    global_table: InflationTable,
    local_table: InflationTable,
    local_window: f64,
    obstacle_params: ObstacleParams,
    obstacles: Option<ObstacleLayer>,
    /// The global costmap: static layer, marks and inflation.
    master: Costmap,
    /// Cells whose mark flipped since `master` was last brought up to date.
    pending: DirtyBounds,
    local: LocalCache,
    /// Changes whenever a cost of `master` may have changed.
    version: u64,
}

/// Squared distance (cells^2) from cell (`c`, `r`) to the nearest cell off a `w` x `h` map:
/// straight across the nearest edge; capped at [`FAR`].
pub(crate) fn border_d2(c: usize, r: usize, w: usize, h: usize) -> u32 {
    let border = crate::costmap::border_cells(c, r, w, h) as u64;
    (border * border).min(FAR as u64) as u32
}

/// The local region last computed: costs over `region` (global cell coordinates, possibly
/// beyond the map) for the marks as they were after `flips` flips.
#[derive(Debug, Clone, Default)]
struct LocalCache {
    valid: bool,
    flips: u64,
    c0: isize,
    r0: isize,
    w: usize,
    h: usize,
    cost: Vec<u8>,
    window: Option<Costmap>,
}

impl LayeredCostmap {
    /// The costmaps of `map` (a rotated map first turned into the world's axes:
    /// [`OccupancyGrid::axis_aligned`]) with the global and local costmaps' parameters; no
    /// marks yet.
    pub fn new(map: &OccupancyGrid, global: &CostmapParams, local: &CostmapParams, obstacle_params: ObstacleParams) -> Self {
        let map = &*map.axis_aligned();
        let (w, h) = (map.width, map.height);
        let global_table = InflationTable::new(global, map.resolution);
        let local_table = InflationTable::new(local, map.resolution);
        let static_lethal: Vec<bool> = map.data.iter().map(|&v| v >= global.lethal_cost_threshold).collect();
        let mut static_d2 = Vec::new();
        squared_edt(w, h, |c, r| static_lethal[r * w + c], global_table.cap().max(local_table.cap()), &mut static_d2);
        // The map's outside is an obstacle to the global costmap too (the local one always
        // took it so): a plan does not run along the map's edge, where the scene's walls may
        // lie just beyond the last row.
        for (i, d2) in static_d2.iter_mut().enumerate() {
            *d2 = (*d2).min(border_d2(i % w, i / w, w, h));
        }
        let cost = (0..w * h).map(|i| static_cost(static_lethal[i], map.data[i] == GRID_UNKNOWN, static_d2[i], &global_table, global.track_unknown_space)).collect();
        let static_layer = Costmap { width: w, height: h, resolution: map.resolution, origin: Point2::new(map.origin.x, map.origin.y), cost };
        Self {
            master: static_layer.clone(),
            static_layer,
            static_lethal,
            static_d2,
            global_table,
            local_table,
            local_window: obstacle_params.local_window,
            obstacle_params,
            obstacles: None,
            pending: DirtyBounds::default(),
            local: LocalCache::default(),
            version: 0,
        }
    }

    /// The static layer inflated (the global costmap without marks).
    pub fn static_layer(&self) -> &Costmap {
        &self.static_layer
    }

    /// The obstacle layer, once a scan has arrived.
    pub fn obstacles(&self) -> Option<&ObstacleLayer> {
        self.obstacles.as_ref()
    }

    /// Feeds a scan taken at `sensor` (world frame) to the obstacle layer.
    pub fn add_scan(&mut self, scan: &LaserScan, sensor: Pose2) {
        let params = self.obstacle_params.clone();
        let ob = self.obstacles.get_or_insert_with(|| ObstacleLayer::new(&self.static_layer, params));
        ob.update(scan, sensor);
        if let Some(b) = ob.take_changes() {
            self.pending.add(b);
        }
    }

    /// Drops the obstacle layer (move_base's `clear_costmaps`): both costmaps fall back to
    /// the static layer until the next scan.
    pub fn clear_obstacles(&mut self) {
        if self.obstacles.take().is_some() {
            self.master.cost.copy_from_slice(&self.static_layer.cost);
            self.version += 1;
        }
        self.pending = DirtyBounds::default();
        self.local.valid = false;
    }

    /// Forgets every mark but keeps the layer (the costmaps' reset in a recovery).
    pub fn reset_marks(&mut self) {
        if let Some(ob) = self.obstacles.as_mut() {
            ob.reset();
            if let Some(b) = ob.take_changes() {
                self.pending.add(b);
            }
        }
    }

    /// The global costmap as of the last [`LayeredCostmap::update_global`].
    pub fn global(&self) -> &Costmap {
        &self.master
    }

    /// The global costmap's version: the same number means the same costs (for one
    /// `LayeredCostmap`).
    pub fn global_version(&self) -> u64 {
        self.version
    }

    /// Brings the global costmap up to date with the marks, re-inflating only around the
    /// cells whose mark changed.
    pub fn update_global(&mut self) {
        let Some(changed) = self.pending.take() else { return };
        let Some(ob) = self.obstacles.as_ref() else { return };
        self.version += 1;
        let (w, h) = (self.master.width, self.master.height);
        let reach = self.global_table.reach();
        let region = changed.expanded(reach, w, h);
        let marks = marks_field(ob.marks(), &self.static_lethal, w, h, region, reach, self.global_table.cap());
        let rw = region.width();
        for r in region.r0..region.r1 {
            for c in region.c0..region.c1 {
                let i = r * w + c;
                self.master.cost[i] = if self.static_lethal[i] || ob.marks()[i] {
                    LETHAL
                } else {
                    let d2 = self.static_d2[i].min(marks[(r - region.r0) * rw + (c - region.c0)]);
                    self.global_table.cost(d2).max(self.static_layer.cost[i])
                };
            }
        }
    }

    /// The rolling local costmap centred on `center` (m): static lethal cells, marks and the
    /// map's outside inflated with the local costmap's parameters over a `local_window` square,
    /// as [`ObstacleLayer::local_costmap`] builds it. Without marks yet, the global costmap.
    pub fn local(&mut self, center: Point2) -> &Costmap {
        let Some(ob) = self.obstacles.as_ref() else { return &self.master };
        let st = &self.static_layer;
        let res = st.resolution;
        let half = (self.local_window / 2.0 / res).ceil() as isize;
        let (cc, cr) = (((center.x - st.origin.x) / res).floor() as isize, ((center.y - st.origin.y) / res).floor() as isize);
        let (wc0, wr0) = (cc.saturating_sub(half), cr.saturating_sub(half));
        let n = (2 * half).max(0) as usize;
        let lc = &mut self.local;
        let inside = lc.valid && wc0 >= lc.c0 && wr0 >= lc.r0 && wc0.saturating_add(n as isize) <= lc.c0 + lc.w as isize && wr0.saturating_add(n as isize) <= lc.r0 + lc.h as isize;
        if !inside || lc.flips != ob.flips() {
            let (c0, r0) = (wc0.saturating_sub(LOCAL_SLACK_CELLS), wr0.saturating_sub(LOCAL_SLACK_CELLS));
            let side = n + 2 * LOCAL_SLACK_CELLS as usize;
            local_region(lc, ob, &self.static_lethal, &self.static_d2, st.width, st.height, &self.local_table, (c0, r0), side);
            lc.flips = ob.flips();
            lc.valid = true;
        }
        let origin = Point2::new(st.origin.x + wc0 as f64 * res, st.origin.y + wr0 as f64 * res);
        let win = lc.window.get_or_insert_with(|| Costmap { width: 0, height: 0, resolution: res, origin, cost: Vec::new() });
        win.width = n;
        win.height = n;
        win.resolution = res;
        win.origin = origin;
        win.cost.clear();
        let (dc, dr) = ((wc0 - lc.c0) as usize, (wr0 - lc.r0) as usize);
        for r in 0..n {
            let start = (dr + r) * lc.w + dc;
            win.cost.extend_from_slice(&lc.cost[start..start + n]);
        }
        win
    }
}

/// The cost of a static-layer cell: LETHAL on obstacles, the inflation by distance `d2`
/// (cells^2), or UNKNOWN for unknown space below the inscribed cost when it is tracked.
fn static_cost(lethal: bool, unknown: bool, d2: u32, table: &InflationTable, track_unknown: bool) -> u8 {
    if lethal {
        return LETHAL;
    }
    let c = table.cost(d2);
    if track_unknown && unknown && c < INSCRIBED {
        UNKNOWN
    } else {
        c
    }
}

/// Squared distances (cells^2) from each cell of `region` (row-major over it) to the nearest
/// mark that is not on a static obstacle, exact up to `cap` and considering marks within
/// `reach` cells of the region.
fn marks_field(marks: &[bool], static_lethal: &[bool], w: usize, h: usize, region: CellBounds, reach: usize, cap: u32) -> Vec<u32> {
    let outer = region.expanded(reach, w, h);
    let mut points = Vec::new();
    for r in outer.r0..outer.r1 {
        for c in outer.c0..outer.c1 {
            let i = r * w + c;
            if marks[i] && !static_lethal[i] {
                points.push((c as isize - region.c0 as isize, r as isize - region.r0 as isize));
            }
        }
    }
    let mut out = vec![FAR; region.area()];
    if points.is_empty() {
        return out;
    }
    let stamp = (2 * reach + 1) * (2 * reach + 1);
    if points.len().saturating_mul(stamp) <= 2 * outer.area() {
        stamp_points(&mut out, region.width(), region.height(), &points, reach);
    } else {
        let ow = outer.width();
        let mut field = Vec::new();
        squared_edt(ow, outer.height(), |c, r| {
            let i = (outer.r0 + r) * w + outer.c0 + c;
            marks[i] && !static_lethal[i]
        }, cap, &mut field);
        let (dc, dr) = (region.c0 - outer.c0, region.r0 - outer.r0);
        for r in 0..region.height() {
            let src = (dr + r) * ow + dc;
            out[r * region.width()..(r + 1) * region.width()].copy_from_slice(&field[src..src + region.width()]);
        }
    }
    out
}

/// Fills `lc` with the local costs over the `side` x `side` cells from `corner` (global cell
/// coordinates, possibly beyond the `w` x `h` map, whose outside is an obstacle).
fn local_region(lc: &mut LocalCache, ob: &ObstacleLayer, static_lethal: &[bool], static_d2: &[u32], w: usize, h: usize, table: &InflationTable, corner: (isize, isize), side: usize) {
    let (c0, r0) = corner;
    lc.c0 = c0;
    lc.r0 = r0;
    lc.w = side;
    lc.h = side;
    lc.cost.clear();
    lc.cost.resize(side * side, LETHAL);
    // The part of the region on the map.
    let clip = |a: isize, n: usize| a.clamp(0, n as isize) as usize;
    let on_map = CellBounds { c0: clip(c0, w), r0: clip(r0, h), c1: clip(c0.saturating_add(side as isize), w), r1: clip(r0.saturating_add(side as isize), h) };
    if on_map.is_empty() {
        return;
    }
    let marks = ob.marks();
    let mf = marks_field(marks, static_lethal, w, h, on_map, table.reach(), table.cap());
    let mw = on_map.width();
    for r in on_map.r0..on_map.r1 {
        for c in on_map.c0..on_map.c1 {
            let i = r * w + c;
            let out = &mut lc.cost[(r as isize - r0) as usize * side + (c as isize - c0) as usize];
            if static_lethal[i] || marks[i] {
                *out = LETHAL;
                continue;
            }
            // static_d2 counts the map's outside as an obstacle already.
            let d2 = static_d2[i].min(mf[(r - on_map.r0) * mw + (c - on_map.c0)]);
            *out = table.cost(d2);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn room() -> OccupancyGrid {
        let mut m = OccupancyGrid::new(90, 70, 0.05, Pose2::new(-1.0, 0.5, 0.0), 0);
        for r in 0..70 {
            for c in 0..90 {
                if c == 0 || r == 0 || (c == 40 && r < 50) || ((60..64).contains(&c) && (20..24).contains(&r)) {
                    m.set(c, r, 100);
                }
                if (70..80).contains(&c) && (50..60).contains(&r) {
                    m.set(c, r, -1);
                }
            }
        }
        m
    }

    fn scan(rng: &mut impl Rng) -> LaserScan {
        let n = 90;
        let inc = std::f64::consts::TAU / n as f64;
        let ranges = (0..n).map(|_| if rng.gen_bool(0.1) { f32::NAN } else { rng.gen_range(0.2..3.2) as f32 }).collect();
        LaserScan { angle_min: -std::f64::consts::PI, angle_max: std::f64::consts::PI - inc, angle_increment: inc, range_min: 0.1, range_max: 3.5, ranges }
    }

    /// The global costmap as the navigator rebuilt it from scratch before.
    fn full_global(st: &Costmap, ob: &ObstacleLayer, p: &CostmapParams) -> Costmap {
        let lethal: Vec<bool> = st.cost.iter().enumerate().map(|(i, &c)| c == LETHAL || ob.is_marked(i)).collect();
        let d = crate::costmap::edt(&lethal, st.width, st.height);
        let cost = (0..lethal.len()).map(|i| if lethal[i] { LETHAL } else { crate::costmap::inflation_cost(d[i] * st.resolution, p).max(st.cost[i]) }).collect();
        Costmap { cost, ..st.clone() }
    }

    #[test]
    fn incremental_costmaps_equal_full_rebuilds() {
        let map = room();
        for (global, local) in [
            (CostmapParams::default(), CostmapParams::default()),
            (CostmapParams { track_unknown_space: true, inflation_radius: 0.3, ..Default::default() }, CostmapParams { inflation_radius: 0.8, cost_scaling_factor: 3.0, robot_radius: 0.15, ..Default::default() }),
        ] {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
            let mut layers = LayeredCostmap::new(&map, &global, &local, ObstacleParams::default());
            let reference = Costmap::from_map(&map, &global);
            assert_eq!(layers.static_layer(), &reference);
            assert_eq!(layers.local(Point2::new(0.5, 1.5)), &reference, "without marks the local costmap is the global one");
            for step in 0..60 {
                // Wander, sometimes near the map's edge so that the window leaves the map.
                let pose = Pose2::new(rng.gen_range(-1.2..3.5), rng.gen_range(0.3..4.0), rng.gen_range(-3.0..3.0));
                layers.add_scan(&scan(&mut rng), pose);
                if step == 30 {
                    layers.reset_marks();
                }
                let center = Point2::new(pose.x + rng.gen_range(-0.1..0.1), pose.y + rng.gen_range(-0.1..0.1));
                let ob = layers.obstacles().unwrap().clone();
                let want_local = ob.local_costmap(&reference, center, &local);
                assert_eq!(layers.local(center), &want_local, "local window at step {step}");
                if step % 3 == 0 {
                    layers.update_global();
                    assert_eq!(layers.global(), &full_global(&reference, &ob, &global), "global costmap at step {step}");
                }
            }
            assert!(layers.obstacles().unwrap().marked_cells() > 0);
            layers.clear_obstacles();
            assert_eq!(layers.global(), &reference);
        }
    }
}
