//! Measurements, not checks, of routes to faster cold pair queries on the shared houses.
//!
//! `route_probe`: what the all-pairs route would cost (issue 17's suggestion: every pair of
//! corner-graph nodes' distances precomputed, and a query the minimum over the nodes its two
//! ends see). Prints the table's build time and size, how many nodes a cell centre joins and what finding them costs, and the
//! table query's time against [`CornerGraph::distance`]'s on pairs of cell centres, with the
//! largest relative difference (it asserts only that both agree on which pairs are reachable).
//!
//! `cargo test --release -p xhab-sim --lib route_probe -- --ignored --nocapture`
//!
//! `heuristic_floor`: how much of the search's work a better heuristic could save at best,
//! and landmark (ALT) bounds at their best.
//!
//! `square_pvs`: how many failed lines of sight a set of nodes seen per 1 m square would spare.
//!
//! `node_arcs`: how many nodes thinning the arcs about the obstacles' vertices would leave.

use super::*;
use crate::navgrid::convex_vertices::{vertex_key, widest_gap};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::sync::Arc;
use std::time::Instant;

/// The default floor's grid of a shared house (`$XHAB_DATA` or `../shared`), or `None` with a
/// loud note when the scene is not there.
fn house_grid(probe: &str, scene: &str) -> Option<Arc<NavGrid>> {
    let data = std::env::var("XHAB_DATA").unwrap_or_else(|_| concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared").to_string());
    let path = format!("{data}/scenes/{scene}");
    let Ok(s) = crate::scene::load(std::path::Path::new(&path), &Default::default()) else {
        eprintln!("{probe}: SKIPPED {scene}: cannot load {path}");
        return None;
    };
    let w = crate::world::World::new(s, Default::default());
    w.grid(w.default_floor()?).ok()
}

/// `n` seeded random pairs of navigable points of `grid` (m).
fn seeded_pairs(grid: &NavGrid, n: usize) -> Vec<([f64; 2], [f64; 2])> {
    use rand::SeedableRng;
    let cells = grid.cells_on_islands(0.0);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    (0..n)
        .filter_map(|_| {
            let a = grid.sample_navigable_point(&cells, &mut rng)?;
            let b = grid.sample_navigable_point(&cells, &mut rng)?;
            Some(([a.x, a.y], [b.x, b.y]))
        })
        .collect()
}

/// The graph distance from node `src` to every node (m; infinite where unreachable), by
/// Dijkstra over the legs.
fn graph_distances(g: &CornerGraph, src: usize) -> Vec<f64> {
    let mut d = vec![f64::INFINITY; g.len()];
    let mut heap = BinaryHeap::new();
    d[src] = 0.0;
    heap.push(Reverse((0u64, src as u32)));
    while let Some(Reverse((k, a))) = heap.pop() {
        let a = a as usize;
        if f64::from_bits(k) > d[a] {
            continue;
        }
        for (b, l) in g.legs(a) {
            let nd = d[a] + l;
            if nd < d[b as usize] {
                d[b as usize] = nd;
                heap.push(Reverse((nd.to_bits(), b)));
            }
        }
    }
    d
}

/// `k` landmark nodes of `g` picked farthest first (each the node farthest, over the graph,
/// from those picked before; unreachable counts as farthest), from node 0, with the distance
/// from each to every node's position as [`CornerGraph::distance`] gives it. Not the graph's
/// own distances: a leg is taut at both of its nodes, so the graph's path to a node must
/// arrive at it as if bending there, and comes out longer than the point's distance, by up to
/// 4.7 m on turtlebot3_house; landmark bounds from it are far from admissible.
fn landmarks(g: &CornerGraph, grid: &NavGrid, k: usize) -> Vec<(usize, Vec<f64>)> {
    let mut picked = vec![(0, graph_distances(g, 0))];
    while picked.len() < k.min(g.len()) {
        let gap = |v: usize| picked.iter().map(|(_, d)| if d[v].is_finite() { d[v] } else { f64::MAX }).fold(f64::INFINITY, f64::min);
        let far = (0..g.len()).max_by(|&a, &b| gap(a).total_cmp(&gap(b))).unwrap_or(0);
        picked.push((far, graph_distances(g, far)));
    }
    picked
        .into_iter()
        .map(|(m, _)| (m, (0..g.len()).into_par_iter().map(|v| g.distance(grid, p2(g.pos(m)), p2(g.pos(v)))).collect()))
        .collect()
}

/// Octile distances (m) over navigable cells from cell `src` (diagonal steps only between
/// two navigable orthogonal neighbours; steps cost 1 and 1.4143 cells): lengths of paths
/// between cell centres, so above the geodesic distance but for the millimetres a step's
/// chord may cut inside the radius beside a corner (the slack covers them).
fn octile_field(grid: &NavGrid, src: usize) -> Vec<f64> {
    let (w, h) = grid.size();
    let res = grid.resolution();
    let mut d = vec![f64::INFINITY; w * h];
    let mut heap = BinaryHeap::new();
    d[src] = 0.0;
    heap.push(Reverse((0u64, src)));
    let nav = |c: isize, r: isize| c >= 0 && r >= 0 && c < w as isize && r < h as isize && grid.is_nav_cell(r as usize * w + c as usize);
    while let Some(Reverse((k, i))) = heap.pop() {
        if f64::from_bits(k) > d[i] {
            continue;
        }
        let (c, r) = ((i % w) as isize, (i / w) as isize);
        for (dc, dr) in [(-1isize, 0isize), (1, 0), (0, -1), (0, 1), (-1, -1), (-1, 1), (1, -1), (1, 1)] {
            let diag = dc != 0 && dr != 0;
            if !nav(c + dc, r + dr) || (diag && !(nav(c + dc, r) && nav(c, r + dr))) {
                continue;
            }
            let j = (r + dr) as usize * w + (c + dc) as usize;
            let nd = d[i] + if diag { 1.4143 } else { 1.0 } * res;
            if nd < d[j] {
                d[j] = nd;
                heap.push(Reverse((nd.to_bits(), j)));
            }
        }
    }
    d
}

/// What the landmark bounds below give up (m), for the rounding and the end tolerances of
/// the point queries they come from; the probe prints how far each bound still comes out
/// above the exact distance (none should).
const LANDMARK_SLACK: f64 = 0.05;

/// A point (m) as a [`Point2`].
fn p2(p: [f64; 2]) -> Point2 {
    Point2::new(p[0], p[1])
}

/// For a pair of points (m) that are connected but do not see each other: their distance
/// (m), their island and the goal's line-of-sight tolerance (m).
fn apart(g: &CornerGraph, grid: &NavGrid, s: [f64; 2], gl: [f64; 2]) -> Option<(f64, u32, f64)> {
    let d = g.distance(grid, p2(s), p2(gl));
    if !d.is_finite() || d <= dist2(s, gl) + 1e-9 {
        return None;
    }
    Some((d, grid.island_at(p2(gl))?, end_eps(grid, gl)))
}

#[test]
#[ignore]
fn route_probe() {
    for scene in ["turtlebot3_house.glb", "aws_small_house.glb"] {
        let Some(grid) = house_grid("route_probe", scene) else { continue };
        let g = grid.corner_graph().clone();
        let n = g.len();
        // 1. All pairs: Dijkstra from every node.
        let t = Instant::now();
        let table: Vec<Vec<f32>> = (0..n).into_par_iter().map(|src| graph_distances(&g, src).into_iter().map(|v| v as f32).collect()).collect();
        let apsp = t.elapsed().as_secs_f64();
        // 2. The nodes each navigable cell's centre joins, on a sample of cells.
        let cells = grid.cells_on_islands(0.0);
        let sample: Vec<usize> = cells.iter().copied().step_by(37).collect();
        let t = Instant::now();
        let seen: Vec<Vec<u32>> = sample
            .par_iter()
            .map(|&i| {
                let c = grid.center(i);
                (0..n).filter(|&k| g.island(k) == grid.island_of[i] && g.joins(&grid, k, c, LOS_EPS)).map(|k| k as u32).collect()
            })
            .collect();
        let vis_s = t.elapsed().as_secs_f64();
        let mean = seen.iter().map(|v| v.len()).sum::<usize>() as f64 / seen.len() as f64;
        let most = seen.iter().map(|v| v.len()).max().unwrap_or(0);
        // 3. Queries between sampled cells: min over the pairs of seen nodes, against distance().
        let m = sample.len();
        let pairs: Vec<(usize, usize)> = (0..4000).map(|q| ((q * 7919) % m, (q * 104729 + 13) % m)).collect();
        let t = Instant::now();
        let answers: Vec<f64> = pairs
            .iter()
            .map(|&(x, y)| {
                let (ps, pg) = (grid.center(sample[x]), grid.center(sample[y]));
                if grid.island_of[sample[x]] != grid.island_of[sample[y]] {
                    return f64::INFINITY;
                }
                if segment_clear(&grid, ps, pg, LOS_EPS) {
                    return dist2(ps, pg);
                }
                let dg: Vec<(usize, f32)> = seen[y].iter().map(|&b| (b as usize, dist2(g.pos(b as usize), pg) as f32)).collect();
                let mut best = f32::INFINITY;
                for &a in &seen[x] {
                    let row = &table[a as usize];
                    let da = dist2(g.pos(a as usize), ps) as f32;
                    for &(b, db) in &dg {
                        best = best.min(da + row[b] + db);
                    }
                }
                best as f64
            })
            .collect();
        let q_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let (mut worst, mut finite) = (0.0f64, 0);
        for (&(x, y), &a) in pairs.iter().zip(&answers) {
            let (ps, pg) = (grid.center(sample[x]), grid.center(sample[y]));
            let want = g.distance(&grid, xhab_types::Point2::new(ps[0], ps[1]), xhab_types::Point2::new(pg[0], pg[1]));
            std::hint::black_box(want);
            if want.is_finite() && a.is_finite() {
                finite += 1;
                worst = worst.max((a - want).abs() / want.max(1.0));
            } else {
                assert_eq!(want.is_finite(), a.is_finite());
            }
        }
        let old_s = t.elapsed().as_secs_f64();
        eprintln!(
            "{scene}: {n} nodes; all pairs {:.1} ms ({:.1} MB as f32); nodes a cell centre joins: mean {mean:.0}, most {most}, {:.1} us of one thread per cell -> {:.0} ms for all {} cells on one thread ({:.0} ms on {} threads); table queries {:.2} us each vs the search's {:.1} us; worst relative difference {worst:.2e} over {finite} pairs",
            apsp * 1e3,
            (n * n * 4) as f64 / 1e6,
            vis_s / sample.len() as f64 * 1e6 * rayon::current_num_threads() as f64,
            vis_s / sample.len() as f64 * cells.len() as f64 * 1e3 * rayon::current_num_threads() as f64,
            cells.len(),
            vis_s / sample.len() as f64 * cells.len() as f64 * 1e3,
            rayon::current_num_threads(),
            q_s / pairs.len() as f64 * 1e6,
            old_s / pairs.len() as f64 * 1e6,
        );
    }
}

/// How much of [`CornerGraph::distance`]'s work a better heuristic could save. For seeded
/// random pairs that do not see each other, it counts what an A* search from the goal does
/// with the straight line to the start as its heuristic (what `distance` uses) and with a
/// perfect one (each node's exact distance to the start): the goal-side seeds it takes (nodes
/// that pass the goal's taut tests and whose line from the goal plus heuristic is below the
/// answer), how many of those the goal does not see (each a failed line-of-sight test), the
/// nodes it settles (the graph distance from the goal plus heuristic below the answer, or on
/// a shortest path) and how many of those ask a line of sight to the start. What the perfect
/// heuristic leaves is a floor under any heuristic's work. Between the two, landmark (ALT)
/// bounds from 16 landmarks ([`landmarks`]) given each landmark's exact distance to the start
/// for free (a query would have to work it out): `|d(L, v) - d(L, s)|` (both sides) and
/// `d(L, v) - d(L, s)` (forward only), less [`LANDMARK_SLACK`], with the straight line as a
/// floor. What they leave is the most landmarks could save. Last, the forward bound with what
/// a query could have at hand instead: an upper bound of `d(L, s)` from an octile field of
/// the cells per landmark ([`octile_field`]).
///
/// `cargo test --release -p xhab-sim --lib heuristic_floor -- --ignored --nocapture`
#[test]
#[ignore]
fn heuristic_floor() {
    for (scene, pairs) in [("turtlebot3_house.glb", 300), ("aws_small_house.glb", 150)] {
        let Some(grid) = house_grid("heuristic_floor", scene) else { continue };
        let g = grid.corner_graph().clone();
        let ends = seeded_pairs(&grid, pairs);
        let marks = landmarks(&g, &grid, 16);
        // Each landmark's cell and octile field.
        let fields: Vec<(Vec<f64>, usize)> = marks
            .iter()
            .filter_map(|&(m, _)| grid.cell_of(p2(g.pos(m))))
            .map(|cl| (octile_field(&grid, cl), cl))
            .collect();
        assert_eq!(fields.len(), marks.len(), "a landmark off the grid");
        // Per pair, for the straight-line heuristic, the perfect one, then the three landmark
        // bounds: seeds, seeds unseen, settled, settled asking a line of sight; and how far
        // each heuristic comes out above the exact distance at worst.
        let counts: Vec<([f64; 20], [f64; 5])> = ends
            .par_iter()
            .filter_map(|&(s, gl)| {
                let (d, ia, eg) = apart(&g, &grid, s, gl)?;
                let es = end_eps(&grid, s);
                let to_start: Vec<f64> = marks.iter().map(|&(m, _)| g.distance(&grid, p2(g.pos(m)), p2(s))).collect();
                // Upper bounds of the same from the octile fields: a path from the landmark to
                // its cell's centre, over the cells, then to the start.
                let cs = grid.cell_of(p2(s))?;
                let above: Vec<f64> = fields.iter().zip(&marks).map(|((f, cl), &(m, _))| f[cs] + dist2(s, grid.center(cs)) + dist2(g.pos(m), grid.center(*cl))).collect();
                let mut c = [0.0; 20];
                let mut over = [f64::NEG_INFINITY; 5];
                for k in (0..g.len()).filter(|&k| g.island(k) == ia) {
                    let a = g.pos(k);
                    let (to_s, to_g) = (g.distance(&grid, p2(a), p2(s)), g.distance(&grid, p2(a), p2(gl)));
                    let seed = g.may_join(&grid, k, gl, eg) != Some(false);
                    let unseen = seed && !segment_clear(&grid, gl, a, eg);
                    let asks = g.may_join(&grid, k, s, es).is_none();
                    let line = dist2(a, s);
                    let bound = |both: bool, ls: &[f64]| {
                        let gaps = marks.iter().zip(ls).map(|((_, dl), &ls)| if both { (dl[k] - ls).abs() } else { dl[k] - ls });
                        gaps.filter(|x| x.is_finite()).fold(f64::NEG_INFINITY, f64::max) - LANDMARK_SLACK
                    };
                    let hs = [line, to_s, bound(true, &to_start).max(line), bound(false, &to_start).max(line), bound(false, &above).max(line)];
                    // How far a bound comes out above the exact distance to the start (an
                    // inadmissible bound: the slack is too small).
                    for (j, &h) in hs.iter().enumerate() {
                        over[j] = over[j].max(h - to_s);
                    }
                    for (j, h) in hs.into_iter().enumerate().map(|(j, h)| (4 * j, h)) {
                        if seed && dist2(gl, a) + h < d - 1e-9 {
                            c[j] += 1.0;
                            c[j + 1] += unseen as u8 as f64;
                        }
                        if to_g + h < d - 1e-9 || to_g + to_s <= d + 1e-9 {
                            c[j + 2] += 1.0;
                            c[j + 3] += asks as u8 as f64;
                        }
                    }
                }
                Some((c, over))
            })
            .collect();
        let m = counts.len().max(1) as f64;
        let mean = |j: usize| counts.iter().map(|c| c.0[j]).sum::<f64>() / m;
        let most_over = |h: usize| counts.iter().map(|c| c.1[h]).fold(f64::NEG_INFINITY, f64::max);
        for (name, j) in [
            ("straight-line heuristic", 0),
            ("perfect heuristic", 4),
            ("16 landmarks, both sides", 8),
            ("16 landmarks, forward only", 12),
            ("16 landmarks, forward only, octile bounds", 16),
        ] {
            eprintln!(
                "{scene}: {} pairs that do not see each other; {name}, per query: {:.1} goal-side seeds, {:.1} of them unseen from the goal; {:.1} nodes settled, {:.1} of them asking a line of sight to the start; at most {:.3} m above the exact distance",
                counts.len(),
                mean(j),
                mean(j + 1),
                mean(j + 2),
                mean(j + 3),
                most_over(j / 4)
            );
        }
    }
}

/// How much a set of nodes seen per 1 m square of the floor (a potentially visible set) would
/// spare the search: for seeded random pairs, how many of the goal-side seeds the search takes
/// now (straight-line heuristic) the goal does not see, how many of those lie outside its
/// square's set, and how many seeds the goal does see lie outside it (the set built here
/// from samples, 0.2 m apart, is not conservative: those would be answers lost). Also the
/// set's mean size and what building it by samples cost.
///
/// `cargo test --release -p xhab-sim --lib square_pvs -- --ignored --nocapture`
#[test]
#[ignore]
fn square_pvs() {
    for (scene, pairs) in [("turtlebot3_house.glb", 2000), ("aws_small_house.glb", 2000)] {
        let Some(grid) = house_grid("square_pvs", scene) else { continue };
        let g = grid.corner_graph().clone();
        let n = g.len();
        let (gw, gh) = grid.size();
        let res = grid.resolution();
        let per = (1.0 / res).round() as usize;
        let (sc, sr) = (gw.div_ceil(per), gh.div_ceil(per));
        let t = Instant::now();
        let pvs: Vec<Vec<bool>> = (0..sc * sr)
            .into_par_iter()
            .map(|q| {
                let (qc, qr) = (q % sc, q / sc);
                let mut seen = vec![false; n];
                for r in (qr * per..((qr + 1) * per).min(gh)).step_by(4) {
                    for c in (qc * per..((qc + 1) * per).min(gw)).step_by(4) {
                        let i = r * gw + c;
                        if !grid.is_nav_cell(i) {
                            continue;
                        }
                        let p = grid.center(i);
                        for k in 0..n {
                            if !seen[k] && g.island(k) == grid.island_of[i] && g.joins(&grid, k, p, LOS_EPS) {
                                seen[k] = true;
                            }
                        }
                    }
                }
                seen
            })
            .collect();
        let build_s = t.elapsed().as_secs_f64();
        let sizes: Vec<usize> = pvs.iter().map(|v| v.iter().filter(|&&b| b).count()).filter(|&m| m > 0).collect();
        let ends = seeded_pairs(&grid, pairs);
        // Per pair: seeds taken, unseen, unseen outside the set, seen outside the set.
        let counts: Vec<[f64; 4]> = ends
            .par_iter()
            .filter_map(|&(s, gl)| {
                let (d, ia, eg) = apart(&g, &grid, s, gl)?;
                let i = grid.cell_of(p2(gl))?;
                let set = &pvs[(i / gw / per) * sc + (i % gw) / per];
                let mut c = [0.0; 4];
                for k in (0..n).filter(|&k| g.island(k) == ia) {
                    let a = g.pos(k);
                    if g.may_join(&grid, k, gl, eg) != Some(false) && dist2(gl, a) + dist2(a, s) < d - 1e-9 {
                        let unseen = !segment_clear(&grid, gl, a, eg);
                        c[0] += 1.0;
                        c[1] += unseen as u8 as f64;
                        c[2] += (unseen && !set[k]) as u8 as f64;
                        c[3] += (!unseen && !set[k]) as u8 as f64;
                    }
                }
                Some(c)
            })
            .collect();
        let m = counts.len().max(1) as f64;
        let mean = |j: usize| counts.iter().map(|c| c[j]).sum::<f64>() / m;
        eprintln!(
            "{scene}: square sets of {:.0} nodes on average (most {}), built from samples in {:.0} ms; per query ({} pairs that do not see each other): {:.1} seeds taken, {:.1} unseen from the goal, {:.1} of those outside the goal's square's set; {:.2} seen seeds outside it",
            sizes.iter().sum::<usize>() as f64 / sizes.len().max(1) as f64,
            sizes.iter().max().unwrap_or(&0),
            build_s * 1e3,
            counts.len(),
            mean(0),
            mean(1),
            mean(2),
            mean(3)
        );
    }
}

/// `node_arcs`: how many of the graph's nodes stand on the arc about one obstacle vertex,
/// and how many an arc would keep at one node every [`passages::ARC_STEP_DEG`] (the spacing
/// the passages' arc nodes use): what thinning the arcs could take off the node count, which
/// the legs' build (pairs of nodes) and the queries' seeds grow with. Nodes are grouped by
/// the nearest end of an obstacle segment near their cell, within the radius and a cell.
///
/// `cargo test --release -p xhab-sim --lib node_arcs -- --ignored --nocapture`
#[test]
#[ignore]
fn node_arcs() {
    for scene in ["turtlebot3_house.glb", "aws_small_house.glb"] {
        let Some(grid) = house_grid("node_arcs", scene) else { continue };
        let g = grid.corner_graph().clone();
        let reach = grid.params.radius + grid.resolution();
        // Each node's vertex, if one is near.
        let vertex: Vec<Option<[f64; 2]>> = (0..g.len())
            .map(|k| {
                let p = g.pos(k);
                let i = grid.cell_of(p2(p))?;
                let v = grid.nearest_around(i).flat_map(|s| grid.segments[s as usize]).min_by(|a, b| dist2(*a, p).total_cmp(&dist2(*b, p)))?;
                (dist2(v, p) <= reach).then_some(v)
            })
            .collect();
        let key = |k: usize| vertex[k].map(vertex_key);
        // Each vertex's nodes, as directions from it (rad).
        let mut groups: std::collections::BTreeMap<(i64, i64), Vec<f64>> = Default::default();
        for (k, v) in vertex.iter().enumerate() {
            if let Some(v) = v {
                let p = g.pos(k);
                groups.entry(vertex_key(*v)).or_default().push((p[1] - v[1]).atan2(p[0] - v[0]));
            }
        }
        let step = passages::ARC_STEP_DEG.to_radians();
        let (mut kept, mut sizes) = (0usize, [0usize; 5]);
        for angles in groups.values_mut() {
            angles.sort_by(f64::total_cmp);
            let span = std::f64::consts::TAU - widest_gap(angles.iter().copied());
            kept += (span / step).ceil() as usize + 1;
            sizes[match angles.len() {
                1 => 0,
                2..=3 => 1,
                4..=6 => 2,
                7..=10 => 3,
                _ => 4,
            }] += 1;
        }
        let on_arcs = vertex.iter().filter(|v| v.is_some()).count();
        let same = (0..g.len()).map(|k| g.legs(k).filter(|&(b, _)| key(k).is_some() && key(k) == key(b as usize)).count()).sum::<usize>() / 2;
        eprintln!(
            "{scene}: {} nodes, {} on the arcs of {} vertices (per vertex: 1 node {}, 2-3 {}, 4-6 {}, 7-10 {}, more {}); one every {} degrees would keep {} of those {}; {} of the {} legs join two nodes of one arc",
            g.len(),
            on_arcs,
            groups.len(),
            sizes[0],
            sizes[1],
            sizes[2],
            sizes[3],
            sizes[4],
            passages::ARC_STEP_DEG,
            kept.min(on_arcs),
            on_arcs,
            same,
            g.leg_count()
        );
    }
}
