//! The robot's camera as observations carry it: a depth image (and an RGB image where asked)
//! rendered from the robot's pose at each step, with the optional seeded depth noise.

use super::camera::CameraParams;
use super::depth_noise::DepthNoise;
use super::renderer::{RenderError, Renderer};
use std::sync::Arc;
use xhab_types::{DepthImage, Pose2};

/// What the camera saw at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraFrame {
    /// Depth along the optical axis (m, 0 = no return within range).
    pub depth: DepthImage,
    /// RGB bytes, row-major, top row first (when the rig renders colour).
    pub rgb: Option<Vec<u8>>,
}

/// A camera mounted on the robot: a renderer shared between runs, intrinsics and mount, what
/// to render, and the depth noise.
#[derive(Debug, Clone)]
pub struct CameraRig {
    /// The renderer (shared by every episode and thread).
    pub renderer: Arc<Renderer>,
    /// Resolution, field of view, mount height (above the floor) and range.
    pub params: CameraParams,
    /// Whether frames carry RGB too.
    pub rgb: bool,
    /// Depth noise (off by default).
    pub noise: DepthNoise,
}

impl CameraRig {
    /// A depth-only camera without noise.
    pub fn depth_only(renderer: Arc<Renderer>, params: CameraParams) -> Self {
        Self { renderer, params, rgb: false, noise: DepthNoise::default() }
    }

    /// The frame seen from the robot at `base` on the floor at `floor_z` (m); `seed` drives
    /// this frame's noise (the same seed gives the same frame).
    pub fn capture(&self, base: Pose2, floor_z: f64, seed: u64) -> Result<CameraFrame, RenderError> {
        let (mut depth, rgb) = if self.rgb {
            let (d, c) = self.renderer.depth_rgb(base, floor_z, &self.params)?;
            (d, Some(c))
        } else {
            (self.renderer.depth(base, floor_z, &self.params)?, None)
        };
        self.noise.apply(&mut depth, seed);
        Ok(CameraFrame { depth, rgb })
    }
}
