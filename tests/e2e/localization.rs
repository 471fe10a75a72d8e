//! AMCL on the shared scenes through `xhab bench`: tracking accuracy against ground truth and
//! the cost of localising in SPL; the scan-plane map it localises on.

use crate::common::{data_dir, xhab};

fn bench(scene: &std::path::Path, episodes: &std::path::Path, localization: &str, out: &std::path::Path) -> serde_json::Value {
    let o = xhab()
        .args(["bench", "--scene", scene.to_str().unwrap(), "--episodes", episodes.to_str().unwrap(), "--agent", "nav", "--localization", localization, "--threads", "2", "--quiet", "--out", out.to_str().unwrap()])
        .output()
        .expect("xhab runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str::<serde_json::Value>(&std::fs::read_to_string(out).unwrap()).unwrap()["aggregate"].clone()
}

#[test]
fn amcl_tracks_within_5_cm_and_2_degrees_and_costs_little_spl() {
    let Some(data) = data_dir("amcl_tracks_within_5_cm_and_2_degrees_and_costs_little_spl") else { return };
    let d = std::env::temp_dir().join(format!("xhab-loc-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    for s in ["turtlebot3_house", "aws_small_house"] {
        let scene = data.join(format!("scenes/{s}.glb"));
        let eps = data.join(format!("episodes/{s}_pointnav.json.gz"));
        let amcl = bench(&scene, &eps, "amcl", &d.join(format!("{s}-amcl.json")));
        let truth = bench(&scene, &eps, "ground_truth", &d.join(format!("{s}-gt.json")));
        let (m, deg) = (amcl["localization_error_m"].as_f64().unwrap(), amcl["localization_error_deg"].as_f64().unwrap());
        let (spl, spl_gt) = (amcl["spl"].as_f64().unwrap(), truth["spl"].as_f64().unwrap());
        eprintln!("{s}: AMCL error {m:.4} m, {deg:.3} deg; SPL {spl:.3} (ground truth {spl_gt:.3})");
        assert!(m <= 0.05 && deg <= 2.0, "{s}: {amcl}");
        assert!(spl >= spl_gt - 0.03, "{s}: SPL {spl} with AMCL, {spl_gt} with ground truth");
    }
}

#[test]
fn laser_height_maps_what_the_lidar_sees() {
    let d = std::env::temp_dir().join(format!("xhab-loc-map-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let occupied = |args: &[&str], name: &str| {
        let out = d.join(name);
        let o = xhab().args(["map", "procedural:3", "--out", out.to_str().unwrap()]).args(args).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (m, _) = xhab_nav::map_server::load_map(&d.join(format!("{name}.yaml"))).unwrap();
        m.data.iter().filter(|&&v| v == xhab_types::GRID_OCCUPIED).count()
    };
    let body = occupied(&[], "body");
    let laser = occupied(&["--laser-height", "0.2"], "laser");
    // Furniture is its legs at 0.2 m; the walls stay.
    assert!(laser < body && laser > body / 4, "{laser} of {body}");
    let bad = xhab().args(["map", "procedural:3", "--laser-height", "7", "--out", d.join("x").to_str().unwrap()]).output().unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--laser-height"));
}
