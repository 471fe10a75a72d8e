//! The built-in default scene: a seeded procedural house of rooms along a corridor, with
//! doors and furniture, all axis-aligned boxes. Same seed, same house, bit for bit.

use super::Scene;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Shape of the procedural house.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HouseParams {
    /// Footprint length along x (m, default 12; varied by +-15% per seed).
    pub length: f64,
    /// Footprint width along y (m, default 9; varied by +-10% per seed).
    pub width: f64,
    /// Wall height (m, default 2.5).
    pub wall_height: f64,
    /// Wall thickness (m, default 0.1).
    pub wall_thickness: f64,
    /// Door opening width (m, default 0.9).
    pub door_width: f64,
    /// Corridor width (m, default 1.5).
    pub corridor_width: f64,
    /// Smallest room side along the corridor (m, default 2.5).
    pub min_room: f64,
    /// Place furniture (default true).
    pub furniture: bool,
    /// Storeys (default 1). With more, each storey has its own rooms and corridor, a stair
    /// hall west of the house joins them by straight flights, and each upper floor is a slab
    /// [`SLAB`] thick on the walls below.
    pub storeys: usize,
}

impl Default for HouseParams {
    fn default() -> Self {
        Self {
            length: 12.0,
            width: 9.0,
            wall_height: 2.5,
            wall_thickness: 0.1,
            door_width: 0.9,
            corridor_width: 1.5,
            min_room: 2.5,
            furniture: true,
            storeys: 1,
        }
    }
}

const FLOOR: [f32; 4] = [0.76, 0.70, 0.60, 1.0];
const WALL: [f32; 4] = [0.92, 0.91, 0.88, 1.0];
const WOOD: [f32; 4] = [0.55, 0.38, 0.22, 1.0];
const FABRIC: [f32; 4] = [0.30, 0.42, 0.62, 1.0];
const BEDDING: [f32; 4] = [0.85, 0.85, 0.92, 1.0];
const STAIR: [f32; 4] = [0.50, 0.36, 0.24, 1.0];

/// A room: an axis-aligned rectangle (m).
#[derive(Debug, Clone, Copy)]
struct Rect {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

/// A wall on a grid line with door openings: along x at `y = at` when `horizontal`, else along y.
struct Wall {
    horizontal: bool,
    at: f64,
    from: f64,
    to: f64,
    doors: Vec<f64>,
}

/// The procedural house with the default shape for `seed`.
pub fn default_house(seed: u64) -> Scene {
    generate_house(seed, &HouseParams::default())
}

/// Generates the house for `seed`: outer walls, a corridor along x, rooms on both sides each
/// with a door to the corridor (so every room is reachable), some doors between neighbouring
/// rooms, and furniture that keeps doors clear. The floor's top is at z = 0. With
/// `storeys > 1`, the storeys stand on each other (see [`HouseParams::storeys`]).
pub fn generate_house(seed: u64, p: &HouseParams) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let len = (p.length * rng.gen_range(0.85..1.15) * 10.0).round() / 10.0;
    let wid = (p.width * rng.gen_range(0.9..1.1) * 10.0).round() / 10.0;
    let mut s = Scene::default();
    let t = p.wall_thickness / 2.0;
    s.add_box("floor", f([-t, -t, -0.05]), f([len + t, wid + t, 0.0]), FLOOR);
    let storeys = p.storeys.max(1);
    let rise = p.wall_height + SLAB;
    for k in 0..storeys {
        let z0 = k as f64 * rise;
        if k > 0 {
            // The slab of this storey on the walls below, with the stairwell left open.
            s.add_box(&format!("s{k}_floor"), f([-t, -t, z0 - SLAB]), f([len + t, wid + t, z0]), FLOOR);
        }
        layout_storey(&mut s, &mut rng, p, len, wid, k, z0, storeys > 1);
        if storeys > 1 {
            stair_hall(&mut s, p, wid, k, storeys, z0);
        }
    }
    s
}

/// Thickness of an upper storey's floor slab (m).
pub const SLAB: f64 = 0.2;
/// Width of the stair hall west of the house (m).
pub const HALL: f64 = 1.7;
/// Width of a flight (m).
pub const STAIR_WIDTH: f64 = 0.9;
/// Where each flight starts along y (m).
pub const STAIR_FOOT: f64 = 1.0;
/// Tread depth (m).
pub const TREAD: f64 = 0.28;
/// Greatest rise of a step (m; Habitat's climb is 0.2).
pub const MAX_RISER: f64 = 0.18;

/// Risers of one flight, and the rise of each (m), for storeys `rise` apart.
pub fn risers(rise: f64) -> (usize, f64) {
    let n = (rise / MAX_RISER).ceil() as usize;
    (n, rise / n as f64)
}

/// One storey's corridor, rooms, walls and furniture at height `z0` (m); with `hall`, a door
/// in the west wall opens from the corridor into the stair hall.
#[allow(clippy::too_many_arguments)]
fn layout_storey(s: &mut Scene, rng: &mut ChaCha8Rng, p: &HouseParams, len: f64, wid: f64, k: usize, z0: f64, hall: bool) {
    let cw = p.corridor_width;
    let south = ((wid - cw) * rng.gen_range(0.4..0.6) * 10.0).round() / 10.0;
    let (yc0, yc1) = (south, south + cw);
    let west_doors = if hall { vec![(yc0 + yc1) / 2.0] } else { vec![] };
    let mut walls = vec![
        Wall { horizontal: true, at: 0.0, from: 0.0, to: len, doors: vec![] },
        Wall { horizontal: true, at: wid, from: 0.0, to: len, doors: vec![] },
        Wall { horizontal: false, at: 0.0, from: 0.0, to: wid, doors: west_doors },
        Wall { horizontal: false, at: len, from: 0.0, to: wid, doors: vec![] },
    ];
    let mut rooms = Vec::new();
    let mut corridor_doors = (vec![], vec![]);
    for (side, (y0, y1)) in [(0, (0.0, yc0)), (1, (yc1, wid))] {
        let cuts = split(rng, 0.0, len, p.min_room);
        for j in 0..cuts.len() - 1 {
            let r = Rect { x0: cuts[j], y0, x1: cuts[j + 1], y1 };
            let door = door_pos(rng, r.x0, r.x1, p.door_width);
            if side == 0 { corridor_doors.0.push(door) } else { corridor_doors.1.push(door) }
            if j > 0 {
                // A wall between neighbours, with a door now and then.
                let doors = if rng.gen_bool(0.35) { vec![door_pos(rng, y0, y1, p.door_width)] } else { vec![] };
                walls.push(Wall { horizontal: false, at: cuts[j], from: y0, to: y1, doors });
            }
            rooms.push(r);
        }
    }
    walls.push(Wall { horizontal: true, at: yc0, from: 0.0, to: len, doors: corridor_doors.0 });
    walls.push(Wall { horizontal: true, at: yc1, from: 0.0, to: len, doors: corridor_doors.1 });
    let prefix = if k == 0 { String::new() } else { format!("s{k}_") };
    let mut door_zones = Vec::new();
    for (i, w) in walls.iter().enumerate() {
        add_wall(s, &format!("{prefix}wall_{i}"), w, p, z0, &mut door_zones);
    }
    if p.furniture {
        for (i, r) in rooms.iter().enumerate() {
            furnish(s, rng, &format!("{prefix}room{i}"), r, &door_zones, p.wall_thickness, z0);
        }
    }
}

/// Storey `k`'s part of the stair hall at `x` in `[-HALL, 0]`: its outer walls, the flight up
/// to the next storey against the west wall, and above the ground storey its floor around the
/// stairwell with a balustrade.
fn stair_hall(s: &mut Scene, p: &HouseParams, wid: f64, k: usize, storeys: usize, z0: f64) {
    let t = p.wall_thickness / 2.0;
    let top = z0 + p.wall_height;
    s.add_box(&format!("s{k}_hall_west"), f([-HALL - t, -t, z0]), f([-HALL + t, wid + t, top]), WALL);
    s.add_box(&format!("s{k}_hall_south"), f([-HALL, -t, z0]), f([-t, t, top]), WALL);
    s.add_box(&format!("s{k}_hall_north"), f([-HALL, wid - t, z0]), f([-t, wid + t, top]), WALL);
    let (x0, x1) = (-HALL + t, -HALL + t + STAIR_WIDTH);
    let rise = p.wall_height + SLAB;
    let (n, h) = risers(rise);
    let y_top = STAIR_FOOT + (n - 1) as f64 * TREAD;
    if k == 0 {
        s.add_box("hall_floor", f([-HALL - t, -t, -0.05]), f([-t, wid + t, 0.0]), FLOOR);
    } else {
        // The floor around the stairwell that the flight from below comes up through.
        let zs = z0 - SLAB;
        s.add_box(&format!("s{k}_hall_floor_south"), f([-HALL + t, t, zs]), f([-t, STAIR_FOOT, z0]), FLOOR);
        s.add_box(&format!("s{k}_hall_floor_north"), f([-HALL + t, y_top, zs]), f([-t, wid - t, z0]), FLOOR);
        s.add_box(&format!("s{k}_hall_floor_east"), f([x1, STAIR_FOOT, zs]), f([-t, y_top, z0]), FLOOR);
        s.add_box(&format!("s{k}_balustrade_east"), f([x1, STAIR_FOOT - 0.05, z0]), f([x1 + 0.05, y_top, z0 + 1.0]), WALL);
        s.add_box(&format!("s{k}_balustrade_south"), f([x0, STAIR_FOOT - 0.05, z0]), f([x1, STAIR_FOOT, z0 + 1.0]), WALL);
    }
    if k + 1 < storeys {
        for j in 1..n {
            let ya = STAIR_FOOT + (j - 1) as f64 * TREAD;
            s.add_box(&format!("s{k}_step_{j}"), f([x0, ya, z0]), f([x1, ya + TREAD, z0 + j as f64 * h]), STAIR);
            // The handrail's panel on the flight's open side.
            s.add_box(&format!("s{k}_stair_rail_{j}"), f([x1, ya, z0 + j as f64 * h]), f([x1 + 0.05, ya + TREAD, z0 + j as f64 * h + 1.0]), WALL);
        }
    }
}

fn f(v: [f64; 3]) -> [f32; 3] {
    v.map(|x| x as f32)
}

/// Cut positions from `a` to `b` (inclusive) into pieces of at least `min` (m).
fn split(rng: &mut ChaCha8Rng, a: f64, b: f64, min: f64) -> Vec<f64> {
    let mut cuts = vec![a];
    let mut x = a;
    while b - x >= 2.0 * min {
        let piece = ((rng.gen_range(min..(min * 1.8).min(b - x - min)) * 10.0).round() / 10.0).max(min);
        x += piece;
        cuts.push(x);
    }
    cuts.push(b);
    cuts
}

/// Centre of a door in the span [a, b], kept 0.3 m from both ends.
fn door_pos(rng: &mut ChaCha8Rng, a: f64, b: f64, dw: f64) -> f64 {
    let (lo, hi) = (a + 0.3 + dw / 2.0, b - 0.3 - dw / 2.0);
    if hi <= lo { (a + b) / 2.0 } else { ((rng.gen_range(lo..hi)) * 20.0).round() / 20.0 }
}

fn add_wall(s: &mut Scene, base: &str, w: &Wall, p: &HouseParams, z0: f64, zones: &mut Vec<Rect>) {
    let t = p.wall_thickness / 2.0;
    let mut doors = w.doors.clone();
    doors.sort_by(|a, b| a.total_cmp(b));
    let mut start = w.from - t;
    let mut pieces = Vec::new();
    for d in &doors {
        pieces.push((start, d - p.door_width / 2.0));
        start = d + p.door_width / 2.0;
        // Keep a metre clear on both sides of the door.
        let (a, b) = (d - p.door_width / 2.0 - 0.1, d + p.door_width / 2.0 + 0.1);
        zones.push(if w.horizontal {
            Rect { x0: a, y0: w.at - 1.0, x1: b, y1: w.at + 1.0 }
        } else {
            Rect { x0: w.at - 1.0, y0: a, x1: w.at + 1.0, y1: b }
        });
    }
    pieces.push((start, w.to + t));
    for (k, (a, b)) in pieces.into_iter().enumerate() {
        if b - a < 1e-6 {
            continue;
        }
        let name = format!("{base}_{k}");
        if w.horizontal {
            s.add_box(&name, f([a, w.at - t, z0]), f([b, w.at + t, z0 + p.wall_height]), WALL);
        } else {
            s.add_box(&name, f([w.at - t, a, z0]), f([w.at + t, b, z0 + p.wall_height]), WALL);
        }
    }
}

fn overlaps(a: &Rect, b: &Rect, gap: f64) -> bool {
    a.x0 < b.x1 + gap && b.x0 < a.x1 + gap && a.y0 < b.y1 + gap && b.y0 < a.y1 + gap
}

/// Places up to three pieces of furniture in a room, clear of door zones and of each other.
fn furnish(s: &mut Scene, rng: &mut ChaCha8Rng, room: &str, r: &Rect, zones: &[Rect], wall_t: f64, z0: f64) {
    let inset = wall_t / 2.0 + 0.05;
    let mut placed: Vec<Rect> = Vec::new();
    let count = rng.gen_range(1..=3);
    for item in 0..count {
        let kind = rng.gen_range(0..5);
        let (sx, sy) = match kind {
            0 => (rng.gen_range(0.8..1.4), rng.gen_range(0.6..0.9)), // table
            1 => (1.9, rng.gen_range(0.9..1.5)),                      // bed
            2 => (rng.gen_range(1.6..2.2), 0.85),                     // sofa
            3 => (rng.gen_range(0.8..1.2), 0.35),                     // shelf
            _ => (0.45, 0.45),                                        // chair
        };
        let (sx, sy) = if rng.gen_bool(0.5) { (sx, sy) } else { (sy, sx) };
        for _ in 0..20 {
            let (w, h) = (r.x1 - r.x0 - 2.0 * inset, r.y1 - r.y0 - 2.0 * inset);
            if w <= sx || h <= sy {
                break;
            }
            let x0 = r.x0 + inset + rng.gen_range(0.0..w - sx);
            let y0 = r.y0 + inset + rng.gen_range(0.0..h - sy);
            let b = Rect { x0, y0, x1: x0 + sx, y1: y0 + sy };
            if zones.iter().any(|z| overlaps(z, &b, 0.0)) || placed.iter().any(|o| overlaps(o, &b, 0.6)) {
                continue;
            }
            let name = format!("{room}_item{item}");
            add_furniture(s, kind, &name, &b, z0);
            placed.push(b);
            break;
        }
    }
}

fn add_furniture(s: &mut Scene, kind: u32, name: &str, b: &Rect, z0: f64) {
    let f = |v: [f64; 3]| f([v[0], v[1], v[2] + z0]);
    let legs = |s: &mut Scene, name: &str, b: &Rect, h: f64, c: [f32; 4]| {
        let f = |v: [f64; 3]| super::house::f([v[0], v[1], v[2] + z0]);
        let l = 0.05;
        for (i, (x, y)) in [(b.x0, b.y0), (b.x1 - l, b.y0), (b.x0, b.y1 - l), (b.x1 - l, b.y1 - l)].into_iter().enumerate() {
            s.add_box(&format!("{name}_leg{i}"), f([x, y, 0.0]), f([x + l, y + l, h]), c);
        }
    };
    match kind {
        0 => {
            s.add_box(&format!("{name}_table_top"), f([b.x0, b.y0, 0.70]), f([b.x1, b.y1, 0.75]), WOOD);
            legs(s, &format!("{name}_table"), b, 0.70, WOOD);
        }
        1 => {
            s.add_box(&format!("{name}_bed"), f([b.x0, b.y0, 0.0]), f([b.x1, b.y1, 0.5]), BEDDING);
        }
        2 => {
            s.add_box(&format!("{name}_sofa"), f([b.x0, b.y0, 0.0]), f([b.x1, b.y1, 0.45]), FABRIC);
            s.add_box(&format!("{name}_sofa_back"), f([b.x0, b.y0, 0.45]), f([b.x1, b.y1, 0.85]), FABRIC);
        }
        3 => {
            s.add_box(&format!("{name}_shelf"), f([b.x0, b.y0, 0.0]), f([b.x1, b.y1, 1.8]), WOOD);
        }
        _ => {
            s.add_box(&format!("{name}_chair_seat"), f([b.x0, b.y0, 0.43]), f([b.x1, b.y1, 0.47]), WOOD);
            s.add_box(&format!("{name}_chair_back"), f([b.x0, b.y1 - 0.05, 0.47]), f([b.x1, b.y1, 0.9]), WOOD);
            legs(s, &format!("{name}_chair"), b, 0.43, WOOD);
        }
    }
}
