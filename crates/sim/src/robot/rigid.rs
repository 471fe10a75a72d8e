//! A robot as a rapier3d rigid body among the scene's static triangles, driven by velocity
//! commands at a fixed physics rate (default 60 Hz).
//!
//! The body is a dynamic capsule with continuous collision detection and roll/pitch locked:
//! it follows the floor under gravity, rides over small steps on its rounded bottom and
//! cannot pass through walls at any commanded speed. The base is driven by setting its
//! horizontal velocity each step (differential drive: forward speed along the heading and a
//! turn rate), with friction 0 so that it slides along walls instead of sticking.

use super::profile::RobotProfile;
use crate::scene::Scene;
use rapier3d::parry::query::ShapeCastOptions;
use rapier3d::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use xhab_types::{normalize_angle, Pose2, Twist};

/// Physics settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PhysicsParams {
    /// Physics steps per simulated second (Hz, default 60).
    pub steps_per_sec: f64,
    /// Gravity (m/s^2, default 9.81, pointing down -z).
    pub gravity: f64,
}

impl Default for PhysicsParams {
    fn default() -> Self {
        Self { steps_per_sec: 60.0, gravity: 9.81 }
    }
}

/// The scene's triangles as one static rapier trimesh, built once and shared by episodes.
#[derive(Clone)]
pub struct PhysicsScene {
    shape: SharedShape,
    triangles: usize,
}

impl std::fmt::Debug for PhysicsScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PhysicsScene({} triangles)", self.triangles)
    }
}

/// Why the physics world could not be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PhysicsError {
    /// The scene's triangles do not form a valid trimesh.
    #[error("cannot build the physics mesh of the scene: {0}")]
    Mesh(String),
    /// A parameter is out of range.
    #[error("physics parameter {0}")]
    Param(String),
}

impl PhysicsScene {
    /// Builds the static trimesh (internal edges fixed so the robot does not catch on them).
    pub fn new(scene: &Scene) -> Result<PhysicsScene, PhysicsError> {
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for m in &scene.meshes {
            let base = vertices.len() as u32;
            vertices.extend(m.positions.iter().map(|p| Vector::new(p[0], p[1], p[2])));
            indices.extend(m.indices.iter().map(|t| [t[0] + base, t[1] + base, t[2] + base]));
        }
        let triangles = indices.len();
        let flags = TriMeshFlags::FIX_INTERNAL_EDGES | TriMeshFlags::MERGE_DUPLICATE_VERTICES;
        let shape = SharedShape::trimesh_with_flags(vertices, indices, flags).map_err(|e| PhysicsError::Mesh(format!("{e:?}")))?;
        Ok(PhysicsScene { shape, triangles })
    }
}

/// One robot in a physics world.
pub struct RigidRobot {
    world: PhysicsWorld,
    body: RigidBodyHandle,
    /// The body's collision shape (for the step-up queries).
    shape: SharedShape,
    profile: RobotProfile,
    dt: f64,
    time: f64,
    /// Velocity actually commanded after clamping and acceleration limits.
    applied: Twist,
    /// Commands that carried NaN or infinite components (treated as zero).
    pub rejected_commands: u64,
    /// The depth of the drop ahead (m) when the last step stopped the base at a cliff.
    cliff: Option<f64>,
}

/// The shallowest drop counted as a cliff (m): thresholds and floor joints are not.
pub const MIN_CLIFF: f64 = 0.05;

impl RigidRobot {
    /// Places the robot at `start` on the floor at height `floor_z` (m).
    pub fn new(scene: &PhysicsScene, profile: &RobotProfile, start: Pose2, floor_z: f64, params: &PhysicsParams) -> Result<RigidRobot, PhysicsError> {
        if !(params.steps_per_sec.is_finite() && params.steps_per_sec >= 10.0) {
            return Err(PhysicsError::Param(format!("steps_per_sec: must be >= 10, got {}", params.steps_per_sec)));
        }
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -(params.gravity as f32));
        world.integration_parameters.dt = (1.0 / params.steps_per_sec) as f32;
        world.colliders.insert(ColliderBuilder::new(scene.shape.clone()).friction(0.0).friction_combine_rule(CoefficientCombineRule::Min).build());
        let r = profile.radius as f32;
        let half = ((profile.height as f32) / 2.0 - r).max(0.0);
        // Centre height so that the capsule's bottom rests 1 mm above the floor.
        let cz = floor_z as f32 + half + r + 0.001;
        let rb = RigidBodyBuilder::dynamic()
            .translation(Vector::new(start.x as f32, start.y as f32, cz))
            .rotation(Vector::new(0.0, 0.0, start.yaw as f32))
            .enabled_rotations(false, false, true)
            .ccd_enabled(true)
            .can_sleep(false)
            .build();
        let body = world.bodies.insert(rb);
        let shape = SharedShape::capsule_z(half, r);
        let col = ColliderBuilder::new(shape.clone())
            .mass(profile.mass as f32)
            .friction(0.0)
            .friction_combine_rule(CoefficientCombineRule::Min)
            .build();
        world.colliders.insert_with_parent(col, body, &mut world.bodies);
        Ok(RigidRobot { world, body, shape, profile: profile.clone(), dt: 1.0 / params.steps_per_sec, time: 0.0, applied: Twist::default(), rejected_commands: 0, cliff: None })
    }

    /// Advances one physics step under `cmd` (m/s, rad/s in the base frame), clamped to the
    /// profile's speed and acceleration limits. Non-finite commands count as zero.
    pub fn step_physics(&mut self, cmd: Twist) {
        let cmd = if cmd.linear.is_finite() && cmd.angular.is_finite() {
            cmd
        } else {
            self.rejected_commands += 1;
            Twist::default()
        };
        let p = &self.profile;
        let target_v = cmd.linear.clamp(-p.max_linear, p.max_linear);
        let target_w = cmd.angular.clamp(-p.max_angular, p.max_angular);
        let dv = p.max_linear_accel * self.dt;
        let dw = p.max_angular_accel * self.dt;
        self.applied.linear += (target_v - self.applied.linear).clamp(-dv, dv);
        self.applied.angular += (target_w - self.applied.angular).clamp(-dw, dw);
        let yaw = self.pose().yaw;
        let mut v = self.applied.linear;
        // A drop deeper than the base can step down is a cliff it stops at (a cliff sensor's
        // job on a real base; Habitat's agent cannot leave its navmesh either).
        if v.abs() > 1e-3 {
            let reach = self.profile.radius + v.abs() * self.dt + 0.02;
            match self.drop_at(yaw, v.signum() * reach) {
                Some(d) if d > self.profile.step_height.max(MIN_CLIFF) + 0.01 => {
                    self.cliff = Some(d);
                    v = 0.0;
                    self.applied.linear = 0.0;
                }
                _ => self.cliff = None,
            }
        }
        let rb = &mut self.world.bodies[self.body];
        let vz = rb.linvel().z;
        rb.set_linvel(Vector::new((v * yaw.cos()) as f32, (v * yaw.sin()) as f32, vz), true);
        rb.set_angvel(Vector::new(0.0, 0.0, self.applied.angular as f32), true);
        let before = rb.translation();
        self.world.step();
        self.time += self.dt;
        if self.profile.step_height > 0.0 && v.abs() > 1e-3 {
            let dir = Vector::new((v.signum() * yaw.cos()) as f32, (v.signum() * yaw.sin()) as f32, 0.0);
            let want = (v.abs() * self.dt) as f32;
            let after = self.world.bodies[self.body].translation();
            if (after - before).dot(dir) < 0.5 * want {
                self.step_up(dir, want);
            }
        }
    }

    /// The base was held back while driving along `dir`: if what holds it is a step no higher
    /// than the profile's `step_height` with room above it, puts the body on the step, `want`
    /// (m, at least 2 cm) further along, as a wheeled base with that climb would (Habitat's
    /// agent follows its navmesh up such steps). Pure geometry queries: deterministic.
    fn step_up(&mut self, dir: Vector, want: f32) {
        let lift = self.profile.step_height as f32 + 0.01;
        let filter = QueryFilter::default().exclude_rigid_body(self.body);
        let (pos, rot) = {
            let rb = &self.world.bodies[self.body];
            (rb.translation(), *rb.rotation())
        };
        let up = Pose::from_parts(pos + Vector::new(0.0, 0.0, lift), rot);
        // The room checks allow the body to touch (5 mm): a base sliding along a wall or
        // under a ledge steps up beside it.
        let snug = Capsule::new_z(self.shape.as_capsule().map_or(0.0, |c| c.half_height()), (self.profile.radius as f32 - 0.005).max(0.001));
        if self.world.intersect_shape(up, &snug, filter).next().is_some() {
            return;
        }
        let d = want.max(0.02);
        let ahead = self.world.cast_shape(&up, dir * d, &snug, ShapeCastOptions::with_max_time_of_impact(1.0), filter);
        if ahead.is_some() {
            return;
        }
        let fwd = Pose::from_parts(up.translation + dir * d, rot);
        // The ground under the moved body: a ball 1 cm narrower than the body whose bottom is the
        // body's bottom, cast down (the body's own sides may touch a wall beside it).
        let half = self.shape.as_capsule().map_or(0.0, |c| c.half_height());
        let rb = (self.profile.radius as f32 - 0.01).max(0.001);
        let foot = Pose::from_parts(fwd.translation - Vector::new(0.0, 0.0, half + self.profile.radius as f32 - rb), rot);
        let down = self.world.cast_shape(&foot, Vector::new(0.0, 0.0, -1.0), &Ball::new(rb), ShapeCastOptions::with_max_time_of_impact(lift + 0.02), filter);
        // Only onto ground higher than where the base stands: a real step.
        if let Some((_, hit)) = down {
            if hit.time_of_impact > 0.0 && hit.time_of_impact < lift - 0.005 {
                let rb = &mut self.world.bodies[self.body];
                rb.set_translation(fwd.translation - Vector::new(0.0, 0.0, hit.time_of_impact - 0.001), true);
                let lv = rb.linvel();
                rb.set_linvel(Vector::new(lv.x, lv.y, 0.0), true);
            }
        }
    }

    /// How far the ground drops (m) at `dist` (m, negative: behind) from the body's centre
    /// along heading `yaw`, under the ground at the centre; `None` where either has no ground
    /// within 10 m (positive: lower ahead).
    pub fn drop_at(&self, yaw: f64, dist: f64) -> Option<f64> {
        let here = self.ground_z()?;
        let t = self.world.bodies[self.body].translation();
        let o = Vector::new(t.x + (dist * yaw.cos()) as f32, t.y + (dist * yaw.sin()) as f32, t.z);
        let filter = QueryFilter::default().exclude_rigid_body(self.body);
        let (_, toi) = self.world.cast_ray(&Ray::new(o, Vector::new(0.0, 0.0, -1.0)), 10.0, true, filter)?;
        Some(here - (o.z - toi) as f64)
    }

    /// The depth of the drop (m) the base stopped at in its last physics step, if it did.
    pub fn cliff(&self) -> Option<f64> {
        self.cliff
    }

    /// Height of the ground under the body's centre (m): the top of what a ray straight down
    /// from the centre meets, or `None` within 10 m.
    pub fn ground_z(&self) -> Option<f64> {
        let t = self.world.bodies[self.body].translation();
        let ray = Ray::new(t, Vector::new(0.0, 0.0, -1.0));
        let filter = QueryFilter::default().exclude_rigid_body(self.body);
        self.world.cast_ray(&ray, 10.0, true, filter).map(|(_, toi)| (t.z - toi) as f64)
    }

    /// How far the ground rises within `ahead` (m) of the body's front along its heading, over
    /// the ground under its centre (m); `None` where no ground is found.
    pub fn rise_ahead(&self, ahead: f64) -> Option<f64> {
        self.rise_toward(self.pose().yaw, ahead)
    }

    /// [`RigidRobot::rise_ahead`] along heading `yaw` (rad).
    pub fn rise_toward(&self, yaw: f64, ahead: f64) -> Option<f64> {
        let here = self.ground_z()?;
        let t = self.world.bodies[self.body].translation();
        let filter = QueryFilter::default().exclude_rigid_body(self.body);
        let mut best: Option<f64> = None;
        for k in 1..=8 {
            let s = (self.profile.radius + ahead * k as f64 / 8.0) as f32;
            let o = Vector::new(t.x + s * yaw.cos() as f32, t.y + s * yaw.sin() as f32, t.z + self.profile.height as f32);
            let ray = Ray::new(o, Vector::new(0.0, 0.0, -1.0));
            if let Some((_, toi)) = self.world.cast_ray(&ray, 10.0, true, filter) {
                let z = (o.z - toi) as f64 - here;
                best = Some(best.map_or(z, |b: f64| b.max(z)));
            }
        }
        best
    }

    /// Ground-truth planar pose (m, rad).
    pub fn pose(&self) -> Pose2 {
        let rb = &self.world.bodies[self.body];
        let t = rb.translation();
        let q = rb.rotation();
        let yaw = (2.0 * (q.w * q.z + q.x * q.y)).atan2(1.0 - 2.0 * (q.y * q.y + q.z * q.z));
        Pose2::new(t.x as f64, t.y as f64, normalize_angle(yaw as f64))
    }

    /// Height of the body's centre (m).
    pub fn z(&self) -> f64 {
        self.world.bodies[self.body].translation().z as f64
    }

    /// Measured velocity in the base frame (m/s, rad/s).
    pub fn twist(&self) -> Twist {
        let rb = &self.world.bodies[self.body];
        let v = rb.linvel();
        let yaw = self.pose().yaw;
        Twist { linear: v.x as f64 * yaw.cos() + v.y as f64 * yaw.sin(), angular: rb.angvel().z as f64 }
    }

    /// Simulated time since the start (s).
    pub fn sim_time(&self) -> f64 {
        self.time
    }

    /// Physics step length (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The robot's profile.
    pub fn profile(&self) -> &RobotProfile {
        &self.profile
    }
}

/// Shares a physics scene between threads.
pub type SharedPhysicsScene = Arc<PhysicsScene>;
