//! Robots under physics: profiles, the rapier3d rigid body, and wheel odometry.

pub mod odometry;
pub mod profile;
pub mod rigid;

pub use odometry::{OdometryNoise, WheelOdometry};
pub use profile::{LaserMount, ProfileError, RobotProfile};
pub use rigid::{PhysicsError, PhysicsParams, PhysicsScene, RigidRobot, SharedPhysicsScene, MIN_CLIFF};
