//! Pinhole depth and colour camera rendered with wgpu (Vulkan), headless: the same images as
//! the ray caster ([`super::camera`]) and the CPU rasteriser ([`super::RasterScene`]).
//!
//! The scene is uploaded once: shared vertex positions with an index buffer for depth, and
//! de-indexed triangles with their face normal and colour for RGB, both in the order of
//! spatial clusters (Morton order of the centroids, 128 triangles each); per view only the
//! clusters whose bounding box meets the view frustum are drawn. A batch of views is drawn
//! in one submission into the layers of a 2D array texture (one render pass per layer, the
//! view's matrices picked by the instance index), copied with one copy into one buffer (rows
//! padded to 256 bytes) and read back. Every view is drawn at the same viewport, so a view's
//! image is bit-identical alone or in any batch.
//!
//! Depth is the optical-axis distance (m) written by the fragment shader into an `R32Float`
//! target (perspective-correct interpolation of the camera-frame z), with a reversed-z
//! `Depth32Float` buffer for the z test, the near plane at [`NEAR`] and `max_depth` as the far
//! plane; the target is cleared to 0, so pixels where nothing is drawn read 0. The projection
//! puts pixel `(u, v)` of the camera (centre ray `forward + x right - y up`, `x = (u - cx) /
//! fx`, `y = (v - cy) / fy`, principal point included in the matrix) at the centre of
//! framebuffer pixel `(u, v)`. No face culling.
//!
//! Without a GPU, Mesa's llvmpipe Vulkan driver (Debian package `mesa-vulkan-drivers`)
//! renders on the CPU ([`GpuRenderer::is_software`]). Pipelines, targets and buffers are kept
//! between calls; they are reallocated only for a new resolution or batch size.

use super::camera::CameraParams;
use crate::scene::Scene;
use std::collections::HashMap;
use std::sync::{mpsc, Arc, Mutex};
use wgpu::util::DeviceExt;
use xhab_types::{DepthImage, Pose2};

/// Near clipping plane (m): surfaces closer to the camera than this are not seen (as in the
/// CPU rasteriser).
pub const NEAR: f64 = 1e-3;

/// Most targets (resolution, batch size, kind) kept between calls.
const MAX_CACHED_TARGETS: usize = 8;

/// Why the GPU renderer could not be created or could not render.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No Vulkan adapter at all (no driver, or no Vulkan loader).
    #[error("no Vulkan adapter: install Mesa's Vulkan driver (Debian package mesa-vulkan-drivers) or a GPU driver")]
    NoAdapter,
    /// The scene has no triangles to upload.
    #[error("the scene has no triangles")]
    EmptyScene,
    /// The adapter refused to give a device.
    #[error("requesting a device from the Vulkan adapter {adapter} failed: {message}")]
    Device {
        /// The adapter asked.
        adapter: String,
        /// wgpu's error.
        message: String,
    },
    /// The camera cannot be rendered (empty image, field of view, depth range or size beyond
    /// the adapter's limits).
    #[error("invalid camera for the GPU renderer: {0}")]
    Camera(String),
    /// wgpu reported a validation error (a bug in this renderer or a driver limit).
    #[error("wgpu validation error: {0}")]
    Validation(String),
    /// The device ran out of memory.
    #[error("GPU out of memory: {0}")]
    OutOfMemory(String),
    /// Waiting for the GPU or mapping the readback buffer failed (device lost, timeout).
    #[error("reading the image back from the GPU failed: {0}")]
    Readback(String),
}

/// Which image a target renders.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Kind {
    Depth,
    Rgb,
}

/// One view's camera as the shaders read it (std430 layout, 96 bytes).
#[derive(Clone, Copy)]
struct ViewUniform {
    /// World (m) to clip coordinates, column-major.
    clip: [f32; 16],
    /// World point (x, y, z, 1) to optical-axis depth (m).
    zrow: [f32; 4],
    /// Camera centre (world, m), w unused.
    origin: [f32; 4],
}

impl ViewUniform {
    const SIZE: u64 = 96;

    fn new(base: Pose2, floor_z: f64, cam: &CameraParams) -> ViewUniform {
        let k = cam.intrinsics();
        let (s, c) = base.yaw.sin_cos();
        let o = [base.x, base.y, floor_z + cam.mount_height];
        let row = |d: [f64; 3]| [d[0], d[1], d[2], -(d[0] * o[0] + d[1] * o[1] + d[2] * o[2])];
        // Camera frame: x right, y down, z forward.
        let (rx, ry, rz) = (row([s, -c, 0.0]), row([0.0, 0.0, -1.0]), row([c, s, 0.0]));
        let (w, h) = (cam.width as f64, cam.height as f64);
        let (far, near) = (cam.max_depth, NEAR);
        // Pixel u (centre at framebuffer x = u + 0.5) = fx x/z + cx; NDC x = 2 fb_x / W - 1,
        // NDC y = 1 - 2 fb_y / H; clip = NDC * z.
        let (ax, bx) = (2.0 * k.fx / w, 2.0 * (k.cx + 0.5) / w - 1.0);
        let (ay, by) = (-2.0 * k.fy / h, 1.0 - 2.0 * (k.cy + 0.5) / h);
        // Reversed z (near -> 1, far -> 0): a float z buffer then resolves depth to ~1e-7
        // relative everywhere, even with a near plane at 1 mm.
        let (az, bz) = (-near / (far - near), far * near / (far - near));
        let rows: [[f64; 4]; 4] = [
            std::array::from_fn(|j| ax * rx[j] + bx * rz[j]),
            std::array::from_fn(|j| ay * ry[j] + by * rz[j]),
            std::array::from_fn(|j| az * rz[j] + if j == 3 { bz } else { 0.0 }),
            rz,
        ];
        let mut clip = [0f32; 16];
        for (r, rv) in rows.iter().enumerate() {
            for (col, v) in rv.iter().enumerate() {
                clip[col * 4 + r] = *v as f32;
            }
        }
        ViewUniform { clip, zrow: rz.map(|v| v as f32), origin: [o[0] as f32, o[1] as f32, o[2] as f32, 1.0] }
    }

    fn write(&self, out: &mut Vec<u8>) {
        for v in self.clip.iter().chain(&self.zrow).chain(&self.origin) {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
}

/// Render targets for `n` views of one resolution (a 2D array texture, one layer per view, and
/// one z buffer reused by each view's pass), its readback buffer and the views' storage buffer.
struct Target {
    color: wgpu::Texture,
    /// One view of each layer, for its render pass.
    layers: Vec<wgpu::TextureView>,
    depth_view: wgpu::TextureView,
    padded_row: u32,
    readback: wgpu::Buffer,
    views: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

/// A headless wgpu renderer of depth and colour images of one scene, uploaded once.
/// Thread-safe (`Send + Sync`); concurrent calls are serialised.
pub struct GpuRenderer {
    info: wgpu::AdapterInfo,
    device: wgpu::Device,
    queue: wgpu::Queue,
    max_dim: u32,
    max_layers: u32,
    max_buffer: u64,
    max_views_binding: u64,
    bind_layout: wgpu::BindGroupLayout,
    depth_pipeline: wgpu::RenderPipeline,
    rgb_pipeline: wgpu::RenderPipeline,
    positions: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    flat_positions: wgpu::Buffer,
    flat_attrs: wgpu::Buffer,
    flat_count: u32,
    targets: Mutex<HashMap<(Kind, usize, usize, usize), Target>>,
    /// Spatial clusters of the triangles (in buffer order), for frustum culling per view.
    clusters: Vec<Cluster>,
}

impl std::fmt::Debug for GpuRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "GpuRenderer({}, {} triangles)", self.adapter_info(), self.flat_count / 3)
    }
}

const SHADER: &str = r#"
struct View {
    clip: mat4x4<f32>,
    zrow: vec4<f32>,
    origin: vec4<f32>,
};
@group(0) @binding(0) var<storage, read> views: array<View>;

struct DepthOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) z: f32,
};

@vertex
fn vs_depth(@location(0) p: vec3<f32>, @builtin(instance_index) i: u32) -> DepthOut {
    let v = views[i];
    let w = vec4<f32>(p, 1.0);
    var out: DepthOut;
    out.pos = v.clip * w;
    out.z = dot(v.zrow, w);
    return out;
}

@fragment
fn fs_depth(in: DepthOut) -> @location(0) f32 {
    return in.z;
}

struct RgbOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) ray: vec3<f32>,
    @location(1) @interpolate(flat) n: vec3<f32>,
    @location(2) @interpolate(flat) c: vec3<f32>,
};

@vertex
fn vs_rgb(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>, @location(2) c: vec3<f32>,
          @builtin(instance_index) i: u32) -> RgbOut {
    let v = views[i];
    var out: RgbOut;
    out.pos = v.clip * vec4<f32>(p, 1.0);
    out.ray = p - v.origin.xyz;
    out.n = n;
    out.c = c;
    return out;
}

@fragment
fn fs_rgb(in: RgbOut) -> @location(0) vec4<f32> {
    let cos_i = abs(dot(in.n, normalize(in.ray)));
    return vec4<f32>(round(in.c * (0.35 + 0.65 * cos_i)) / 255.0, 1.0);
}
"#;

fn block<F: std::future::Future>(f: F) -> F::Output {
    pollster::block_on(f)
}

/// The adapter's description: name, backend, device type (and driver).
fn describe(info: &wgpu::AdapterInfo) -> String {
    let driver = if info.driver.is_empty() { String::new() } else { format!(", driver {} {}", info.driver, info.driver_info) };
    format!("{} ({:?}, {:?}{driver})", info.name, info.backend, info.device_type)
}

impl GpuRenderer {
    /// Finds a Vulkan adapter (a GPU first, else a software one such as llvmpipe; the
    /// environment variable `XHAB_GPU_ADAPTER` picks one whose name contains it), opens a
    /// device without a window or surface, uploads the scene and builds the pipelines.
    pub fn new(scene: &Scene) -> Result<GpuRenderer, GpuError> {
        // Gather the geometry first: an empty scene needs no device.
        let mut positions: Vec<[f32; 3]> = Vec::new();
        // Triangles: corner indices into `positions`, normal (unit) and colour (bytes 0..255).
        let mut tris: Vec<([u32; 3], [f32; 6])> = Vec::new();
        for m in &scene.meshes {
            let color = m.base_color.map(|v| (v.clamp(0.0, 1.0) * 255.0).round());
            let base = positions.len() as u32;
            positions.extend_from_slice(&m.positions);
            for t in &m.indices {
                if t.iter().any(|&i| i as usize >= m.positions.len()) {
                    continue;
                }
                let p = t.map(|i| m.positions[i as usize].map(|x| x as f64));
                let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
                let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
                let n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
                let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-300);
                let attr = [(n[0] / l) as f32, (n[1] / l) as f32, (n[2] / l) as f32, color[0], color[1], color[2]];
                tris.push((t.map(|i| i + base), attr));
            }
        }
        if tris.is_empty() {
            return Err(GpuError::EmptyScene);
        }
        let (tris, clusters) = cluster(&positions, tris);
        let indices: Vec<u32> = tris.iter().flat_map(|t| t.0).collect();
        let flat_pos: Vec<[f32; 3]> = tris.iter().flat_map(|t| t.0.map(|i| positions[i as usize])).collect();
        let flat_attr: Vec<[f32; 6]> = tris.iter().flat_map(|t| [t.1; 3]).collect();

        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let mut adapters = block(instance.enumerate_adapters(wgpu::Backends::VULKAN));
        if let Ok(want) = std::env::var("XHAB_GPU_ADAPTER") {
            let want = want.to_lowercase();
            adapters.retain(|a| a.get_info().name.to_lowercase().contains(&want));
        }
        let rank = |t: wgpu::DeviceType| match t {
            wgpu::DeviceType::DiscreteGpu => 0,
            wgpu::DeviceType::IntegratedGpu => 1,
            wgpu::DeviceType::VirtualGpu => 2,
            wgpu::DeviceType::Other => 3,
            wgpu::DeviceType::Cpu => 4,
        };
        adapters.sort_by_key(|a| rank(a.get_info().device_type));
        let adapter = adapters.into_iter().next().ok_or(GpuError::NoAdapter)?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        let (device, queue) = block(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("xhab gpu camera"),
            required_features: wgpu::Features::empty(),
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device { adapter: describe(&info), message: e.to_string() })?;
        // Errors are caught by error scopes around each call; anything else is logged, never a panic.
        device.on_uncaptured_error(Arc::new(|e| tracing::error!("wgpu: {e}")));

        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("xhab camera shaders"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let bind_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("views"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("camera"),
            bind_group_layouts: &[Some(&bind_layout)],
            immediate_size: 0,
        });
        let depth_state = wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: Default::default(),
            bias: Default::default(),
        };
        let primitive = wgpu::PrimitiveState { cull_mode: None, ..Default::default() };
        let pos_layout = wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
        };
        let attr_layout = wgpu::VertexBufferLayout {
            array_stride: 24,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![1 => Float32x3, 2 => Float32x3],
        };
        let pipeline = |label: &str, vs: &str, fs: &str, buffers: &[Option<wgpu::VertexBufferLayout>], format| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive,
                depth_stencil: Some(depth_state.clone()),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let depth_pipeline = pipeline("depth", "vs_depth", "fs_depth", &[Some(pos_layout.clone())], wgpu::TextureFormat::R32Float);
        let rgb_pipeline = pipeline("rgb", "vs_rgb", "fs_rgb", &[Some(pos_layout), Some(attr_layout)], wgpu::TextureFormat::Rgba8Unorm);
        let bytes = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
        let buffer = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let vertex = wgpu::BufferUsages::VERTEX;
        let positions_buf = buffer("positions", &bytes(positions.as_flattened()), vertex);
        let index_bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let indices_buf = buffer("indices", &index_bytes, wgpu::BufferUsages::INDEX);
        let flat_positions = buffer("triangle positions", &bytes(flat_pos.as_flattened()), vertex);
        let flat_attrs = buffer("triangle normals and colours", &bytes(flat_attr.as_flattened()), vertex);
        check(block(oom.pop()))?;
        check(block(scope.pop()))?;

        Ok(GpuRenderer {
            max_dim: limits.max_texture_dimension_2d,
            max_layers: limits.max_texture_array_layers,
            max_buffer: limits.max_buffer_size,
            max_views_binding: limits.max_storage_buffer_binding_size as u64,
            info,
            device,
            queue,
            bind_layout,
            depth_pipeline,
            rgb_pipeline,
            positions: positions_buf,
            indices: indices_buf,
            index_count: indices.len() as u32,
            flat_positions,
            flat_attrs,
            flat_count: flat_pos.len() as u32,
            targets: Mutex::new(HashMap::new()),
            clusters,
        })
    }

    /// The adapter in use: name, backend, device type and driver.
    pub fn adapter_info(&self) -> String {
        describe(&self.info)
    }

    /// True when the adapter renders on the CPU (device type `Cpu`, e.g. Mesa's llvmpipe).
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// Number of triangles uploaded.
    pub fn triangle_count(&self) -> usize {
        self.index_count as usize / 3
    }

    /// Renders the depth image seen from the robot at `base` standing on the floor at
    /// `floor_z` (m): depth along the optical axis (m), 0 where nothing is seen within
    /// `max_depth` (or nearer than [`NEAR`]), as [`super::render_depth`] gives it.
    pub fn render_depth(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> Result<DepthImage, GpuError> {
        Ok(self.render_depth_batch(&[(base, floor_z)], cam)?.remove(0))
    }

    /// Renders the depth images of many views (robot pose, floor height in m) in one
    /// submission with one readback (more only when the batch exceeds the adapter's limits);
    /// each image as [`GpuRenderer::render_depth`] gives it.
    pub fn render_depth_batch(&self, views: &[(Pose2, f64)], cam: &CameraParams) -> Result<Vec<DepthImage>, GpuError> {
        let mut out = Vec::with_capacity(views.len());
        self.render(Kind::Depth, views, cam, &mut |px: &[u8]| {
            let data = px.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
            out.push(DepthImage { width: cam.width, height: cam.height, data });
        })?;
        Ok(out)
    }

    /// Renders the colour image seen from the robot at `base` (RGB bytes, row-major, top row
    /// first), as [`super::render_rgb`] does: the base colour of the nearest triangle
    /// (sRGB-less bytes of the mesh's linear base colour) shaded by `0.35 + 0.65 |cos
    /// incidence|`, black where nothing is seen within `max_depth`.
    pub fn render_rgb(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> Result<Vec<u8>, GpuError> {
        Ok(self.render_rgb_batch(&[(base, floor_z)], cam)?.remove(0))
    }

    /// Renders the colour images of many views (robot pose, floor height in m) in one
    /// submission; each image as [`GpuRenderer::render_rgb`] gives it.
    pub fn render_rgb_batch(&self, views: &[(Pose2, f64)], cam: &CameraParams) -> Result<Vec<Vec<u8>>, GpuError> {
        let mut out = Vec::with_capacity(views.len());
        self.render(Kind::Rgb, views, cam, &mut |px: &[u8]| {
            out.push(px.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect());
        })?;
        Ok(out)
    }

    /// Runs of triangles (buffer order) whose clusters may be seen from the view: clusters
    /// whose bounding box lies wholly outside one plane of the frustum (near, `max_depth`, the
    /// image sides one pixel beyond the edge) are skipped. Nothing visible is dropped.
    fn visible(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> Vec<std::ops::Range<u32>> {
        let k = cam.intrinsics();
        let (s, c) = base.yaw.sin_cos();
        let o = [base.x, base.y, floor_z + cam.mount_height];
        let (w, h) = (cam.width as f64, cam.height as f64);
        let [xl, xr, yt, yb] = [(-k.cx - 1.0) / k.fx, (w - k.cx) / k.fx, (-k.cy - 1.0) / k.fy, (h - k.cy) / k.fy];
        let far = cam.max_depth * (1.0 + 1e-6) + 1e-6;
        let near = NEAR * 0.5;
        let mut out: Vec<std::ops::Range<u32>> = Vec::new();
        for cl in &self.clusters {
            let mut all = 0x3fu32;
            for corner in 0..8 {
                let p = [0, 1, 2].map(|a| if corner >> a & 1 == 0 { cl.min[a] } else { cl.max[a] } as f64);
                let (dx, dy) = (p[0] - o[0], p[1] - o[1]);
                let (x, y, z) = (dx * s - dy * c, o[2] - p[2], dx * c + dy * s);
                all &= (z < near) as u32
                    | ((z > far) as u32) << 1
                    | ((x < xl * z) as u32) << 2
                    | ((x > xr * z) as u32) << 3
                    | ((y < yt * z) as u32) << 4
                    | ((y > yb * z) as u32) << 5;
                if all == 0 {
                    break;
                }
            }
            if all != 0 {
                continue;
            }
            match out.last_mut() {
                Some(r) if r.end == cl.start => r.end = cl.end,
                _ => out.push(cl.start..cl.end),
            }
        }
        out
    }

    /// Views that fit in one submission of `w` x `h` images (array layers, readback buffer
    /// size, view buffer binding).
    fn chunk_size(&self, w: usize, h: usize) -> usize {
        let row_bytes = (w * 4).next_multiple_of(256) as u64;
        let by_buffer = (self.max_buffer / (row_bytes * h as u64)).max(1) as usize;
        let by_binding = (self.max_views_binding / ViewUniform::SIZE).max(1) as usize;
        (self.max_layers as usize).min(by_buffer).min(by_binding).min(256).max(1)
    }

    /// Renders `views` in chunks that fit one submission; calls `emit` with each view's pixels
    /// (4 bytes each, row-major, tightly packed), in order.
    fn render(&self, kind: Kind, views: &[(Pose2, f64)], cam: &CameraParams, emit: &mut dyn FnMut(&[u8])) -> Result<(), GpuError> {
        let (w, h) = (cam.width, cam.height);
        if w == 0 || h == 0 {
            return Err(GpuError::Camera(format!("empty image {w}x{h}")));
        }
        if w > self.max_dim as usize || h > self.max_dim as usize {
            return Err(GpuError::Camera(format!("{w}x{h} px exceeds the adapter's texture limit of {} px", self.max_dim)));
        }
        if !(cam.max_depth > NEAR) || !(cam.hfov_deg > 0.0 && cam.hfov_deg < 180.0) {
            return Err(GpuError::Camera(format!("max_depth {} m must exceed the near plane {NEAR} m and hfov {} deg lie in (0, 180)", cam.max_depth, cam.hfov_deg)));
        }
        let chunk = self.chunk_size(w, h);
        let mut targets = self.targets.lock().unwrap_or_else(|e| e.into_inner());
        for part in views.chunks(chunk) {
            let key = (kind, w, h, part.len());
            if !targets.contains_key(&key) {
                if targets.len() >= MAX_CACHED_TARGETS {
                    targets.clear();
                }
                let t = self.target(kind, w, h, part.len())?;
                targets.insert(key, t);
            }
            let t = &targets[&key];
            self.render_chunk(kind, t, part, cam, emit)?;
        }
        Ok(())
    }

    /// Allocates the layers, z buffer, readback buffer and view buffer for `n` views of `w` x `h`.
    fn target(&self, kind: Kind, w: usize, h: usize, n: usize) -> Result<Target, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let format = match kind {
            Kind::Depth => wgpu::TextureFormat::R32Float,
            Kind::Rgb => wgpu::TextureFormat::Rgba8Unorm,
        };
        let texture = |label, format, layers, usage| {
            self.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width: w as u32, height: h as u32, depth_or_array_layers: layers },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let color = texture("camera images", format, n as u32, wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC);
        let depth = texture("z buffer", wgpu::TextureFormat::Depth32Float, 1, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let layers = (0..n as u32)
            .map(|i| {
                color.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("camera image"),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: i,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let padded_row = (w as u32 * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: padded_row as u64 * (h * n) as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let views = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("views"),
            size: ViewUniform::SIZE * n as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("views"),
            layout: &self.bind_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: views.as_entire_binding() }],
        });
        let t = Target { layers, color, depth_view: depth.create_view(&Default::default()), padded_row, readback, views, bind_group };
        check(block(oom.pop()))?;
        check(block(scope.pop()))?;
        Ok(t)
    }

    /// Draws the views into their layers, copies them into the readback buffer, waits, and emits
    /// each view's pixels.
    fn render_chunk(&self, kind: Kind, t: &Target, views: &[(Pose2, f64)], cam: &CameraParams, emit: &mut dyn FnMut(&[u8])) -> Result<(), GpuError> {
        let (w, h) = (cam.width, cam.height);
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let mut uniforms = Vec::with_capacity(views.len() * ViewUniform::SIZE as usize);
        for &(base, floor_z) in views {
            ViewUniform::new(base, floor_z, cam).write(&mut uniforms);
        }
        self.queue.write_buffer(&t.views, 0, &uniforms);
        let mut enc = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("camera") });
        // One pass per view, each into its own layer at the same viewport: a view renders the
        // same bits alone or in any batch.
        for (i, layer) in t.layers.iter().enumerate().take(views.len()) {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("camera view"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: layer,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &t.depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0.0), store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &t.bind_group, &[]);
            let inst = i as u32..i as u32 + 1;
            let (base, floor_z) = views[i];
            let ranges = self.visible(base, floor_z, cam);
            match kind {
                Kind::Depth => {
                    pass.set_pipeline(&self.depth_pipeline);
                    pass.set_vertex_buffer(0, self.positions.slice(..));
                    pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
                    for r in ranges {
                        pass.draw_indexed(3 * r.start..3 * r.end, 0, inst.clone());
                    }
                }
                Kind::Rgb => {
                    pass.set_pipeline(&self.rgb_pipeline);
                    pass.set_vertex_buffer(0, self.flat_positions.slice(..));
                    pass.set_vertex_buffer(1, self.flat_attrs.slice(..));
                    for r in ranges {
                        pass.draw(3 * r.start..3 * r.end, inst.clone());
                    }
                }
            }
        }
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo { texture: &t.color, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::All },
            wgpu::TexelCopyBufferInfo {
                buffer: &t.readback,
                layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(t.padded_row), rows_per_image: Some(h as u32) },
            },
            wgpu::Extent3d { width: w as u32, height: h as u32, depth_or_array_layers: views.len() as u32 },
        );
        let (tx, rx) = mpsc::channel();
        enc.map_buffer_on_submit(&t.readback, wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.queue.submit([enc.finish()]);
        check(block(oom.pop()))?;
        check(block(scope.pop()))?;
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| GpuError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|_| GpuError::Readback("the map callback was dropped".into()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        {
            let data = t.readback.get_mapped_range(..).map_err(|e| GpuError::Readback(e.to_string()))?;
            let mut px = vec![0u8; w * h * 4];
            for i in 0..views.len() {
                for r in 0..h {
                    let start = (i * h + r) * t.padded_row as usize;
                    px[r * w * 4..(r + 1) * w * 4].copy_from_slice(&data[start..start + w * 4]);
                }
                emit(&px);
            }
        }
        t.readback.unmap();
        Ok(())
    }
}

/// An error caught by an error scope, as a [`GpuError`].
fn check(e: Option<wgpu::Error>) -> Result<(), GpuError> {
    match e {
        None => Ok(()),
        Some(e @ wgpu::Error::OutOfMemory { .. }) => Err(GpuError::OutOfMemory(e.to_string())),
        Some(e) => Err(GpuError::Validation(e.to_string())),
    }
}

/// Triangles per cluster.
const CLUSTER: usize = 128;

/// A run of triangles `start..end` (buffer order) and its bounding box (world, m).
struct Cluster {
    min: [f32; 3],
    max: [f32; 3],
    start: u32,
    end: u32,
}


/// Sorts the triangles by the Morton code of their centroids and cuts them into clusters of
/// [`CLUSTER`] with their bounding boxes.
fn cluster(positions: &[[f32; 3]], tris: Vec<([u32; 3], [f32; 6])>) -> (Vec<([u32; 3], [f32; 6])>, Vec<Cluster>) {
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for t in &tris {
        for &i in &t.0 {
            for a in 0..3 {
                lo[a] = lo[a].min(positions[i as usize][a]);
                hi[a] = hi[a].max(positions[i as usize][a]);
            }
        }
    }
    let code = |t: &([u32; 3], [f32; 6])| super::raster::morton_code(std::array::from_fn(|a| t.0.iter().map(|&i| positions[i as usize][a]).sum::<f32>() / 3.0), lo, hi);
    let mut keyed: Vec<(u64, usize)> = tris.iter().enumerate().map(|(i, t)| (code(t), i)).collect();
    keyed.sort_unstable();
    let tris: Vec<([u32; 3], [f32; 6])> = keyed.iter().map(|&(_, i)| tris[i]).collect();
    let clusters = (0..tris.len())
        .step_by(CLUSTER)
        .map(|start| {
            let end = (start + CLUSTER).min(tris.len());
            let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
            for t in &tris[start..end] {
                for &i in &t.0 {
                    for a in 0..3 {
                        min[a] = min[a].min(positions[i as usize][a]);
                        max[a] = max[a].max(positions[i as usize][a]);
                    }
                }
            }
            Cluster { min, max, start: start as u32, end: end as u32 }
        })
        .collect();
    (tris, clusters)
}
