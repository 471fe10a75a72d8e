//! Every parameter name of the ROS 1 (noetic) nodes xhab stands in for, with its type, range
//! and noetic code default: move_base, costmap_2d (the costmap and its static, obstacle, voxel
//! and inflation layers, and the obstacle layer's observation sources), dwa_local_planner,
//! base_local_planner's TrajectoryPlannerROS, global_planner, navfn and amcl.
//!
//! Names, defaults and ranges come from the noetic sources (`param(...)` calls and the
//! dynamic_reconfigure `.cfg` files). Ranges are those ROS needs to work (a positive period, a
//! probability in [0, 1]), not the sliders' limits of dynamic_reconfigure.
//! Whether a name takes effect is decided where it is read ([`super::load`]); a known name that
//! nothing reads is reported as having no effect.

use super::value::{Range, Ty};

/// Which node (or part of one) a parameter belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RosNode {
    /// move_base's own parameters (its private namespace).
    MoveBase,
    /// A costmap_2d costmap (`global_costmap/`, `local_costmap/`).
    Costmap,
    /// costmap_2d::StaticLayer.
    StaticLayer,
    /// costmap_2d::ObstacleLayer.
    ObstacleLayer,
    /// costmap_2d::VoxelLayer (the obstacle layer's names and these).
    VoxelLayer,
    /// costmap_2d::InflationLayer.
    InflationLayer,
    /// One of an obstacle layer's `observation_sources`.
    ObservationSource,
    /// dwa_local_planner (`DWAPlannerROS/`).
    Dwa,
    /// base_local_planner's trajectory rollout planner (`TrajectoryPlannerROS/`).
    TrajectoryPlanner,
    /// global_planner (`GlobalPlanner/`).
    GlobalPlanner,
    /// navfn (`NavfnROS/`).
    Navfn,
    /// amcl.
    Amcl,
}

/// What xhab does with a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    /// Read into [`crate::navigator::NavParams`].
    Used,
    /// Known to ROS, without effect in xhab.
    Ignored,
    /// An old name of the parameter named here (read in its place, with a warning).
    Renamed(&'static str),
    /// xhab's own parameter, read in the namespace of the ROS node it belongs with.
    Extension,
}

/// One parameter name.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamSpec {
    /// The name inside the node's namespace.
    pub name: &'static str,
    /// ROS noetic's code default, as text (xhab's own default for extensions).
    pub default: &'static str,
    /// What xhab does with it.
    pub effect: Effect,
    pub(crate) ty: Ty,
}

const fn p(name: &'static str, ty: Ty, default: &'static str, effect: Effect) -> ParamSpec {
    ParamSpec { name, default, effect, ty }
}

use Effect::{Extension as X, Ignored as I, Used as U};
const B: Ty = Ty::Bool;
const S: Ty = Ty::Str;
const F: Ty = Ty::Float(Range::Any);
const F0: Ty = Ty::Float(Range::NonNeg);
const FP: Ty = Ty::Float(Range::Pos);
const P01: Ty = Ty::Float(Range::Within(0.0, 1.0));
const I0: Ty = Ty::Int(Range::NonNeg);
const I1: Ty = Ty::Int(Range::AtLeast(1.0));

const MOVE_BASE: &[ParamSpec] = &[
    p("base_global_planner", S, "navfn/NavfnROS", U),
    p("base_local_planner", S, "base_local_planner/TrajectoryPlannerROS", U),
    p("planner_frequency", F0, "0.0", U),
    p("controller_frequency", FP, "20.0", U),
    p("planner_patience", F0, "5.0", U),
    p("controller_patience", F0, "15.0", U),
    p("max_planning_retries", Ty::Int(Range::AtLeast(-1.0)), "-1", U),
    p("oscillation_timeout", F0, "0.0", U),
    p("oscillation_distance", F0, "0.5", U),
    p("recovery_behavior_enabled", B, "true", U),
    p("clearing_rotation_allowed", B, "true", U),
    p("conservative_reset_dist", F0, "3.0", I),
    p("clearing_radius", F0, "local_costmap/circumscribed_radius", I),
    p("shutdown_costmaps", B, "false", I),
    p("make_plan_clear_costmap", B, "true", I),
    p("make_plan_add_unreachable_goal", B, "true", I),
    p("recovery_behaviors", Ty::List, "[conservative_reset, rotate_recovery, aggressive_reset]", I),
    p("restore_defaults", B, "false", I),
    // costmap_2d finds these by searchParam from the costmaps' namespaces up to move_base's.
    p("footprint", Ty::Footprint, "[]", U),
    p("robot_radius", Ty::Float(Range::NonNeg), "0.46", U),
    p("max_recoveries", I0, "4", X),
    p("recovery_rotation_speed", FP, "1.0", X),
];

const COSTMAP: &[ParamSpec] = &[
    p("global_frame", S, "map", I),
    p("robot_base_frame", S, "base_link", I),
    p("transform_tolerance", F0, "0.3", I),
    p("update_frequency", F0, "5.0", I),
    p("publish_frequency", F0, "0.0", I),
    p("width", FP, "10", U),
    p("height", FP, "10", U),
    p("resolution", FP, "0.05", I),
    p("origin_x", F, "0.0", I),
    p("origin_y", F, "0.0", I),
    p("rolling_window", B, "false", I),
    p("track_unknown_space", B, "false", U),
    p("always_send_full_costmap", B, "false", I),
    p("footprint", Ty::Footprint, "[]", U),
    p("robot_radius", Ty::Float(Range::NonNeg), "0.46", U),
    p("footprint_padding", F0, "0.01", U),
    p("footprint_topic", S, "footprint", I),
    p("published_footprint_topic", S, "footprint", I),
    p("plugins", Ty::List, "(pre-Hydro layers)", U),
    // Pre-Hydro names, moved into the layers when `plugins` is absent (and copied into them
    // when it is present).
    p("static_map", B, "false", I),
    p("map_type", S, "costmap", I),
    p("map_topic", S, "map", I),
    p("unknown_cost_value", Ty::Int(Range::Within(-1.0, 255.0)), "-1", I),
    p("lethal_cost_threshold", Ty::Int(Range::Within(0.0, 100.0)), "100", U),
    p("observation_sources", S, "", U),
    p("max_obstacle_height", F0, "2.0", I),
    p("obstacle_range", F0, "2.5", U),
    p("raytrace_range", F0, "3.0", U),
    p("origin_z", F, "0.0", I),
    p("z_resolution", FP, "0.2", I),
    p("z_voxels", I1, "10", I),
    p("mark_threshold", I0, "0", I),
    p("unknown_threshold", I0, "15", I),
    p("publish_voxel_map", B, "false", I),
    p("inflation_radius", F0, "0.55", U),
    p("cost_scaling_factor", F0, "10.0", U),
    // move_base reads these two from local_costmap/.
    p("inscribed_radius", F0, "0.325", I),
    p("circumscribed_radius", F0, "0.46", I),
    p("restore_defaults", B, "false", I),
];

const STATIC_LAYER: &[ParamSpec] = &[
    p("enabled", B, "true", I),
    p("map_topic", S, "map", I),
    p("first_map_only", B, "false", I),
    p("subscribe_to_updates", B, "false", I),
    p("track_unknown_space", B, "true", U),
    p("use_maximum", B, "false", I),
    p("lethal_cost_threshold", Ty::Int(Range::Within(0.0, 100.0)), "100", U),
    p("unknown_cost_value", Ty::Int(Range::Within(-1.0, 255.0)), "-1", I),
    p("trinary_costmap", B, "true", I),
];

const OBSTACLE_LAYER: &[ParamSpec] = &[
    p("enabled", B, "true", I),
    p("footprint_clearing_enabled", B, "true", I),
    p("max_obstacle_height", F0, "2.0", I),
    p("combination_method", Ty::Int(Range::Within(0.0, 1.0)), "1", I),
    p("track_unknown_space", B, "false", I),
    p("transform_tolerance", F0, "0.2", I),
    p("observation_sources", S, "", U),
    p("obstacle_range", F0, "2.5", U),
    p("raytrace_range", F0, "3.0", U),
];

const VOXEL_ONLY: &[ParamSpec] = &[
    p("origin_z", F, "0.0", I),
    p("z_resolution", FP, "0.2", I),
    p("z_voxels", I1, "10", I),
    p("mark_threshold", I0, "0", I),
    p("unknown_threshold", I0, "15", I),
    p("publish_voxel_map", B, "false", I),
];

const INFLATION_LAYER: &[ParamSpec] = &[
    p("enabled", B, "true", I),
    p("inflation_radius", F0, "0.55", U),
    p("cost_scaling_factor", F0, "10.0", U),
    p("inflate_unknown", B, "false", I),
];

const OBSERVATION_SOURCE: &[ParamSpec] = &[
    p("topic", S, "(the source's name)", I),
    p("sensor_frame", S, "", I),
    p("observation_persistence", F0, "0.0", I),
    p("expected_update_rate", F0, "0.0", I),
    p("data_type", S, "PointCloud", U),
    p("min_obstacle_height", F, "0.0", I),
    p("max_obstacle_height", F, "2.0", I),
    p("inf_is_valid", B, "false", U),
    p("clearing", B, "false", U),
    p("marking", B, "true", U),
    p("obstacle_range", F0, "2.5", U),
    p("raytrace_range", F0, "3.0", U),
];

const DWA: &[ParamSpec] = &[
    // base_local_planner's LocalPlannerLimits, shared by the local planners.
    p("max_vel_trans", F0, "0.55", U),
    p("min_vel_trans", F0, "0.1", U),
    p("max_vel_x", F0, "0.55", U),
    p("min_vel_x", F, "0.0", U),
    p("max_vel_y", F, "0.1", I),
    p("min_vel_y", F, "-0.1", I),
    p("max_vel_theta", F0, "1.0", U),
    p("min_vel_theta", F0, "0.4", U),
    p("acc_lim_x", F0, "2.5", U),
    p("acc_lim_y", F0, "2.5", I),
    p("acc_lim_theta", F0, "3.2", U),
    p("acc_lim_trans", F0, "0.1", I),
    p("prune_plan", B, "false", I),
    p("xy_goal_tolerance", F0, "0.1", U),
    p("yaw_goal_tolerance", F0, "0.1", I),
    p("trans_stopped_vel", F0, "0.1", I),
    p("theta_stopped_vel", F0, "0.1", I),
    // Renamed in Indigo; noetic warns and no longer reads the old names.
    p("max_trans_vel", F0, "0.55", Effect::Renamed("max_vel_trans")),
    p("min_trans_vel", F0, "0.1", Effect::Renamed("min_vel_trans")),
    p("max_rot_vel", F0, "1.0", Effect::Renamed("max_vel_theta")),
    p("min_rot_vel", F0, "0.4", Effect::Renamed("min_vel_theta")),
    p("acc_limit_trans", F0, "0.1", Effect::Renamed("acc_lim_trans")),
    p("rot_stopped_vel", F0, "0.1", Effect::Renamed("theta_stopped_vel")),
    // DWAPlanner.cfg.
    p("sim_time", FP, "1.7", U),
    p("sim_granularity", FP, "0.025", U),
    p("angular_sim_granularity", FP, "0.1", I),
    p("path_distance_bias", F0, "0.6", U),
    p("goal_distance_bias", F0, "0.8", U),
    p("occdist_scale", F0, "0.01", U),
    p("twirling_scale", F0, "0.0", I),
    p("stop_time_buffer", F0, "0.2", I),
    p("oscillation_reset_dist", F0, "0.05", I),
    p("oscillation_reset_angle", F0, "0.2", I),
    p("forward_point_distance", F, "0.325", U),
    p("scaling_speed", F0, "0.25", I),
    p("max_scaling_factor", F0, "0.2", I),
    p("vx_samples", I1, "3", U),
    p("vy_samples", I0, "10", I),
    p("vth_samples", I1, "20", U),
    p("use_dwa", B, "true", I),
    p("restore_defaults", B, "false", I),
    // dwa_planner(_ros).cpp.
    p("controller_frequency", FP, "(move_base's, 20.0)", U),
    p("sum_scores", B, "false", I),
    p("publish_cost_grid_pc", B, "false", I),
    p("publish_traj_pc", B, "false", I),
    p("global_frame_id", S, "odom", I),
    p("cheat_factor", F0, "1.0", I),
    p("latch_xy_goal_tolerance", B, "false", I),
    // xhab's own.
    p("rotate_first_angle", F0, "1.0", X),
    p("local_goal_distance", FP, "1.5", X),
];

const TRAJECTORY_PLANNER: &[ParamSpec] = &[
    p("prune_plan", B, "true", I),
    p("yaw_goal_tolerance", F0, "0.05", I),
    p("xy_goal_tolerance", F0, "0.10", U),
    p("acc_lim_x", F0, "2.5", U),
    p("acc_lim_y", F0, "2.5", I),
    p("acc_lim_theta", F0, "3.2", U),
    // rotate_recovery reads this one from TrajectoryPlannerROS's namespace.
    p("acc_lim_th", F0, "3.2", I),
    p("stop_time_buffer", F0, "0.2", I),
    p("latch_xy_goal_tolerance", B, "false", I),
    p("controller_frequency", FP, "(move_base's, 20.0)", U),
    p("sim_time", FP, "1.0", U),
    p("sim_granularity", FP, "0.025", U),
    p("angular_sim_granularity", FP, "sim_granularity", I),
    p("vx_samples", I1, "3", U),
    p("vtheta_samples", I1, "20", U),
    p("path_distance_bias", F0, "0.6", I),
    p("goal_distance_bias", F0, "0.6", I),
    p("pdist_scale", F0, "0.6", Effect::Renamed("path_distance_bias")),
    p("gdist_scale", F0, "0.6", Effect::Renamed("goal_distance_bias")),
    p("occdist_scale", F0, "0.01", I),
    p("meter_scoring", B, "false", I),
    p("heading_lookahead", F0, "0.325", I),
    p("oscillation_reset_dist", F0, "0.05", I),
    p("escape_reset_dist", F0, "0.10", I),
    p("escape_reset_theta", F0, "pi/4", I),
    p("holonomic_robot", B, "true", I),
    p("max_vel_x", F0, "0.5", U),
    p("min_vel_x", F, "0.1", U),
    p("max_vel_theta", F0, "1.0", U),
    p("min_vel_theta", F, "-1.0", I),
    p("max_rotational_vel", F0, "1.0", U),
    p("min_in_place_vel_theta", F0, "0.4", I),
    p("min_in_place_rotational_vel", F0, "0.4", Effect::Renamed("min_in_place_vel_theta")),
    p("escape_vel", F, "-0.1", I),
    p("backup_vel", F, "-0.1", Effect::Renamed("escape_vel")),
    p("world_model", S, "costmap", I),
    p("dwa", B, "true", I),
    p("heading_scoring", B, "false", I),
    p("heading_scoring_timestep", F0, "0.8", I),
    p("simple_attractor", B, "false", I),
    p("y_vels", Ty::Any, "-0.3,-0.1,0.1,0.3", I),
    p("point_grid/max_sensor_range", F0, "2.0", I),
    p("point_grid/min_pt_separation", F0, "0.01", I),
    p("point_grid/max_obstacle_height", F0, "2.0", I),
    p("point_grid/grid_resolution", FP, "0.2", I),
    p("restore_defaults", B, "false", I),
];

const GLOBAL_PLANNER: &[ParamSpec] = &[
    p("old_navfn_behavior", B, "false", I),
    p("use_quadratic", B, "true", I),
    p("use_dijkstra", B, "true", U),
    p("use_grid_path", B, "false", I),
    p("allow_unknown", B, "true", I),
    p("planner_window_x", F0, "0.0", I),
    p("planner_window_y", F0, "0.0", I),
    p("default_tolerance", F0, "0.0", U),
    p("publish_scale", I1, "100", I),
    p("outline_map", B, "true", I),
    p("lethal_cost", Ty::Int(Range::Within(1.0, 255.0)), "253", I),
    p("neutral_cost", Ty::Int(Range::Within(1.0, 255.0)), "50", U),
    p("cost_factor", FP, "3.0", U),
    p("publish_potential", B, "true", I),
    p("orientation_mode", Ty::Int(Range::Within(0.0, 6.0)), "1", I),
    p("orientation_window_size", I1, "1", I),
    p("visualize_potential", B, "false", I),
    p("restore_defaults", B, "false", I),
    p("smooth_max_cost", Ty::Int(Range::Within(0.0, 252.0)), "60", X),
];

const NAVFN: &[ParamSpec] = &[
    p("visualize_potential", B, "false", I),
    p("allow_unknown", B, "true", I),
    p("planner_window_x", F0, "0.0", I),
    p("planner_window_y", F0, "0.0", I),
    p("default_tolerance", F0, "0.0", U),
    p("smooth_max_cost", Ty::Int(Range::Within(0.0, 252.0)), "60", X),
];

const AMCL: &[ParamSpec] = &[
    p("min_particles", I1, "100", U),
    p("max_particles", I1, "5000", U),
    p("kld_err", Ty::Float(Range::Open(0.0, 1.0)), "0.01", U),
    p("kld_z", Ty::Float(Range::Open(0.0, 1.0)), "0.99", U),
    p("update_min_d", F0, "0.2", U),
    p("update_min_a", F0, "pi/6", U),
    p("resample_interval", I1, "2", U),
    p("transform_tolerance", F0, "0.1", I),
    p("recovery_alpha_slow", P01, "0.001", U),
    p("recovery_alpha_fast", P01, "0.1", U),
    p("do_beamskip", B, "false", U),
    p("beam_skip_distance", F0, "0.5", U),
    p("beam_skip_threshold", P01, "0.3", U),
    p("beam_skip_error_threshold", P01, "0.9", U),
    p("tf_broadcast", B, "true", I),
    p("force_update_after_initialpose", B, "false", I),
    p("force_update_after_set_map", B, "false", I),
    p("gui_publish_rate", F, "-1.0", I),
    p("save_pose_rate", F, "0.5", I),
    p("use_map_topic", B, "false", I),
    p("first_map_only", B, "false", I),
    p("selective_resampling", B, "false", I),
    p("laser_min_range", F, "-1.0", I),
    p("laser_max_range", F, "-1.0", I),
    p("laser_max_beams", Ty::Int(Range::AtLeast(2.0)), "30", U),
    p("laser_z_hit", P01, "0.95", U),
    p("laser_z_short", P01, "0.1", U),
    p("laser_z_max", P01, "0.05", U),
    p("laser_z_rand", P01, "0.05", U),
    p("laser_sigma_hit", FP, "0.2", U),
    p("laser_lambda_short", F0, "0.1", U),
    p("laser_likelihood_max_dist", F0, "2.0", U),
    p("laser_model_type", S, "likelihood_field", U),
    p("odom_model_type", S, "diff", U),
    p("odom_alpha1", F0, "0.2", U),
    p("odom_alpha2", F0, "0.2", U),
    p("odom_alpha3", F0, "0.2", U),
    p("odom_alpha4", F0, "0.2", U),
    p("odom_alpha5", F0, "0.2", I),
    p("odom_frame_id", S, "odom", I),
    p("base_frame_id", S, "base_link", I),
    p("global_frame_id", S, "map", I),
    p("initial_pose_x", F, "0.0", I),
    p("initial_pose_y", F, "0.0", I),
    p("initial_pose_a", F, "0.0", I),
    p("initial_cov_xx", F0, "0.25", I),
    p("initial_cov_yy", F0, "0.25", I),
    p("initial_cov_aa", F0, "(pi/12)^2", I),
    p("bag_scan_period", F, "-1.0", I),
    p("std_warn_level_x", F0, "0.2", I),
    p("std_warn_level_y", F0, "0.2", I),
    p("std_warn_level_yaw", F0, "0.1", I),
    p("restore_defaults", B, "false", I),
    // xhab's own.
    p("laser_no_return_likelihood", P01, "0.1", X),
];

/// Every parameter name of `node`.
pub fn specs(node: RosNode) -> &'static [ParamSpec] {
    match node {
        RosNode::MoveBase => MOVE_BASE,
        RosNode::Costmap => COSTMAP,
        RosNode::StaticLayer => STATIC_LAYER,
        RosNode::ObstacleLayer => OBSTACLE_LAYER,
        RosNode::VoxelLayer => VOXEL_ONLY,
        RosNode::InflationLayer => INFLATION_LAYER,
        RosNode::ObservationSource => OBSERVATION_SOURCE,
        RosNode::Dwa => DWA,
        RosNode::TrajectoryPlanner => TRAJECTORY_PLANNER,
        RosNode::GlobalPlanner => GLOBAL_PLANNER,
        RosNode::Navfn => NAVFN,
        RosNode::Amcl => AMCL,
    }
}

/// The spec of `name` in `node` (a voxel layer also knows the obstacle layer's names).
pub fn spec(node: RosNode, name: &str) -> Option<&'static ParamSpec> {
    let found = specs(node).iter().find(|s| s.name == name);
    match (found, node) {
        (None, RosNode::VoxelLayer) => spec(RosNode::ObstacleLayer, name),
        _ => found,
    }
}

/// Names of `node` a misspelt `name` may have meant (for "did you mean").
pub(crate) fn names(node: RosNode) -> impl Iterator<Item = &'static str> {
    let voxel = if node == RosNode::VoxelLayer { OBSTACLE_LAYER } else { &[] };
    specs(node).iter().chain(voxel).map(|s| s.name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_per_node_and_renames_point_at_known_names() {
        for node in [
            RosNode::MoveBase,
            RosNode::Costmap,
            RosNode::StaticLayer,
            RosNode::ObstacleLayer,
            RosNode::VoxelLayer,
            RosNode::InflationLayer,
            RosNode::ObservationSource,
            RosNode::Dwa,
            RosNode::TrajectoryPlanner,
            RosNode::GlobalPlanner,
            RosNode::Navfn,
            RosNode::Amcl,
        ] {
            let mut seen = std::collections::HashSet::new();
            for s in specs(node) {
                assert!(seen.insert(s.name), "{node:?}: {} twice", s.name);
                if let Effect::Renamed(to) = s.effect {
                    assert!(spec(node, to).is_some(), "{node:?}: {} renamed to unknown {to}", s.name);
                }
            }
        }
        assert_eq!(spec(RosNode::VoxelLayer, "observation_sources").map(|s| s.effect), Some(Effect::Used));
    }
}
