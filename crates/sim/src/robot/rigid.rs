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
    profile: RobotProfile,
    dt: f64,
    time: f64,
    /// Velocity actually commanded after clamping and acceleration limits.
    applied: Twist,
    /// Commands that carried NaN or infinite components (treated as zero).
    pub rejected_commands: u64,
}

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
        let col = ColliderBuilder::capsule_z(half, r)
            .mass(profile.mass as f32)
            .friction(0.0)
            .friction_combine_rule(CoefficientCombineRule::Min)
            .build();
        world.colliders.insert_with_parent(col, body, &mut world.bodies);
        Ok(RigidRobot { world, body, profile: profile.clone(), dt: 1.0 / params.steps_per_sec, time: 0.0, applied: Twist::default(), rejected_commands: 0 })
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
        let rb = &mut self.world.bodies[self.body];
        let vz = rb.linvel().z;
        let v = self.applied.linear;
        rb.set_linvel(Vector::new((v * yaw.cos()) as f32, (v * yaw.sin()) as f32, vz), true);
        rb.set_angvel(Vector::new(0.0, 0.0, self.applied.angular as f32), true);
        self.world.step();
        self.time += self.dt;
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
