//! Colour images: the nearest triangle's id at every pixel (drawn by the same row spans as
//! depth, the clusters dealt to one buffer per thread as for depth), then each pixel shaded by the colour rule of [`crate::sensors::surface`]. What a
//! pixel needs of its triangle (normal, the plane's barycentric basis) is worked out once per
//! run of pixels that see the same triangle, not once per pixel.

use super::depth::{depth_of, MERGE_ROWS};
use super::{span, HiZ, RasterScene, Setup, Target, View, Vis};
use crate::sensors::camera::CameraParams;
use crate::sensors::surface::shade;
use rayon::prelude::*;
use xhab_types::{DepthImage, Pose2};

/// One triangle as the shading of its pixels needs it (world frame, f64): the ray
/// `origin + t dir` meets its plane at `t = -n_oa / (n . dir)`, at the point `oa + t dir`
/// relative to corner 0, whose weights of corners 1 and 2 are its dot products with `m1`, `m2`.
struct TriShading {
    id: u32,
    /// Normal (not unit) and its length.
    n: [f64; 3],
    ln: f64,
    /// The camera origin relative to corner 0, and `n . oa`.
    oa: [f64; 3],
    n_oa: f64,
    /// `(e2 x n) / |n|^2` and `(n x e1) / |n|^2`, with `e1`, `e2` the edges from corner 0.
    m1: [f64; 3],
    m2: [f64; 3],
}

impl TriShading {
    fn new(id: u32, v: &[[f32; 3]; 3], origin: [f64; 3]) -> TriShading {
        let a = v[0].map(|x| x as f64);
        let sub = |p: [f32; 3]| [p[0] as f64 - a[0], p[1] as f64 - a[1], p[2] as f64 - a[2]];
        let (e1, e2) = (sub(v[1]), sub(v[2]));
        let n = cross(e1, e2);
        let nn = dot(n, n);
        let oa = [origin[0] - a[0], origin[1] - a[1], origin[2] - a[2]];
        TriShading { id, n, ln: nn.sqrt().max(1e-300), oa, n_oa: dot(n, oa), m1: cross(e2, n).map(|x| x / nn), m2: cross(n, e1).map(|x| x / nn) }
    }

    /// Barycentric weights where the ray along `dir` meets the plane, given `denom = n . dir`;
    /// the centroid for a ray parallel to the plane or a degenerate triangle.
    #[inline]
    fn barycentric(&self, dir: [f64; 3], denom: f64) -> [f64; 3] {
        let t = -self.n_oa / denom;
        let ap = [self.oa[0] + t * dir[0], self.oa[1] + t * dir[1], self.oa[2] + t * dir[2]];
        let (b1, b2) = (dot(ap, self.m1), dot(ap, self.m2));
        if !(b1.is_finite() && b2.is_finite()) {
            return [1.0 / 3.0; 3];
        }
        [1.0 - b1 - b2, b1, b2]
    }
}

/// A view's inverse depth (1/m, rows of `view.w`) and the triangle seen at each pixel.
struct Ids {
    zb: Vec<f32>,
    ids: Vec<u32>,
}

impl Target for Ids {
    fn draw(&mut self, view: &View, tris: &[Setup]) {
        span::raster_ids(view, tris, &mut self.zb, &mut self.ids);
    }

    fn hiz(&self, view: &View) -> HiZ {
        HiZ::new(view, self.zb.chunks(view.w))
    }
}

impl RasterScene {
    /// Inverse depth (1/m, `1 / max_depth` where nothing is hit) and triangle ids (`u32::MAX`
    /// where none) of a view, its clusters dealt to `parts` buffers drawn in parallel and
    /// merged as each buffer keeps its pixels (the nearest, then the smaller id), so the
    /// result does not depend on `parts`.
    fn ids(&self, view: &View, parts: usize) -> (Vec<f32>, Vec<u32>) {
        let (w, n) = (view.w, view.w * view.h);
        let draw = |mine: &Vec<Vis>| {
            let mut t = Ids { zb: vec![1.0 / view.far; n], ids: vec![u32::MAX; n] };
            self.render_clusters(view, mine, &mut t);
            t
        };
        let lists = self.deal(view, parts);
        let mut bufs: Vec<Ids> = if lists.len() == 1 { vec![draw(&lists[0])] } else { lists.par_iter().map(draw).collect() };
        let Ids { mut zb, mut ids } = bufs.swap_remove(0);
        let rows = w * MERGE_ROWS;
        zb.par_chunks_mut(rows).zip(ids.par_chunks_mut(rows)).enumerate().for_each(|(i, (zc, ic))| {
            for b in &bufs {
                for (j, (z, id)) in zc.iter_mut().zip(ic.iter_mut()).enumerate() {
                    let (oz, oid) = (b.zb[i * rows + j], b.ids[i * rows + j]);
                    if oz > *z || (oz == *z && oid < *id) {
                        *z = oz;
                        *id = oid;
                    }
                }
            }
        });
        (zb, ids)
    }

    /// Renders the colour image seen from the robot at `base` (RGB bytes, row-major, top row
    /// first), as [`crate::sensors::render_rgb`] does: the base colour of the nearest triangle
    /// at the pixel's ray (factor times texture, the texture coordinates interpolated from
    /// where the ray meets the triangle's plane, so perspective-correct) shaded by
    /// `0.35 + 0.65 |cos incidence|` ([`crate::sensors::surface`]), black where nothing is hit
    /// within `max_depth`.
    pub fn render_rgb(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> Vec<u8> {
        self.render_depth_rgb(base, floor_z, cam).1
    }

    /// The depth image ([`RasterScene::render_depth`], to the bit) and the colour image
    /// ([`RasterScene::render_rgb`]) of one view, from one rasterisation.
    pub fn render_depth_rgb(&self, base: Pose2, floor_z: f64, cam: &CameraParams) -> (DepthImage, Vec<u8>) {
        if cam.width == 0 || cam.height == 0 {
            return (DepthImage { width: cam.width, height: cam.height, data: Vec::new() }, Vec::new());
        }
        let (zb, ids) = self.ids(&View::new(base, floor_z, cam), rayon::current_num_threads());
        let far = cam.max_depth as f32;
        let depth = DepthImage { width: cam.width, height: cam.height, data: zb.iter().map(|&z| depth_of(z, far)).collect() };
        let k = cam.intrinsics();
        let (s, c) = base.yaw.sin_cos();
        let origin = [base.x, base.y, floor_z + cam.mount_height];
        let mut data = vec![0u8; cam.width * cam.height * 3];
        data.par_chunks_mut(cam.width * 3).enumerate().for_each(|(v, row)| {
            let y = (v as f64 - k.cy) / k.fy;
            let mut tri: Option<TriShading> = None;
            for u in 0..cam.width {
                let id = ids[v * cam.width + u];
                if id == u32::MAX || depth.data[v * cam.width + u] == 0.0 {
                    continue;
                }
                let x = (u as f64 - k.cx) / k.fx;
                let dir = [c + x * s, s - x * c, -y];
                let t = match &tri {
                    Some(t) if t.id == id => t,
                    _ => tri.insert(TriShading::new(id, &self.tris[id as usize].v, origin)),
                };
                let denom = dot(t.n, dir);
                let cos = (denom / (t.ln * dot(dir, dir).sqrt())).abs();
                let color = self.surfaces.color(&self.surf[id as usize], || t.barycentric(dir, denom));
                row[u * 3..u * 3 + 3].copy_from_slice(&shade(color, cos));
            }
        });
        (depth, data)
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
