//! Where the navigation stack's laser scans come from: a planar lidar ray-cast in the scene, or
//! the depth camera's image flattened by depthimage_to_laserscan, as ROS-X-Habitat fed
//! move_base and amcl from Habitat's depth camera.

use std::sync::Arc;
use xhab_nav::depth_to_scan::{depth_to_scan, DepthToScanParams};
use xhab_sim::sensors::{CameraFrame, CameraRig, Lidar, LidarParams, RayScene, RenderError};
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
    /// A lidar with `params` (the robot profile's `laser.lidar()`: LDS-01 at its mount).
    pub fn lidar(scene: Arc<RayScene>, params: LidarParams) -> Self {
        ScanSource::Lidar { scene, params }
    }

    /// Where the scan's origin sits on the base (m, rad): the lidar's mount, or the camera at
    /// the base's centre.
    pub fn mount(&self) -> Pose2 {
        match self {
            ScanSource::Lidar { params, .. } => Pose2::new(params.mount_xy[0], params.mount_xy[1], 0.0),
            ScanSource::Depth { .. } => Pose2::default(),
        }
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

/// What a [`ScanSensor`] scans with (one per run: the variants' size difference costs nothing).
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)]
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

    /// As [`ScanSensor::scan`], but a depth source whose camera is the one that rendered
    /// `seen` (a frame from `base` at this step: same renderer, intrinsics, mount and noise)
    /// flattens that frame instead of rendering its own, as depthimage_to_laserscan turns the
    /// camera's published image into the scan.
    pub fn scan_seen(&mut self, base: Pose2, floor_z: f64, seen: Option<(&CameraRig, &CameraFrame)>) -> Result<LaserScan, RenderError> {
        if let (SensorState::Depth(rig, params), Some((r, frame))) = (&self.state, seen) {
            if Arc::ptr_eq(&rig.renderer, &r.renderer) && rig.params == r.params && rig.noise == r.noise {
                self.taken += 1;
                return Ok(depth_to_scan(&frame.depth, &rig.params.intrinsics(), params));
            }
        }
        self.scan(base, floor_z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use xhab_sim::scene::house::default_house;
    use xhab_sim::sensors::{CameraParams, DepthNoise, Renderer, RendererKind};

    #[test]
    fn a_depth_source_flattens_the_frame_of_its_own_camera_and_renders_for_another() {
        let renderer = Arc::new(Renderer::new(RendererKind::Raster, &default_house(2)).unwrap());
        let params = CameraParams { width: 64, height: 48, ..Default::default() };
        let rig = |p: CameraParams| Arc::new(CameraRig { renderer: renderer.clone(), params: p, rgb: false, noise: DepthNoise::default() });
        let source = ScanSource::Depth { rig: rig(params.clone()), params: DepthToScanParams::default() };
        let base = Pose2::new(3.0, 2.0, 0.4);
        // Ranges by bits (NaN where depthimage_to_laserscan's truncated beam angles skip a beam).
        let bits = |s: LaserScan| s.ranges.iter().map(|r| r.to_bits()).collect::<Vec<_>>();
        let own = bits(source.sensor(1).scan(base, 0.0).unwrap());
        // A frame of the same camera is used as is: one that saw depth 2 m everywhere gives ranges
        // of 2 m (ahead) to 2 sqrt(2) m (at the 45° edges).
        let camera = rig(params.clone());
        let mut frame = camera.capture(base, 0.0, 0).unwrap();
        assert_eq!(bits(source.sensor(1).scan_seen(base, 0.0, Some((&camera, &frame))).unwrap()), own);
        frame.depth.data.iter_mut().for_each(|d| *d = 2.0);
        let flat = source.sensor(1).scan_seen(base, 0.0, Some((&camera, &frame))).unwrap();
        let seen: Vec<f32> = flat.ranges.iter().copied().filter(|r| !r.is_nan()).collect();
        assert!(seen.len() > 40 && seen.iter().all(|r| *r >= 2.0 && *r <= 2.0 * 2f32.sqrt() + 1e-3), "{:?}", flat.ranges);
        // Another camera's frame (a different mount) is not: the source renders its own.
        let other = rig(CameraParams { mount_height: params.mount_height + 0.3, ..params });
        assert_eq!(bits(source.sensor(1).scan_seen(base, 0.0, Some((&other, &frame))).unwrap()), own);
    }
}
