//! The native navigation stack as an agent: the move_base-like navigator drives the physics
//! simulator with velocity commands (controller at 1 / controller_period Hz), localised by
//! ground truth or by wheel odometry alone.

use serde::{Deserialize, Serialize};
use std::sync::Arc;
use xhab_nav::amcl::Amcl;
use xhab_nav::navigator::{AbortReason, NavParams, NavStatus, Navigator};
use xhab_sim::navgrid::NavGrid;
use crate::scan_source::ScanSource;
use xhab_types::{OccupancyGrid, Pose2};

/// Where the navigator believes the robot is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Localization {
    /// The simulator's ground truth.
    #[default]
    GroundTruth,
    /// Integrated wheel odometry with noise (drifts).
    Odom,
    /// AMCL on the static map, from the start pose with ROS's initial covariance
    /// (0.5 m, pi/12 rad standard deviations), fed by odometry and the lidar.
    Amcl,
}

/// What the nav agent needs beyond the run config.
#[derive(Debug, Clone)]
pub struct NavSetup {
    /// Navigator parameters.
    pub params: NavParams,
    /// The static map (`None`: the map of the episode's floor, as `xhab map` makes it).
    pub map: Option<Arc<OccupancyGrid>>,
    /// Localisation source.
    pub localization: Localization,
    /// The laser scans feeding the obstacle layer and AMCL (a lidar, or the depth camera
    /// through depthimage_to_laserscan), if any.
    pub scan: Option<ScanSource>,
    /// Scan period (s, default 0.1 = 10 Hz).
    pub scan_period: f64,
}

impl NavSetup {
    /// The setup for a benchmark whose success radius is `success_distance` (m): the
    /// navigator's goal approach allows for it (unless the parameters set their own).
    pub fn scored(&self, success_distance: f64) -> NavSetup {
        let mut s = self.clone();
        if !(s.params.goal_approach.success_radius > 0.0) {
            s.params.goal_approach.success_radius = success_distance;
        }
        s
    }

    /// Whether AMCL localises on the scan-plane map ([`localization_map`]) rather than on the
    /// navigation map.
    pub fn scan_plane_localization(&self) -> bool {
        self.localization == Localization::Amcl && self.map.is_none() && self.scan.is_some()
    }
}

/// Initial position spread of AMCL at an episode's start (m, ROS's initialpose default).
pub const INITIAL_STD_XY: f64 = 0.5;
/// Initial heading spread of AMCL at an episode's start (rad, pi/12 as in ROS).
pub const INITIAL_STD_YAW: f64 = std::f64::consts::PI / 12.0;

/// When scans are taken in an episode: at the first step at or after each multiple of the
/// period (from the episode's start). The simulator and the navigator keep the same schedule,
/// so in lock-step the navigator knows which steps bring a scan.
#[derive(Debug, Clone, Copy)]
pub struct ScanSchedule {
    /// Period between scans (s).
    pub period: f64,
    /// Scans taken so far.
    pub taken: u64,
}

impl ScanSchedule {
    /// A schedule with `period` (s), no scan taken yet.
    pub fn new(period: f64) -> Self {
        Self { period, taken: 0 }
    }
    /// Whether a scan is due at episode time `t` (s).
    pub fn due(&self, t: f64) -> bool {
        t + 1e-9 >= self.taken as f64 * self.period
    }

    /// The scan of the step at episode time `t` (s) when one is due: taken by `sensor` from
    /// `base` (flattening `seen`, the step's camera frame, when it comes from the same camera);
    /// `None` when none is due or there is no sensor.
    pub fn take(&mut self, sensor: Option<&mut crate::scan_source::ScanSensor>, t: f64, base: Pose2, floor_z: f64, seen: Option<(&xhab_sim::sensors::CameraRig, &xhab_sim::sensors::CameraFrame)>) -> Result<Option<xhab_types::LaserScan>, String> {
        match sensor {
            Some(s) if self.due(t) => {
                self.taken += 1;
                s.scan_seen(base, floor_z, seen).map(Some).map_err(|e| format!("scan at {t:.2} s: {e}"))
            }
            _ => Ok(None),
        }
    }
}

/// The native navigation stack (localisation, costmaps, planner, DWA) for one episode,
/// independent of the transport: fed the step's inputs
/// (in-process by the runner, over ROS by the nav node), it answers with a command. Both
/// transports run this same code, so their results are identical.
pub struct NavStack {
    nav: Navigator,
    amcl: Option<Amcl>,
    localization: Localization,
    map_to_odom: Pose2,
    scans: ScanSchedule,
    err_sum: [f64; 2],
    err_n: usize,
    /// Position error (m) and filter spread (m) at the last AMCL update.
    last_fix: Option<[f64; 2]>,
}

/// What the navigator asks for after a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NavReply {
    /// Drive with this velocity for one controller period.
    Drive(xhab_types::Twist),
    /// The goal is reached: call Habitat's stop.
    Stop,
    /// The navigator gave up (no plan, recoveries exhausted).
    Abort,
}

/// One step's inputs to the navigator.
#[derive(Debug, Clone, Copy)]
pub struct NavInputs<'a> {
    /// Time since the episode began (s), rounded to the nanosecond as ROS stamps carry it.
    pub t: f64,
    /// Odometry pose of the base in the odom frame (m, rad).
    pub odom: Pose2,
    /// Measured base velocity (m/s, rad/s).
    pub twist: xhab_types::Twist,
    /// Ground-truth pose (m, rad): used by ground-truth localisation and to score AMCL.
    pub truth: Option<Pose2>,
    /// The scan taken at this step, if one is due (see [`NavStack::scan_due`]).
    pub scan: Option<&'a xhab_types::LaserScan>,
    /// Where the scan's origin sits on the base (m, rad): base_link -> the scan's frame.
    pub scan_mount: Pose2,
}

impl NavStack {
    /// A navigator on `map` heading for `goal`; AMCL (when asked) localises on `amcl_map`
    /// (the map of what the laser sees; `map` where there is one map) and starts at `start`
    /// with ROS's initial spread (0.5 m, pi/12 rad), or the spread given.
    pub fn new(setup: &NavSetup, map: &OccupancyGrid, amcl_map: &OccupancyGrid, goal: xhab_types::Point2, start: Pose2, spread: Option<(f64, f64)>, seed: u64) -> NavStack {
        let mut nav = Navigator::new(setup.params.clone());
        nav.set_map(map);
        nav.set_goal(goal, 0.0);
        let amcl = (setup.localization == Localization::Amcl).then(|| {
            let mut a = Amcl::new(amcl_map, setup.params.amcl.clone(), seed);
            let (sxy, syaw) = spread.unwrap_or((INITIAL_STD_XY, INITIAL_STD_YAW));
            a.init(start, sxy, syaw);
            a
        });
        NavStack { nav, amcl, localization: setup.localization, map_to_odom: Pose2::default(), scans: ScanSchedule::new(setup.scan_period), err_sum: [0.0; 2], err_n: 0, last_fix: None }
    }

    /// A new goal (m, map frame) at time `now` (s): the filter and the costmaps live on.
    pub fn set_goal(&mut self, goal: xhab_types::Point2, now: f64) {
        self.nav.set_goal(goal, now);
    }

    /// A new pose estimate (`initialpose`): the robot is at `pose` (map frame) while
    /// odometry reads `odom`; AMCL restarts there with `spread` (m, rad).
    pub fn set_initial_pose(&mut self, pose: Pose2, odom: Pose2, spread: (f64, f64)) {
        self.map_to_odom = pose.compose(odom.inverse());
        if let Some(a) = self.amcl.as_mut() {
            a.init(pose, spread.0, spread.1);
        }
    }

    /// Replaces the navigation map (a new `map` message).
    pub fn set_map(&mut self, map: &OccupancyGrid) {
        self.nav.set_map(map);
    }

    /// Clears the obstacle marks (move_base's `clear_costmaps`).
    pub fn clear_costmaps(&mut self) {
        self.nav.clear_costmaps();
    }

    /// Whether a scan is due at episode time `t` (s) (see [`ScanSchedule`]).
    pub fn scan_due(&self, t: f64) -> bool {
        self.scans.due(t)
    }

    /// One controller step.
    pub fn step(&mut self, inp: NavInputs<'_>) -> NavReply {
        let mut pose = match (self.localization, inp.truth) {
            (Localization::GroundTruth, Some(t)) => t,
            _ => self.map_to_odom.compose(inp.odom),
        };
        if let Some(scan) = inp.scan {
            self.scans.taken += 1;
            if let Some(a) = self.amcl.as_mut() {
                if a.update(inp.odom, scan, inp.scan_mount) {
                    let (estimate, m2o) = a.estimate_and_map_to_odom();
                    self.map_to_odom = m2o;
                    pose = self.map_to_odom.compose(inp.odom);
                    // The goal check allows for the filter's spread (one standard deviation of
                    // the position, both axes together).
                    let spread = (estimate.variance[0] + estimate.variance[1]).max(0.0).sqrt();
                    self.nav.set_localization_spread(spread);
                    if let Some(truth) = inp.truth {
                        let err = pose.position().dist(truth.position());
                        self.err_sum[0] += err;
                        self.err_sum[1] += xhab_types::normalize_angle(pose.yaw - truth.yaw).abs();
                        self.err_n += 1;
                        self.last_fix = Some([err, spread]);
                        tracing::debug!(t = inp.t, err, spread, x = pose.x, y = pose.y, true_x = truth.x, true_y = truth.y, odom_x = inp.odom.x, odom_y = inp.odom.y, yaw_err = xhab_types::normalize_angle(pose.yaw - truth.yaw), yaw_sd = estimate.variance[2].sqrt(), particles = a.len(), returns = scan.returns(), status = ?self.nav.status(), "amcl update");
                    }
                }
            }
            if self.amcl.is_some() {
                self.nav.set_scan_returns(scan.returns());
            }
            // Taken where the laser is, placed where the robot believes it is.
            self.nav.add_scan(scan, pose.compose(inp.scan_mount));
        }
        let cmd = self.nav.tick(inp.t, pose, inp.twist);
        match cmd.status {
            NavStatus::Succeeded => NavReply::Stop,
            NavStatus::Aborted => NavReply::Abort,
            _ => NavReply::Drive(cmd.twist),
        }
    }

    /// The map -> odom correction (identity without AMCL).
    pub fn map_to_odom(&self) -> Pose2 {
        self.map_to_odom
    }

    /// The AMCL filter, if localising with it.
    pub fn amcl(&self) -> Option<&Amcl> {
        self.amcl.as_ref()
    }

    /// The navigator.
    pub fn navigator(&self) -> &Navigator {
        &self.nav
    }

    /// Why the navigator gave up, once it has.
    pub fn abort_reason(&self) -> Option<AbortReason> {
        self.nav.abort_reason()
    }

    /// Position error against ground truth (m) and the filter's position spread (m) at the
    /// last AMCL update; `None` before any (or without ground truth).
    pub fn last_fix(&self) -> Option<[f64; 2]> {
        self.last_fix
    }

    /// Mean localisation error so far: position (m), heading (rad); `None` before any update.
    pub fn localization_error(&self) -> Option<[f64; 2]> {
        (self.err_n > 0).then(|| [self.err_sum[0] / self.err_n as f64, self.err_sum[1] / self.err_n as f64])
    }
}

/// Half the thickness of the band around the scan plane that the localisation map is cut
/// from (m): geometry within it shows in the map as the laser would see it.
pub const SCAN_PLANE_HALF_BAND: f64 = 0.025;

/// The map AMCL localises on when it is not the navigation map: without a user's map (which
/// serves both, as ROS's one map), the scene cut at the lidar's height
/// ([`NavGrid::slice_map`]): what a SLAM run with that lidar would map. A table is then its
/// legs, as the lidar sees it, not the block the costmap must keep the body away from.
pub fn localization_map(setup: &NavSetup, grid: &NavGrid, scene: &xhab_sim::scene::Scene) -> Option<OccupancyGrid> {
    let source = setup.scan.as_ref()?;
    setup.scan_plane_localization().then(|| grid.slice_map(scene, source.height(), SCAN_PLANE_HALF_BAND))
}

/// Episode time of `sim_s`, rounded to the nanosecond (what a ROS stamp carries).
pub fn episode_time(sim_s: f64) -> f64 {
    (sim_s * 1e9).round() / 1e9
}
