//! Where the navigation stack's laser scans come from: a planar lidar ray-cast in the scene, or
//! the depth camera's image flattened by depthimage_to_laserscan, as ROS-X-Habitat fed
//! move_base and amcl from Habitat's depth camera.

use std::sync::Arc;
use xhab_nav::depth_to_scan::{depth_to_scan, DepthToScanParams};
use xhab_sim::sensors::{CameraRig, Lidar, LidarParams, RayScene, RenderError};
use xhab_types::{LaserScan, Pose2};

/// A scan source: what it is and how it is set.
#[derive(Debug, Clone)]
pub enum ScanSource {
    /// A planar lidar (TurtleBot3 LDS-01 defaults).
    Lidar {
        /// The scene for ray casting.
        scene: Arc<RayScene>,
        /// Beams, range, mount height, noise.
        params: LidarParams,
    },
    /// The depth camera through depthimage_to_laserscan.
    Depth {
        /// The camera.
        rig: Arc<CameraRig>,
        /// scan_height, range_min, range_max.
        params: DepthToScanParams,
    },
}

impl ScanSource {
    /// A lidar with the default (LDS-01) parameters.
    pub fn lidar(scene: Arc<RayScene>) -> Self {
        ScanSource::Lidar { scene, params: LidarParams::default() }
    }

    /// Height of the scan plane above the floor (m): the lidar's mount, or the camera's (the
    /// scan is the image rows around the optical centre).
    pub fn height(&self) -> f64 {
        match self {
            ScanSource::Lidar { params, .. } => params.mount_height,
            ScanSource::Depth { rig, .. } => rig.params.mount_height,
        }
    }

    /// `lidar` or `depth`, as reports name it.
    pub fn name(&self) -> &'static str {
        match self {
            ScanSource::Lidar { .. } => "lidar",
            ScanSource::Depth { .. } => "depth",
        }
    }

    /// A sensor of this source with its own seeded noise stream.
    pub fn sensor(&self, seed: u64) -> ScanSensor {
        let state = match self {
            ScanSource::Lidar { scene, params } => SensorState::Lidar(scene.clone(), Lidar::new(params.clone(), seed)),
            ScanSource::Depth { rig, params } => SensorState::Depth(rig.clone(), params.clone()),
        };
        ScanSensor { state, seed, taken: 0 }
    }
}

#[derive(Debug, Clone)]
enum SensorState {
    Lidar(Arc<RayScene>, Lidar),
    Depth(Arc<CameraRig>, DepthToScanParams),
}

/// A scan source in use during one run: scans in order, each with its own noise draw.
#[derive(Debug, Clone)]
pub struct ScanSensor {
    state: SensorState,
    seed: u64,
    taken: u64,
}

impl ScanSensor {
    /// The scan from the robot at `base` on the floor at `floor_z` (m), in the laser frame
    /// (at the base's centre, facing its heading).
    pub fn scan(&mut self, base: Pose2, floor_z: f64) -> Result<LaserScan, RenderError> {
        self.taken += 1;
        match &mut self.state {
            SensorState::Lidar(scene, l) => Ok(l.scan(scene, base, floor_z)),
            SensorState::Depth(rig, params) => {
                let frame = rig.capture(base, floor_z, self.seed.wrapping_mul(0x9e37_79b9_7f4a_7c15).wrapping_add(self.taken))?;
                Ok(depth_to_scan(&frame.depth, &rig.params.intrinsics(), params))
            }
        }
    }
}
