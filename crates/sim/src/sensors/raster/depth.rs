//! Depth images: the clusters in view are dealt round-robin (in nearest-first order) to as
//! many whole-image inverse depth buffers as there are threads, drawn in parallel, and the
//! buffers merged by keeping the nearest at each pixel. Keeping the nearest does not depend on
//! the order of drawing, so the image is the one-buffer image to the bit, whatever the number
//! of threads; and unlike splitting the image, no cluster is set up twice.

use super::{span, HiZ, RasterScene, Setup, Target, View, Vis};
use crate::sensors::camera::CameraParams;
use rayon::prelude::*;
use xhab_types::{DepthImage, Pose2};

/// Rows merged and converted per task.
pub(super) const MERGE_ROWS: usize = 32;

/// An image's rows, holding inverse depth (1/m) while drawing.
struct Rows<'a> {
    rows: Vec<&'a mut [f32]>,
}

impl Target for Rows<'_> {
    fn draw(&mut self, view: &View, tris: &[Setup]) {
        span::raster_depth(view, tris, &mut self.rows);
    }

    fn hiz(&self, view: &View) -> HiZ {
        HiZ::new(view, self.rows.iter().map(|r| &**r))
    }
}

impl RasterScene {
    /// The depth image from `base` on the floor at `floor_z`, its clusters drawn into `parts`
    /// buffers (in parallel when more than one) and merged.
    pub(super) fn depth(&self, base: Pose2, floor_z: f64, cam: &CameraParams, parts: usize) -> DepthImage {
        let (w, h) = (cam.width, cam.height);
        if w == 0 || h == 0 {
            return DepthImage { width: w, height: h, data: Vec::new() };
        }
        let view = View::new(base, floor_z, cam);
        let lists = self.deal(&view, parts);
        let draw = |mine: &Vec<Vis>| {
            let mut data = vec![1.0 / view.far; w * h];
            self.render_clusters(&view, mine, &mut Rows { rows: data.chunks_mut(w).collect() });
            data
        };
        let mut bufs: Vec<Vec<f32>> = if lists.len() == 1 { vec![draw(&lists[0])] } else { lists.par_iter().map(draw).collect() };
        let mut data = bufs.swap_remove(0);
        let far = view.far;
        data.par_chunks_mut(w * MERGE_ROWS).enumerate().for_each(|(i, chunk)| {
            for b in &bufs {
                for (z, o) in chunk.iter_mut().zip(&b[i * w * MERGE_ROWS..]) {
                    *z = if *o > *z { *o } else { *z };
                }
            }
            for z in chunk.iter_mut() {
                *z = depth_of(*z, far);
            }
        });
        DepthImage { width: w, height: h, data }
    }
}

/// The depth (m, 0 where nothing is hit within `far`) of a pixel whose inverse depth buffer
/// holds `inv` (1/m; `1 / far` where nothing was drawn).
#[inline(always)]
pub(super) fn depth_of(inv: f32, far: f32) -> f32 {
    let d = 1.0 / inv;
    if inv > 1.0 / far && d <= far {
        d
    } else {
        0.0
    }
}
