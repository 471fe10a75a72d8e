//! The maps in maps/ are what scripts/make_maps.sh makes today: regenerated into a temporary
//! folder with the CLI under test and compared byte for byte.

use std::process::Command;

#[test]
fn shipped_maps_match_what_the_script_makes() {
    let root = crate::common::repo_root();
    let dir = std::env::temp_dir().join(format!("xhab-maps-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let st = Command::new("bash")
        .arg(root.join("scripts/make_maps.sh"))
        .arg(&dir)
        .env("XHAB", env!("CARGO_BIN_EXE_xhab"))
        .status()
        .expect("running scripts/make_maps.sh");
    assert!(st.success(), "scripts/make_maps.sh failed");
    let mut made: Vec<String> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    made.sort();
    let mut shipped: Vec<String> = std::fs::read_dir(root.join("maps"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "README.md")
        .collect();
    shipped.sort();
    assert_eq!(made, shipped, "maps/ holds other files than scripts/make_maps.sh makes: rerun it");
    assert!(made.iter().filter(|n| n.ends_with(".yaml")).count() >= 4);
    for name in &made {
        let a = std::fs::read(dir.join(name)).unwrap();
        let b = std::fs::read(root.join("maps").join(name)).unwrap();
        assert!(a == b, "maps/{name} differs from what scripts/make_maps.sh makes now: rerun the script if the change is intended");
    }
    // Each map reads back as map_server reads it, at the size its picture shows.
    for name in made.iter().filter(|n| n.ends_with(".yaml")) {
        let (grid, _) = xhab_nav::map_server::load_map(&root.join("maps").join(name)).unwrap();
        assert!(grid.width > 100 && grid.height > 100, "{name}: {}x{}", grid.width, grid.height);
        let free = grid.data.iter().filter(|&&v| v == xhab_types::GRID_FREE).count();
        assert!(free as f64 * grid.resolution * grid.resolution > 50.0, "{name}: {free} free cells");
    }
    std::fs::remove_dir_all(&dir).ok();
}
