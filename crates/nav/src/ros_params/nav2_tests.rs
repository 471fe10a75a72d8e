//! Nav2 (ROS 2) files against the loader: each mapped name takes effect, unknown names get a
//! "did you mean", bad values name the file and the Nav2 key, and a whole Nav2 params file
//! loads with the expected values and warnings.

use super::nav2::is_nav2;
use super::*;
use crate::navigator::NavParams;

fn load(files: &[(&str, &str)]) -> Result<LoadedParams, ParamError> {
    let sources: Vec<ParamSource> = files.iter().enumerate().map(|(i, (text, ns))| ParamSource { name: format!("n{i}.yaml"), text: text.to_string(), namespace: ns.to_string() }).collect();
    nav_params_from_sources(&sources)
}

fn ok(text: &str) -> LoadedParams {
    load(&[(text, "")]).unwrap_or_else(|e| panic!("{text}: {e}"))
}

fn err(text: &str) -> String {
    match load(&[(text, "")]) {
        Ok(l) => panic!("{text}: loaded, {:?}", l.warnings),
        Err(e) => e.to_string(),
    }
}

/// `NODE: {ros__parameters: {BODY}}`, with the costmaps nested as Nav2 writes them.
fn node(node: &str, body: &str) -> String {
    if node.ends_with("costmap") {
        format!("{node}:\n  {node}:\n    ros__parameters: {{{body}}}\n")
    } else {
        format!("{node}:\n  ros__parameters: {{{body}}}\n")
    }
}

const DWB: &str = "FollowPath: {plugin: 'dwb_core::DWBLocalPlanner', ";

type Case = (&'static str, String, fn(&NavParams) -> f64, f64);

#[test]
fn each_mapped_nav2_name_takes_effect() {
    let dwb = |kv: &str| format!("{DWB}{kv}}}");
    let cases: Vec<Case> = vec![
        ("controller_server", "controller_frequency: 10.0".into(), |p| p.dwa.controller_period, 0.1),
        ("controller_server", dwb("max_vel_x: 0.3"), |p| p.dwa.max_vel_x, 0.3),
        ("controller_server", dwb("min_vel_x: 0.05"), |p| p.dwa.min_vel_x, 0.05),
        ("controller_server", dwb("max_vel_theta: 2.5"), |p| p.dwa.max_vel_theta, 2.5),
        ("controller_server", dwb("max_speed_xy: 0.3"), |p| p.dwa.max_vel_trans, 0.3),
        ("controller_server", dwb("min_speed_xy: 0.02"), |p| p.dwa.min_vel_trans, 0.02),
        ("controller_server", dwb("min_speed_theta: 0.2"), |p| p.dwa.min_vel_theta, 0.2),
        ("controller_server", dwb("acc_lim_x: 1.5"), |p| p.dwa.acc_lim_x, 1.5),
        ("controller_server", dwb("acc_lim_theta: 2.0"), |p| p.dwa.acc_lim_theta, 2.0),
        ("controller_server", dwb("vx_samples: 9"), |p| p.dwa.vx_samples as f64, 9.0),
        ("controller_server", dwb("vtheta_samples: 30"), |p| p.dwa.vth_samples as f64, 30.0),
        ("controller_server", dwb("sim_time: 1.2"), |p| p.dwa.sim_time, 1.2),
        ("controller_server", dwb("linear_granularity: 0.05"), |p| p.dwa.sim_granularity, 0.05),
        ("controller_server", dwb("PathDist.scale: 30.0"), |p| p.dwa.path_distance_bias, 30.0),
        ("controller_server", dwb("GoalDist.scale: 20.0"), |p| p.dwa.goal_distance_bias, 20.0),
        ("controller_server", dwb("BaseObstacle.scale: 0.02"), |p| p.dwa.occdist_scale, 0.02),
        ("controller_server", dwb("PathAlign.forward_point_distance: 0.1"), |p| p.dwa.forward_point_distance, 0.1),
        // Critics also as YAML maps (`PathDist: {scale: ...}`).
        ("controller_server", dwb("PathDist: {scale: 28.0}"), |p| p.dwa.path_distance_bias, 28.0),
        ("controller_server", "goal_checker: {plugin: 'nav2_controller::SimpleGoalChecker', xy_goal_tolerance: 0.2}".into(), |p| p.dwa.xy_goal_tolerance, 0.2),
        ("controller_server", "goal_checker_plugins: [gc], gc: {plugin: 'nav2_controller::SimpleGoalChecker', xy_goal_tolerance: 0.3}".into(), |p| p.dwa.xy_goal_tolerance, 0.3),
        ("controller_server", "progress_checker: {plugin: 'nav2_controller::SimpleProgressChecker', required_movement_radius: 0.3}".into(), |p| p.move_base.oscillation_distance, 0.3),
        ("controller_server", "progress_checker_plugin: pc, pc: {movement_time_allowance: 7.0}".into(), |p| p.move_base.oscillation_timeout, 7.0),
        ("planner_server", "GridBased: {plugin: 'nav2_navfn_planner/NavfnPlanner', tolerance: 0.4}".into(), |p| p.planner.default_tolerance, 0.4),
        ("planner_server", "GridBased: {plugin: 'nav2_navfn_planner/NavfnPlanner', use_astar: false}".into(), |p| f64::from(u8::from(p.planner.use_astar)), 0.0),
        ("global_costmap", "robot_radius: 0.3".into(), |p| p.global_costmap.robot_radius, 0.3),
        ("local_costmap", "robot_radius: 0.3".into(), |p| p.local_costmap.robot_radius, 0.3),
        ("local_costmap", "footprint_padding: 0.02".into(), |p| p.local_costmap.footprint_padding, 0.02),
        ("global_costmap", "track_unknown_space: true".into(), |p| f64::from(u8::from(p.global_costmap.track_unknown_space)), 1.0),
        ("global_costmap", "lethal_cost_threshold: 90".into(), |p| p.global_costmap.lethal_cost_threshold as f64, 90.0),
        ("local_costmap", "width: 5, height: 5".into(), |p| p.obstacle_layer.local_window, 5.0),
        ("global_costmap", "inflation_layer: {plugin: 'nav2_costmap_2d::InflationLayer', inflation_radius: 0.3}".into(), |p| p.global_costmap.inflation_radius, 0.3),
        ("local_costmap", "inflation_layer.cost_scaling_factor: 2.5".into(), |p| p.local_costmap.cost_scaling_factor, 2.5),
        ("local_costmap", "obstacle_layer: {observation_sources: scan, scan: {data_type: LaserScan, obstacle_max_range: 2.0}}".into(), |p| p.obstacle_layer.obstacle_range, 2.0),
        ("local_costmap", "plugins: [vox, inflation_layer], vox: {plugin: 'nav2_costmap_2d::VoxelLayer', observation_sources: s, s: {data_type: LaserScan, raytrace_max_range: 4.0}}".into(), |p| p.obstacle_layer.raytrace_range, 4.0),
        ("local_costmap", "obstacle_layer: {observation_sources: scan, scan: {data_type: LaserScan, clearing: false}}".into(), |p| f64::from(u8::from(p.obstacle_layer.clearing)), 0.0),
        ("local_costmap", "obstacle_layer: {observation_sources: scan, scan: {data_type: LaserScan, marking: false}}".into(), |p| f64::from(u8::from(p.obstacle_layer.marking)), 0.0),
        ("local_costmap", "obstacle_layer: {observation_sources: scan, scan: {data_type: LaserScan, inf_is_valid: false}}".into(), |p| f64::from(u8::from(p.obstacle_layer.clear_on_max_range)), 0.0),
        ("amcl", "alpha1: 0.05".into(), |p| p.amcl.odom_alpha1, 0.05),
        ("amcl", "alpha2: 0.05".into(), |p| p.amcl.odom_alpha2, 0.05),
        ("amcl", "alpha3: 0.05".into(), |p| p.amcl.odom_alpha3, 0.05),
        ("amcl", "alpha4: 0.05".into(), |p| p.amcl.odom_alpha4, 0.05),
        ("amcl", "min_particles: 300".into(), |p| p.amcl.min_particles as f64, 300.0),
        ("amcl", "max_particles: 3000".into(), |p| p.amcl.max_particles as f64, 3000.0),
        ("amcl", "pf_err: 0.03".into(), |p| p.amcl.kld_err, 0.03),
        ("amcl", "pf_z: 0.95".into(), |p| p.amcl.kld_z, 0.95),
        ("amcl", "update_min_d: 0.3".into(), |p| p.amcl.update_min_d, 0.3),
        ("amcl", "update_min_a: 0.3".into(), |p| p.amcl.update_min_a, 0.3),
        ("amcl", "resample_interval: 3".into(), |p| p.amcl.resample_interval as f64, 3.0),
        ("amcl", "recovery_alpha_slow: 0.002".into(), |p| p.amcl.recovery_alpha_slow, 0.002),
        ("amcl", "recovery_alpha_fast: 0.2".into(), |p| p.amcl.recovery_alpha_fast, 0.2),
        ("amcl", "max_beams: 90".into(), |p| p.amcl.laser_max_beams as f64, 90.0),
        ("amcl", "z_hit: 0.6".into(), |p| p.amcl.laser_z_hit, 0.6),
        ("amcl", "z_short: 0.06".into(), |p| p.amcl.laser_z_short, 0.06),
        ("amcl", "z_max: 0.06".into(), |p| p.amcl.laser_z_max, 0.06),
        ("amcl", "z_rand: 0.4".into(), |p| p.amcl.laser_z_rand, 0.4),
        ("amcl", "sigma_hit: 0.25".into(), |p| p.amcl.laser_sigma_hit, 0.25),
        ("amcl", "lambda_short: 0.2".into(), |p| p.amcl.laser_lambda_short, 0.2),
        ("amcl", "laser_likelihood_max_dist: 1.5".into(), |p| p.amcl.laser_likelihood_max_dist, 1.5),
        ("amcl", "do_beamskip: true".into(), |p| f64::from(u8::from(p.amcl.do_beamskip)), 1.0),
        ("amcl", "beam_skip_distance: 0.4".into(), |p| p.amcl.beam_skip_distance, 0.4),
        ("amcl", "beam_skip_threshold: 0.4".into(), |p| p.amcl.beam_skip_threshold, 0.4),
        ("amcl", "beam_skip_error_threshold: 0.8".into(), |p| p.amcl.beam_skip_error_threshold, 0.8),
    ];
    for (n, body, get, want) in cases {
        let text = node(n, &body);
        assert_ne!(get(&NavParams::default()), want, "{text}: pick a value other than the default");
        let loaded = ok(&text);
        assert_eq!(get(&loaded.params), want, "{text}");
        assert!(loaded.warnings.is_empty(), "{text}: {:?}", loaded.warnings);
    }
    let beam = ok(&node("amcl", "laser_model_type: beam"));
    assert_eq!(beam.params.amcl.laser_model_type, crate::amcl::LaserModelType::Beam);
}

#[test]
fn nav2_files_are_told_from_ros1_files() {
    assert!(is_nav2(&node("amcl", "alpha1: 0.1")));
    assert!(is_nav2("robot1:\n  global_costmap:\n    global_costmap:\n      ros__parameters: {}\n"));
    assert!(!is_nav2("DWAPlannerROS: {max_vel_x: 0.2}\nros__parameters: 3\n"));
    assert!(!is_nav2("controller_frequency: 10\n"));
}

#[test]
fn unknown_nav2_names_are_warned_about_with_the_nearest_name() {
    let w = ok(&node("controller_server", &format!("{DWB}max_vel_xx: 0.2}}"))).warnings;
    assert_eq!(w[0], "n0.yaml: controller_server/FollowPath.max_vel_xx: unknown parameter, ignored (did you mean `FollowPath.max_vel_x`?)");
    let w = ok(&node("amcl", "z_hitt: 0.5, sigma_hit: 0.3")).warnings;
    assert_eq!(w, ["n0.yaml: amcl/z_hitt: unknown parameter, ignored (did you mean `z_hit`?)"]);
    let w = ok(&node("controler_server", "controller_frequency: 5.0")).warnings;
    assert_eq!(w, ["n0.yaml: controler_server: unknown Nav2 node, ignored (did you mean `controller_server`?)"]);
    // A misspelt plugin-level name is suggested in its plugin's namespace.
    let w = ok(&node("controller_server", "controller_frequncy: 5.0")).warnings;
    assert!(w[0].contains("did you mean `controller_frequency`"), "{w:?}");
    // ROS 1 names in a Nav2 node are unknown there, with Nav2's name suggested where near.
    let w = ok(&node("amcl", "laser_z_hit: 0.5")).warnings;
    assert!(w[0].starts_with("n0.yaml: amcl/laser_z_hit: unknown parameter"), "{w:?}");
    // Known names without effect are listed once, by their Nav2 keys.
    let w = ok(&(node("amcl", "alpha5: 0.1, base_frame_id: base_link") + &node("bt_navigator", "bt_loop_duration: 10"))).warnings;
    assert_eq!(w, ["3 ROS parameter(s) without effect in xhab (not implemented, or overridden): amcl/alpha5, amcl/base_frame_id, bt_navigator/bt_loop_duration"]);
}

#[test]
fn plugins_xhab_does_not_run_are_warned_about() {
    let w = ok(&node("controller_server", "FollowPath: {plugin: 'nav2_mppi_controller::MPPIController', batch_size: 2000}")).warnings;
    assert!(w[0].contains("`FollowPath` (nav2_mppi_controller::MPPIController) is not a controller xhab runs"), "{w:?}");
    assert!(w[1].contains("controller_server/FollowPath.batch_size"), "{w:?}");
    let l = ok(&node("planner_server", "GridBased: {plugin: 'nav2_smac_planner/SmacPlanner2D', tolerance: 0.3}"));
    assert_eq!(l.params.planner.default_tolerance, 0.3);
    assert!(l.warnings[0].contains("in place of `GridBased` (nav2_smac_planner/SmacPlanner2D)"), "{:?}", l.warnings);
    let w = ok(&node("local_costmap", "plugins: [denoise], denoise: {plugin: 'nav2_costmap_2d::DenoiseLayer', minimal_group_size: 2}")).warnings;
    assert!(w.iter().any(|w| w.contains("n0.yaml: local_costmap/local_costmap/plugins: `denoise` (nav2_costmap_2d::DenoiseLayer) is not a layer xhab runs")), "{w:?}");
}

#[test]
fn a_footprint_string_is_a_polygon_and_an_empty_one_leaves_the_radius() {
    let l = ok(&node("global_costmap", r#"footprint: "[[-0.1, -0.1], [-0.1, 0.1], [0.2, 0.0]]", robot_radius: 0.5"#));
    assert_eq!(l.params.global_costmap.footprint, vec![[-0.1, -0.1], [-0.1, 0.1], [0.2, 0.0]]);
    assert!(l.global_shape_given && !l.local_shape_given);
    // A valid footprint wins; robot_radius is then without effect.
    assert!(l.warnings[0].ends_with("global_costmap/global_costmap/robot_radius"), "{:?}", l.warnings);
    let l = ok(&node("local_costmap", r#"footprint: "[]", robot_radius: 0.25"#));
    assert_eq!((l.params.local_costmap.robot_radius, l.params.local_costmap.footprint.len()), (0.25, 0));
    let e = err(&node("global_costmap", r#"footprint: "[[0.1, 0.1], [0.2]]""#));
    assert!(e.starts_with("n0.yaml: global_costmap/global_costmap/footprint: "), "{e}");
}

#[test]
fn costmaps_load_nested_flat_and_under_a_namespace() {
    let flat = "global_costmap:\n  ros__parameters: {robot_radius: 0.3}\n";
    assert_eq!(ok(flat).params.global_costmap.robot_radius, 0.3);
    let ns = "robot1:\n  local_costmap:\n    local_costmap:\n      ros__parameters: {robot_radius: 0.3}\nrobot2:\n  local_costmap:\n    local_costmap:\n      ros__parameters: {robot_radius: 0.4}\n";
    assert_eq!(load(&[(ns, "robot1")]).unwrap().params.local_costmap.robot_radius, 0.3);
    assert_eq!(load(&[(ns, "robot2")]).unwrap().params.local_costmap.robot_radius, 0.4);
    // No namespace: every node, in file order (the last wins).
    assert_eq!(ok(ns).params.local_costmap.robot_radius, 0.4);
}

#[test]
fn bad_nav2_values_name_the_file_and_the_nav2_key() {
    let e = err(&node("controller_server", "controller_frequency: -1.0"));
    assert_eq!(e, "n0.yaml: controller_server/controller_frequency: must be > 0, got -1.0");
    let e = err(&node("amcl", "z_hit: 1.5"));
    assert_eq!(e, "n0.yaml: amcl/z_hit: must be in [0, 1], got 1.5");
    let e = err(&node("amcl", "max_beams: 60.5"));
    assert!(e.starts_with("n0.yaml: amcl/max_beams: expected an integer"), "{e}");
    let e = err(&node("local_costmap", "inflation_layer.inflation_radius: fast"));
    assert!(e.starts_with("n0.yaml: local_costmap/local_costmap/inflation_layer.inflation_radius: expected a number"), "{e}");
    // Checks of the ROS 1 loader name the Nav2 key too.
    let e = err(&node("controller_server", &format!("{DWB}min_vel_x: 0.3, max_vel_x: 0.2}}")));
    assert!(e.starts_with("n0.yaml: controller_server/FollowPath.m") && e.contains("min_vel_x (0.3) must be <= max_vel_x (0.2)"), "{e}");
    let e = err(&node("amcl", "laser_model_type: sonar"));
    assert!(e.starts_with("n0.yaml: amcl/laser_model_type: must be beam"), "{e}");
    let e = err(&node("amcl", "robot_model_type: 'nav2_amcl::OmniMotionModel'"));
    assert!(e.starts_with("n0.yaml: amcl/robot_model_type: xhab's robots are differential drives"), "{e}");
    let e = err(&node("local_costmap", "obstacle_layer: {observation_sources: scan, scan: {data_type: Sonar}}"));
    assert!(e.starts_with("n0.yaml: local_costmap/local_costmap/obstacle_layer.scan.data_type: must be LaserScan"), "{e}");
}

#[test]
fn nav2_and_ros1_files_layer_in_order() {
    let nav2 = node("controller_server", &format!("{DWB}max_vel_x: 0.3, sim_time: 1.2}}"));
    let l = load(&[(&nav2, ""), ("DWAPlannerROS: {max_vel_x: 0.25}\n", "")]).unwrap();
    assert_eq!((l.params.dwa.max_vel_x, l.params.dwa.sim_time), (0.25, 1.2));
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    let l = load(&[("DWAPlannerROS: {max_vel_x: 0.25}\n", ""), (&nav2, "")]).unwrap();
    assert_eq!(l.params.dwa.max_vel_x, 0.3);
}

/// The shipped Nav2-layout file: nav2_bringup's nodes and plugins, TurtleBot3 Burger's values.
#[test]
fn a_whole_nav2_params_file_loads_with_its_values() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/params/nav2/nav2_params.yaml");
    let l = load_nav_params(&[path.parse().unwrap()]).unwrap();
    let p = &l.params;
    assert_eq!(p.dwa.controller_period, 0.1);
    assert_eq!((p.dwa.max_vel_x, p.dwa.min_vel_x, p.dwa.max_vel_trans, p.dwa.min_vel_trans), (0.22, 0.0, 0.22, 0.05));
    assert_eq!((p.dwa.max_vel_theta, p.dwa.min_vel_theta, p.dwa.acc_lim_x, p.dwa.acc_lim_theta), (2.0, 0.3, 2.0, 3.0));
    assert_eq!((p.dwa.vx_samples, p.dwa.vth_samples, p.dwa.sim_time, p.dwa.sim_granularity), (20, 40, 1.5, 0.05));
    assert_eq!((p.dwa.path_distance_bias, p.dwa.goal_distance_bias, p.dwa.occdist_scale, p.dwa.forward_point_distance), (30.0, 20.0, 0.02, 0.1));
    assert_eq!(p.dwa.xy_goal_tolerance, 0.2);
    assert_eq!((p.move_base.oscillation_distance, p.move_base.oscillation_timeout), (0.4, 12.0));
    assert_eq!((p.planner.default_tolerance, p.planner.use_astar), (0.4, true));
    assert_eq!(p.global_costmap.footprint, vec![[-0.105, -0.105], [-0.105, 0.105], [0.041, 0.105], [0.041, -0.105]]);
    assert_eq!(p.local_costmap.robot_radius, 0.105);
    assert!(l.global_shape_given && l.local_shape_given);
    assert_eq!((p.global_costmap.inflation_radius, p.global_costmap.cost_scaling_factor), (0.5, 3.0));
    assert_eq!((p.local_costmap.inflation_radius, p.local_costmap.cost_scaling_factor), (0.5, 3.0));
    assert!(p.global_costmap.track_unknown_space);
    assert_eq!((p.obstacle_layer.obstacle_range, p.obstacle_layer.raytrace_range, p.obstacle_layer.local_window), (3.0, 3.5, 3.0));
    assert!(p.obstacle_layer.marking && p.obstacle_layer.clearing);
    let a = &p.amcl;
    assert_eq!((a.odom_alpha1, a.odom_alpha4, a.min_particles, a.max_particles, a.kld_err), (0.1, 0.1, 500, 2000, 0.05));
    assert_eq!((a.laser_max_beams, a.laser_z_hit, a.laser_z_rand, a.laser_sigma_hit, a.resample_interval), (60, 0.5, 0.5, 0.2, 1));
    assert_eq!((a.update_min_d, a.update_min_a, a.recovery_alpha_slow, a.recovery_alpha_fast), (0.25, 0.2, 0.0, 0.0));
    assert_eq!(a.laser_model_type, crate::amcl::LaserModelType::LikelihoodField);
    // Only one warning: the known keys without effect, none of the mapped ones among them.
    assert_eq!(l.warnings.len(), 1, "{:?}", l.warnings);
    let w = &l.warnings[0];
    for idle in ["amcl/alpha5", "amcl/base_frame_id", "bt_navigator/bt_loop_duration", "controller_server/FollowPath.decel_lim_x", "controller_server/general_goal_checker.yaw_goal_tolerance", "local_costmap/local_costmap/static_layer.map_subscribe_transient_local", "global_costmap/global_costmap/resolution", "planner_server/expected_planner_frequency", "map_server/yaml_filename"] {
        assert!(w.contains(&format!(" {idle},")) || w.ends_with(&format!(" {idle}")), "{idle} not in {w}");
    }
    for used in ["FollowPath.max_vel_x,", "PathDist.scale", "inflation_radius", "alpha1", "pf_err", "required_movement_radius", "GridBased.tolerance", "/plugins", "FollowPath.plugin", "GridBased.plugin", "obstacle_max_range"] {
        assert!(!w.contains(used), "{used} in {w}");
    }
}
