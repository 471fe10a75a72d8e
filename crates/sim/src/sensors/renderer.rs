//! One camera interface over the renderers: CPU ray casting (the reference), the CPU
//! rasteriser and wgpu (Vulkan, headless); commands pick one with `--renderer`.

use super::camera::{render_depth, render_rgb, CameraParams};
use super::gpu::GpuRenderer;
use super::gpu_adapter::GpuAdapter;
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
    /// wgpu on a Vulkan adapter (a GPU, or Mesa's llvmpipe without one).
    Wgpu,
}

/// Why a renderer cannot be built.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The scene has nothing to draw.
    #[error("the scene has no triangles to render")]
    EmptyScene,
    /// The GPU path failed (no adapter, no driver, device lost).
    #[error(transparent)]
    Gpu(#[from] super::gpu::GpuError),
}

/// A renderer built for one scene (built once per run and shared, so the size difference of
/// the variants costs nothing).
#[allow(clippy::large_enum_variant)]
pub enum Renderer {
    /// Ray casting.
    Raycast(RayScene),
    /// Rasterising.
    Raster(RasterScene),
    /// wgpu.
    Wgpu(GpuRenderer),
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
            RendererKind::Wgpu => Renderer::Wgpu(GpuRenderer::new(scene)?),
        })
    }

    /// The fastest renderer here: wgpu on a real GPU, else the CPU rasteriser (which beats
    /// Mesa's software Vulkan driver on CPU). Also says why, for the log line.
    /// The adapter is looked at before anything is built, so that without a GPU no time goes
    /// to a software device that would be dropped.
    pub fn auto(scene: &Scene) -> Result<(Renderer, String), RenderError> {
        let raster = |why: String| Ok((Renderer::new(RendererKind::Raster, scene)?, why));
        let adapter = match GpuAdapter::find() {
            Ok(a) if a.is_software() => return raster(format!("only a software adapter ({}): the CPU rasteriser is faster", a.describe())),
            found => found,
        };
        match adapter.and_then(|a| GpuRenderer::with_adapter(scene, a)) {
            Ok(g) => {
                let why = format!("GPU adapter {}", g.adapter_info());
                Ok((Renderer::Wgpu(g), why))
            }
            Err(e) => raster(format!("no GPU renderer ({e}): using the CPU rasteriser")),
        }
    }

    /// Its name as `--renderer` spells it.
    pub fn name(&self) -> &'static str {
        match self {
            Renderer::Raycast(_) => "raycast",
            Renderer::Raster(_) => "raster",
            Renderer::Wgpu(_) => "wgpu",
        }
    }

    /// Depth (m along the optical axis, 0 = no hit) seen from `base` on the floor at `floor_z`.
    pub fn depth(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> Result<DepthImage, RenderError> {
        Ok(match self {
            Renderer::Raycast(r) => render_depth(r, base, floor_z, cam),
            Renderer::Raster(r) => r.render_depth(base, floor_z, cam),
            Renderer::Wgpu(r) => r.render_depth(base, floor_z, cam)?,
        })
    }

    /// RGB bytes (row-major, top row first) seen from `base`.
    pub fn rgb(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> Result<Vec<u8>, RenderError> {
        Ok(match self {
            Renderer::Raycast(r) => render_rgb(r, base, floor_z, cam),
            Renderer::Raster(r) => r.render_rgb(base, floor_z, cam),
            Renderer::Wgpu(r) => r.render_rgb(base, floor_z, cam)?,
        })
    }

    /// Depth and RGB of one view, as [`Renderer::depth`] and [`Renderer::rgb`] give them (the
    /// rasteriser and wgpu draw the view once for both).
    pub fn depth_rgb(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> Result<(DepthImage, Vec<u8>), RenderError> {
        Ok(match self {
            Renderer::Raster(r) => r.render_depth_rgb(base, floor_z, cam),
            Renderer::Wgpu(r) => r.render_depth_rgb(base, floor_z, cam)?,
            Renderer::Raycast(_) => (self.depth(base, floor_z, cam)?, self.rgb(base, floor_z, cam)?),
        })
    }

    /// Depth for many views (`(base, floor_z)` each), in order; wgpu renders them in one
    /// submission and reads them back in one copy.
    pub fn depth_batch(&self, views: &[(Pose2, f64)], cam: &CameraParams) -> Result<Vec<DepthImage>, RenderError> {
        Ok(match self {
            Renderer::Raycast(r) => views.par_iter().map(|(b, z)| render_depth(r, *b, *z, cam)).collect(),
            Renderer::Raster(r) => r.render_depth_batch(views, cam),
            Renderer::Wgpu(r) => r.render_depth_batch(views, cam)?,
        })
    }

    /// Depth and RGB for many views, in order, each pair as [`Renderer::depth_rgb`] gives it:
    /// the rasteriser renders one view per thread, wgpu all of them in one submission.
    pub fn depth_rgb_batch(&self, views: &[(Pose2, f64)], cam: &CameraParams) -> Result<Vec<(DepthImage, Vec<u8>)>, RenderError> {
        Ok(match self {
            Renderer::Raycast(r) => views.par_iter().map(|(b, z)| (render_depth(r, *b, *z, cam), render_rgb(r, *b, *z, cam))).collect(),
            Renderer::Raster(r) => r.render_depth_rgb_batch(views, cam),
            Renderer::Wgpu(r) => r.render_depth_rgb_batch(views, cam)?,
        })
    }
}
