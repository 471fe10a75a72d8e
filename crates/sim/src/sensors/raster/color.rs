//! Colour images: the nearest triangle's id at every pixel (drawn by the same row spans as
//! depth, the clusters dealt to one buffer per thread as for depth), then each pixel shaded
//! by the colour rule of [`crate::sensors::surface`]. What a pixel needs of its triangle (its
//! [`TrianglePlane`], its material) is worked out once per run of pixels that see the same
//! triangle.

use super::depth::depth_of;
use super::{span, RasterScene, Setup, Target, View, MERGE_ROWS};
use crate::sensors::camera::CameraParams;
use crate::sensors::mipmap::{footprint, level_and_weight};
use crate::sensors::surface::{shade, Paint, Srgb, TrianglePlane};
use rayon::prelude::*;
use xhab_types::{DepthImage, Pose2};

/// A view's inverse depth (1/m, rows of `view.w`) and the triangle seen at each pixel.
struct Ids {
    zb: Vec<f32>,
    ids: Vec<u32>,
}

impl Target for Ids {
    fn draw(&mut self, view: &View, tris: &[Setup]) {
        span::raster_ids(view, tris, &mut self.zb, &mut self.ids);
    }

    fn zb(&self) -> &[f32] {
        &self.zb
    }
}

impl RasterScene {
    /// Inverse depth (1/m, `1 / max_depth` where nothing is hit) and triangle ids (`u32::MAX`
    /// where none) of a view, its clusters drawn into `parts` buffers and merged as each
    /// buffer keeps its pixels (the nearest, then the smaller id), so the result does not
    /// depend on `parts`.
    fn ids(&self, view: &View, parts: usize) -> (Vec<f32>, Vec<u32>) {
        let n = view.w * view.h;
        let mut bufs = self.draw_dealt(view, parts, || Ids { zb: vec![1.0 / view.far; n], ids: vec![u32::MAX; n] });
        let Ids { mut zb, mut ids } = bufs.swap_remove(0);
        let rows = view.w * MERGE_ROWS;
        zb.par_chunks_mut(rows).zip(ids.par_chunks_mut(rows)).enumerate().for_each(|(i, (zc, ic))| {
            for b in &bufs {
                let (oz, oid) = (&b.zb[i * rows..], &b.ids[i * rows..]);
                for (j, (z, id)) in zc.iter_mut().zip(ic.iter_mut()).enumerate() {
                    if oz[j] > *z || (oz[j] == *z && oid[j] < *id) {
                        *z = oz[j];
                        *id = oid[j];
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
        self.depth_rgb(base, floor_z, cam, rayon::current_num_threads())
    }

    /// The depth and colour images of many views (robot pose, floor height in m), one view
    /// per rayon task; each pair as [`RasterScene::render_depth_rgb`] gives it.
    pub fn render_depth_rgb_batch(&self, views: &[(Pose2, f64)], cam: &CameraParams) -> Vec<(DepthImage, Vec<u8>)> {
        views.par_iter().map(|&(base, floor_z)| self.depth_rgb(base, floor_z, cam, 1)).collect()
    }

    /// [`RasterScene::render_depth_rgb`] with the view's clusters dealt to `parts` buffers
    /// and, for more than one, its rows coloured in parallel (the images do not depend on it).
    fn depth_rgb<'s>(&'s self, base: Pose2, floor_z: f64, cam: &CameraParams, parts: usize) -> (DepthImage, Vec<u8>) {
        if cam.width == 0 || cam.height == 0 {
            return (DepthImage { width: cam.width, height: cam.height, data: Vec::new() }, Vec::new());
        }
        let (zb, ids) = self.ids(&View::new(base, floor_z, cam), parts);
        let far = cam.max_depth as f32;
        let depth = DepthImage { width: cam.width, height: cam.height, data: zb.iter().map(|&z| depth_of(z, far)).collect() };
        let k = cam.intrinsics();
        let (s, c) = base.yaw.sin_cos();
        let origin = [base.x, base.y, floor_z + cam.mount_height];
        let pixel_angle = (1.0 / k.fx) as f32;
        let mut data = vec![0u8; cam.width * cam.height * 3];
        let w = cam.width;
        let xs: Vec<f64> = (0..w).map(|u| (u as f64 - k.cx) / k.fx).collect();
        let srgb = Srgb::get();
        // Per run of pixels that see one triangle: its plane along the row and how it is
        // painted, then per pixel one division for where its ray meets the plane. A row's
        // textured pixels are sampled after its geometry, in a second loop (each loop short
        // enough for the processor to keep several pixels in flight).
        let colour_row = |sc: &mut RowScratch<'s>, (v, row): (usize, &mut [u8])| {
            let y = (v as f64 - k.cy) / k.fy;
            // The ray through column offset x is d0 + x d1, of length sqrt(1 + x^2 + y^2).
            let (d0, d1) = ([c, s, -y], [s, -c, 0.0]);
            let (ids, depth) = (&ids[v * w..(v + 1) * w], &depth.data[v * w..(v + 1) * w]);
            sc.runs.clear();
            sc.texels.clear();
            let mut u = 0;
            while u < w {
                let id = ids[u];
                let end = u + ids[u..].iter().take_while(|&&i| i == id).count();
                if id == u32::MAX {
                    u = end;
                    continue;
                }
                let surf = &self.surf[id as usize];
                let rp = TrianglePlane::new(&self.tris[id as usize].v, origin).along(d0, d1, &surf.uv);
                let paint = self.surfaces.paint(surf);
                let first = sc.texels.len();
                for (px, (&x, &d)) in (u..end).zip(xs[u..end].iter().zip(&depth[u..end])) {
                    if d == 0.0 {
                        continue;
                    }
                    let denom = rp.denom(x);
                    let len = (1.0 + x * x + y * y).sqrt();
                    let cos = (denom / (rp.ln * len)).abs();
                    match paint {
                        Paint::Flat(col) => row[px * 3..px * 3 + 3].copy_from_slice(&shade(col, cos)),
                        Paint::Texture { chain, .. } => {
                            let (t, uv) = rp.hit(x, denom);
                            let fp = footprint((t * len) as f32, pixel_angle, cos as f32);
                            let (l, wt) = level_and_weight(fp, surf.texel_scale, chain.levels.len());
                            sc.texels.push(Texel { px: px as u32, l: l as u32, uv, wt, cos });
                        }
                    }
                }
                if sc.texels.len() > first {
                    sc.runs.push((paint, sc.texels.len()));
                }
                u = end;
            }
            let mut from = 0;
            for &(paint, to) in &sc.runs {
                for t in &sc.texels[from..to] {
                    let p = t.px as usize;
                    row[p * 3..p * 3 + 3].copy_from_slice(&shade(paint.at_level(srgb, t.uv, t.l as usize, t.wt), t.cos));
                }
                from = to;
            }
        };
        if parts > 1 {
            data.par_chunks_mut(w * 3).enumerate().for_each_init(RowScratch::default, colour_row);
        } else {
            let mut sc = RowScratch::default();
            data.chunks_mut(w * 3).enumerate().for_each(|r| colour_row(&mut sc, r));
        }
        (depth, data)
    }
}

/// Where a row's textured pixel samples its texture: column, level and weight of the next
/// ([`level_and_weight`]), texture coordinates, and the cosine of incidence it is shaded by.
struct Texel {
    px: u32,
    l: u32,
    uv: [f32; 2],
    wt: f32,
    cos: f64,
}

/// A row's textured pixels and, per run of them on one triangle, its paint and where its
/// pixels end in `texels`.
#[derive(Default)]
struct RowScratch<'a> {
    runs: Vec<(Paint<'a>, usize)>,
    texels: Vec<Texel>,
}
