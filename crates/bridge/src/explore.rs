//! Frontier-based exploration: the robot, under physics with its sensors, builds an occupancy
//! map of a scene it has never seen, going to the nearest reachable frontier until none is
//! left, as users of the original ran a mapping package before navigating.
//!
//! Sensors: the planar lidar (free space all around, walls), the depth camera projected onto
//! the floor plan (obstacles anywhere in the body band, such as table tops above the lidar's
//! plane, and floor seen free), and a ring of downward cliff rays (where the floor ends).
//! The map is built with known poses (the simulator's ground truth); the navigator plans on
//! the map built so far (unknown space counts as free, as move_base with
//! `track_unknown_space: false`).

use serde::{Deserialize, Serialize};
use xhab_nav::costmap::{Costmap, INSCRIBED};
use xhab_nav::frontier::{find_frontiers, frontier_near, nearest_frontier, FrontierParams};
use xhab_nav::mapping::{Mapper, MapperParams};
use xhab_nav::navigator::{NavParams, NavStatus, Navigator};
use xhab_sim::navgrid::NavGrid;
use xhab_sim::robot::{PhysicsError, PhysicsParams, PhysicsScene, RigidRobot, RobotProfile};
use xhab_nav::depth_projection::{project_depth, ProjectionParams};
use xhab_sim::sensors::{CameraParams, Lidar, LidarParams, RayScene, Renderer};
use xhab_types::{OccupancyGrid, Point2, Pose2};

/// How far beyond the scene's grid the map reaches (m).
const MARGIN: f64 = 1.0;

/// Exploration settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExploreParams {
    /// Frontier search.
    pub frontier: FrontierParams,
    /// Occupancy mapping (its resolution is replaced by the scene grid's).
    pub mapper: MapperParams,
    /// Lidar.
    pub lidar: LidarParams,
    /// Time between scans (s, default 0.1 = 10 Hz).
    pub scan_period: f64,
    /// Time between depth images (s, default 0.2 = 5 Hz).
    pub camera_period: f64,
    /// Which depth points are obstacles and which floor.
    pub projection: ProjectionParams,
    /// Cliff rays: this many, on a circle this far beyond the robot's radius (default 16, 0.2 m).
    pub cliff_rays: usize,
    /// Distance of the cliff rays beyond the robot's radius (m, default 0.2).
    pub cliff_distance: f64,
    /// Time between frontier searches while heading for a target (s, default 2).
    pub planner_period: f64,
    /// Exploration ends after this much simulated time (s, default 1800).
    pub max_time: f64,
    /// Physics.
    pub physics: PhysicsParams,
}

impl Default for ExploreParams {
    fn default() -> Self {
        Self {
            frontier: FrontierParams::default(),
            mapper: MapperParams::default(),
            lidar: LidarParams::default(),
            scan_period: 0.1,
            camera_period: 0.2,
            projection: ProjectionParams::default(),
            cliff_rays: 16,
            cliff_distance: 0.2,
            planner_period: 2.0,
            max_time: 1800.0,
            physics: PhysicsParams::default(),
        }
    }
}

/// Why exploration ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExploreEnd {
    /// No reachable frontier is left.
    Done,
    /// The time budget ran out.
    TimeLimit,
    /// The robot left the floor (fell off an edge of the scene).
    Fell,
}

/// What an exploration run produced.
#[derive(Debug, Clone)]
pub struct Exploration {
    /// The map built (the scene grid's cells, and a margin of 1 m around them).
    pub map: OccupancyGrid,
    /// Why it ended.
    pub end: ExploreEnd,
    /// Simulated time (s).
    pub sim_s: f64,
    /// Distance driven (m).
    pub travel_m: f64,
    /// Frontier targets reached.
    pub targets_reached: usize,
    /// Frontier targets given up (aborted by the navigator, then blacklisted).
    pub targets_abandoned: usize,
    /// Ground-truth poses, one per second of simulated time.
    pub trajectory: Vec<Pose2>,
}

/// Why exploration could not start.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExploreError {
    /// The physics world could not be built.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
    /// A parameter is out of range.
    #[error("{0}")]
    Param(String),
    /// The depth camera failed.
    #[error("depth camera: {0}")]
    Render(#[from] xhab_sim::sensors::RenderError),
}

/// What the robot senses with.
pub struct ExploreSensors<'a> {
    /// The scene for lidar and cliff rays.
    pub rays: &'a RayScene,
    /// The depth camera's renderer and parameters, if the robot has one.
    pub camera: Option<(&'a Renderer, CameraParams)>,
}

/// Explores the floor of `grid` from `start` (m, rad) with the robot `profile` and its
/// `sensors`, driven by a navigator with `nav`; seeded (lidar noise).
#[allow(clippy::too_many_arguments)]
pub fn explore(grid: &NavGrid, physics: &PhysicsScene, sensors: &ExploreSensors<'_>, profile: &RobotProfile, nav: &NavParams, p: &ExploreParams, start: Pose2, seed: u64) -> Result<Exploration, ExploreError> {
    let rays = sensors.rays;
    for (name, v) in [("scan_period", p.scan_period), ("camera_period", p.camera_period), ("planner_period", p.planner_period), ("max_time", p.max_time), ("controller_period", nav.dwa.controller_period)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(ExploreError::Param(format!("{name}: must be > 0, got {v}")));
        }
    }
    let mut robot = RigidRobot::new(physics, profile, start, grid.floor_z, &p.physics)?;
    let res = grid.resolution();
    let (w, h) = grid.size();
    let o = grid.origin();
    // The map spans the scene's grid and a margin where cliffs past the floor's edge can be
    // marked; it keeps the grid's cell boundaries.
    let m = (MARGIN / res).ceil() * res;
    let mut mapper = Mapper::new(Point2::new(o.x - m, o.y - m), Point2::new(o.x + w as f64 * res + m, o.y + h as f64 * res + m), MapperParams { resolution: res, ..p.mapper.clone() });
    let mut lidar = Lidar::new(p.lidar.clone(), seed);
    let mut navigator = Navigator::new(nav.clone());
    let period = nav.dwa.controller_period;
    let steps = (period / robot.dt()).round().max(1.0) as usize;
    let (mut scans, mut frames, mut last_search) = (0u64, 0u64, f64::NEG_INFINITY);
    let mut target: Option<Point2> = None;
    let mut blacklist: Vec<Point2> = Vec::new();
    let (mut reached, mut abandoned, mut travel) = (0usize, 0usize, 0.0);
    let mut trajectory = vec![start];
    let end = loop {
        let t = robot.sim_time();
        let pose = robot.pose();
        if robot.z() < grid.floor_z - 0.5 {
            break ExploreEnd::Fell;
        }
        if t >= p.max_time {
            break ExploreEnd::TimeLimit;
        }
        if t + 1e-9 >= scans as f64 * p.scan_period {
            scans += 1;
            let scan = lidar.scan(rays, pose, grid.floor_z);
            mapper.integrate(&scan, pose);
            navigator.add_scan(&scan, pose);
            let cliffs = cliffs(rays, pose, grid, profile.radius + p.cliff_distance, p.cliff_rays);
            if !cliffs.is_empty() {
                mapper.integrate_points(&cliffs, &[]);
                // The navigator must know at once: the robot is near an edge.
                last_search = f64::NEG_INFINITY;
            }
        }
        if let Some((r, cam)) = &sensors.camera {
            if t + 1e-9 >= frames as f64 * p.camera_period {
                frames += 1;
                let depth = r.depth(pose, grid.floor_z, cam)?;
                let pts = project_depth(&depth, &cam.intrinsics(), pose, cam.mount_height, &p.projection);
                mapper.integrate_points(&pts.obstacles, &pts.floor);
            }
        }
        // A new target when there is none, or when the map grown since shows that the target's
        // frontier is gone (seen from afar) or that the target lies in an obstacle's inflation;
        // otherwise the choice is kept, so that the robot does not dither between frontiers.
        if target.is_none() || t - last_search >= p.planner_period {
            last_search = t;
            let map = mapper.to_grid();
            let cm = Costmap::from_map(&map, &nav.global_costmap);
            let valid = |g: Point2| frontier_near(&map, g, p.frontier.blacklist_radius) && cm.cost_at(g) < INSCRIBED;
            if !target.is_some_and(valid) {
                let frontiers = find_frontiers(&map, &cm, pose.position(), &blacklist, &p.frontier);
                let Some(f) = nearest_frontier(&frontiers) else { break ExploreEnd::Done };
                let goal = f.target.expect("reachable frontiers have a target");
                tracing::debug!("t {t:.1} s: frontier of {:.2} m at ({:.2}, {:.2}), {:.2} m away", f.size_m, goal.x, goal.y, f.distance);
                target = Some(goal);
                navigator.set_goal(goal, t);
            }
            navigator.set_map(&map);
        }
        let cmd = navigator.tick(t, pose, robot.twist());
        match cmd.status {
            NavStatus::Succeeded => {
                reached += 1;
                tracing::debug!("t {t:.1} s: reached {target:?}");
                // Reached: if its frontier is still there from here it cannot be seen, so
                // it is not worth coming back for.
                blacklist.extend(target.take());
                continue;
            }
            NavStatus::Aborted => {
                abandoned += 1;
                tracing::debug!("t {t:.1} s: gave up on {target:?}");
                blacklist.extend(target.take());
                continue;
            }
            NavStatus::Recovering => {
                if let (Some(g), Some(cm)) = (target, navigator.costmap()) {
                    tracing::debug!("recovering at ({:.2}, {:.2}), {:.2} m from the target, whose cost is {}; plan {} poses", pose.x, pose.y, pose.position().dist(g), cm.cost_at(g), navigator.plan().len());
                }
            }
            _ => {}
        }
        let before = robot.pose().position();
        for _ in 0..steps {
            robot.step_physics(cmd.twist);
        }
        travel += before.dist(robot.pose().position());
        if (robot.sim_time()).floor() > t.floor() {
            trajectory.push(robot.pose());
        }
    };
    Ok(Exploration { map: mapper.to_grid(), end, sim_s: robot.sim_time(), travel_m: travel, targets_reached: reached, targets_abandoned: abandoned, trajectory })
}

/// Cliff rays: `n` rays cast down on a circle of `radius` (m) around the robot; the points
/// where no floor lies within the agent's `max_climb` below the floor height.
fn cliffs(rays: &RayScene, pose: Pose2, grid: &NavGrid, radius: f64, n: usize) -> Vec<Point2> {
    let top = 0.5;
    (0..n)
        .filter_map(|i| {
            let a = pose.yaw + i as f64 * std::f64::consts::TAU / n as f64;
            let q = Point2::new(pose.x + radius * a.cos(), pose.y + radius * a.sin());
            rays.cast([q.x, q.y, grid.floor_z + top], [0.0, 0.0, -1.0], top + grid.params.max_climb).is_none().then_some(q)
        })
        .collect()
}

/// A start for exploration: the cell of the grid's largest island nearest its centre with
/// 0.2 m to spare around the robot (or, failing that, any navigable one), facing +x; `None`
/// when the floor has no navigable cell.
pub fn default_start(grid: &NavGrid) -> Option<Pose2> {
    let (k, island) = grid.islands.iter().enumerate().max_by(|a, b| a.1.cells.cmp(&b.1.cells).then(b.0.cmp(&a.0)))?;
    let (w, h) = grid.size();
    let (res, o) = (grid.resolution(), grid.origin());
    let nearest = |spare: f64| {
        let mut best: Option<(f64, Point2)> = None;
        for r in 0..h {
            for c in 0..w {
                let q = Point2::new(o.x + (c as f64 + 0.5) * res, o.y + (r as f64 + 0.5) * res);
                if grid.is_navigable(q) && grid.island_at(q) == Some(k as u32) && grid.clearance_at(q) >= grid.params.radius + spare {
                    let d = q.dist(island.centre);
                    if best.is_none_or(|b| d < b.0) {
                        best = Some((d, q));
                    }
                }
            }
        }
        best.map(|(_, q)| Pose2::new(q.x, q.y, 0.0))
    };
    nearest(0.2).or_else(|| nearest(0.0))
}
