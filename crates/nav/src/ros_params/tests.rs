//! The loader against small files: each implemented ROS name holds to its effect, bad values
//! name the file and key, unknown keys get a "did you mean", and the shipped sets load clean.

use super::*;
use crate::navigator::NavParams;

/// Sources named `f0.yaml`, `f1.yaml`, ... with their namespaces.
fn load(files: &[(&str, &str)]) -> Result<LoadedParams, ParamError> {
    let sources: Vec<ParamSource> = files.iter().enumerate().map(|(i, (text, ns))| ParamSource { name: format!("f{i}.yaml"), text: text.to_string(), namespace: ns.to_string() }).collect();
    nav_params_from_sources(&sources)
}

fn ok(text: &str) -> LoadedParams {
    load(&[(text, "")]).unwrap_or_else(|e| panic!("{text}: {e}"))
}

fn err(text: &str) -> String {
    match load(&[(text, "")]) {
        Ok(_) => panic!("{text}: loaded"),
        Err(e) => e.to_string(),
    }
}

/// `text` sets a parameter that `get` reads back as `want`, which the default is not.
fn holds(text: &str, get: fn(&NavParams) -> f64, want: f64) {
    assert_ne!(get(&NavParams::default()), want, "{text}: pick a value other than the default");
    let loaded = ok(text);
    assert_eq!(get(&loaded.params), want, "{text}");
    assert!(loaded.warnings.is_empty(), "{text}: {:?}", loaded.warnings);
}

/// A YAML text, how to read the parameter it sets back, and the value it sets.
type Case = (&'static str, fn(&NavParams) -> f64, f64);

#[test]
fn each_implemented_name_takes_effect() {
    let cases: &[Case] = &[
        // move_base
        ("controller_frequency: 10", |p| p.dwa.controller_period, 0.1),
        ("planner_frequency: 2.0", |p| p.move_base.planner_frequency, 2.0),
        ("planner_patience: 1.5", |p| p.move_base.planner_patience, 1.5),
        ("controller_patience: 15", |p| p.move_base.controller_patience, 15.0),
        ("oscillation_timeout: 0", |p| p.move_base.oscillation_timeout, 0.0),
        ("oscillation_distance: 0.2", |p| p.move_base.oscillation_distance, 0.2),
        ("max_planning_retries: 3", |p| p.move_base.max_planning_retries as f64, 3.0),
        ("recovery_behavior_enabled: false", |p| f64::from(u8::from(p.move_base.recovery_behavior_enabled)), 0.0),
        ("clearing_rotation_allowed: false", |p| f64::from(u8::from(p.move_base.clearing_rotation_allowed)), 0.0),
        ("max_recoveries: 2", |p| p.move_base.max_recoveries as f64, 2.0),
        ("recovery_rotation_speed: 0.5", |p| p.move_base.recovery_rotation_speed, 0.5),
        ("move_base/planner_patience: 1.5", |p| p.move_base.planner_patience, 1.5),
        // costmaps: top level, and in the layer the name belongs to
        ("global_costmap: {robot_radius: 0.3}", |p| p.global_costmap.robot_radius, 0.3),
        ("robot_radius: 0.3", |p| p.local_costmap.robot_radius, 0.3),
        ("local_costmap/footprint_padding: 0.02", |p| p.local_costmap.footprint_padding, 0.02),
        ("global_costmap/inflation_radius: 0.3", |p| p.global_costmap.inflation_radius, 0.3),
        ("local_costmap/inflation_layer/inflation_radius: 0.3", |p| p.local_costmap.inflation_radius, 0.3),
        ("global_costmap/cost_scaling_factor: 3.0", |p| p.global_costmap.cost_scaling_factor, 3.0),
        ("global_costmap/inflation_layer/cost_scaling_factor: 3.0", |p| p.global_costmap.cost_scaling_factor, 3.0),
        ("global_costmap/lethal_cost_threshold: 100", |p| p.global_costmap.lethal_cost_threshold as f64, 100.0),
        ("global_costmap/static_layer/lethal_cost_threshold: 100", |p| p.global_costmap.lethal_cost_threshold as f64, 100.0),
        ("global_costmap/track_unknown_space: true", |p| f64::from(u8::from(p.global_costmap.track_unknown_space)), 1.0),
        ("local_costmap/obstacle_range: 3.0", |p| p.obstacle_layer.obstacle_range, 3.0),
        ("global_costmap/obstacle_layer/raytrace_range: 3.5", |p| p.obstacle_layer.raytrace_range, 3.5),
        ("local_costmap: {observation_sources: s, s: {data_type: LaserScan, obstacle_range: 1.0, clearing: true}}", |p| p.obstacle_layer.obstacle_range, 1.0),
        ("local_costmap: {observation_sources: s, s: {data_type: LaserScan, clearing: true, marking: false}}", |p| f64::from(u8::from(p.obstacle_layer.marking)), 0.0),
        ("local_costmap: {observation_sources: s, s: {data_type: LaserScan, clearing: false, inf_is_valid: true}}", |p| f64::from(u8::from(p.obstacle_layer.clearing)), 0.0),
        ("local_costmap: {observation_sources: s, s: {data_type: LaserScan, clearing: true, inf_is_valid: false}}", |p| f64::from(u8::from(p.obstacle_layer.clear_on_max_range)), 0.0),
        ("local_costmap: {width: 3, height: 3}", |p| p.obstacle_layer.local_window, 3.0),
        // DWA
        ("DWAPlannerROS/max_vel_x: 0.22", |p| p.dwa.max_vel_x, 0.22),
        ("DWAPlannerROS/min_vel_x: -0.1", |p| p.dwa.min_vel_x, -0.1),
        ("DWAPlannerROS/max_vel_trans: 0.3", |p| p.dwa.max_vel_trans, 0.3),
        ("DWAPlannerROS/max_vel_theta: 2.0", |p| p.dwa.max_vel_theta, 2.0),
        ("DWAPlannerROS/min_vel_trans: 0.05", |p| p.dwa.min_vel_trans, 0.05),
        ("DWAPlannerROS/min_vel_theta: 0.2", |p| p.dwa.min_vel_theta, 0.2),
        ("DWAPlannerROS/acc_lim_x: 1.0", |p| p.dwa.acc_lim_x, 1.0),
        ("DWAPlannerROS/acc_lim_theta: 2.0", |p| p.dwa.acc_lim_theta, 2.0),
        ("DWAPlannerROS/sim_time: 1.5", |p| p.dwa.sim_time, 1.5),
        ("DWAPlannerROS/sim_granularity: 0.05", |p| p.dwa.sim_granularity, 0.05),
        ("DWAPlannerROS/vx_samples: 20", |p| p.dwa.vx_samples as f64, 20.0),
        ("DWAPlannerROS/vth_samples: 40", |p| p.dwa.vth_samples as f64, 40.0),
        ("DWAPlannerROS/path_distance_bias: 20", |p| p.dwa.path_distance_bias, 20.0),
        ("DWAPlannerROS/goal_distance_bias: 20", |p| p.dwa.goal_distance_bias, 20.0),
        ("DWAPlannerROS/occdist_scale: 0.02", |p| p.dwa.occdist_scale, 0.02),
        ("DWAPlannerROS/forward_point_distance: 0.2", |p| p.dwa.forward_point_distance, 0.2),
        ("DWAPlannerROS/xy_goal_tolerance: 0.05", |p| p.dwa.xy_goal_tolerance, 0.05),
        ("DWAPlannerROS/controller_frequency: 10", |p| p.dwa.controller_period, 0.1),
        ("DWAPlannerROS/rotate_first_angle: 0.5", |p| p.dwa.rotate_first_angle, 0.5),
        ("DWAPlannerROS/local_goal_distance: 1.0", |p| p.dwa.local_goal_distance, 1.0),
        // TrajectoryPlannerROS, when it is the local planner
        ("base_local_planner: base_local_planner/TrajectoryPlannerROS\nTrajectoryPlannerROS/max_vel_x: 0.3", |p| p.dwa.max_vel_x, 0.3),
        ("TrajectoryPlannerROS/max_rotational_vel: 2.0", |p| p.dwa.max_vel_theta, 2.0),
        ("TrajectoryPlannerROS/vtheta_samples: 30", |p| p.dwa.vth_samples as f64, 30.0),
        ("TrajectoryPlannerROS/min_vel_x: 0.1", |p| p.dwa.min_vel_x, 0.1),
        // global planner
        ("GlobalPlanner/use_dijkstra: true", |p| f64::from(u8::from(p.planner.use_astar)), 0.0),
        ("GlobalPlanner/default_tolerance: 0.0", |p| p.planner.default_tolerance, 0.0),
        ("GlobalPlanner/neutral_cost: 66", |p| p.planner.neutral_cost, 66.0),
        ("GlobalPlanner/cost_factor: 0.8", |p| p.planner.cost_factor, 0.8),
        ("GlobalPlanner/smooth_max_cost: 100", |p| p.planner.smooth_max_cost as f64, 100.0),
        ("NavfnROS/default_tolerance: 0.2", |p| p.planner.default_tolerance, 0.2),
        // amcl, in its namespace or at the top
        ("amcl/min_particles: 500", |p| p.amcl.min_particles as f64, 500.0),
        ("max_particles: 3000", |p| p.amcl.max_particles as f64, 3000.0),
        ("kld_err: 0.02", |p| p.amcl.kld_err, 0.02),
        ("kld_z: 0.5", |p| p.amcl.kld_z, 0.5),
        ("update_min_d: 0.1", |p| p.amcl.update_min_d, 0.1),
        ("update_min_a: 0.2", |p| p.amcl.update_min_a, 0.2),
        ("update_min_a: !degrees 90", |p| p.amcl.update_min_a, std::f64::consts::FRAC_PI_2),
        ("resample_interval: 1", |p| p.amcl.resample_interval as f64, 1.0),
        ("recovery_alpha_slow: 0.001", |p| p.amcl.recovery_alpha_slow, 0.001),
        ("recovery_alpha_fast: 0.1", |p| p.amcl.recovery_alpha_fast, 0.1),
        ("amcl/odom_alpha1: 0.1", |p| p.amcl.odom_alpha1, 0.1),
        ("amcl/odom_alpha2: 0.1", |p| p.amcl.odom_alpha2, 0.1),
        ("amcl/odom_alpha3: 0.1", |p| p.amcl.odom_alpha3, 0.1),
        ("amcl/odom_alpha4: 0.1", |p| p.amcl.odom_alpha4, 0.1),
        ("laser_max_beams: 180", |p| p.amcl.laser_max_beams as f64, 180.0),
        ("laser_z_hit: 0.5", |p| p.amcl.laser_z_hit, 0.5),
        ("laser_z_short: 0.05", |p| p.amcl.laser_z_short, 0.05),
        ("laser_z_max: 0.1", |p| p.amcl.laser_z_max, 0.1),
        ("laser_z_rand: 0.5", |p| p.amcl.laser_z_rand, 0.5),
        ("laser_sigma_hit: 0.1", |p| p.amcl.laser_sigma_hit, 0.1),
        ("laser_lambda_short: 0.2", |p| p.amcl.laser_lambda_short, 0.2),
        ("laser_likelihood_max_dist: 1.0", |p| p.amcl.laser_likelihood_max_dist, 1.0),
        ("laser_no_return_likelihood: 1.0", |p| p.amcl.laser_no_return_likelihood, 1.0),
        ("do_beamskip: true", |p| f64::from(u8::from(p.amcl.do_beamskip)), 1.0),
        ("beam_skip_distance: 0.4", |p| p.amcl.beam_skip_distance, 0.4),
        ("beam_skip_threshold: 0.4", |p| p.amcl.beam_skip_threshold, 0.4),
        ("beam_skip_error_threshold: 0.8", |p| p.amcl.beam_skip_error_threshold, 0.8),
        ("laser_model_type: beam", |p| f64::from(u8::from(p.amcl.laser_model_type == crate::amcl::LaserModelType::Beam)), 1.0),
        ("odom_model_type: diff-corrected", |p| f64::from(u8::from(p.amcl.odom_model_type == crate::amcl::OdomModelType::DiffCorrected)), 1.0),
    ];
    for &(text, get, want) in cases {
        holds(text, get, want);
    }
}

#[test]
fn footprints_come_as_lists_or_strings_and_win_over_robot_radius() {
    let square = vec![[-0.105, -0.105], [-0.105, 0.105], [0.041, 0.105], [0.041, -0.105]];
    let l = ok("global_costmap/footprint: [[-0.105, -0.105], [-0.105, 0.105], [0.041, 0.105], [0.041, -0.105]]\nglobal_costmap/robot_radius: 0.3\n");
    assert_eq!(l.params.global_costmap.footprint, square);
    assert!(l.global_shape_given && !l.local_shape_given);
    assert!(l.warnings[0].contains("global_costmap/robot_radius"), "unread once a footprint is given: {:?}", l.warnings);
    let l = ok("footprint: '[[-0.105, -0.105], [-0.105, 0.105], [0.041, 0.105], [0.041, -0.105]]'\n");
    assert_eq!((&l.params.global_costmap.footprint, &l.params.local_costmap.footprint), (&square, &square));
    // "[]" is no footprint: robot_radius decides.
    let l = ok("local_costmap: {footprint: '[]', robot_radius: 0.2}\n");
    assert!(l.params.local_costmap.footprint.is_empty() && l.params.local_costmap.robot_radius == 0.2 && l.local_shape_given);
}

#[test]
fn the_robot_sizes_only_costmaps_the_files_did_not_shape() {
    let mut l = ok("global_costmap/robot_radius: 0.3\n");
    l.size_to_robot(0.2, Some(&[[-0.2, -0.1], [0.2, -0.1], [0.2, 0.1]]));
    assert_eq!((l.params.global_costmap.robot_radius, l.params.global_costmap.footprint.len()), (0.3, 0));
    assert_eq!((l.params.local_costmap.robot_radius, l.params.local_costmap.footprint.len()), (0.2, 3));
    let mut l = ok("");
    l.size_to_robot(0.15, None);
    assert_eq!((l.params.global_costmap.robot_radius, l.params.local_costmap.robot_radius), (0.15, 0.15));
}

#[test]
fn layering_follows_rosparam_namespaces_and_load_order() {
    let common = "inflation_radius: 0.2\ncost_scaling_factor: 20.0\nobstacle_range: 3.0\n";
    let l = load(&[(common, "global_costmap"), (common, "local_costmap"), ("local_costmap: {cost_scaling_factor: 10.0}\n", "")]).unwrap();
    assert_eq!((l.params.global_costmap.inflation_radius, l.params.local_costmap.inflation_radius), (0.2, 0.2));
    assert_eq!((l.params.global_costmap.cost_scaling_factor, l.params.local_costmap.cost_scaling_factor), (20.0, 10.0));
    assert_eq!(l.params.obstacle_layer.obstacle_range, 3.0);
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    // A file for amcl's own namespace.
    let l = load(&[("min_particles: 500\nodom_alpha1: 0.1\n", "amcl")]).unwrap();
    assert_eq!((l.params.amcl.min_particles, l.params.amcl.odom_alpha1), (500, 0.1));
}

#[test]
fn plugins_name_the_layers_and_the_costmap_top_wins() {
    let text = "local_costmap:
  plugins:
    - {name: obstacles, type: 'costmap_2d::ObstacleLayer'}
    - {name: inflater, type: 'costmap_2d::InflationLayer'}
    - {name: people, type: 'social_navigation_layers::ProxemicLayer'}
  obstacles: {observation_sources: laser, laser: {data_type: LaserScan, clearing: true, raytrace_range: 4.0}, obstacle_range: 2.0}
  inflater: {inflation_radius: 0.4, cost_scaling_factor: 5.0}
  cost_scaling_factor: 7.0
  people: {amplitude: 77}
";
    let l = ok(text);
    let (c, o) = (&l.params.local_costmap, &l.params.obstacle_layer);
    assert_eq!((c.inflation_radius, c.cost_scaling_factor), (0.4, 7.0));
    assert_eq!((o.obstacle_range, o.raytrace_range, o.clearing, o.clear_on_max_range), (2.0, 4.0, true, false));
    assert_eq!(l.warnings.len(), 2, "{:?}", l.warnings);
    assert!(l.warnings[0].contains("`people` (social_navigation_layers::ProxemicLayer) is not a layer xhab runs"), "{}", l.warnings[0]);
    assert!(l.warnings[1].contains("local_costmap/inflater/cost_scaling_factor") && l.warnings[1].contains("local_costmap/people/amplitude"), "{}", l.warnings[1]);
    // Without an inflation layer xhab still inflates, and says so.
    let l = ok("global_costmap/plugins: [{name: map, type: 'costmap_2d::StaticLayer'}]\nglobal_costmap/map/lethal_cost_threshold: 90\n");
    assert_eq!(l.params.global_costmap.lethal_cost_threshold, 90);
    assert!(l.warnings[0].contains("no costmap_2d::InflationLayer"), "{:?}", l.warnings);
}

#[test]
fn bad_values_name_the_file_and_key() {
    let cases = [
        ("DWAPlannerROS:\n  sim_granularity: 0\n", "f0.yaml: DWAPlannerROS/sim_granularity: must be > 0, got 0"),
        ("DWAPlannerROS/vx_samples: 0\n", "f0.yaml: DWAPlannerROS/vx_samples: must be >= 1, got 0"),
        ("DWAPlannerROS/vth_samples: 2.5\n", "f0.yaml: DWAPlannerROS/vth_samples: expected an integer, got 2.5"),
        ("DWAPlannerROS/max_vel_theta: -1\n", "f0.yaml: DWAPlannerROS/max_vel_theta: must be >= 0, got -1"),
        ("DWAPlannerROS/max_vel_x: fast\n", "f0.yaml: DWAPlannerROS/max_vel_x: expected a number, got \"fast\""),
        ("DWAPlannerROS/max_vel_x: .nan\n", "f0.yaml: DWAPlannerROS/max_vel_x: must be a finite number, got .nan"),
        ("DWAPlannerROS: {min_vel_x: 0.3, max_vel_x: 0.2}\n", "f0.yaml: DWAPlannerROS/max_vel_x: min_vel_x (0.3) must be <= max_vel_x (0.2)"),
        ("local_costmap/resolution: -0.05\n", "f0.yaml: local_costmap/resolution: must be > 0, got -0.05"),
        ("global_costmap/resolution: 0\n", "f0.yaml: global_costmap/resolution: must be > 0, got 0"),
        ("controller_frequency: 0\n", "f0.yaml: controller_frequency: must be > 0, got 0"),
        ("shutdown_costmaps: maybe\n", "f0.yaml: shutdown_costmaps: expected true or false, got \"maybe\""),
        ("global_costmap/footprint: [[0, 0], [1, 0]]\n", "f0.yaml: global_costmap/footprint: a footprint needs at least 3 points, got 2"),
        ("global_costmap: {observation_sources: s, s: {data_type: Sonar}}\n", "f0.yaml: global_costmap/s/data_type: must be LaserScan, PointCloud or PointCloud2, got \"Sonar\""),
        ("global_costmap/observation_sources: [scan]\n", "f0.yaml: global_costmap/observation_sources: expected a string, got a list (source names separated by spaces)"),
        ("global_costmap/plugins: static_layer\n", "f0.yaml: global_costmap/plugins: expected a list of {name, type} maps, got \"static_layer\""),
        ("amcl: {min_particles: 600, max_particles: 500}\n", "f0.yaml: amcl/max_particles: min_particles (600) must be <= max_particles (500)"),
        ("laser_z_hit: 1.5\n", "f0.yaml: laser_z_hit: must be in [0, 1], got 1.5"),
        ("kld_err: 0\n", "f0.yaml: kld_err: must be in (0, 1), got 0"),
        ("odom_model_type: omni\n", "f0.yaml: odom_model_type: xhab's robots are differential drives: diff or diff-corrected, got \"omni\""),
        ("laser_model_type: fancy\n", "f0.yaml: laser_model_type: must be beam, likelihood_field or likelihood_field_prob, got \"fancy\""),
        ("base_local_planner: 3\n", "f0.yaml: base_local_planner: expected a string, got 3"),
    ];
    for (text, want) in cases {
        assert_eq!(err(text), want, "{text}");
    }
    // The later file's key is the one named.
    let e = load(&[("DWAPlannerROS/sim_time: 1.0\n", ""), ("DWAPlannerROS/sim_time: -1\n", "")]).unwrap_err().to_string();
    assert_eq!(e, "f1.yaml: DWAPlannerROS/sim_time: must be > 0, got -1");
}

#[test]
fn unknown_keys_get_the_nearest_known_name() {
    let l = ok("DWAPlannerROS: {max_vel_X: 0.3, vtheta_samples: 40}\nplaner_patience: 3\nDWAPlannerRos/sim_time: 1.0\nlocal_costmap/inflation_layr/inflation_radius: 0.3\nsomething_else: 1\n");
    let w = &l.warnings;
    assert_eq!(w[0], "f0.yaml: DWAPlannerROS/max_vel_X: unknown parameter, ignored (did you mean `max_vel_x`?)");
    assert_eq!(w[1], "f0.yaml: DWAPlannerROS/vtheta_samples: unknown parameter, ignored (did you mean `vth_samples`?)");
    assert_eq!(w[2], "f0.yaml: planer_patience: unknown parameter, ignored (did you mean `planner_patience`?)");
    assert_eq!(w[3], "f0.yaml: DWAPlannerRos/sim_time: unknown parameter, ignored (did you mean `DWAPlannerROS/sim_time`?)");
    assert_eq!(w[4], "f0.yaml: local_costmap/inflation_layr/inflation_radius: unknown parameter, ignored (did you mean `inflation_layer/inflation_radius`?)");
    assert_eq!(w[5], "f0.yaml: something_else: unknown parameter, ignored");
    assert_eq!(w.len(), 6, "{w:?}");
    assert_eq!(l.params.dwa.max_vel_x, NavParams::default().dwa.max_vel_x);
}

#[test]
fn old_names_are_read_with_a_warning_and_ignored_names_are_listed_once() {
    let l = ok("DWAPlannerROS: {max_trans_vel: 0.22, max_rot_vel: 2.75, min_rot_vel: 1.37}\nshutdown_costmaps: false\nglobal_costmap: {global_frame: map, update_frequency: 10.0}\nrotate_recovery/frequency: 20\n");
    assert_eq!((l.params.dwa.max_vel_trans, l.params.dwa.max_vel_theta, l.params.dwa.min_vel_theta), (0.22, 2.75, 1.37));
    assert_eq!(l.warnings[0], "f0.yaml: DWAPlannerROS/max_trans_vel: old name of `max_vel_trans` (noetic warns and no longer reads it), read as `max_vel_trans`");
    assert!(l.warnings[1].contains("max_rot_vel") && l.warnings[1].contains("max_vel_theta"));
    assert!(l.warnings[2].contains("min_rot_vel") && l.warnings[2].contains("min_vel_theta"));
    assert_eq!(
        l.warnings[3],
        "4 ROS parameter(s) without effect in xhab (not implemented, or overridden): shutdown_costmaps, global_costmap/global_frame, global_costmap/update_frequency, rotate_recovery/frequency"
    );
    assert_eq!(l.warnings.len(), 4);
}

#[test]
fn xhab_settles_what_it_keeps_once_and_says_so() {
    let l = ok("controller_frequency: 20\nDWAPlannerROS/controller_frequency: 10\nlocal_costmap/obstacle_range: 2.0\nglobal_costmap/obstacle_range: 3.0\nlocal_costmap: {width: 3, height: 5}\n");
    assert_eq!((l.params.dwa.controller_period, l.params.obstacle_layer.obstacle_range, l.params.obstacle_layer.local_window), (0.05, 2.0, 5.0));
    let w = l.warnings.join("\n");
    assert!(w.contains("DWAPlannerROS/controller_frequency: 10 Hz differs from move_base's"), "{w}");
    assert!(w.contains("obstacle_range (local 2, global 3)"), "{w}");
    assert!(w.contains("width 3 m and height 5 m differ"), "{w}");
    // Another planner plugin: xhab runs its own, with the DWA parameters.
    let l = ok("base_local_planner: teb_local_planner/TebLocalPlannerROS\nDWAPlannerROS/max_vel_x: 0.3\n");
    assert_eq!(l.params.dwa.max_vel_x, 0.3);
    assert!(l.warnings[0].contains("in place of `teb_local_planner/TebLocalPlannerROS`"), "{:?}", l.warnings);
    // The planner not selected is read by nobody.
    let l = ok("base_global_planner: navfn/NavfnROS\nGlobalPlanner/default_tolerance: 0.1\nNavfnROS/default_tolerance: 0.2\n");
    assert_eq!(l.params.planner.default_tolerance, 0.2);
    assert!(l.warnings[0].ends_with(": GlobalPlanner/default_tolerance"), "{:?}", l.warnings);
}

#[test]
fn every_shipped_parameter_set_loads_without_warnings() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("params");
    let mut sets = 0;
    for entry in std::fs::read_dir(&root).unwrap() {
        let dir = entry.unwrap().path();
        // nav2/ holds Nav2 files (nav2_tests.rs loads them).
        if !dir.is_dir() || dir.ends_with("nav2") {
            continue;
        }
        let f = |name: &str, ns: &str| ParamFile { path: dir.join(name), namespace: ns.into() };
        let files = [
            f("costmap_common_params.yaml", "global_costmap"),
            f("costmap_common_params.yaml", "local_costmap"),
            f("global_costmap_params.yaml", ""),
            f("local_costmap_params.yaml", ""),
            f("move_base_params.yaml", ""),
            f("global_planner_params.yaml", ""),
            f("dwa_local_planner_params.yaml", ""),
            f("amcl_params.yaml", "amcl"),
        ];
        let l = load_nav_params(&files).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        assert!(l.warnings.is_empty(), "{}: {:?}", dir.display(), l.warnings);
        assert!(l.global_shape_given && l.local_shape_given, "{}", dir.display());
        // The sets spell out xhab's defaults, sized to the robot.
        let mut want = NavParams::default();
        (want.global_costmap.robot_radius, want.global_costmap.footprint) = (l.params.global_costmap.robot_radius, l.params.global_costmap.footprint.clone());
        want.local_costmap = want.global_costmap.clone();
        (want.dwa.max_vel_x, want.dwa.max_vel_trans, want.dwa.max_vel_theta, want.dwa.acc_lim_x) = (l.params.dwa.max_vel_x, l.params.dwa.max_vel_x, l.params.dwa.max_vel_theta, l.params.dwa.acc_lim_x);
        want.amcl.update_min_a = l.params.amcl.update_min_a;
        assert_eq!(l.params, want, "{}", dir.display());
        sets += 1;
    }
    assert_eq!(sets, 4);
}
