//! One camera interface over the renderers: CPU ray casting (the reference) and the CPU
//! rasteriser; commands pick one with `--renderer`.

use super::camera::{render_depth, render_rgb, CameraParams};
use super::raster::RasterScene;
use super::raycast::RayScene;
use crate::scene::Scene;
use rayon::prelude::*;
use xhab_types::{DepthImage, Pose2};

/// The renderers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RendererKind {
    /// parry3d BVH ray casting, one ray per pixel (the reference).
    Raycast,
    /// Tiled, culled, multi-threaded CPU rasteriser.
    Raster,
}

/// Why a renderer cannot be built.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The scene has nothing to draw.
    #[error("the scene has no triangles to render")]
    EmptyScene,
}

/// A renderer built for one scene.
pub enum Renderer {
    /// Ray casting.
    Raycast(RayScene),
    /// Rasterising.
    Raster(RasterScene),
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Renderer({})", self.name())
    }
}

impl Renderer {
    /// Builds renderer `kind` for `scene` (acceleration structures, clusters).
    pub fn new(kind: RendererKind, scene: &Scene) -> Result<Renderer, RenderError> {
        Ok(match kind {
            RendererKind::Raycast => Renderer::Raycast(RayScene::new(scene).ok_or(RenderError::EmptyScene)?),
            RendererKind::Raster => Renderer::Raster(RasterScene::new(scene).ok_or(RenderError::EmptyScene)?),
        })
    }

    /// Its name as `--renderer` spells it.
    pub fn name(&self) -> &'static str {
        match self {
            Renderer::Raycast(_) => "raycast",
            Renderer::Raster(_) => "raster",
        }
    }

    /// Depth (m along the optical axis, 0 = no hit) seen from `base` on the floor at `floor_z`.
    pub fn depth(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> DepthImage {
        match self {
            Renderer::Raycast(r) => render_depth(r, base, floor_z, cam),
            Renderer::Raster(r) => r.render_depth(base, floor_z, cam),
        }
    }

    /// RGB bytes (row-major, top row first) seen from `base`.
    pub fn rgb(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> Vec<u8> {
        match self {
            Renderer::Raycast(r) => render_rgb(r, base, floor_z, cam),
            Renderer::Raster(r) => r.render_rgb(base, floor_z, cam),
        }
    }

    /// Depth for many views (`(base, floor_z)` each), in order.
    pub fn depth_batch(&self, views: &[(Pose2, f64)], cam: &CameraParams) -> Vec<DepthImage> {
        match self {
            Renderer::Raycast(r) => views.par_iter().map(|(b, z)| render_depth(r, *b, *z, cam)).collect(),
            Renderer::Raster(r) => r.render_depth_batch(views, cam),
        }
    }
}
