//! Every parameter name of the Nav2 (ROS 2) nodes and plugins xhab stands in for, with its
//! type, range, Nav2 default, and the ROS 1 name it is read as (`None`: known, without effect).
//!
//! Names and defaults come from Nav2's sources and docs (Jazzy/Kilted: nav2_controller,
//! dwb_core and dwb_critics, nav2_navfn_planner, nav2_smac_planner, nav2_costmap_2d,
//! nav2_amcl). The ROS 1 names follow Nav2's migration guides (DWA → DWB, move_base →
//! controller_server's progress checker, amcl's renames); the ROS 1 name is relative to the
//! prefix [`super::nav2`] gives the role (`DWAPlannerROS/`, `global_costmap/LAYER/`, `amcl/`, ...).

use super::value::{Range, Ty};

/// Which Nav2 node, or plugin inside one, a name belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Nav2Role {
    /// controller_server's own names.
    ControllerServer,
    /// A controller plugin of controller_server (dwb_core::DWBLocalPlanner), and its critics.
    Dwb,
    /// A goal checker plugin (nav2_controller::SimpleGoalChecker).
    GoalChecker,
    /// A progress checker plugin (nav2_controller::SimpleProgressChecker).
    ProgressChecker,
    /// planner_server's own names.
    PlannerServer,
    /// A planner plugin (nav2_navfn_planner or nav2_smac_planner).
    Planner,
    /// A costmap node's own names (global_costmap, local_costmap).
    Costmap,
    /// nav2_costmap_2d::StaticLayer.
    StaticLayer,
    /// nav2_costmap_2d::ObstacleLayer.
    ObstacleLayer,
    /// nav2_costmap_2d::VoxelLayer (the obstacle layer's names and these).
    VoxelLayer,
    /// nav2_costmap_2d::InflationLayer.
    InflationLayer,
    /// One observation source of an obstacle or voxel layer.
    ObservationSource,
    /// amcl.
    Amcl,
}

/// One Nav2 parameter name.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nav2Spec {
    /// The name inside the node's (or plugin's) namespace, `.`-separated as Nav2 writes it.
    pub name: &'static str,
    /// Nav2's default, as text.
    pub default: &'static str,
    /// The ROS 1 name xhab reads it as, `None` when it has no effect in xhab.
    pub ros1: Option<&'static str>,
    pub(crate) ty: Ty,
}

const fn n(name: &'static str, ty: Ty, default: &'static str, ros1: Option<&'static str>) -> Nav2Spec {
    Nav2Spec { name, default, ros1, ty }
}

const B: Ty = Ty::Bool;
const S: Ty = Ty::Str;
const L: Ty = Ty::List;
const F: Ty = Ty::Float(Range::Any);
const F0: Ty = Ty::Float(Range::NonNeg);
const FP: Ty = Ty::Float(Range::Pos);
const P01: Ty = Ty::Float(Range::Within(0.0, 1.0));
const I0: Ty = Ty::Int(Range::NonNeg);
const I1: Ty = Ty::Int(Range::AtLeast(1.0));
const NO: Option<&str> = None;

/// Names every ROS 2 node has.
const COMMON: &[Nav2Spec] = &[n("use_sim_time", B, "false", NO)];

const CONTROLLER_SERVER: &[Nav2Spec] = &[
    n("controller_frequency", FP, "20.0", Some("controller_frequency")),
    n("min_x_velocity_threshold", F0, "0.0001", NO),
    n("min_y_velocity_threshold", F0, "0.0001", NO),
    n("min_theta_velocity_threshold", F0, "0.0001", NO),
    n("failure_tolerance", F, "0.0", NO),
    n("progress_checker_plugin", S, "progress_checker", NO),
    n("progress_checker_plugins", L, "[progress_checker]", NO),
    n("goal_checker_plugins", L, "[goal_checker]", NO),
    n("controller_plugins", L, "[FollowPath]", NO),
    n("odom_topic", S, "odom", NO),
    n("odom_duration", F0, "0.3", NO),
    n("speed_limit_topic", S, "speed_limit", NO),
    n("enable_stamped_cmd_vel", B, "true", NO),
    n("use_realtime_priority", B, "false", NO),
    n("publish_zero_velocity", B, "true", NO),
    n("costmap_update_timeout", F0, "0.3", NO),
    n("bond_heartbeat_period", F0, "0.1", NO),
];

const DWB: &[Nav2Spec] = &[
    n("plugin", S, "(required)", NO),
    n("max_vel_x", F0, "0.0", Some("max_vel_x")),
    n("min_vel_x", F, "0.0", Some("min_vel_x")),
    n("max_vel_y", F, "0.0", NO),
    n("min_vel_y", F, "0.0", NO),
    n("max_vel_theta", F0, "0.0", Some("max_vel_theta")),
    n("max_speed_xy", F0, "0.0", Some("max_vel_trans")),
    n("min_speed_xy", F0, "0.0", Some("min_vel_trans")),
    n("min_speed_theta", F0, "0.0", Some("min_vel_theta")),
    n("acc_lim_x", F0, "0.0", Some("acc_lim_x")),
    n("acc_lim_y", F0, "0.0", NO),
    n("acc_lim_theta", F0, "0.0", Some("acc_lim_theta")),
    n("decel_lim_x", F, "0.0", NO),
    n("decel_lim_y", F, "0.0", NO),
    n("decel_lim_theta", F, "0.0", NO),
    n("vx_samples", I1, "20", Some("vx_samples")),
    n("vy_samples", I0, "5", NO),
    n("vtheta_samples", I1, "20", Some("vth_samples")),
    n("sim_time", FP, "1.7", Some("sim_time")),
    n("linear_granularity", FP, "0.5", Some("sim_granularity")),
    n("angular_granularity", FP, "0.025", NO),
    n("include_last_point", B, "true", NO),
    n("discretize_by_time", B, "false", NO),
    n("time_granularity", FP, "0.5", NO),
    n("transform_tolerance", F0, "0.1", NO),
    n("xy_goal_tolerance", F0, "0.25", NO),
    n("trans_stopped_velocity", F0, "0.25", NO),
    n("short_circuit_trajectory_evaluation", B, "true", NO),
    n("stateful", B, "true", NO),
    n("prune_plan", B, "true", NO),
    n("prune_distance", F0, "2.0", NO),
    n("forward_prune_distance", F0, "2.0", NO),
    n("shorten_transformed_plan", B, "true", NO),
    n("debug_trajectory_details", B, "false", NO),
    n("publish_evaluation", B, "true", NO),
    n("publish_global_plan", B, "true", NO),
    n("publish_transformed_plan", B, "true", NO),
    n("publish_local_plan", B, "true", NO),
    n("publish_trajectories", B, "true", NO),
    n("publish_cost_grid_pc", B, "false", NO),
    n("marker_lifetime", F0, "0.1", NO),
    n("default_critic_namespaces", L, "[dwb_critics]", NO),
    n("critics", L, "(required)", NO),
    n("trajectory_generator_name", S, "dwb_plugins::StandardTrajectoryGenerator", NO),
    n("goal_checker_name", S, "dwb_plugins::SimpleGoalChecker", NO),
    // Critics: DWA's biases (xhab, like DWB, scores distances in cells).
    n("PathDist.scale", F0, "32.0", Some("path_distance_bias")),
    n("GoalDist.scale", F0, "24.0", Some("goal_distance_bias")),
    n("BaseObstacle.scale", F0, "0.02", Some("occdist_scale")),
    n("PathAlign.forward_point_distance", F, "0.325", Some("forward_point_distance")),
    n("PathAlign.scale", F0, "32.0", NO),
    n("GoalAlign.scale", F0, "24.0", NO),
    n("GoalAlign.forward_point_distance", F, "0.325", NO),
    n("RotateToGoal.scale", F0, "32.0", NO),
    n("RotateToGoal.slowing_factor", F0, "5.0", NO),
    n("RotateToGoal.lookahead_time", F, "-1.0", NO),
    n("RotateToGoal.xy_goal_tolerance", F0, "0.25", NO),
    n("RotateToGoal.trans_stopped_velocity", F0, "0.25", NO),
    n("Oscillation.scale", F0, "1.0", NO),
    n("Oscillation.oscillation_reset_dist", F0, "0.05", NO),
    n("Oscillation.oscillation_reset_angle", F0, "0.2", NO),
    n("Oscillation.oscillation_reset_time", F, "-1.0", NO),
    n("Oscillation.x_only_threshold", F0, "0.05", NO),
    n("BaseObstacle.sum_scores", B, "false", NO),
    n("ObstacleFootprint.scale", F0, "1.0", NO),
    n("ObstacleFootprint.sum_scores", B, "false", NO),
    n("Twirling.scale", F0, "0.0", NO),
    n("PreferForward.scale", F0, "1.0", NO),
    n("PreferForward.penalty", F0, "1.0", NO),
    n("PreferForward.strafe_x", F0, "0.1", NO),
    n("PreferForward.strafe_theta", F0, "0.2", NO),
    n("PreferForward.theta_scale", F0, "10.0", NO),
    n("PathDist.aggregation_type", S, "last", NO),
    n("GoalDist.aggregation_type", S, "last", NO),
    n("PathAlign.aggregation_type", S, "last", NO),
    n("GoalAlign.aggregation_type", S, "last", NO),
];

const GOAL_CHECKER: &[Nav2Spec] = &[
    n("plugin", S, "(required)", NO),
    n("xy_goal_tolerance", F0, "0.25", Some("xy_goal_tolerance")),
    n("yaw_goal_tolerance", F0, "0.25", NO),
    n("stateful", B, "true", NO),
    n("trans_stopped_velocity", F0, "0.25", NO),
    n("rot_stopped_velocity", F0, "0.25", NO),
];

const PROGRESS_CHECKER: &[Nav2Spec] = &[
    n("plugin", S, "(required)", NO),
    n("required_movement_radius", F0, "0.5", Some("oscillation_distance")),
    n("movement_time_allowance", F0, "10.0", Some("oscillation_timeout")),
    n("required_movement_angle", F0, "0.5", NO),
];

const PLANNER_SERVER: &[Nav2Spec] = &[
    // A warning threshold in Nav2: how often to replan is the behaviour tree's.
    n("expected_planner_frequency", F0, "1.0", NO),
    n("planner_plugins", L, "[GridBased]", NO),
    n("costmap_update_timeout", F0, "1.0", NO),
    n("bond_heartbeat_period", F0, "0.1", NO),
];

const PLANNER: &[Nav2Spec] = &[
    n("plugin", S, "(required)", NO),
    n("tolerance", F0, "0.5", Some("default_tolerance")),
    // Inverted into global_planner's use_dijkstra.
    n("use_astar", B, "false", Some("use_dijkstra")),
    n("allow_unknown", B, "true", NO),
    n("use_final_approach_orientation", B, "false", NO),
    n("downsample_costmap", B, "false", NO),
    n("downsampling_factor", I1, "1", NO),
    n("max_iterations", Ty::Int(Range::AtLeast(-1.0)), "1000000", NO),
    n("max_on_approach_iterations", Ty::Int(Range::AtLeast(-1.0)), "1000", NO),
    n("max_planning_time", F0, "2.0", NO),
    n("cost_travel_multiplier", F0, "2.0", NO),
    n("terminal_checking_interval", I1, "5000", NO),
    n("smoother.max_iterations", I1, "1000", NO),
    n("smoother.w_smooth", F0, "0.3", NO),
    n("smoother.w_data", F0, "0.2", NO),
    n("smoother.tolerance", F0, "1e-10", NO),
];

const COSTMAP: &[Nav2Spec] = &[
    n("update_frequency", F0, "5.0", NO),
    n("publish_frequency", F0, "1.0", NO),
    n("global_frame", S, "map", NO),
    n("robot_base_frame", S, "base_link", NO),
    n("transform_tolerance", F0, "0.3", NO),
    n("initial_transform_timeout", F0, "60.0", NO),
    n("width", FP, "5", Some("width")),
    n("height", FP, "5", Some("height")),
    n("resolution", FP, "0.1", NO),
    n("origin_x", F, "0.0", NO),
    n("origin_y", F, "0.0", NO),
    n("rolling_window", B, "false", NO),
    n("track_unknown_space", B, "false", Some("track_unknown_space")),
    n("always_send_full_costmap", B, "false", NO),
    n("footprint", Ty::Footprint, "[]", Some("footprint")),
    n("robot_radius", F0, "0.1", Some("robot_radius")),
    n("footprint_padding", F0, "0.01", Some("footprint_padding")),
    n("plugins", L, "[static_layer, obstacle_layer, inflation_layer]", NO),
    n("filters", L, "[]", NO),
    n("lethal_cost_threshold", Ty::Int(Range::Within(0.0, 100.0)), "100", Some("lethal_cost_threshold")),
    n("unknown_cost_value", Ty::Int(Range::Within(-1.0, 255.0)), "255", NO),
    n("trinary_costmap", B, "true", NO),
    n("use_maximum", B, "false", NO),
    n("map_topic", S, "map", NO),
    n("map_vis_z", F, "0.0", NO),
    n("subscribe_to_updates", B, "false", NO),
];

const STATIC_LAYER: &[Nav2Spec] = &[
    n("plugin", S, "nav2_costmap_2d::StaticLayer", NO),
    n("enabled", B, "true", NO),
    n("subscribe_to_updates", B, "false", NO),
    n("map_subscribe_transient_local", B, "true", NO),
    n("transform_tolerance", F0, "0.0", NO),
    n("map_topic", S, "map", NO),
    n("footprint_clearing_enabled", B, "false", NO),
    n("restore_cleared_footprint", B, "true", NO),
];

const OBSTACLE_LAYER: &[Nav2Spec] = &[
    n("plugin", S, "nav2_costmap_2d::ObstacleLayer", NO),
    n("enabled", B, "true", NO),
    n("footprint_clearing_enabled", B, "true", NO),
    n("min_obstacle_height", F, "0.0", NO),
    n("max_obstacle_height", F, "2.0", NO),
    n("combination_method", Ty::Int(Range::Within(0.0, 2.0)), "1", NO),
    n("observation_sources", S, "", Some("observation_sources")),
    n("transform_tolerance", F0, "0.2", NO),
    n("tf_filter_tolerance", F0, "0.05", NO),
];

const VOXEL_ONLY: &[Nav2Spec] = &[
    n("origin_z", F, "0.0", NO),
    n("z_resolution", FP, "0.2", NO),
    n("z_voxels", I1, "10", NO),
    n("mark_threshold", I0, "0", NO),
    n("unknown_threshold", I0, "15", NO),
    n("publish_voxel_map", B, "false", NO),
];

const INFLATION_LAYER: &[Nav2Spec] = &[
    n("plugin", S, "nav2_costmap_2d::InflationLayer", NO),
    n("enabled", B, "true", NO),
    n("inflation_radius", F0, "0.55", Some("inflation_radius")),
    n("cost_scaling_factor", F0, "10.0", Some("cost_scaling_factor")),
    n("inflate_unknown", B, "false", NO),
    n("inflate_around_unknown", B, "false", NO),
];

const OBSERVATION_SOURCE: &[Nav2Spec] = &[
    n("topic", S, "", NO),
    n("sensor_frame", S, "", NO),
    n("observation_persistence", F0, "0.0", NO),
    n("expected_update_rate", F0, "0.0", NO),
    n("data_type", S, "LaserScan", Some("data_type")),
    n("min_obstacle_height", F, "0.0", NO),
    n("max_obstacle_height", F, "0.0", NO),
    n("inf_is_valid", B, "false", Some("inf_is_valid")),
    n("marking", B, "true", Some("marking")),
    n("clearing", B, "false", Some("clearing")),
    n("obstacle_max_range", F0, "2.5", Some("obstacle_range")),
    n("obstacle_min_range", F0, "0.0", NO),
    n("raytrace_max_range", F0, "3.0", Some("raytrace_range")),
    n("raytrace_min_range", F0, "0.0", NO),
];

const AMCL: &[Nav2Spec] = &[
    n("alpha1", F0, "0.2", Some("odom_alpha1")),
    n("alpha2", F0, "0.2", Some("odom_alpha2")),
    n("alpha3", F0, "0.2", Some("odom_alpha3")),
    n("alpha4", F0, "0.2", Some("odom_alpha4")),
    n("alpha5", F0, "0.2", NO),
    n("min_particles", I1, "500", Some("min_particles")),
    n("max_particles", I1, "2000", Some("max_particles")),
    n("pf_err", Ty::Float(Range::Open(0.0, 1.0)), "0.05", Some("kld_err")),
    n("pf_z", Ty::Float(Range::Open(0.0, 1.0)), "0.99", Some("kld_z")),
    n("update_min_d", F0, "0.25", Some("update_min_d")),
    n("update_min_a", F0, "0.2", Some("update_min_a")),
    n("resample_interval", I1, "1", Some("resample_interval")),
    n("recovery_alpha_slow", P01, "0.0", Some("recovery_alpha_slow")),
    n("recovery_alpha_fast", P01, "0.0", Some("recovery_alpha_fast")),
    n("laser_model_type", S, "likelihood_field", Some("laser_model_type")),
    n("laser_max_range", F, "100.0", NO),
    n("laser_min_range", F, "-1.0", NO),
    n("max_beams", Ty::Int(Range::AtLeast(2.0)), "60", Some("laser_max_beams")),
    n("z_hit", P01, "0.5", Some("laser_z_hit")),
    n("z_short", P01, "0.05", Some("laser_z_short")),
    n("z_max", P01, "0.05", Some("laser_z_max")),
    n("z_rand", P01, "0.5", Some("laser_z_rand")),
    n("sigma_hit", FP, "0.2", Some("laser_sigma_hit")),
    n("lambda_short", F0, "0.1", Some("laser_lambda_short")),
    n("laser_likelihood_max_dist", F0, "2.0", Some("laser_likelihood_max_dist")),
    n("do_beamskip", B, "false", Some("do_beamskip")),
    n("beam_skip_distance", F0, "0.5", Some("beam_skip_distance")),
    n("beam_skip_threshold", P01, "0.3", Some("beam_skip_threshold")),
    n("beam_skip_error_threshold", P01, "0.9", Some("beam_skip_error_threshold")),
    // Read as odom_model_type (diff).
    n("robot_model_type", S, "nav2_amcl::DifferentialMotionModel", Some("odom_model_type")),
    n("base_frame_id", S, "base_footprint", NO),
    n("global_frame_id", S, "map", NO),
    n("odom_frame_id", S, "odom", NO),
    n("scan_topic", S, "scan", NO),
    n("map_topic", S, "map", NO),
    n("tf_broadcast", B, "true", NO),
    n("transform_tolerance", F0, "1.0", NO),
    n("save_pose_rate", F, "0.5", NO),
    n("set_initial_pose", B, "false", NO),
    n("always_reset_initial_pose", B, "false", NO),
    n("first_map_only", B, "false", NO),
    n("freespace_downsampling", B, "false", NO),
    n("initial_pose.x", F, "0.0", NO),
    n("initial_pose.y", F, "0.0", NO),
    n("initial_pose.z", F, "0.0", NO),
    n("initial_pose.yaw", F, "0.0", NO),
    n("bond_heartbeat_period", F0, "0.1", NO),
];

/// Nav2 nodes xhab knows and has no counterpart of parameters for: their keys are reported as
/// without effect, never as unknown.
pub const OTHER_NODES: &[&str] = &[
    "bt_navigator",
    "bt_navigator_navigate_through_poses_rclcpp_node",
    "bt_navigator_navigate_to_pose_rclcpp_node",
    "controller_server_rclcpp_node",
    "planner_server_rclcpp_node",
    "map_server",
    "map_saver",
    "smoother_server",
    "behavior_server",
    "recoveries_server",
    "waypoint_follower",
    "velocity_smoother",
    "collision_monitor",
    "docking_server",
    "route_server",
    "robot_state_publisher",
    "lifecycle_manager",
    "lifecycle_manager_navigation",
    "lifecycle_manager_localization",
    "slam_toolbox",
    "loopback_simulator",
];

/// Every parameter name of `role`.
pub fn nav2_specs(role: Nav2Role) -> &'static [Nav2Spec] {
    match role {
        Nav2Role::ControllerServer => CONTROLLER_SERVER,
        Nav2Role::Dwb => DWB,
        Nav2Role::GoalChecker => GOAL_CHECKER,
        Nav2Role::ProgressChecker => PROGRESS_CHECKER,
        Nav2Role::PlannerServer => PLANNER_SERVER,
        Nav2Role::Planner => PLANNER,
        Nav2Role::Costmap => COSTMAP,
        Nav2Role::StaticLayer => STATIC_LAYER,
        Nav2Role::ObstacleLayer => OBSTACLE_LAYER,
        Nav2Role::VoxelLayer => VOXEL_ONLY,
        Nav2Role::InflationLayer => INFLATION_LAYER,
        Nav2Role::ObservationSource => OBSERVATION_SOURCE,
        Nav2Role::Amcl => AMCL,
    }
}

/// The spec of `name` in `role` (a voxel layer also knows the obstacle layer's names; a
/// node's own names include `use_sim_time`).
pub fn nav2_spec(role: Nav2Role, name: &str) -> Option<&'static Nav2Spec> {
    nav2_names(role).find(|s| s.name == name)
}

/// Every spec `role` knows, including the inherited ones.
pub(crate) fn nav2_names(role: Nav2Role) -> impl Iterator<Item = &'static Nav2Spec> {
    let voxel = if role == Nav2Role::VoxelLayer { OBSTACLE_LAYER } else { &[] };
    let common = if matches!(role, Nav2Role::ControllerServer | Nav2Role::PlannerServer | Nav2Role::Costmap | Nav2Role::Amcl) { COMMON } else { &[] };
    nav2_specs(role).iter().chain(voxel).chain(common)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_per_role() {
        use Nav2Role::*;
        for role in [ControllerServer, Dwb, GoalChecker, ProgressChecker, PlannerServer, Planner, Costmap, StaticLayer, ObstacleLayer, VoxelLayer, InflationLayer, ObservationSource, Amcl] {
            let mut seen = std::collections::HashSet::new();
            for s in nav2_names(role) {
                assert!(seen.insert(s.name), "{role:?}: {} twice", s.name);
            }
        }
        assert_eq!(nav2_spec(Nav2Role::VoxelLayer, "observation_sources").and_then(|s| s.ros1), Some("observation_sources"));
    }
}
