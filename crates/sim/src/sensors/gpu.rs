//! Pinhole depth and colour camera rendered with wgpu (Vulkan), headless: the same images as
//! the ray caster ([`super::camera`]) and the CPU rasteriser ([`super::RasterScene`]).
//!
//! The scene is uploaded once: shared vertex positions with an index buffer for depth, and
//! de-indexed triangles with their face normal, colour, texture coordinates and texture for
//! RGB, both in the order of
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
//! Colour follows [`super::surface`] exactly: untextured triangles carry their sRGB colour;
//! textured ones their linear factor and their texels per metre ([`super::mipmap::texel_scale`]),
//! and the fragment shader samples the texture by hand (over the mip pyramid with
//! the level of detail of [`super::mipmap`], from the ray's length, the pixel's angular size
//! `1 / fx` carried in the view's `origin.w` and the cosine of incidence; bilinear within a
//! level, wrap modes, the same sRGB tables) from one storage buffer holding every level of
//! every texture (RGBA8, one `u32` per texel, the CPU's pyramid bytes) with a table of one
//! entry per level (offset, size, wrap modes and the texture's level count), so the GPU's image
//! agrees with the CPU renderers' to within rounding. Pyramids larger in all than the
//! adapter's `max_storage_buffer_binding_size` are refused ([`GpuError::Textures`]).
//!
//! Depth and colour of a view come from one pass when both are asked for
//! ([`GpuRenderer::render_depth_rgb`]): the colour pipeline's vertex stage also carries the
//! optical-axis depth, worked out as the depth pipeline's, and the fragment stage writes it to
//! a second attachment, so each image is the one its own pass gives, to the bit (a test), for
//! one pass's cost (1.27x the frames/s of two passes on aws_small_house on an H200).
//!
//! Without a GPU, Mesa's llvmpipe Vulkan driver (Debian package `mesa-vulkan-drivers`)
//! renders on the CPU ([`GpuRenderer::is_software`]). Pipelines, targets and buffers are kept
//! between calls; they are reallocated only for a new resolution or batch size.

use super::camera::CameraParams;
use super::gpu_adapter::GpuAdapter;
use super::mipmap::texel_scale;
use super::surface::{srgb_table, Surfaces};
use crate::scene::{Scene, Wrap};
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
    /// The scene's textures do not fit in one storage buffer binding of this adapter; render
    /// with the CPU renderers, or use smaller textures.
    #[error("the scene's textures ({bytes} bytes) exceed the adapter's storage buffer binding limit of {limit} bytes")]
    Textures {
        /// Bytes of texels (4 per texel).
        bytes: u64,
        /// The adapter's `max_storage_buffer_binding_size` (or `max_buffer_size`, if smaller).
        limit: u64,
    },
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

/// Which images a target renders.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Kind {
    Depth,
    Rgb,
    /// Depth and colour from one pass (two attachments).
    DepthRgb,
}

impl Kind {
    /// The formats of the kind's colour attachments, in order (4 bytes a pixel each).
    fn formats(self) -> &'static [wgpu::TextureFormat] {
        match self {
            Kind::Depth => &[wgpu::TextureFormat::R32Float],
            Kind::Rgb => &[wgpu::TextureFormat::Rgba8Unorm],
            Kind::DepthRgb => &[wgpu::TextureFormat::R32Float, wgpu::TextureFormat::Rgba8Unorm],
        }
    }
}

/// One view's camera as the shaders read it (std430 layout, 96 bytes).
#[derive(Clone, Copy)]
struct ViewUniform {
    /// World (m) to clip coordinates, column-major.
    clip: [f32; 16],
    /// World point (x, y, z, 1) to optical-axis depth (m).
    zrow: [f32; 4],
    /// Camera centre (world, m); w: a pixel's angular size `1 / fx` (rad).
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
        ViewUniform { clip, zrow: rz.map(|v| v as f32), origin: [o[0] as f32, o[1] as f32, o[2] as f32, (1.0 / k.fx) as f32] }
    }

    fn write(&self, out: &mut Vec<u8>) {
        for v in self.clip.iter().chain(&self.zrow).chain(&self.origin) {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
}

/// Render targets for `n` views of one resolution (per colour attachment a 2D array texture,
/// one layer per view, and one z buffer reused by each view's pass), its readback buffer (the
/// attachments one after the other) and the views' storage buffer.
struct Target {
    colors: Vec<wgpu::Texture>,
    /// Per layer, one view of it in each attachment, for its render pass.
    layers: Vec<Vec<wgpu::TextureView>>,
    depth_view: wgpu::TextureView,
    padded_row: u32,
    readback: wgpu::Buffer,
    views: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

/// A headless wgpu renderer of depth and colour images of one scene, uploaded once.
/// Thread-safe (`Send + Sync`); concurrent calls are serialised.
pub struct GpuRenderer {
    /// The adapter the device was opened on.
    gpu: GpuAdapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    max_dim: u32,
    max_layers: u32,
    max_buffer: u64,
    max_views_binding: u64,
    bind_layout: wgpu::BindGroupLayout,
    depth_pipeline: wgpu::RenderPipeline,
    rgb_pipeline: wgpu::RenderPipeline,
    depth_rgb_pipeline: wgpu::RenderPipeline,
    positions: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    flat_positions: wgpu::Buffer,
    flat_attrs: wgpu::Buffer,
    flat_count: u32,
    /// Every texture's texels (RGBA8 as one `u32` each), their table and the sRGB table.
    texels: wgpu::Buffer,
    tex_table: wgpu::Buffer,
    srgb: wgpu::Buffer,
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

// One mip level of a texture: first texel in `texels`, size (texels), wrap modes s | t << 8
// (0 repeat, 1 clamp to edge, 2 mirrored repeat) | the texture's level count << 16. A
// texture's levels are consecutive entries, finest first.
struct TexInfo {
    offset: u32,
    width: u32,
    height: u32,
    wrap: u32,
};
@group(0) @binding(1) var<storage, read> texels: array<u32>;
@group(0) @binding(2) var<storage, read> textures: array<TexInfo>;
// 0..256: sRGB byte to linear; 256 + k: the linear value where encoding steps from k to k + 1.
@group(0) @binding(3) var<storage, read> srgb: array<f32, 512>;

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
    @location(3) uv: vec2<f32>,
    @location(4) @interpolate(flat) tex: u32,
    @location(5) @interpolate(flat) scale: f32,
    @location(6) @interpolate(flat) pix: f32,
    // Optical-axis depth (m), as vs_depth gives it.
    @location(7) z: f32,
};

@vertex
fn vs_rgb(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>, @location(2) c: vec3<f32>,
          @location(3) uv: vec2<f32>, @location(4) tex: u32, @location(5) scale: f32,
          @builtin(instance_index) i: u32) -> RgbOut {
    let v = views[i];
    let w = vec4<f32>(p, 1.0);
    var out: RgbOut;
    out.pos = v.clip * w;
    out.z = dot(v.zrow, w);
    out.ray = p - v.origin.xyz;
    out.n = n;
    out.c = c;
    out.uv = uv;
    out.tex = tex;
    out.scale = scale;
    out.pix = v.origin.w;
    return out;
}

// Texel index in 0..n of texel coordinate i under a wrap mode (as scene::Wrap::apply).
fn wrap_index(i: i32, n: i32, mode: u32) -> i32 {
    if mode == 1u {
        return clamp(i, 0, n - 1);
    }
    if mode == 2u {
        let p = 2 * n;
        var k = i % p;
        if k < 0 {
            k += p;
        }
        if k >= n {
            k = p - 1 - k;
        }
        return k;
    }
    var k = i % n;
    if k < 0 {
        k += n;
    }
    return k;
}

fn texel(t: TexInfo, x: i32, y: i32) -> vec3<f32> {
    let p = texels[t.offset + u32(y) * t.width + u32(x)];
    return vec3<f32>(srgb[p & 0xffu], srgb[(p >> 8u) & 0xffu], srgb[(p >> 16u) & 0xffu]);
}

// Linear RGB of texture t at uv: bilinear over wrapped texels (as surface::sample_bilinear).
fn sample_tex(t: TexInfo, uv: vec2<f32>) -> vec3<f32> {
    let x = uv.x * f32(t.width) - 0.5;
    let y = uv.y * f32(t.height) - 0.5;
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let i = i32(x0);
    let j = i32(y0);
    let w = i32(t.width);
    let h = i32(t.height);
    let ws = t.wrap & 0xffu;
    let wt = (t.wrap >> 8u) & 0xffu;
    let xa = wrap_index(i, w, ws);
    let xb = wrap_index(i + 1, w, ws);
    let ya = wrap_index(j, h, wt);
    let yb = wrap_index(j + 1, h, wt);
    let top = texel(t, xa, ya) * (1.0 - fx) + texel(t, xb, ya) * fx;
    let bottom = texel(t, xa, yb) * (1.0 - fx) + texel(t, xb, yb) * fx;
    return top * (1.0 - fy) + bottom * fy;
}

// A linear value as an sRGB byte value 0..255 (as surface::linear_to_srgb_byte: a binary
// search of the step thresholds).
fn srgb_byte(x: f32) -> f32 {
    var c = 0u;
    for (var s = 128u; s > 0u; s = s >> 1u) {
        if c + s <= 255u && srgb[256u + c + s - 1u] <= x {
            c += s;
        }
    }
    return f32(c);
}

// Linear RGB of the texture whose level 0 is entry `first` at uv for level of detail `lod`
// in [0, levels - 1]: level floor(lod), the next, or both blended in a band of width
// mipmap::BLEND (0.25) around each half level (as mipmap::MipChain::sample).
fn sample_mip(first: u32, uv: vec2<f32>, lod: f32) -> vec3<f32> {
    let levels = textures[first].wrap >> 16u;
    let l = min(u32(lod), levels - 1u);
    let w = clamp((lod - f32(l) - (1.0 - 0.25) * 0.5) / 0.25, 0.0, 1.0);
    if l + 1u < levels && w >= 1.0 {
        return sample_tex(textures[first + l + 1u], uv);
    }
    if l + 1u < levels && w > 0.0 {
        let a = sample_tex(textures[first + l], uv);
        let b = sample_tex(textures[first + l + 1u], uv);
        return a * (1.0 - w) + b * w;
    }
    return sample_tex(textures[first + l], uv);
}

// The fragment's colour: the rule of surface.rs.
fn colour(in: RgbOut) -> vec4<f32> {
    var c = in.c;
    let cos_i = abs(dot(in.n, normalize(in.ray)));
    if in.tex != 0xffffffffu {
        // Level of detail (as mipmap::footprint and mipmap::level_of_detail).
        let texels = length(in.ray) * in.pix / max(cos_i, 0.001) * in.scale;
        var lod = 0.0;
        if texels > 1.0 {
            let levels = textures[in.tex].wrap >> 16u;
            lod = min(log2(texels), f32(levels - 1u));
        }
        let lin = sample_mip(in.tex, in.uv, lod) * in.c;
        c = vec3<f32>(srgb_byte(lin.x), srgb_byte(lin.y), srgb_byte(lin.z));
    }
    return vec4<f32>(round(c * (0.35 + 0.65 * cos_i)) / 255.0, 1.0);
}

@fragment
fn fs_rgb(in: RgbOut) -> @location(0) vec4<f32> {
    return colour(in);
}

struct DepthRgbFrag {
    @location(0) z: f32,
    @location(1) c: vec4<f32>,
};

@fragment
fn fs_depth_rgb(in: RgbOut) -> DepthRgbFrag {
    var out: DepthRgbFrag;
    out.z = in.z;
    out.c = colour(in);
    return out;
}
"#;

/// Waits for a wgpu future on this thread.
pub(super) fn block<F: std::future::Future>(f: F) -> F::Output {
    pollster::block_on(f)
}

impl GpuRenderer {
    /// Finds a Vulkan adapter ([`GpuAdapter::find`]: a GPU first, else a software one such as
    /// llvmpipe; the environment variable `XHAB_GPU_ADAPTER` picks one whose name contains
    /// it), opens a device without a window or surface, uploads the scene and builds the
    /// pipelines.
    pub fn new(scene: &Scene) -> Result<GpuRenderer, GpuError> {
        GpuRenderer::build(scene, None)
    }

    /// As [`GpuRenderer::new`], on an adapter already found.
    pub fn with_adapter(scene: &Scene, adapter: GpuAdapter) -> Result<GpuRenderer, GpuError> {
        GpuRenderer::build(scene, Some(adapter))
    }

    /// [`GpuRenderer::new`] on `adapter`, else on the adapter found once the scene is known to
    /// have triangles (an empty scene needs no device).
    fn build(scene: &Scene, adapter: Option<GpuAdapter>) -> Result<GpuRenderer, GpuError> {
        // Gather the geometry first: an empty scene needs no device.
        let mut positions: Vec<[f32; 3]> = Vec::new();
        // Triangles: corner indices into `positions` and their colour attributes.
        let mut tris: Vec<([u32; 3], TriAttr)> = Vec::new();
        let surfaces = Surfaces::new(scene);
        let (texel_bytes, tex_table, first_level) = texture_tables(&surfaces);
        for (k, m) in scene.meshes.iter().enumerate() {
            let mat = &surfaces.materials[k];
            // Textured: the linear factor and the table entry of the texture's level 0; else
            // the sRGB bytes (0..255).
            let (color, tex) = match mat.texture.and_then(|t| first_level.get(t as usize)) {
                Some(&first) => (mat.factor, first),
                None => (mat.flat.map(|b| b as f32), u32::MAX),
            };
            let size = mat.texture.and_then(|t| surfaces.textures.get(t as usize)).map_or(0, |c| c.levels[0].width.max(c.levels[0].height));
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
                let uv = if tex == u32::MAX { [[0.0; 2]; 3] } else { t.map(|i| m.uvs.get(i as usize).copied().unwrap_or_default()) };
                let scale = if tex == u32::MAX { 0.0 } else { texel_scale(&t.map(|i| m.positions[i as usize]), &uv, size) };
                let attr = TriAttr { n: [(n[0] / l) as f32, (n[1] / l) as f32, (n[2] / l) as f32], color, uv, tex, scale };
                tris.push((t.map(|i| i + base), attr));
            }
        }
        if tris.is_empty() {
            return Err(GpuError::EmptyScene);
        }
        let (tris, clusters) = cluster(&positions, tris);
        let indices: Vec<u32> = tris.iter().flat_map(|t| t.0).collect();
        let flat_pos: Vec<[f32; 3]> = tris.iter().flat_map(|t| t.0.map(|i| positions[i as usize])).collect();
        let mut flat_attr: Vec<u8> = Vec::with_capacity(tris.len() * 3 * TriAttr::VERTEX_BYTES as usize);
        for (_, a) in &tris {
            for corner in 0..3 {
                a.write_vertex(corner, &mut flat_attr);
            }
        }

        let gpu = match adapter {
            Some(a) => a,
            None => GpuAdapter::find()?,
        };
        let limits = gpu.adapter.limits();
        let limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        if texel_bytes.len() as u64 > limit {
            return Err(GpuError::Textures { bytes: texel_bytes.len() as u64, limit });
        }
        let (device, queue) = block(gpu.adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("xhab gpu camera"),
            required_features: wgpu::Features::empty(),
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::Device { adapter: gpu.describe(), message: e.to_string() })?;
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
            entries: &[0, 1, 2, 3].map(|binding| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: if binding == 0 { wgpu::ShaderStages::VERTEX } else { wgpu::ShaderStages::FRAGMENT },
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }),
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
            array_stride: TriAttr::VERTEX_BYTES,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![1 => Float32x3, 2 => Float32x3, 3 => Float32x2, 4 => Uint32, 5 => Float32],
        };
        let pipeline = |label: &str, vs: &str, fs: &str, buffers: &[Option<wgpu::VertexBufferLayout>], formats: &[wgpu::TextureFormat]| {
            let targets: Vec<Option<wgpu::ColorTargetState>> = formats.iter().map(|&format| Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL })).collect();
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
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let depth_pipeline = pipeline("depth", "vs_depth", "fs_depth", &[Some(pos_layout.clone())], Kind::Depth.formats());
        let rgb_buffers = [Some(pos_layout), Some(attr_layout)];
        let rgb_pipeline = pipeline("rgb", "vs_rgb", "fs_rgb", &rgb_buffers, Kind::Rgb.formats());
        let depth_rgb_pipeline = pipeline("depth and rgb", "vs_rgb", "fs_depth_rgb", &rgb_buffers, Kind::DepthRgb.formats());
        let bytes = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
        let buffer = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let vertex = wgpu::BufferUsages::VERTEX;
        let positions_buf = buffer("positions", &bytes(positions.as_flattened()), vertex);
        let index_bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let indices_buf = buffer("indices", &index_bytes, wgpu::BufferUsages::INDEX);
        let flat_positions = buffer("triangle positions", &bytes(flat_pos.as_flattened()), vertex);
        let flat_attrs = buffer("triangle normals, colours and texture coordinates", &flat_attr, vertex);
        let storage = wgpu::BufferUsages::STORAGE;
        let texels = buffer("texels", &texel_bytes, storage);
        let tex_table = buffer("texture table", &tex_table, storage);
        let srgb = buffer("srgb table", &bytes(srgb_table()), storage);
        check(block(oom.pop()))?;
        check(block(scope.pop()))?;

        Ok(GpuRenderer {
            max_dim: limits.max_texture_dimension_2d,
            max_layers: limits.max_texture_array_layers,
            max_buffer: limits.max_buffer_size,
            max_views_binding: limits.max_storage_buffer_binding_size,
            gpu,
            device,
            queue,
            bind_layout,
            depth_pipeline,
            rgb_pipeline,
            depth_rgb_pipeline,
            positions: positions_buf,
            indices: indices_buf,
            index_count: indices.len() as u32,
            flat_positions,
            flat_attrs,
            flat_count: flat_pos.len() as u32,
            texels,
            tex_table,
            srgb,
            targets: Mutex::new(HashMap::new()),
            clusters,
        })
    }

    /// The adapter in use: name, backend, device type and driver.
    pub fn adapter_info(&self) -> String {
        self.gpu.describe()
    }

    /// True when the adapter renders on the CPU (device type `Cpu`, e.g. Mesa's llvmpipe).
    pub fn is_software(&self) -> bool {
        self.gpu.is_software()
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
        self.render(Kind::Depth, views, cam, &mut |px: &[u8]| out.push(depth_image(px, cam)))?;
        Ok(out)
    }

    /// Renders the colour image seen from the robot at `base` (RGB bytes, row-major, top row
    /// first), as [`super::render_rgb`] does: the base colour of the nearest triangle (factor
    /// times texture, sRGB) shaded by `0.35 + 0.65 |cos incidence|` ([`super::surface`]),
    /// black where nothing is seen within `max_depth`.
    pub fn render_rgb(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> Result<Vec<u8>, GpuError> {
        Ok(self.render_rgb_batch(&[(base, floor_z)], cam)?.remove(0))
    }

    /// Renders the colour images of many views (robot pose, floor height in m) in one
    /// submission; each image as [`GpuRenderer::render_rgb`] gives it.
    pub fn render_rgb_batch(&self, views: &[(Pose2, f64)], cam: &CameraParams) -> Result<Vec<Vec<u8>>, GpuError> {
        let mut out = Vec::with_capacity(views.len());
        self.render(Kind::Rgb, views, cam, &mut |px: &[u8]| out.push(rgb_bytes(px)))?;
        Ok(out)
    }

    /// Renders the depth image ([`GpuRenderer::render_depth`], to the bit) and the colour image
    /// ([`GpuRenderer::render_rgb`]) of one view in one pass.
    pub fn render_depth_rgb(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> Result<(DepthImage, Vec<u8>), GpuError> {
        Ok(self.render_depth_rgb_batch(&[(base, floor_z)], cam)?.remove(0))
    }

    /// Renders the depth and colour images of many views in one submission, each view in one
    /// pass ([`GpuRenderer::render_depth_rgb`]).
    pub fn render_depth_rgb_batch(&self, views: &[(Pose2, f64)], cam: &CameraParams) -> Result<Vec<(DepthImage, Vec<u8>)>, GpuError> {
        let mut out = Vec::with_capacity(views.len());
        self.render(Kind::DepthRgb, views, cam, &mut |px: &[u8]| {
            let (depth, rgb) = px.split_at(cam.width * cam.height * 4);
            out.push((depth_image(depth, cam), rgb_bytes(rgb)));
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

    /// Views that fit in one submission of `w` x `h` images of `kind` (array layers, readback
    /// buffer size, view buffer binding).
    fn chunk_size(&self, kind: Kind, w: usize, h: usize) -> usize {
        let row_bytes = (w * 4).next_multiple_of(256) as u64;
        let by_buffer = (self.max_buffer / (row_bytes * h as u64 * kind.formats().len() as u64)).max(1) as usize;
        let by_binding = (self.max_views_binding / ViewUniform::SIZE).max(1) as usize;
        (self.max_layers as usize).min(by_buffer).min(by_binding).clamp(1, 256)
    }

    /// Renders `views` in chunks that fit one submission; calls `emit` with each view's pixels
    /// (4 bytes each, row-major, tightly packed; the kind's attachments one after the other),
    /// in order.
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
        let chunk = self.chunk_size(kind, w, h);
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
        let colors: Vec<wgpu::Texture> =
            kind.formats().iter().map(|&format| texture("camera images", format, n as u32, wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC)).collect();
        let depth = texture("z buffer", wgpu::TextureFormat::Depth32Float, 1, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let layers = (0..n as u32)
            .map(|i| {
                colors
                    .iter()
                    .map(|color| {
                        color.create_view(&wgpu::TextureViewDescriptor {
                            label: Some("camera image"),
                            dimension: Some(wgpu::TextureViewDimension::D2),
                            base_array_layer: i,
                            array_layer_count: Some(1),
                            ..Default::default()
                        })
                    })
                    .collect()
            })
            .collect();
        let padded_row = (w as u32 * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: padded_row as u64 * (h * n * colors.len()) as u64,
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
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: views.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: self.texels.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: self.tex_table.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: self.srgb.as_entire_binding() },
            ],
        });
        let t = Target { layers, colors, depth_view: depth.create_view(&Default::default()), padded_row, readback, views, bind_group };
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
            let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = layer
                .iter()
                .map(|view| {
                    Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Store },
                    })
                })
                .collect();
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("camera view"),
                color_attachments: &attachments,
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
                Kind::Rgb | Kind::DepthRgb => {
                    pass.set_pipeline(if kind == Kind::Rgb { &self.rgb_pipeline } else { &self.depth_rgb_pipeline });
                    pass.set_vertex_buffer(0, self.flat_positions.slice(..));
                    pass.set_vertex_buffer(1, self.flat_attrs.slice(..));
                    for r in ranges {
                        pass.draw(3 * r.start..3 * r.end, inst.clone());
                    }
                }
            }
        }
        // Each attachment's layers after the previous attachment's.
        let attachment_bytes = t.padded_row as usize * h * views.len();
        for (k, color) in t.colors.iter().enumerate() {
            enc.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo { texture: color, mip_level: 0, origin: wgpu::Origin3d::ZERO, aspect: wgpu::TextureAspect::All },
                wgpu::TexelCopyBufferInfo {
                    buffer: &t.readback,
                    layout: wgpu::TexelCopyBufferLayout { offset: (k * attachment_bytes) as u64, bytes_per_row: Some(t.padded_row), rows_per_image: Some(h as u32) },
                },
                wgpu::Extent3d { width: w as u32, height: h as u32, depth_or_array_layers: views.len() as u32 },
            );
        }
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
            let image = w * h * 4;
            let mut px = vec![0u8; image * t.colors.len()];
            for i in 0..views.len() {
                for k in 0..t.colors.len() {
                    for r in 0..h {
                        let start = k * attachment_bytes + (i * h + r) * t.padded_row as usize;
                        px[k * image + r * w * 4..][..w * 4].copy_from_slice(&data[start..start + w * 4]);
                    }
                }
                emit(&px);
            }
        }
        t.readback.unmap();
        Ok(())
    }
}

/// A view's depth image from its `R32Float` attachment's pixels (4 bytes each, tightly packed).
fn depth_image(px: &[u8], cam: &CameraParams) -> DepthImage {
    let data = px.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    DepthImage { width: cam.width, height: cam.height, data }
}

/// A view's RGB bytes from its RGBA8 attachment's pixels (alpha dropped).
fn rgb_bytes(px: &[u8]) -> Vec<u8> {
    px.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
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
fn cluster<T: Copy>(positions: &[[f32; 3]], tris: Vec<([u32; 3], T)>) -> (Vec<([u32; 3], T)>, Vec<Cluster>) {
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for t in &tris {
        for &i in &t.0 {
            for a in 0..3 {
                lo[a] = lo[a].min(positions[i as usize][a]);
                hi[a] = hi[a].max(positions[i as usize][a]);
            }
        }
    }
    let code = |t: &([u32; 3], T)| super::raster::morton_code(std::array::from_fn(|a| t.0.iter().map(|&i| positions[i as usize][a]).sum::<f32>() / 3.0), lo, hi);
    let mut keyed: Vec<(u64, usize)> = tris.iter().enumerate().map(|(i, t)| (code(t), i)).collect();
    keyed.sort_unstable();
    let tris: Vec<([u32; 3], T)> = keyed.iter().map(|&(_, i)| tris[i]).collect();
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

/// The colour attributes of one triangle for the RGB pipeline.
#[derive(Clone, Copy)]
struct TriAttr {
    /// Unit face normal (world).
    n: [f32; 3],
    /// sRGB bytes (0..255) when untextured, else the linear factor.
    color: [f32; 3],
    /// Texture coordinates of the corners.
    uv: [[f32; 2]; 3],
    /// Table entry of the texture's level 0, `u32::MAX` when untextured.
    tex: u32,
    /// Level-0 texels per metre ([`texel_scale`]; 0 when untextured).
    scale: f32,
}

impl TriAttr {
    /// Bytes of one vertex: normal, colour, texture coordinates (f32), texture (u32) and
    /// texels per metre (f32).
    const VERTEX_BYTES: u64 = 40;

    fn write_vertex(&self, corner: usize, out: &mut Vec<u8>) {
        for v in self.n.iter().chain(&self.color).chain(&self.uv[corner]) {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out.extend_from_slice(&self.tex.to_le_bytes());
        out.extend_from_slice(&self.scale.to_le_bytes());
    }
}

/// Every level of every texture's pyramid back to back (RGBA8 bytes, 4 per texel: one `u32`
/// each in the shader), the table the shader reads (one entry per level: its first texel,
/// width, height, and wrap modes `s | t << 8 | levels << 16`) and each texture's first entry.
/// The buffers are never empty (a storage binding must have a size).
fn texture_tables(surfaces: &Surfaces) -> (Vec<u8>, Vec<u8>, Vec<u32>) {
    let code = |w: Wrap| match w {
        Wrap::Repeat => 0u32,
        Wrap::ClampToEdge => 1,
        Wrap::MirroredRepeat => 2,
    };
    let mut texels = Vec::with_capacity(surfaces.textures.iter().flat_map(|c| &c.levels).map(|t| t.rgba.len()).sum());
    let mut table = Vec::new();
    let mut first = Vec::with_capacity(surfaces.textures.len());
    for c in &surfaces.textures {
        first.push((table.len() / 16) as u32);
        let levels = (c.levels.len() as u32).min(255);
        for t in c.levels.iter().take(levels as usize) {
            let offset = (texels.len() / 4) as u32;
            texels.extend_from_slice(&t.rgba);
            for v in [offset, t.width, t.height, code(t.wrap_s) | code(t.wrap_t) << 8 | levels << 16] {
                table.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    if texels.is_empty() {
        texels.resize(4, 0);
    }
    if table.is_empty() {
        table.resize(16, 0);
    }
    (texels, table, first)
}
