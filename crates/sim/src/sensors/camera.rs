//! Pinhole depth camera rendered by ray casting: one ray per pixel, rows in parallel.

use super::raycast::RayScene;
use super::surface::shade;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use xhab_types::{DepthImage, Intrinsics, Pose2};

/// A depth camera mounted on the robot, looking along its heading (Habitat defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraParams {
    /// Image width (px, default 256).
    pub width: usize,
    /// Image height (px, default 256).
    pub height: usize,
    /// Horizontal field of view (degrees, default 90).
    pub hfov_deg: f64,
    /// Height of the optical centre above the floor (m, default 1.25; LoCoBot 0.65).
    pub mount_height: f64,
    /// Farthest depth reported; beyond it depth is 0 (m, default 10).
    pub max_depth: f64,
}

impl Default for CameraParams {
    fn default() -> Self {
        Self { width: 256, height: 256, hfov_deg: 90.0, mount_height: 1.25, max_depth: 10.0 }
    }
}

impl CameraParams {
    /// The camera's intrinsics (ROS convention).
    pub fn intrinsics(&self) -> Intrinsics {
        Intrinsics::from_hfov(self.width, self.height, self.hfov_deg.to_radians())
    }
}

/// Renders the colour image seen from the robot at `base` (RGB bytes, row-major, top row
/// first): each pixel the base colour at the point hit (factor times texture, sRGB), shaded by
/// the angle of incidence ([`super::surface`]); black where nothing is hit.
pub fn render_rgb(scene: &RayScene, base: Pose2, floor_z: f64, cam: &CameraParams) -> Vec<u8> {
    let k = cam.intrinsics();
    let (s, c) = base.yaw.sin_cos();
    let origin = [base.x, base.y, floor_z + cam.mount_height];
    let mut data = vec![0u8; cam.width * cam.height * 3];
    if data.is_empty() {
        return data;
    }
    data.par_chunks_mut(cam.width * 3).enumerate().for_each(|(v, row)| {
        let y = (v as f64 - k.cy) / k.fy;
        for u in 0..cam.width {
            let x = (u as f64 - k.cx) / k.fx;
            let dir = [c + x * s, s - x * c, -y];
            if let Some((_, rgb, cos)) = scene.cast_color(origin, dir, cam.max_depth, 1.0 / k.fx) {
                row[u * 3..u * 3 + 3].copy_from_slice(&shade(rgb, cos));
            }
        }
    });
    data
}

/// Renders the depth image seen from the robot at `base` standing on the floor at `floor_z`
/// (m): depth along the optical axis (m), 0 where nothing is hit within `max_depth`.
pub fn render_depth(scene: &RayScene, base: Pose2, floor_z: f64, cam: &CameraParams) -> DepthImage {
    let k = cam.intrinsics();
    let (s, c) = base.yaw.sin_cos();
    let forward = [c, s, 0.0];
    let right = [s, -c, 0.0];
    let origin = [base.x, base.y, floor_z + cam.mount_height];
    let mut data = vec![0f32; cam.width * cam.height];
    if data.is_empty() {
        return DepthImage { width: cam.width, height: cam.height, data };
    }
    data.par_chunks_mut(cam.width).enumerate().for_each(|(v, row)| {
        let y = (v as f64 - k.cy) / k.fy;
        for (u, px) in row.iter_mut().enumerate() {
            let x = (u as f64 - k.cx) / k.fx;
            // Optical (x right, y down, z forward) to world; z component 1 so t = depth.
            let dir = [forward[0] + x * right[0], forward[1] + x * right[1], -y];
            *px = scene.cast(origin, dir, cam.max_depth).map_or(0.0, |t| t as f32);
        }
    });
    DepthImage { width: cam.width, height: cam.height, data }
}
