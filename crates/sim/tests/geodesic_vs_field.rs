//! The corner graph against today's Dijkstra field on the shared scenes: 100 random goals,
//! 100 random starts each (10,000 pairs per scene).
//!
//! What holds and is asserted: the graph and the field agree on which pairs are reachable;
//! the per-goal [`GoalField`] agrees with the pairwise query within 0.5% (the first picks its anchor for the cell centre, the second for the point itself); at most 1% of
//! pairs come out more than 0.5% longer than the field, none more than 5% longer (bend points
//! are one cell apart, and the graph leaves out those along straight walls). Pairs may come out
//! shorter (the field's wavefront inherits anchors and misses shortcuts): how many, and how many
//! of those paths `try_step` walks leg by leg, is printed.

use rand::SeedableRng;
use std::path::PathBuf;
use xhab_sim::geodesic::{geodesic_distance, GeodesicField};
use xhab_sim::goal_field::GoalField;
use xhab_sim::kinematic::try_step;
use xhab_sim::navgrid::NavGrid;
use xhab_sim::world::World;

fn grid_of(scene: &str) -> Option<std::sync::Arc<NavGrid>> {
    let dir = std::env::var_os("XHAB_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared")));
    let path = dir.join("scenes").join(scene);
    if !path.is_file() {
        assert!(std::env::var("XHAB_REQUIRE_DATA").as_deref() != Ok("1"), "shared data missing at {}", path.display());
        crate::data::skipped(&format!("geodesic_vs_field {scene}"), &format!("shared data not found at {}", path.display()));
        return None;
    }
    let s = xhab_sim::scene::load(&path, &Default::default()).expect("scene loads");
    let w = World::new(s, Default::default());
    Some(w.grid(w.default_floor().expect("a floor")).expect("grid builds"))
}

fn compare(scene: &str) {
    let Some(g) = grid_of(scene) else { return };
    let (goals, starts) = (100, 100);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
    let cells = g.cells_on_islands(0.0);
    let (mut pairs, mut worst_long, mut long, mut shorter, mut worst_short, mut walkable) = (0, 0.0f64, 0, 0, 0.0f64, 0);
    for _ in 0..goals {
        let goal = g.sample_navigable_point(&cells, &mut rng).expect("a point").xy();
        let field = GeodesicField::new(&g, &[goal]);
        let lazy = GoalField::new(&g, &[goal]);
        for _ in 0..starts {
            let s = g.sample_navigable_point(&cells, &mut rng).expect("a point").xy();
            let old = field.distance(&g, s);
            let new = geodesic_distance(&g, s, goal);
            let per_goal = lazy.distance(&g, s);
            assert_eq!(old.is_finite(), new.is_finite(), "{scene}: {s:?} -> {goal:?}: field {old}, graph {new}");
            assert_eq!(new.is_finite(), per_goal.is_finite(), "{scene}: {s:?} -> {goal:?}: graph {new}, goal field {per_goal}");
            if !old.is_finite() {
                continue;
            }
            pairs += 1;
            assert!((new - per_goal).abs() <= 5e-3 * new.max(1.0), "{scene}: {s:?} -> {goal:?}: pair query {new} vs goal field {per_goal}");
            assert!(new >= s.dist(goal) - 1e-9, "{scene}: shorter than the straight line");
            let e = (new - old) / old;
            worst_long = worst_long.max(e);
            assert!(e <= 0.05, "{scene}: {s:?} -> {goal:?}: {new} vs field {old} ({:.3}% longer)", e * 100.0);
            if e > 0.005 {
                long += 1;
            }
            if e < -0.005 {
                shorter += 1;
                worst_short = worst_short.min(e);
                let path = lazy.path(&g, s);
                let len: f64 = path.windows(2).map(|l| l[0].dist(l[1])).sum();
                assert!((len - per_goal).abs() < 1e-6, "{scene}: path length {len} vs distance {per_goal}");
                if path.windows(2).skip(1).all(|l| !try_step(&g, l[0], l[1]).1) {
                    walkable += 1;
                }
            }
        }
    }
    eprintln!(
        "{scene}: {pairs} reachable pairs; {long} more than 0.5% longer than the field (worst {:.3}%); {shorter} more than 0.5% shorter (worst {:.2}%), {walkable} of those walked leg by leg",
        worst_long * 100.0,
        worst_short * 100.0
    );
    assert!(pairs > 1000, "{scene}: too few reachable pairs ({pairs})");
    assert!(long * 100 <= pairs, "{scene}: {long} of {pairs} pairs more than 0.5% longer than the field");
}

#[test]
fn corner_graph_matches_the_field_on_turtlebot3_house() {
    compare("turtlebot3_house.glb");
}

#[test]
fn corner_graph_matches_the_field_on_aws_small_house() {
    compare("aws_small_house.glb");
}
