//! The lidar's planar slice against the 3D BVH cast on the shared scenes: the same hits along
//! horizontal rays at the scan height, from random navigable points (360 beams each).

use rand::{Rng, SeedableRng};
use xhab_sim::sensors::RayScene;
use xhab_sim::world::World;

fn compare(scene: &str) {
    let Some(dir) = crate::data::data_dir(&format!("scan_slice {scene}")) else { return };
    let s = xhab_sim::scene::load(&dir.join("scenes").join(scene), &Default::default()).expect("scene loads");
    let rays = RayScene::new(&s).expect("triangles");
    let w = World::new(s, Default::default());
    let g = w.grid(w.default_floor().expect("a floor")).expect("grid builds");
    let cells = g.cells_on_islands(0.0);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let (mut beams, mut worst, mut mismatched) = (0, 0.0f64, Vec::new());
    for _ in 0..50 {
        let p = g.sample_navigable_point(&cells, &mut rng).expect("a point").xy();
        let z = g.floor_z + rng.gen_range(0.05..1.0);
        let slice = rays.slice(z);
        for i in 0..360 {
            let a = i as f64 * std::f64::consts::TAU / 360.0 + 0.001;
            let (c, sn) = (a.cos(), a.sin());
            let flat = slice.cast([p.x, p.y], [c, sn], 3.5);
            let full = rays.cast([p.x, p.y, z], [c, sn, 0.0], 3.5);
            beams += 1;
            match (flat, full) {
                (Some(x), Some(y)) => {
                    // parry3d works in f32: a few micrometres at a few metres.
                    let e = (x - y).abs();
                    worst = worst.max(e);
                    if e > 1e-4 {
                        mismatched.push((p, z, a, flat, full));
                    }
                }
                (None, None) => {}
                // A grazing hit (a ray along a wall's plane, through a seam) may go either way
                // in f32; only count it.
                _ => mismatched.push((p, z, a, flat, full)),
            }
        }
    }
    eprintln!("scan_slice {scene}: {beams} beams, worst range difference {worst:.2e} m, {} mismatched", mismatched.len());
    assert!(mismatched.len() * 1000 <= beams, "{scene}: {} of {beams} beams differ, e.g. {:?}", mismatched.len(), &mismatched[..mismatched.len().min(5)]);
}

#[test]
fn slice_casts_match_the_3d_casts_on_turtlebot3_house() {
    compare("turtlebot3_house.glb");
}

#[test]
fn slice_casts_match_the_3d_casts_on_aws_small_house() {
    compare("aws_small_house.glb");
}
