//! PointNav episode generation with Habitat's rules (habitat-lab `generate_pointnav_episode`).
//!
//! For each episode: sample a goal on an island of radius >= `island_radius_limit`, then up to
//! `number_retries_per_target` starts; keep a start on the same floor (|dz| <= 0.5 m) whose
//! geodesic distance is within [`closest_dist_limit`, `furthest_dist_limit`], and, when the
//! geodesic/euclidean ratio is below `geodesic_to_euclid_min_ratio`, only with probability
//! 20 * (ratio - 0.98)^2 (so that easy, straight episodes are rare).

use super::{Dataset, Episode, Goal};
use crate::geodesic::geodesic_distance;
use crate::navgrid::NavGrid;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Settings of the episode generator (habitat-lab names and defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GeneratorParams {
    /// Shortest allowed geodesic start-goal distance (m, default 1).
    pub closest_dist_limit: f64,
    /// Longest allowed geodesic start-goal distance (m, default 30).
    pub furthest_dist_limit: f64,
    /// Below this geodesic/euclidean ratio an episode is kept only with probability
    /// 20 (ratio - 0.98)^2 (default 1.1).
    pub geodesic_to_euclid_min_ratio: f64,
    /// Smallest island radius for goals (m, default 1.5).
    pub island_radius_limit: f64,
    /// Starts tried per goal (default 10).
    pub number_retries_per_target: u32,
    /// Radius stored with each goal (m, default 0.2).
    pub goal_radius: f64,
}

impl Default for GeneratorParams {
    fn default() -> Self {
        Self {
            closest_dist_limit: 1.0,
            furthest_dist_limit: 30.0,
            geodesic_to_euclid_min_ratio: 1.1,
            island_radius_limit: 1.5,
            number_retries_per_target: 10,
            goal_radius: 0.2,
        }
    }
}

/// Why episodes could not be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GenerateError {
    /// No island is large enough for goals.
    #[error("no navigable island has a radius of at least {0} m")]
    NoIsland(f64),
    /// No flight of stairs joins two storeys (for episodes across storeys).
    #[error("no flight of stairs joins two storeys of the scene")]
    NoFlight,
    /// Too many goals were tried without finding enough episodes.
    #[error("found only {found} of {wanted} episodes after {tries} goals: the scene is too small or too cramped for the limits")]
    Exhausted {
        /// Episodes found.
        found: usize,
        /// Episodes asked for.
        wanted: usize,
        /// Goals tried.
        tries: usize,
    },
}

/// Generates `count` episodes on `grid` (one floor) from `seed`. The same grid, parameters
/// and seed give the same episodes, bit for bit.
pub fn generate_episodes(
    grid: &NavGrid,
    scene_id: &str,
    count: usize,
    seed: u64,
    params: &GeneratorParams,
) -> Result<Dataset, GenerateError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // Cells of islands large enough for goals, sampled uniformly by area.
    let cells = grid.cells_on_islands(params.island_radius_limit);
    let all_cells = grid.cells_on_islands(0.0);
    if cells.is_empty() {
        return Err(GenerateError::NoIsland(params.island_radius_limit));
    }
    let mut episodes = Vec::with_capacity(count);
    let max_targets = 200 * count.max(1) + 1000;
    let mut tries = 0;
    while episodes.len() < count {
        if tries >= max_targets {
            return Err(GenerateError::Exhausted { found: episodes.len(), wanted: count, tries });
        }
        tries += 1;
        let Some(goal) = grid.sample_navigable_point(&cells, &mut rng) else { continue };
        for _ in 0..params.number_retries_per_target {
            let Some(start) = grid.sample_navigable_point(&all_cells, &mut rng) else { continue };
            if (start.z - goal.z).abs() > 0.5 {
                continue;
            }
            // One pair query per start tried (most goals take a start or two): cheaper than
            // a field towards the goal, and exact at both ends.
            let d = geodesic_distance(grid, start.xy(), goal.xy());
            let euclid = start.xy().dist(goal.xy());
            if !keeps(d, euclid, params, &mut rng) {
                continue;
            }
            episodes.push(episode(episodes.len(), scene_id, start, goal, d, params, &mut rng));
            break;
        }
    }
    Ok(Dataset { episodes })
}

/// Generates `count` episodes whose start and goal stand on different storeys of `world` that
/// flights of stairs join (`xhab episodes --cross-floor`), from `seed`, with Habitat's other
/// rules: goals on islands of at least `island_radius_limit`, the 3D geodesic of
/// [`crate::storey_path`] within the distance limits, and the same rule on the ratio of
/// geodesic to straight-line (3D) distance. Starts and goals stand on floors, not on flights.
/// The same world, parameters and seed give the same episodes, bit for bit.
pub fn generate_cross_storey_episodes(
    world: &crate::world::World,
    scene_id: &str,
    count: usize,
    seed: u64,
    params: &GeneratorParams,
) -> Result<Dataset, GenerateError> {
    let joined = world.connected_storeys();
    if joined.is_empty() {
        return Err(GenerateError::NoFlight);
    }
    let mut storeys: Vec<usize> = joined.iter().flat_map(|&(a, b)| [a, b]).collect();
    storeys.sort();
    storeys.dedup();
    let mut grids = Vec::new();
    let mut goal_cells = Vec::new();
    let mut start_cells = Vec::new();
    for &k in &storeys {
        let Ok(g) = world.grid(k) else { return Err(GenerateError::NoFlight) };
        let off_flight = |v: Vec<usize>| -> Vec<usize> { v.into_iter().filter(|&i| !g.cell_is_stair(i)).collect() };
        goal_cells.push(off_flight(g.cells_on_islands(params.island_radius_limit)));
        start_cells.push(off_flight(g.cells_on_islands(0.0)));
        grids.push(g);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut episodes = Vec::with_capacity(count);
    let max_targets = 200 * count.max(1) + 1000;
    let mut tries = 0;
    while episodes.len() < count {
        if tries >= max_targets {
            return Err(GenerateError::Exhausted { found: episodes.len(), wanted: count, tries });
        }
        tries += 1;
        let gk = rng.gen_range(0..storeys.len());
        if goal_cells[gk].is_empty() {
            continue;
        }
        let Some(goal) = grids[gk].sample_navigable_point(&goal_cells[gk], &mut rng) else { continue };
        for _ in 0..params.number_retries_per_target {
            let sk = rng.gen_range(0..storeys.len());
            if sk == gk || start_cells[sk].is_empty() {
                continue;
            }
            let Some(start) = grids[sk].sample_navigable_point(&start_cells[sk], &mut rng) else { continue };
            let d = crate::storey_path::distance(world, start, goal);
            let euclid = ((start.x - goal.x).powi(2) + (start.y - goal.y).powi(2) + (start.z - goal.z).powi(2)).sqrt();
            if !keeps(d, euclid, params, &mut rng) {
                continue;
            }
            episodes.push(episode(episodes.len(), scene_id, start, goal, d, params, &mut rng));
            break;
        }
    }
    Ok(Dataset { episodes })
}

/// Habitat's rules on a candidate pair with geodesic `d` and straight-line distance `euclid`
/// (m): `d` within the distance limits, and a pair whose ratio is below
/// `geodesic_to_euclid_min_ratio` kept only with probability 20 (ratio - 0.98)^2 (drawn from
/// `rng` only then).
fn keeps(d: f64, euclid: f64, params: &GeneratorParams, rng: &mut ChaCha8Rng) -> bool {
    if !d.is_finite() || d < params.closest_dist_limit || d > params.furthest_dist_limit {
        return false;
    }
    let ratio = d / euclid.max(1e-9);
    ratio >= params.geodesic_to_euclid_min_ratio || rng.gen::<f64>() <= 20.0 * (ratio - 0.98).powi(2)
}

/// Episode number `id` from `start` to `goal` with geodesic `d` (m); the start heading is drawn
/// from `rng` as Habitat draws it (an angle about the up axis; facing Habitat's -z is our yaw
/// pi/2).
fn episode(id: usize, scene_id: &str, start: xhab_types::Point3, goal: xhab_types::Point3, d: f64, params: &GeneratorParams, rng: &mut ChaCha8Rng) -> Episode {
    let angle = rng.gen::<f64>() * std::f64::consts::TAU;
    Episode {
        episode_id: id.to_string(),
        scene_id: scene_id.to_string(),
        start_position: start,
        start_yaw: xhab_types::normalize_angle(angle + std::f64::consts::FRAC_PI_2),
        goals: vec![Goal { position: goal, radius: params.goal_radius }],
        geodesic_distance: Some(d),
        info: serde_json::json!({ "geodesic_distance": d }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::navgrid::AgentParams;
    use crate::scene::house::{generate_house, HouseParams};

    #[test]
    fn a_pair_is_kept_by_habitats_distance_limits_and_ratio_rule() {
        let p = GeneratorParams::default();
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        // Outside [1, 30] m, or undefined: never kept, whatever the ratio.
        for (d, e) in [(0.99, 0.5), (30.01, 10.0), (f64::INFINITY, 3.0), (f64::NAN, 3.0)] {
            assert!(!keeps(d, e, &p, &mut rng), "{d} m kept");
        }
        // At or above the ratio: kept without a draw (the stream is untouched).
        let before = rng.clone();
        assert!(keeps(5.5, 5.0, &p, &mut rng) && keeps(1.0, 0.5, &p, &mut rng) && keeps(30.0, 3.0, &p, &mut rng));
        assert_eq!(rng.gen::<u64>(), before.clone().gen::<u64>(), "a pair above the ratio drew from the stream");
        // Below it: kept with probability 20 (ratio - 0.98)^2, within four standard deviations.
        for ratio in [1.0, 1.03, 1.06, 1.09] {
            let want = 20.0 * (ratio - 0.98f64).powi(2);
            let n = 20_000;
            let kept = (0..n).filter(|_| keeps(4.0 * ratio, 4.0, &p, &mut rng)).count() as f64;
            let sd = (n as f64 * want * (1.0 - want)).sqrt();
            assert!((kept - n as f64 * want).abs() <= 4.0 * sd, "ratio {ratio}: kept {kept} of {n}, expected {:.0}", n as f64 * want);
        }
    }

    #[test]
    fn generated_episodes_follow_the_rules_they_claim() {
        let scene = generate_house(3, &HouseParams::default());
        let grid = NavGrid::build(&scene, &AgentParams::default(), 0.0).unwrap();
        let p = GeneratorParams::default();
        let ds = generate_episodes(&grid, "house", 60, 11, &p).unwrap();
        assert_eq!(ds.episodes.len(), 60);
        let mut below_ratio = 0;
        for e in &ds.episodes {
            let (s, g) = (e.start_position, e.goals[0].position);
            let d = e.geodesic_distance.unwrap();
            assert!((p.closest_dist_limit..=p.furthest_dist_limit).contains(&d), "episode {}: {d} m", e.episode_id);
            assert!((d - geodesic_distance(&grid, s.xy(), g.xy())).abs() <= 5e-3 * d, "episode {}: recorded {d} m", e.episode_id);
            assert!(grid.is_navigable(s.xy()) && grid.is_navigable(g.xy()) && (s.z - g.z).abs() <= 0.5);
            let island = grid.island_at(g.xy()).expect("the goal is on an island") as usize;
            assert!(grid.islands[island].radius >= p.island_radius_limit, "episode {}: goal island of radius {}", e.episode_id, grid.islands[island].radius);
            assert_eq!(grid.island_at(s.xy()), Some(island as u32));
            assert_eq!(e.goals[0].radius, p.goal_radius);
            if d / s.xy().dist(g.xy()) < p.geodesic_to_euclid_min_ratio {
                below_ratio += 1;
            }
        }
        // Straight pairs are common in a house of rooms; the rule keeps few of them.
        assert!(below_ratio <= 15, "{below_ratio} of 60 episodes below the ratio");
    }
}
