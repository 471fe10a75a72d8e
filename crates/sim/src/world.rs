//! A loaded scene with its floors and their navigation grids, shared between episodes.

use crate::navgrid::{detect_floors, AgentParams, Floor, NavGrid, NavGridError, StoreyBounds};
use crate::scene::Scene;
use crate::storey_path::Portal;
use std::sync::{Arc, OnceLock};
use xhab_types::{Point2, Point3};

/// How far an episode's start may be from a floor's height to belong to it (m), as
/// Habitat's same-floor rule.
pub const FLOOR_MATCH: f64 = 0.5;

/// A scene, its floors, and lazily built navigation grids (one per floor), safe to share
/// between threads.
#[derive(Debug)]
pub struct World {
    /// The scene (world frame).
    pub scene: Arc<Scene>,
    /// The agent the grids are built for.
    pub params: AgentParams,
    /// The floors, lowest first.
    pub floors: Vec<Floor>,
    grids: Vec<OnceLock<Result<Arc<NavGrid>, String>>>,
    portals: OnceLock<Vec<Portal>>,
}

impl World {
    /// Wraps a scene; floors are detected now, grids built on first use.
    pub fn new(scene: Scene, params: AgentParams) -> World {
        let floors = detect_floors(&scene, &params);
        let grids = floors.iter().map(|_| OnceLock::new()).collect();
        World { scene: Arc::new(scene), params, floors, grids, portals: OnceLock::new() }
    }

    /// The floor `auto` means: the lowest detected floor.
    pub fn default_floor(&self) -> Option<usize> {
        if self.floors.is_empty() {
            None
        } else {
            Some(0)
        }
    }

    /// Index of the floor nearest to height `z` (m) within [`FLOOR_MATCH`].
    pub fn floor_at(&self, z: f64) -> Option<usize> {
        let mut best: Option<(f64, usize)> = None;
        for (i, f) in self.floors.iter().enumerate() {
            let d = (f.z - z).abs();
            if d <= FLOOR_MATCH && best.is_none_or(|b| d < b.0) {
                best = Some((d, i));
            }
        }
        best.map(|b| b.1)
    }

    /// Where adjacent storeys' grids overlap on their flights of stairs, found on first use.
    pub fn portals(&self) -> &[Portal] {
        self.portals.get_or_init(|| crate::storey_path::find_portals(self))
    }

    /// Pairs of storeys (lower, upper) that a flight of stairs joins.
    pub fn connected_storeys(&self) -> Vec<(usize, usize)> {
        let mut out: Vec<(usize, usize)> = self.portals().iter().map(|p| (p.lower, p.lower + 1)).collect();
        out.dedup();
        out
    }

    /// The storey `p` (m) stands on: among the storeys whose grid has a walking surface
    /// within `max_climb` of `p.z` under `p` and lets the agent stand there, the one whose
    /// floor is nearest in height (on a flight both storeys qualify); otherwise the floor
    /// within [`FLOOR_MATCH`] of `p.z`, as [`World::floor_at`].
    pub fn storey_of(&self, p: Point3) -> Option<usize> {
        let q = Point2::new(p.x, p.y);
        let mut best: Option<(f64, usize)> = None;
        for (i, f) in self.floors.iter().enumerate() {
            let Ok(g) = self.grid(i) else { continue };
            let on = g.ground_at(q).is_some_and(|z| (z - p.z).abs() <= self.params.max_climb) && g.is_navigable(q);
            let d = (f.z - p.z).abs();
            if on && best.is_none_or(|b| d < b.0) {
                best = Some((d, i));
            }
        }
        best.map(|b| b.1).or_else(|| self.floor_at(p.z))
    }

    /// The floor heights of the storeys below and above floor `i` (m).
    pub fn storey_bounds(&self, i: usize) -> StoreyBounds {
        StoreyBounds {
            below: i.checked_sub(1).and_then(|k| self.floors.get(k)).map(|f| f.z),
            above: self.floors.get(i + 1).map(|f| f.z),
        }
    }

    /// The navigation grid of floor `i`, built on first use.
    pub fn grid(&self, i: usize) -> Result<Arc<NavGrid>, NavGridError> {
        let cell = self.grids.get(i).ok_or_else(|| NavGridError::NoFloor(format!(": no floor number {i}")))?;
        cell.get_or_init(|| {
            NavGrid::build_storey(&self.scene, &self.params, self.floors[i].z, self.storey_bounds(i)).map(Arc::new).map_err(|e| e.to_string())
        })
            .clone()
            .map_err(NavGridError::NoFloor)
    }

    /// The navigation grid of the floor at height `z` (m).
    pub fn grid_at(&self, z: f64) -> Result<Arc<NavGrid>, NavGridError> {
        let i = self.floor_at(z).ok_or_else(|| {
            let known: Vec<String> = self.floors.iter().map(|f| format!("{:.2}", f.z)).collect();
            NavGridError::NoFloor(format!(" within {FLOOR_MATCH} m of height {z:.3} m (floors at [{}] m)", known.join(", ")))
        })?;
        self.grid(i)
    }
}
