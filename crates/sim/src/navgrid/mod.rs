//! The traversable region of a disc agent on one floor of a scene, on a fine grid.
//!
//! A cell is *navigable* when the floor under it is walkable (slope <= `max_slope`, height within
//! `max_climb` of the floor) and its centre is at least `radius` from every obstacle, where an
//! obstacle is scene geometry between `floor + max_climb` and `floor + height`, or the edge of
//! the floor. Distances to geometry are exact (see [`clearance`]), so the region's boundary is
//! not quantised to the grid. Navigable cells form islands (4-connected components).

mod band_edges;
mod build_laps;
mod clearance;
mod components;
pub(crate) mod convex_vertices;
mod floors;
mod slice;
mod stairs;
mod storey_band;
pub(crate) mod raster;

pub use build_laps::BuildLaps;
pub use floors::{detect_floors, Floor};
pub use stairs::StoreyBounds;
pub(crate) use clearance::{closest_on_segment, SeenSegments, SegmentLine};

use crate::scene::Scene;
use components::components;
pub(crate) use components::components_where;
use raster::GridSpec;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use xhab_types::{OccupancyGrid, Point2, Pose2, GRID_FREE, GRID_OCCUPIED, GRID_UNKNOWN};

/// How far below the clearance radius a point may be and still count as navigable (m).
/// Absorbs the interpolation error of the clearance field at convex corners.
pub const NAV_TOLERANCE: f64 = 0.01;

/// The navigation agent's body and the grid it is planned on (Habitat PointNav defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AgentParams {
    /// Agent (cylinder) radius (m, default 0.1).
    pub radius: f64,
    /// Agent height (m, default 1.5).
    pub height: f64,
    /// Highest step the agent climbs (m, default 0.2).
    pub max_climb: f64,
    /// Steepest walkable slope (degrees, default 45).
    pub max_slope_deg: f64,
    /// Cell size of the navigation grid (m, default 0.05).
    pub cell_size: f64,
}

impl Default for AgentParams {
    fn default() -> Self {
        Self { radius: 0.1, height: 1.5, max_climb: 0.2, max_slope_deg: 45.0, cell_size: 0.05 }
    }
}

/// Why a navigation grid could not be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum NavGridError {
    /// A parameter is out of range.
    #[error("agent parameter {field}: {reason}")]
    BadParam {
        /// The parameter's name.
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The scene has no walkable floor (or none near the requested height).
    #[error("no walkable floor found{0}")]
    NoFloor(String),
    /// The grid would be too large.
    #[error("the scene is {w} x {h} cells at {res} m: larger than the 40 million cell limit (raise cell_size)")]
    TooLarge {
        /// Cells along x.
        w: usize,
        /// Cells along y.
        h: usize,
        /// Cell size (m).
        res: f64,
    },
}

/// A connected component of the navigable region.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Island {
    /// Number of cells.
    pub cells: usize,
    /// Area (m^2).
    pub area: f64,
    /// Centroid of the island's cell centres (m, world frame).
    pub centre: Point2,
    /// Largest distance from the centroid to a cell centre of the island (m).
    pub radius: f64,
}

/// The navigable region of one floor.
#[derive(Debug, Clone)]
pub struct NavGrid {
    /// The agent the region was built for.
    pub params: AgentParams,
    /// Floor height (m, world z).
    pub floor_z: f64,
    pub(crate) spec: GridSpec,
    /// Walkable floor height per cell (m), NaN where there is none.
    pub(crate) ground: Vec<f32>,
    /// True where geometry stands in the agent's body band.
    pub(crate) occupied: Vec<bool>,
    /// Distance from the cell centre to the nearest obstacle (m, capped).
    pub(crate) clearance: Vec<f32>,
    /// Island index per cell (`u32::MAX`: not navigable).
    pub(crate) island_of: Vec<u32>,
    /// The islands.
    pub islands: Vec<Island>,
    /// True for navigable cells on the region's boundary (where shortest paths may bend).
    pub(crate) corner: Vec<bool>,
    /// Where a shortest path bending at a corner cell touches the region's boundary (m).
    pub(crate) anchor: Vec<[f64; 2]>,
    /// The obstacle segments (m): scene geometry in the body band, projected to the ground.
    pub(crate) segments: Vec<clearance::Seg>,
    /// True on stair cells, on a storey with stairs (empty otherwise).
    pub(crate) stair: Vec<bool>,
    /// Index of the segment nearest to each cell centre, when a segment is the nearest
    /// obstacle and within reach (`u32::MAX` otherwise).
    pub(crate) nearest: Vec<u32>,
    /// Per cell that a line-of-sight walk tests against its neighbours' segments (clearance
    /// above 0 and under the radius plus a half-diagonal), the distinct [`nearest`](Self::nearest)
    /// segments of its 3 x 3 block, in the block's row order, `u32::MAX` after the last;
    /// [`MANY_NEAR`] first where there are more than four; all `u32::MAX` elsewhere.
    pub(crate) near_segs: Vec<[u32; 4]>,
    /// Per cell, how many cells away the nearest cell lies that a line-of-sight walk tests
    /// (see [`sure_reach`](crate::geodesic::sure_reach)).
    pub(crate) sure_reach: Vec<u8>,
    /// Per cell, the line-of-sight tolerance (m) below which every segment through the cell
    /// fails [`segment_clear`](crate::geodesic::segment_clear) there (see
    /// [`block_margins`](crate::geodesic::block_margins)).
    pub(crate) block_margin: Vec<f32>,
    /// Per cell, one bit: whether its [`block_margin`](Self::block_margin) exceeds
    /// [`LOS_EPS`](crate::geodesic::LOS_EPS).
    pub(crate) los_blocked: Vec<u64>,
    /// The geodesic fields built lately on this grid.
    pub(crate) fields: crate::field_cache::FieldCache,
    /// The bend points of shortest paths and the legs between them, built on first use.
    pub(crate) corner_graph: std::sync::OnceLock<std::sync::Arc<crate::corner_graph::CornerGraph>>,
    /// The time each step of this grid's build took.
    laps: BuildLaps,
}

/// Rows of the grid one thread rasterises at a time in [`NavGrid::build_storey`].
const RASTER_BAND_ROWS: usize = 16;

/// [`NavGrid::near_segs`]' mark of a cell whose 3 x 3 block has more than four distinct
/// nearest segments (its walk looks at the block's cells instead).
const MANY_NEAR: u32 = u32::MAX - 1;

/// Triangles one thread sorts at a time in [`NavGrid::build_storey`].
const GATHER_CHUNK: usize = 4096;

impl NavGrid {
    /// The geodesic field of `goals` on this grid, shared with whoever asked for the same
    /// goals lately in this process.
    pub fn field(&self, goals: &[xhab_types::Point2]) -> std::sync::Arc<crate::goal_field::GoalField> {
        self.fields.get(self, goals)
    }

    /// The corner graph of this floor (the bend points of shortest paths), built on first use.
    pub fn corner_graph(&self) -> &std::sync::Arc<crate::corner_graph::CornerGraph> {
        self.corner_graph.get_or_init(|| std::sync::Arc::new(crate::corner_graph::CornerGraph::new(self)))
    }

    /// The time each step of this grid's build took (the corner graph, built on first use, is
    /// not among them).
    pub fn build_laps(&self) -> &BuildLaps {
        &self.laps
    }

    /// Builds the navigable region of `scene` on the floor at height `floor_z` (m).
    pub fn build(scene: &Scene, params: &AgentParams, floor_z: f64) -> Result<NavGrid, NavGridError> {
        Self::build_storey(scene, params, floor_z, StoreyBounds::default())
    }

    /// Builds the navigable region of the storey whose floor is at `floor_z` (m), with the
    /// flights of stairs that join it to the storeys at `bounds` (see [`stairs`]). Without a
    /// flight the grid is exactly [`NavGrid::build`]'s; with one, every cell's body band
    /// stands on its own ground and a drop of more than `max_climb` between neighbouring cells
    /// is an edge like the floor's.
    pub fn build_storey(scene: &Scene, params: &AgentParams, floor_z: f64, bounds: StoreyBounds) -> Result<NavGrid, NavGridError> {
        validate(params)?;
        let b = scene.bounds();
        if b.is_empty() {
            return Err(NavGridError::NoFloor(": the scene is empty".into()));
        }
        let res = params.cell_size;
        let pad = 2.0 * res;
        let x0 = ((b.min[0] as f64 - pad) / res).floor() * res;
        let y0 = ((b.min[1] as f64 - pad) / res).floor() * res;
        let w = (((b.max[0] as f64 + pad) - x0) / res).ceil() as usize;
        let h = (((b.max[1] as f64 + pad) - y0) / res).ceil() as usize;
        if w.saturating_mul(h) > 40_000_000 {
            return Err(NavGridError::TooLarge { w, h, res });
        }
        let spec = GridSpec { x0, y0, res, w, h };
        let n = w * h;
        let band_lo = floor_z + params.max_climb;
        let band_hi = floor_z + params.height;
        let ground_lo = floor_z - params.max_climb;
        let ground_hi = floor_z + params.max_climb;
        let cos_slope = params.max_slope_deg.to_radians().cos();

        let mut ground = vec![f32::NAN; n];
        let mut occupied = vec![false; n];
        // Lowest surface above the agent's head per cell, and whether it faces up (then the
        // cell is inside a closed solid: a shelf, a wall's core).
        let mut roof = vec![(f32::INFINITY, false); n];
        let mut segs = Vec::new();
        // The triangles that matter (walkable, in the body band, or above it), sorted in
        // parallel chunks joined in scene order, each with its flags and rows; then bands of
        // rows are filled in parallel, every band taking its triangles in scene order (the
        // same cells as one pass, any thread count).
        let mut laps = BuildLaps::start();
        let chunks = scene.triangle_chunks(GATHER_CHUNK);
        // Each kept triangle as (mesh, index, walkable, faces up, band only, first row, last
        // row). A band-only triangle lies wholly inside the body band and is not walkable: it
        // only marks the cells it covers as occupied, whatever its heights over each, so it is
        // drawn as if level at its lowest (the same cells, without a clip per cell).
        type Kept = (u32, u32, bool, bool, bool, u32, u32);
        let gathered: Vec<(Vec<Kept>, Vec<clearance::Seg>, Vec<i8>)> = chunks
            .par_iter()
            .map(|(m, range)| {
                let (mut kept, mut segs, mut sides) = (Vec::new(), Vec::new(), Vec::new());
                let (mut poly, mut tmp) = (Vec::new(), Vec::new());
                for ti in range.clone() {
                    let t = scene.meshes[*m].triangle(ti).map(|p| p.map(|v| v as f64));
                    let zlo = t[0][2].min(t[1][2]).min(t[2][2]);
                    let zhi = t[0][2].max(t[1][2]).max(t[2][2]);
                    let Some(nz) = raster::abs_normal_z(&t) else { continue };
                    let walkable = nz >= cos_slope && zhi >= ground_lo && zlo <= ground_hi;
                    let in_band = zhi > band_lo && zlo < band_hi;
                    let above = zhi >= band_hi;
                    if !walkable && !in_band && !above {
                        continue;
                    }
                    if in_band {
                        band_edges::band_edges_with(&t, band_lo, band_hi, &mut poly, &mut tmp, &mut segs, &mut sides);
                    }
                    let (ymin, ymax) = (t[0][1].min(t[1][1]).min(t[2][1]), t[0][1].max(t[1][1]).max(t[2][1]));
                    let r0 = ((ymin - y0) / res).floor();
                    let r1 = ((ymax - y0) / res).floor();
                    if r1 < 0.0 || r0 >= h as f64 {
                        continue;
                    }
                    let (r0, r1) = (r0.max(0.0) as u32, (r1 as usize).min(h - 1) as u32);
                    let band_only = !walkable && zlo > band_lo && zhi < band_hi;
                    kept.push((*m as u32, ti as u32, walkable, raster::normal_z_sign(&t) > 0.0, band_only, r0, r1));
                }
                (kept, segs, sides)
            })
            .collect();
        segs.reserve(gathered.iter().map(|g| g.1.len()).sum());
        let mut sides: Vec<i8> = Vec::with_capacity(segs.capacity());
        let mut tris: Vec<Kept> = Vec::with_capacity(gathered.iter().map(|g| g.0.len()).sum());
        let mut in_bands: Vec<Vec<u32>> = vec![Vec::new(); h.div_ceil(RASTER_BAND_ROWS)];
        for (kept, chunk_segs, chunk_sides) in gathered {
            segs.extend(chunk_segs);
            sides.extend(chunk_sides);
            for t in kept {
                let k = tris.len() as u32;
                tris.push(t);
                for b in t.5 as usize / RASTER_BAND_ROWS..=t.6 as usize / RASTER_BAND_ROWS {
                    in_bands[b].push(k);
                }
            }
        }
        laps.lap("band edges");
        let band = RASTER_BAND_ROWS * w;
        ground.par_chunks_mut(band).zip(occupied.par_chunks_mut(band)).zip(roof.par_chunks_mut(band)).zip(in_bands.par_iter()).enumerate().for_each(
            |(b, (((ground, occupied), roof), list))| {
                let rows = b * RASTER_BAND_ROWS..((b + 1) * RASTER_BAND_ROWS).min(h);
                let first = rows.start * w;
                for &k in list {
                    let (m, ti, walkable, faces_up, band_only, _, _) = tris[k as usize];
                    let mut t = scene.meshes[m as usize].triangle(ti as usize).map(|p| p.map(|v| v as f64));
                    if band_only {
                        let zlo = t[0][2].min(t[1][2]).min(t[2][2]);
                        for p in &mut t {
                            p[2] = zlo;
                        }
                    }
                    raster::for_each_cell_in_rows(&spec, &t, 0.0, rows.clone(), |c, r, lo, hi| {
                        let i = r * w + c - first;
                        if lo >= band_hi && (lo as f32) < roof[i].0 {
                            roof[i] = (lo as f32, faces_up);
                        }
                        if walkable && hi >= ground_lo && lo <= ground_hi {
                            let g = hi.min(ground_hi) as f32;
                            if ground[i].is_nan() || g > ground[i] {
                                ground[i] = g;
                            }
                        }
                        if hi > band_lo && lo < band_hi {
                            occupied[i] = true;
                        }
                    });
                }
            },
        );
        laps.lap("fill");
        if ground.iter().all(|g| g.is_nan()) {
            return Err(NavGridError::NoFloor(format!(" near height {floor_z:.3} m")));
        }
        let cap = params.radius + 4.0 * res;
        let stairs = stairs::find(scene, params, &spec, floor_z, bounds);
        laps.lap("stairs");
        // The edge of the floor is an obstacle too (no floor = a drop the agent must keep away
        // from). Its distance counts only below the segments' (at most `cap`): the transform
        // is exact to a cell and a half beyond the cap, and infinite past that.
        let edge_cap = (cap / res + 1.5).powi(2).ceil() as u32;
        // The cells without floor, and each cell's distance to them (cells).
        let floor_edge = |ground: &[f32]| {
            let no_floor: Vec<bool> = ground.iter().map(|g| g.is_nan()).collect();
            let edge = clearance::edt(&no_floor, w, h, edge_cap);
            (no_floor, edge)
        };
        let (mut clear, mut nearest, drops, (no_floor, edge)) = if let Some(st) = &stairs {
            ground = st.ground.clone();
            let banded = storey_band::clearance(scene, params, &spec, floor_z, &ground, &mut occupied, &mut roof, cap);
            laps.lap("banded clearance");
            segs = banded.segments;
            (banded.clear, banded.nearest, banded.drops, floor_edge(&ground))
        } else {
            // The steps that do not read each other's results run side by side: the closed
            // solids and the boundary edges, then the segments' distances and the edge's.
            let ((), boundary) = rayon::join(|| fill_enclosed(&mut occupied, &ground, &roof, &spec), || band_edges::boundary_edges(&segs, &sides));
            segs = boundary;
            laps.lap("enclosed, boundary edges");
            // Cells off the region whose eight neighbours are off it too read no distance
            // and no nearest segment (their clearance is 0, and no test looks further).
            let off = |i: usize| occupied[i] || ground[i].is_nan();
            let deep: Vec<bool> = (0..n)
                .into_par_iter()
                .map(|i| {
                    let (c, r) = (i % w, i / w);
                    (r.saturating_sub(1)..=(r + 1).min(h - 1)).all(|y| (c.saturating_sub(1)..=(c + 1).min(w - 1)).all(|x| off(y * w + x)))
                })
                .collect();
            let ((c, near), floor) = rayon::join(|| clearance::segment_distance(&spec, &segs, cap, &deep), || floor_edge(&ground));
            laps.lap("segment distance, edge transform");
            (c, near, Vec::new(), floor)
        };
        for i in 0..n {
            if occupied[i] || no_floor[i] {
                clear[i] = 0.0;
                continue;
            }
            let e = ((edge[i] as f64 - 0.5) * res).max(0.0) as f32;
            if e < clear[i] {
                clear[i] = e;
                nearest[i] = u32::MAX;
            }
        }
        storey_band::apply_drops(&mut clear, &mut nearest, &ground, &drops, &spec, cap, params.max_climb);
        laps.lap("edge distance");
        let mut grid = NavGrid {
            params: params.clone(),
            floor_z,
            spec,
            ground,
            occupied,
            clearance: clear,
            island_of: vec![u32::MAX; n],
            islands: Vec::new(),
            corner: vec![false; n],
            anchor: Vec::new(),
            segments: segs,
            stair: stairs.map(|s| s.stair).unwrap_or_default(),
            nearest,
            near_segs: Vec::new(),
            sure_reach: Vec::new(),
            block_margin: Vec::new(),
            los_blocked: Vec::new(),
            fields: Default::default(),
            corner_graph: Default::default(),
            laps: BuildLaps::default(),
        };
        // The line-of-sight margins, the cells' near segments and reach, and the islands read
        // none of the others.
        let ((margins, near), ((labels, islands), reach)) = rayon::join(
            || rayon::join(|| crate::geodesic::block_margins(&grid), || grid.near_segments()),
            || rayon::join(|| grid.label_islands(), || crate::geodesic::sure_reach(&grid)),
        );
        grid.sure_reach = reach;
        grid.los_blocked = crate::geodesic::los_bits(&margins);
        grid.block_margin = margins;
        grid.near_segs = near;
        (grid.island_of, grid.islands) = (labels, islands);
        laps.lap("line-of-sight tables, islands");
        grid.find_corners();
        laps.lap("corners");
        grid.laps = laps;
        Ok(grid)
    }

    /// Grid size in cells (width, height).
    pub fn size(&self) -> (usize, usize) {
        (self.spec.w, self.spec.h)
    }
    /// Cell size (m).
    pub fn resolution(&self) -> f64 {
        self.spec.res
    }
    /// World position of the lower-left corner of cell (0, 0) (m).
    pub fn origin(&self) -> Point2 {
        Point2::new(self.spec.x0, self.spec.y0)
    }
    /// Number of navigable cells.
    pub fn navigable_cells(&self) -> usize {
        self.island_of.iter().filter(|&&i| i != u32::MAX).count()
    }
    /// Centre of cell index `i` (m).
    pub(crate) fn center(&self, i: usize) -> [f64; 2] {
        let (c, r) = (i % self.spec.w, i / self.spec.w);
        [self.spec.x0 + (c as f64 + 0.5) * self.spec.res, self.spec.y0 + (r as f64 + 0.5) * self.spec.res]
    }
    /// Index of the cell containing `p`, or `None` outside the grid.
    pub(crate) fn cell_of(&self, p: Point2) -> Option<usize> {
        let c = xhab_types::axis_cell((p.x - self.spec.x0) / self.spec.res, self.spec.w)?;
        let r = xhab_types::axis_cell((p.y - self.spec.y0) / self.spec.res, self.spec.h)?;
        Some(r * self.spec.w + c)
    }
    /// Whether cell `i` is navigable.
    pub(crate) fn is_nav_cell(&self, i: usize) -> bool {
        self.island_of[i] != u32::MAX
    }

    /// Clearance at `p` (m): bilinear interpolation of the cell-centre distances; 0 outside.
    pub fn clearance_at(&self, p: Point2) -> f64 {
        let fx = (p.x - self.spec.x0) / self.spec.res - 0.5;
        let fy = (p.y - self.spec.y0) / self.spec.res - 0.5;
        if !(fx >= 0.0 && fy >= 0.0 && fx < (self.spec.w - 1) as f64 && fy < (self.spec.h - 1) as f64) {
            return 0.0;
        }
        let (c, r) = (fx as usize, fy as usize);
        let (tx, ty) = (fx - c as f64, fy - r as f64);
        let w = self.spec.w;
        let v = |cc: usize, rr: usize| self.clearance[rr * w + cc] as f64;
        let a = v(c, r) * (1.0 - tx) + v(c + 1, r) * tx;
        let b = v(c, r + 1) * (1.0 - tx) + v(c + 1, r + 1) * tx;
        a * (1.0 - ty) + b * ty
    }

    /// Height of the walking surface under `p` (m): the floor, or on a flight the tread under
    /// it; `None` off the grid or where there is no surface.
    pub fn ground_at(&self, p: Point2) -> Option<f64> {
        let i = self.cell_of(p)?;
        self.ground[i].is_finite().then_some(self.ground[i] as f64)
    }

    /// Height of the agent's feet at `p` (m): on a storey with stairs, the mean height of the
    /// walking surface over the agent's footprint (the cells within its radius whose surface
    /// is within a climb of the one under its centre), so that it rises evenly up a flight as
    /// on Habitat's navmesh; the floor's height elsewhere.
    pub fn surface_height(&self, p: Point2) -> f64 {
        if !self.has_stairs() {
            return self.floor_z;
        }
        let Some(i) = self.cell_of(p).filter(|&i| self.ground[i].is_finite()) else { return self.floor_z };
        let g0 = self.ground[i] as f64;
        let (w, h) = (self.spec.w as isize, self.spec.h as isize);
        let reach = (self.params.radius / self.spec.res).ceil() as isize;
        let (c, r) = ((i % self.spec.w) as isize, (i / self.spec.w) as isize);
        let (mut sum, mut n) = (0.0, 0usize);
        for dr in -reach..=reach {
            for dc in -reach..=reach {
                let (cc, rr) = (c + dc, r + dr);
                if cc < 0 || rr < 0 || cc >= w || rr >= h {
                    continue;
                }
                let j = (rr * w + cc) as usize;
                let q = self.center(j);
                let g = self.ground[j] as f64;
                if (q[0] - p.x).hypot(q[1] - p.y) <= self.params.radius && g.is_finite() && (g - g0).abs() <= self.params.max_climb {
                    sum += g;
                    n += 1;
                }
            }
        }
        if n == 0 { g0 } else { sum / n as f64 }
    }

    /// Whether this storey has a flight of stairs to another storey.
    pub fn has_stairs(&self) -> bool {
        !self.stair.is_empty()
    }

    /// Whether cell `i` lies on a flight of stairs.
    pub fn cell_is_stair(&self, i: usize) -> bool {
        self.stair.get(i).copied().unwrap_or(false)
    }

    /// Whether `p` lies on a flight of stairs (m, planar).
    pub fn on_stairs(&self, p: Point2) -> bool {
        self.cell_of(p).is_some_and(|i| self.cell_is_stair(i))
    }

    /// Whether the agent fits at `p` (m, planar) on this floor.
    pub fn is_navigable(&self, p: Point2) -> bool {
        match self.cell_of(p) {
            Some(i) if self.ground[i].is_finite() => self.clearance_at(p) >= self.params.radius - NAV_TOLERANCE,
            _ => false,
        }
    }

    /// The island of `p`: that of its cell, or of the nearest navigable cell within one cell.
    pub fn island_at(&self, p: Point2) -> Option<u32> {
        let i = self.cell_of(p)?;
        if self.is_nav_cell(i) {
            return Some(self.island_of[i]);
        }
        self.nearest_nav_cell(p, 1).map(|j| self.island_of[j])
    }

    /// The cell nearest to `p` (by its centre, searched ring by ring outwards over the whole
    /// grid) among those `wanted` accepts, and its centre's distance from `p` (m); the first
    /// found wins a tie. `None` when no cell is accepted.
    pub fn nearest_cell_where(&self, p: Point2, wanted: impl Fn(usize) -> bool) -> Option<(usize, f64)> {
        let (w, h) = (self.spec.w, self.spec.h);
        if w == 0 || h == 0 || !(p.x.is_finite() && p.y.is_finite()) {
            return None;
        }
        let res = self.resolution();
        let o = self.origin();
        let clamp = |v: f64, n: usize| (((v / res).floor()).max(0.0) as usize).min(n - 1) as isize;
        let (pc, pr) = (clamp(p.x - o.x, w), clamp(p.y - o.y, h));
        let mut best: Option<(usize, f64)> = None;
        for ring in 0..w.max(h) as isize {
            // Every cell of this ring lies at least (ring - 1) cells from p.
            if best.is_some_and(|b| (ring as f64 - 1.0) * res > b.1) {
                break;
            }
            for dr in -ring..=ring {
                for dc in -ring..=ring {
                    if dr.abs() != ring && dc.abs() != ring {
                        continue;
                    }
                    let (c, r) = (pc + dc, pr + dr);
                    if c < 0 || r < 0 || c >= w as isize || r >= h as isize {
                        continue;
                    }
                    let j = r as usize * w + c as usize;
                    if !wanted(j) {
                        continue;
                    }
                    let q = self.center(j);
                    let off = (q[0] - p.x).hypot(q[1] - p.y);
                    if best.is_none_or(|b| off < b.1) {
                        best = Some((j, off));
                    }
                }
            }
        }
        best
    }

    /// The navigable cell nearest to `p` within `reach` cells, if any.
    pub(crate) fn nearest_nav_cell(&self, p: Point2, reach: isize) -> Option<usize> {
        let i = self.cell_of(p)?;
        let (c, r) = ((i % self.spec.w) as isize, (i / self.spec.w) as isize);
        let mut best: Option<(f64, usize)> = None;
        for dr in -reach..=reach {
            for dc in -reach..=reach {
                let (cc, rr) = (c + dc, r + dr);
                if cc < 0 || rr < 0 || cc >= self.spec.w as isize || rr >= self.spec.h as isize {
                    continue;
                }
                let j = rr as usize * self.spec.w + cc as usize;
                if self.is_nav_cell(j) {
                    let q = self.center(j);
                    let d = (q[0] - p.x).hypot(q[1] - p.y);
                    if best.is_none_or(|(bd, bj)| d < bd || (d == bd && j < bj)) {
                        best = Some((d, j));
                    }
                }
            }
        }
        best.map(|b| b.1)
    }

    /// A uniformly random navigable point (m, with its floor height as z) among `cells`
    /// (indices of navigable cells; all of them when empty), or `None` after 16 misses.
    pub fn sample_navigable_point(&self, cells: &[usize], rng: &mut impl rand::Rng) -> Option<xhab_types::Point3> {
        let pick = |rng: &mut dyn rand::RngCore| -> Option<usize> {
            if cells.is_empty() {
                let n = self.navigable_cells();
                if n == 0 {
                    return None;
                }
                let k = rng.next_u64() as usize % n;
                self.island_of.iter().enumerate().filter(|(_, &l)| l != u32::MAX).nth(k).map(|(i, _)| i)
            } else {
                Some(cells[(rng.next_u64() % cells.len() as u64) as usize])
            }
        };
        for _ in 0..16 {
            let i = pick(rng)?;
            let c = self.center(i);
            let res = self.spec.res;
            let p = Point2::new(c[0] + (rng.gen::<f64>() - 0.5) * res, c[1] + (rng.gen::<f64>() - 0.5) * res);
            if let Some(j) = self.cell_of(p) {
                if self.is_nav_cell(j) && self.is_navigable(p) {
                    return Some(xhab_types::Point3::new(p.x, p.y, self.ground[j] as f64));
                }
            }
        }
        None
    }

    /// A random pose: a navigable point as [`NavGrid::sample_navigable_point`] gives it, then
    /// a heading uniform in [-pi, pi) (rad), both drawn from `rng`; `None` as that gives it.
    pub fn sample_pose(&self, cells: &[usize], rng: &mut impl rand::Rng) -> Option<xhab_types::Pose2> {
        let p = self.sample_navigable_point(cells, rng)?;
        Some(xhab_types::Pose2::new(p.x, p.y, rng.gen_range(-std::f64::consts::PI..std::f64::consts::PI)))
    }

    /// Indices of navigable cells on islands of at least `min_radius` (m).
    pub fn cells_on_islands(&self, min_radius: f64) -> Vec<usize> {
        (0..self.island_of.len())
            .filter(|&i| {
                let k = self.island_of[i];
                k != u32::MAX && self.islands[k as usize].radius >= min_radius
            })
            .collect()
    }

    /// The map of this floor in map_server terms: occupied where geometry stands in the body
    /// band (or inside a closed solid), free where there is walkable floor, unknown elsewhere.
    pub fn occupancy_grid(&self) -> OccupancyGrid {
        let (w, h) = (self.spec.w, self.spec.h);
        let mut g = OccupancyGrid::new(w, h, self.spec.res, Pose2::new(self.spec.x0, self.spec.y0, 0.0), GRID_UNKNOWN);
        for i in 0..w * h {
            g.data[i] = if self.occupied[i] {
                GRID_OCCUPIED
            } else if self.ground[i].is_finite() {
                GRID_FREE
            } else {
                GRID_UNKNOWN
            };
        }
        g
    }

    /// The islands of the navigable cells: each cell's island (`u32::MAX` off the region) and
    /// each island's size, centroid and radius.
    fn label_islands(&self) -> (Vec<u32>, Vec<Island>) {
        let (w, h) = (self.spec.w, self.spec.h);
        let nav: Vec<bool> = (0..w * h)
            .into_par_iter()
            .map(|i| self.ground[i].is_finite() && self.clearance[i] as f64 >= self.params.radius)
            .collect();
        let (labels, sizes) = components(&nav, w, h);
        // The cells' centres in cell order, each island's sums held in registers along a run
        // of its cells (the same additions in the same order, so the same bits, without a
        // store and load between each).
        let (x0, y0, res) = (self.spec.x0, self.spec.y0, self.spec.res);
        // Each row's runs of one island: (row, first column, columns, island).
        let runs = || {
            labels.chunks(w).enumerate().flat_map(|(r, row)| {
                row.chunk_by(|a, b| a == b).scan(0, move |c, run| Some((r, std::mem::replace(c, *c + run.len()), run.len(), run[0]))).filter(|run| run.3 != u32::MAX)
            })
        };
        let mut sum = vec![[0.0f64; 2]; sizes.len()];
        for (r, c0, len, k) in runs() {
            let (y, mut s) = (y0 + (r as f64 + 0.5) * res, sum[k as usize]);
            for c in c0..c0 + len {
                s[0] += x0 + (c as f64 + 0.5) * res;
                s[1] += y;
            }
            sum[k as usize] = s;
        }
        let centres: Vec<[f64; 2]> = sum.iter().zip(&sizes).map(|(s, &n)| [s[0] / n as f64, s[1] / n as f64]).collect();
        let mut radius = vec![0.0f64; sizes.len()];
        for (r, c0, len, k) in runs() {
            let (y, o, mut m) = (y0 + (r as f64 + 0.5) * res, centres[k as usize], radius[k as usize]);
            for c in c0..c0 + len {
                let x = x0 + (c as f64 + 0.5) * res;
                m = m.max((x - o[0]).powi(2) + (y - o[1]).powi(2));
            }
            radius[k as usize] = m;
        }
        // (squared above: no libm call per cell)
        radius.iter_mut().for_each(|r| *r = r.sqrt());
        let a = self.spec.res * self.spec.res;
        let islands = (0..sizes.len())
            .map(|k| Island {
                cells: sizes[k],
                area: sizes[k] as f64 * a,
                centre: Point2::new(centres[k][0], centres[k][1]),
                radius: radius[k],
            })
            .collect();
        (labels, islands)
    }

    /// The point of cell `i`'s nearest obstacle segment closest to `p` (m), if the cell has one.
    pub(crate) fn nearest_point(&self, i: usize, p: [f64; 2]) -> Option<[f64; 2]> {
        let k = *self.nearest.get(i)?;
        (k != u32::MAX).then(|| closest_on_segment(p, &self.segments[k as usize]))
    }

    /// The nearest obstacle segments of cell `i` and its eight neighbours, in row order (a
    /// segment may come more than once). A cell's own nearest segment is nearest to its
    /// centre only: elsewhere in the cell another can be nearer (a wall sliced into pieces,
    /// the other side of a corner), and each such segment is the nearest of a neighbouring
    /// centre.
    pub(crate) fn nearest_around(&self, i: usize) -> impl Iterator<Item = u32> + '_ {
        let (w, h) = (self.spec.w, self.spec.h);
        let (c, r) = (i % w, i / w);
        (r.saturating_sub(1)..=(r + 1).min(h - 1))
            .flat_map(move |y| (c.saturating_sub(1)..=(c + 1).min(w - 1)).map(move |x| self.nearest[y * w + x]))
            .filter(|&k| k != u32::MAX)
    }

    /// Distance from segment `s` to the obstacle segments [`NavGrid::nearest_around`] cell
    /// `i` (m), if it has any.
    pub(crate) fn nearest_segment_distance(&self, i: usize, s: &clearance::Seg) -> Option<f64> {
        self.nearest_around(i).map(|k| clearance::segment_segment_distance(s, &self.segments[k as usize])).reduce(f64::min)
    }

    /// Whether segment `line` keeps at least `min` (m) from every obstacle segment
    /// [`NavGrid::nearest_around`] cell `i` (the same answer as comparing
    /// [`NavGrid::nearest_segment_distance`] with `min`), if it has any; stops at the first
    /// that comes nearer. `seen` holds segments already found clear of this line (a walk's
    /// cells share most neighbours), and takes those found here. It runs per cell of a
    /// line-of-sight walk, so it reads the block's distinct segments from
    /// [`NavGrid::near_segs`] (the block itself only where they are too many).
    pub(crate) fn nearest_segments_clear(&self, i: usize, line: &SegmentLine, min: f64, seen: &mut SeenSegments) -> Option<bool> {
        let near = self.near_segs[i];
        if near[0] == MANY_NEAR {
            return self.segments_clear(self.nearest_around(i), line, min, seen);
        }
        self.segments_clear(near.into_iter().take_while(|&k| k != u32::MAX), line, min, seen)
    }

    /// [`NavGrid::nearest_segments_clear`] over the obstacle segments `ids`.
    #[inline(always)]
    fn segments_clear(&self, ids: impl Iterator<Item = u32>, line: &SegmentLine, min: f64, seen: &mut SeenSegments) -> Option<bool> {
        let mut any = false;
        for k in ids {
            any = true;
            if seen.contains(k) {
                continue;
            }
            if !line.clear_of(&self.segments[k as usize], min) {
                return Some(false);
            }
            seen.insert(k);
        }
        any.then_some(true)
    }

    /// [`NavGrid::near_segs`] of every cell (rows in parallel).
    fn near_segments(&self) -> Vec<[u32; 4]> {
        let w = self.spec.w;
        let sure = crate::geodesic::sure_clearance(self);
        let mut out = vec![[u32::MAX; 4]; w * self.spec.h];
        out.par_chunks_mut(w).enumerate().for_each(|(r, row)| {
            for (c, near) in row.iter_mut().enumerate() {
                let i = r * w + c;
                // The walk settles other cells by their clearance alone (see `segment_clear`).
                let cl = self.clearance[i] as f64;
                if !(cl > 0.0 && cl < sure) {
                    continue;
                }
                let mut m = 0;
                for k in self.nearest_around(i) {
                    if near[..m].contains(&k) {
                        continue;
                    }
                    if m == near.len() {
                        *near = [MANY_NEAR, u32::MAX, u32::MAX, u32::MAX];
                        break;
                    }
                    near[m] = k;
                    m += 1;
                }
            }
        });
        out
    }

    /// Marks the bend points (navigable cells on the region's boundary) and moves each onto
    /// the true boundary, the radius from its nearest obstacle (rows in parallel).
    fn find_corners(&mut self) {
        let (w, h) = (self.spec.w as isize, self.spec.h as isize);
        let r = self.params.radius;
        let mut corner = std::mem::take(&mut self.corner);
        let mut anchor: Vec<[f64; 2]> = vec![[0.0; 2]; (w * h) as usize];
        let this = &*self;
        let nav = |c: isize, rr: isize| c >= 0 && rr >= 0 && c < w && rr < h && this.island_of[(rr * w + c) as usize] != u32::MAX;
        corner.par_chunks_mut(w as usize).zip(anchor.par_chunks_mut(w as usize)).enumerate().for_each(|(rr, (corner, anchor))| {
            let rr = rr as isize;
            for c in 0..w {
                let i = (rr * w + c) as usize;
                let p = this.center(i);
                anchor[c as usize] = p;
                if !nav(c, rr) {
                    continue;
                }
                // Any cell on the region's boundary may be a bend point: convex corners of the
                // obstacles are arcs of radius r, and shortest paths touch them anywhere.
                let on_boundary = (-1..=1).any(|dy| (-1..=1).any(|dx| !nav(c + dx, rr + dy)));
                if !on_boundary {
                    continue;
                }
                corner[c as usize] = true;
                // Move the bend point onto the true boundary: radius r from the nearest obstacle.
                if let Some(q) = this.nearest_point(i, p) {
                    let d = [p[0] - q[0], p[1] - q[1]];
                    let l = d[0].hypot(d[1]);
                    if l > 1e-9 {
                        anchor[c as usize] = [q[0] + d[0] / l * r, q[1] + d[1] / l * r];
                    }
                }
            }
        });
        self.corner = corner;
        self.anchor = anchor;
    }
}

/// Free floor pockets smaller than this are the insides of walls (m^2).
const MIN_POCKET_AREA: f64 = 0.25;
/// Free floor pockets smaller than this, mostly under upward-facing surfaces, are the insides
/// of closed solids such as shelves (m^2). Larger regions are never filled, so that a
/// ceiling with inverted normals cannot swallow a room.
const MAX_SOLID_AREA: f64 = 4.0;

/// Marks as occupied the free floor inside closed solids: pockets too small to be rooms, and
/// small regions roofed by upward-facing surfaces (seen from below, the inside of a box).
fn fill_enclosed(occupied: &mut [bool], ground: &[f32], roof: &[(f32, bool)], spec: &GridSpec) {
    let (w, h) = (spec.w, spec.h);
    let free: Vec<bool> = (0..w * h).map(|i| ground[i].is_finite() && !occupied[i]).collect();
    let (labels, sizes) = components(&free, w, h);
    let mut roofed = vec![0usize; sizes.len()];
    for i in 0..w * h {
        if labels[i] != u32::MAX && roof[i].1 {
            roofed[labels[i] as usize] += 1;
        }
    }
    let a = spec.res * spec.res;
    for i in 0..w * h {
        let k = labels[i];
        if k == u32::MAX {
            continue;
        }
        let (n, up) = (sizes[k as usize], roofed[k as usize]);
        let area = n as f64 * a;
        if area < MIN_POCKET_AREA || (area < MAX_SOLID_AREA && 2 * up > n) {
            occupied[i] = true;
        }
    }
}

fn validate(p: &AgentParams) -> Result<(), NavGridError> {
    let check = |field: &'static str, v: f64, ok: bool, want: &str| {
        if v.is_finite() && ok {
            Ok(())
        } else {
            Err(NavGridError::BadParam { field, reason: format!("must be {want}, got {v}") })
        }
    };
    check("radius", p.radius, p.radius > 0.0, "> 0")?;
    check("height", p.height, p.height > p.max_climb, "> max_climb")?;
    check("max_climb", p.max_climb, p.max_climb >= 0.0, ">= 0")?;
    check("max_slope_deg", p.max_slope_deg, (0.0..90.0).contains(&p.max_slope_deg), "in [0, 90)")?;
    check("cell_size", p.cell_size, p.cell_size >= 0.005 && p.cell_size <= 0.5, "in [0.005, 0.5]")?;
    Ok(())
}
