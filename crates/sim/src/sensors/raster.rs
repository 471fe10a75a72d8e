//! Pinhole depth and colour camera rendered by CPU rasterisation: the same images as the ray
//! caster ([`super::camera`]), many times faster.
//!
//! Triangles are grouped into spatial clusters (Morton order of their centroids) with
//! bounding boxes; each cluster also keeps its distinct corners (`corners.rs`), which a view
//! transforms and projects once, in a vectorised loop, to reject triangles that are behind the
//! near plane, beyond `max_depth` or cover no pixel centre before the full setup. Per view,
//! clusters outside the frustum or beyond `max_depth` are culled and the rest sorted nearest
//! first; the nearest quarter is drawn, then the others are drawn unless every 16 x 16 tile
//! their rectangle covers is already nearer (hierarchical z).
//!
//! Coverage uses homogeneous edge functions (the ray through a pixel centre hits the triangle
//! iff it lies in the cone spanned by the camera-frame corners), so triangles crossing the
//! camera plane need no clipping for coverage; only their pixel bounding box is taken from
//! the part in front of a near plane. Triangles are drawn by row spans (`span.rs`: one
//! crossing column per edge and row, computed so that the two triangles of a shared edge
//! agree to the bit, which settles ties on shared edges by a top-left rule). Inverse depth
//! (linear in the image) is interpolated from the triangle's plane, and a buffer keeps the
//! nearest.
//!
//! A single view deals its clusters to one buffer per thread and keeps the nearest of them
//! (`depth.rs`). A colour view keeps the triangle id beside the inverse depth (so its depth
//! is the depth image to the bit), equally near triangles settled by the smaller id, and
//! shades each pixel from its triangle (`color.rs`). A batch renders one view per task.
//! Results do not depend on the number of threads.

use super::camera::CameraParams;
use super::surface::{SurfaceTri, Surfaces};
use crate::rounding::{ceil_bounded, floor_bounded};
use crate::scene::Scene;
use rayon::prelude::*;
use xhab_types::{DepthImage, Pose2};

mod color;
mod corners;
mod depth;
mod span;

use corners::{ClusterCorners, ViewCorners, MARGIN};

/// Triangles per cluster.
const CLUSTER: usize = 96;
/// Near plane for bounding boxes (m): surfaces closer than this may be missed.
const NEAR: f32 = 1e-3;

/// One scene triangle: corners in the world frame (m).
#[derive(Clone, Copy)]
struct Tri {
    v: [[f32; 3]; 3],
}

/// A run of triangles and its axis-aligned bounding box (world, m).
#[derive(Clone, Copy)]
struct Cluster {
    min: [f32; 3],
    max: [f32; 3],
    start: u32,
    end: u32,
}

/// The scene's triangles in spatial clusters, for rasterising depth and colour images; built
/// once and shared between threads (it is `Sync`).
pub struct RasterScene {
    tris: Vec<Tri>,
    clusters: Vec<Cluster>,
    /// Texture coordinates and material of each triangle of `tris` (same order), for colour.
    surf: Vec<SurfaceTri>,
    /// The scene's materials and textures.
    surfaces: Surfaces,
    corners: ClusterCorners,
}

impl std::fmt::Debug for RasterScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "RasterScene({} triangles, {} clusters)", self.tris.len(), self.clusters.len())
    }
}

/// The 30-bit Morton code of point `p` quantised to 1024 steps per axis in the box `[lo, hi]`
/// (shared by the rasteriser's and the GPU renderer's triangle clusters).
pub(crate) fn morton_code(p: [f32; 3], lo: [f32; 3], hi: [f32; 3]) -> u64 {
    let mut m = 0u64;
    for i in 0..3 {
        let q = ((p[i] - lo[i]) / (hi[i] - lo[i]).max(1e-6) * 1023.0).clamp(0.0, 1023.0) as u32;
        m |= spread3(q) << i;
    }
    m
}

/// Spreads the low 10 bits of `x` to every third bit.
fn spread3(x: u32) -> u64 {
    let mut x = (x & 0x3ff) as u64;
    x = (x | (x << 16)) & 0x0300_00ff;
    x = (x | (x << 8)) & 0x0300_f00f;
    x = (x | (x << 4)) & 0x030c_30c3;
    (x | (x << 2)) & 0x0924_9249
}

/// The camera of one view: pose, intrinsics and frustum (camera frame x right, y down, z
/// forward; `xu`, `yv` are pixel coordinates relative to the principal point).
struct View {
    o: [f32; 3],
    s: f32,
    c: f32,
    cx: f32,
    cy: f32,
    inv_fx: f32,
    inv_fy: f32,
    fx: f32,
    fy: f32,
    w: usize,
    h: usize,
    far: f32,
    /// Frustum slopes x/z (left, right) and y/z (top, bottom), one pixel beyond the image.
    slopes: [f32; 4],
}

impl View {
    /// The camera's view from the robot at `base` on the floor at `floor_z` (m).
    fn new(base: Pose2, floor_z: f64, cam: &CameraParams) -> View {
        let k = cam.intrinsics();
        let (s, c) = base.yaw.sin_cos();
        let (w, h) = (cam.width, cam.height);
        View {
            o: [base.x as f32, base.y as f32, (floor_z + cam.mount_height) as f32],
            s: s as f32,
            c: c as f32,
            cx: k.cx as f32,
            cy: k.cy as f32,
            inv_fx: (1.0 / k.fx) as f32,
            inv_fy: (1.0 / k.fy) as f32,
            fx: k.fx as f32,
            fy: k.fy as f32,
            w,
            h,
            far: cam.max_depth as f32,
            slopes: [
                ((-k.cx - 1.0) / k.fx) as f32,
                ((w as f64 - k.cx) / k.fx) as f32,
                ((-k.cy - 1.0) / k.fy) as f32,
                ((h as f64 - k.cy) / k.fy) as f32,
            ],
        }
    }

    /// World point to the camera frame (m).
    #[inline(always)]
    fn to_cam(&self, p: [f32; 3]) -> [f32; 3] {
        let dx = p[0] - self.o[0];
        let dy = p[1] - self.o[1];
        [dx * self.s - dy * self.c, self.o[2] - p[2], dx * self.c + dy * self.s]
    }

    /// Bits of the frustum planes (near, far, left, right, top, bottom) that a camera-frame
    /// point lies outside of.
    #[inline(always)]
    fn outcode(&self, p: [f32; 3]) -> u32 {
        let [xl, xr, yt, yb] = self.slopes;
        (p[2] < NEAR) as u32
            | ((p[2] > self.far) as u32) << 1
            | ((p[0] < xl * p[2]) as u32) << 2
            | ((p[0] > xr * p[2]) as u32) << 3
            | ((p[1] < yt * p[2]) as u32) << 4
            | ((p[1] > yb * p[2]) as u32) << 5
    }
}

/// A cluster in view: index, nearest depth (m), pixel rectangle `[u0, u1, v0, v1]` inclusive.
#[derive(Clone, Copy)]
struct Vis {
    idx: u32,
    zmin: f32,
    rect: [u16; 4],
}

/// Side of the square tiles of [`HiZ`] (px).
const TILE: usize = 16;

/// The farthest inverse depth drawn in each tile of an image: what lies behind it everywhere
/// is hidden.
struct HiZ {
    tw: usize,
    min_inv: Vec<f32>,
}

impl HiZ {
    /// The tiles of the view's inverse depth `zb` (rows of `view.w`).
    fn new(view: &View, zb: &[f32]) -> HiZ {
        let tw = view.w.div_ceil(TILE);
        let mut min_inv = vec![f32::INFINITY; tw * view.h.div_ceil(TILE)];
        for (v, row) in zb.chunks(view.w).enumerate() {
            let t = &mut min_inv[v / TILE * tw..][..tw];
            for (i, chunk) in row.chunks(TILE).enumerate() {
                t[i] = chunk.iter().fold(t[i], |m, &z| m.min(z));
            }
        }
        HiZ { tw, min_inv }
    }

    /// True when everything drawn over the cluster's rectangle is nearer than its nearest point.
    fn occludes(&self, v: &Vis) -> bool {
        if v.zmin < NEAR {
            return false;
        }
        let inv = 1.0 / v.zmin;
        let [u0, u1, v0, v1] = v.rect.map(|x| x as usize / TILE);
        (v0..=v1).all(|ty| self.min_inv[ty * self.tw + u0..=ty * self.tw + u1].iter().all(|&m| m > inv))
    }
}

/// A triangle ready to rasterise: for each edge `e * xu + f * yv + g >= t` inside, inverse
/// depth `a * xu + b * yv + c` (1/m), pixel bounding box (inclusive) and triangle index.
#[derive(Clone, Copy)]
struct Setup {
    edges: [[f32; 4]; 3],
    inv_z: [f32; 3],
    bbox: [u16; 4],
    id: u32,
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The pixel bounding box `[u0, u1, v0, v1]` of the part of camera-frame triangle `p` in front
/// of the near plane, or `None` when none of it is.
fn clipped_bbox(view: &View, p: [[f32; 3]; 3]) -> Option<[i32; 4]> {
    let (mut x0, mut x1, mut y0, mut y1) = (f32::INFINITY, f32::NEG_INFINITY, f32::INFINITY, f32::NEG_INFINITY);
    let mut add = |q: [f32; 3]| {
        let r = 1.0 / q[2];
        let (x, y) = (view.cx + view.fx * (q[0] * r), view.cy + view.fy * (q[1] * r));
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    };
    for i in 0..3 {
        let (a, b) = (p[i], p[(i + 1) % 3]);
        if a[2] >= NEAR {
            add(a);
        }
        if (a[2] < NEAR) != (b[2] < NEAR) {
            let t = (NEAR - a[2]) / (b[2] - a[2]);
            add([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), NEAR]);
        }
    }
    if x0 > x1 {
        return None;
    }
    let (wm, hm) = (view.w as i32 - 1, view.h as i32 - 1);
    Some([
        // (`min` and `max` drop NaN, so the bounds are numbers: clamped, they are bounded.)
        ceil_bounded((x0 - MARGIN).clamp(-1.0, view.w as f32)).max(0),
        floor_bounded((x1 + MARGIN).clamp(-1.0, view.w as f32)).min(wm),
        ceil_bounded((y0 - MARGIN).clamp(-1.0, view.h as f32)).max(0),
        floor_bounded((y1 + MARGIN).clamp(-1.0, view.h as f32)).min(hm),
    ])
}

/// Sets up one camera-frame triangle `p` with pixel bounding box `bbox` (computed here when
/// `None`), or `None` when it covers no pixel centre.
#[inline(always)]
fn setup(view: &View, p: [[f32; 3]; 3], bbox: Option<[i32; 4]>, id: u32) -> Option<Setup> {
    let [u0, u1, v0, v1] = match bbox {
        Some(b) => b,
        None => clipped_bbox(view, p)?,
    };
    if u0 > u1 || v0 > v1 {
        return None;
    }
    // Plane n . q = d; inverse depth along the pixel ray (xu/fx, yv/fy, 1) is n . r / d.
    let [a, b, c] = p;
    let n = cross([b[0] - a[0], b[1] - a[1], b[2] - a[2]], [c[0] - a[0], c[1] - a[1], c[2] - a[2]]);
    let d = dot(n, a);
    if !(d.abs() > 1e-12) {
        return None;
    }
    let sign = if d > 0.0 { 1.0 } else { -1.0 };
    let inv_z = [n[0] * view.inv_fx / d, n[1] * view.inv_fy / d, n[2] / d];
    // Edge opposite each corner: the ray is inside iff sign * (q_i x q_j) . r >= 0 for all.
    let edge = |q: [f32; 3], r: [f32; 3]| {
        let k = cross(q, r);
        let (e, f, g) = (sign * k[0] * view.inv_fx, sign * k[1] * view.inv_fy, sign * k[2]);
        // Top-left rule: a pixel centre exactly on an edge belongs to one side only.
        let t = if e > 0.0 || (e == 0.0 && f > 0.0) { 0.0 } else { f32::from_bits(1) };
        [e, f, g, t]
    };
    Some(Setup {
        edges: [edge(a, b), edge(b, c), edge(c, a)],
        inv_z,
        bbox: [u0 as u16, u1 as u16, v0 as u16, v1 as u16],
        id,
    })
}

/// What a view is drawn into: an inverse depth buffer (rows of `view.w`) that keeps the
/// nearest, and whatever else the image needs.
trait Target {
    /// Rasterises set-up triangles.
    fn draw(&mut self, view: &View, tris: &[Setup]);
    /// The inverse depth drawn so far (1/m).
    fn zb(&self) -> &[f32];
}

/// Rows merged (and converted) per task when the buffers of one view are merged.
const MERGE_ROWS: usize = 32;

impl RasterScene {
    /// Gathers the scene's triangles into clusters; `None` for a scene without triangles.
    pub fn new(scene: &Scene) -> Option<RasterScene> {
        let mut tris = Vec::with_capacity(scene.triangle_count());
        for m in &scene.meshes {
            for t in 0..m.indices.len() {
                tris.push(Tri { v: m.triangle(t) });
            }
        }
        let surf = Surfaces::triangles(scene);
        if tris.is_empty() {
            return None;
        }
        let b = scene.bounds();
        let code = |t: &Tri| morton_code(std::array::from_fn(|i| (t.v[0][i] + t.v[1][i] + t.v[2][i]) / 3.0), b.min, b.max);
        let mut keyed: Vec<(u64, usize)> = tris.iter().enumerate().map(|(i, t)| (code(t), i)).collect();
        keyed.sort_unstable();
        let tris: Vec<Tri> = keyed.iter().map(|&(_, i)| tris[i]).collect();
        let surf: Vec<SurfaceTri> = keyed.iter().map(|&(_, i)| surf[i]).collect();
        let clusters: Vec<Cluster> = (0..tris.len())
            .step_by(CLUSTER)
            .map(|start| {
                let end = (start + CLUSTER).min(tris.len());
                let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
                for t in &tris[start..end] {
                    for p in t.v {
                        for i in 0..3 {
                            min[i] = min[i].min(p[i]);
                            max[i] = max[i].max(p[i]);
                        }
                    }
                }
                Cluster { min, max, start: start as u32, end: end as u32 }
            })
            .collect();
        let corners = ClusterCorners::new(&tris, &clusters);
        Some(RasterScene { tris, clusters, surf, surfaces: Surfaces::new(scene), corners })
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// Clusters in the view frustum, nearest first, with their nearest depth (m) and pixel
    /// rectangle (inclusive; the whole image when they reach the near plane).
    fn visible(&self, view: &View) -> Vec<Vis> {
        let full = [0, view.w as u16 - 1, 0, view.h as u16 - 1];
        let mut vis: Vec<Vis> = Vec::new();
        for (idx, cl) in self.clusters.iter().enumerate() {
            let mut corners = [[0f32; 3]; 8];
            for (i, q) in corners.iter_mut().enumerate() {
                let pick = |k: usize| if i >> k & 1 == 0 { cl.min[k] } else { cl.max[k] };
                *q = view.to_cam([pick(0), pick(1), pick(2)]);
            }
            if corners.iter().fold(u32::MAX, |m, &q| m & view.outcode(q)) != 0 {
                continue;
            }
            let zmin = corners.iter().fold(f32::INFINITY, |m, q| m.min(q[2]));
            let rect = if zmin < NEAR {
                full
            } else {
                let (mut x0, mut x1, mut y0, mut y1) = (f32::INFINITY, f32::NEG_INFINITY, f32::INFINITY, f32::NEG_INFINITY);
                for q in corners {
                    let (x, y) = (q[0] / q[2], q[1] / q[2]);
                    (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
                }
                // One pixel of margin against rounding, then limited to the image (n >= 1 px).
                // (`min` and `max` drop NaN, so the bounds are numbers: clamped, they are bounded.)
                let lo = |c: f32, f: f32, x: f32, n: usize| (floor_bounded((c + f * x).clamp(-1.0, n as f32)) - 1).clamp(0, n as i32 - 1) as u16;
                let hi = |c: f32, f: f32, x: f32, n: usize| (ceil_bounded((c + f * x).clamp(-1.0, n as f32)) + 1).clamp(0, n as i32 - 1) as u16;
                [lo(view.cx, view.fx, x0, view.w), hi(view.cx, view.fx, x1, view.w), lo(view.cy, view.fy, y0, view.h), hi(view.cy, view.fy, y1, view.h)]
            };
            vis.push(Vis { idx: idx as u32, zmin, rect });
        }
        vis.sort_unstable_by(|a, b| a.zmin.total_cmp(&b.zmin).then(a.idx.cmp(&b.idx)));
        vis
    }

    /// Draws the clusters in view into up to `parts` targets that `make` gives (at least one;
    /// in parallel when more than one), the clusters dealt round-robin in nearest-first order
    /// so that each target gets near and far ones alike. The caller merges the targets.
    fn draw_dealt<T: Target + Send>(&self, view: &View, parts: usize, make: impl Fn() -> T + Sync) -> Vec<T> {
        let vis = self.visible(view);
        let parts = parts.clamp(1, vis.len().max(1));
        let draw = |k: usize| {
            let mine: Vec<Vis> = vis.iter().skip(k).step_by(parts).copied().collect();
            let mut t = make();
            self.render_clusters(view, &mine, &mut t);
            t
        };
        if parts == 1 {
            vec![draw(0)]
        } else {
            (0..parts).into_par_iter().map(draw).collect()
        }
    }

    /// Sets up the triangles of the clusters `vis`, appending to `out`; `vc` is scratch.
    fn setup_clusters(&self, view: &View, vis: &[Vis], out: &mut Vec<Setup>, vc: &mut ViewCorners) {
        for v in vis {
            let cl = &self.clusters[v.idx as usize];
            self.corners.to_view(v.idx as usize, view, vc);
            for id in cl.start..cl.end {
                let c = self.corners.tri[id as usize];
                let Ok(bbox) = vc.bbox(c) else { continue };
                if bbox.is_some_and(|[u0, u1, v0, v1]| u0 > u1 || v0 > v1) {
                    continue;
                }
                if let Some(s) = setup(view, c.map(|i| vc.cam(i)), bbox, id) {
                    out.push(s);
                }
            }
        }
    }

    /// Draws the clusters `vis` (nearest first) into `target`; after the nearest quarter,
    /// those behind what is drawn over their whole rectangle are skipped.
    fn render_clusters<T: Target>(&self, view: &View, vis: &[Vis], target: &mut T) {
        let mut tris = Vec::new();
        let mut vc = ViewCorners::default();
        let split = if vis.len() > 64 { vis.len() / 4 } else { vis.len() };
        self.setup_clusters(view, &vis[..split], &mut tris, &mut vc);
        target.draw(view, &tris);
        if split < vis.len() {
            let hiz = HiZ::new(view, target.zb());
            let rest: Vec<Vis> = vis[split..].iter().filter(|v| !hiz.occludes(v)).copied().collect();
            tris.clear();
            self.setup_clusters(view, &rest, &mut tris, &mut vc);
            target.draw(view, &tris);
        }
    }

    /// Renders the depth image seen from the robot at `base` standing on the floor at
    /// `floor_z` (m), as [`super::render_depth`] does: depth along the optical axis (m), 0
    /// where nothing is hit within `max_depth`. Uses all rayon threads.
    pub fn render_depth(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> DepthImage {
        self.depth(base, floor_z, cam, rayon::current_num_threads())
    }

    /// Renders the depth images of many views (robot pose, floor height in m), one view per
    /// rayon task; each image as [`RasterScene::render_depth`] gives it.
    pub fn render_depth_batch(&self, views: &[(Pose2, f64)], cam: &CameraParams) -> Vec<DepthImage> {
        views.par_iter().map(|&(base, floor_z)| self.depth(base, floor_z, cam, 1)).collect()
    }
}
