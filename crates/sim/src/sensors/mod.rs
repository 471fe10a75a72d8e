//! Sensors by CPU ray casting (parry3d BVH), CPU rasterisation and wgpu: the depth camera and a planar lidar.

pub mod camera;
pub mod camera_rig;
pub mod depth_noise;
pub mod gpu;
pub mod gpu_adapter;
pub mod lidar;
pub mod mipmap;
pub mod raster;
pub mod raycast;
pub mod renderer;
pub mod scan_slice;
pub mod surface;

pub use camera::{render_depth, render_rgb, CameraParams};
pub use camera_rig::{CameraFrame, CameraRig};
pub use depth_noise::DepthNoise;
pub use gpu::{GpuError, GpuRenderer};
pub use gpu_adapter::GpuAdapter;
pub use lidar::{Lidar, LidarParams};
pub use raster::RasterScene;
pub use raycast::RayScene;
pub use scan_slice::ScanSlice;
pub use renderer::{RenderError, Renderer, RendererKind};
