//! Depth images: the clusters in view are dealt round-robin (in nearest-first order) to as
//! many whole-image inverse depth buffers as there are threads, drawn in parallel, and the
//! buffers merged by keeping the nearest at each pixel. Keeping the nearest does not depend on
//! the order of drawing, so the image is the one-buffer image to the bit, whatever the number
//! of threads; and unlike splitting the image, no cluster is set up twice.

use super::{span, RasterScene, Setup, Target, View, MERGE_ROWS};
use crate::sensors::camera::CameraParams;
use rayon::prelude::*;
use xhab_types::{DepthImage, Pose2};

/// A view's inverse depth (1/m, rows of `view.w`).
struct Depth(Vec<f32>);

impl Target for Depth {
    fn draw(&mut self, view: &View, tris: &[Setup]) {
        span::raster_depth(view, tris, &mut self.0);
    }

    fn zb(&self) -> &[f32] {
        &self.0
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
        let mut bufs = self.draw_dealt(&view, parts, || Depth(vec![1.0 / view.far; w * h]));
        let Depth(mut data) = bufs.swap_remove(0);
        let rows = w * MERGE_ROWS;
        data.par_chunks_mut(rows).enumerate().for_each(|(i, chunk)| {
            for Depth(b) in &bufs {
                for (z, o) in chunk.iter_mut().zip(&b[i * rows..]) {
                    *z = if *o > *z { *o } else { *z };
                }
            }
            for z in chunk.iter_mut() {
                *z = depth_of(*z, view.far);
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
