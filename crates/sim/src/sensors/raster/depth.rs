//! Depth images: each column strip of a view is drawn straight into its part of the image's
//! rows and converted to depth there, in parallel; nothing is copied or merged afterwards.

use super::{span, HiZ, RasterScene, Setup, Target, View};
use crate::sensors::camera::CameraParams;
use rayon::prelude::*;
use xhab_types::{DepthImage, Pose2};

/// One strip's part of every image row, holding inverse depth (1/m) while drawing.
struct StripRows<'a> {
    rows: Vec<&'a mut [f32]>,
}

impl Target for StripRows<'_> {
    fn draw(&mut self, view: &View, tris: &[Setup]) {
        span::raster_depth(view, tris, &mut self.rows);
    }

    fn hiz(&self, view: &View) -> HiZ {
        HiZ::new(view, self.rows.iter().map(|r| &**r))
    }
}

impl RasterScene {
    /// The depth image from `base` on the floor at `floor_z`, drawn as `strips` column strips
    /// (in parallel when more than one). The strips are fixed by the image width alone, so the
    /// result does not depend on the number of threads.
    pub(super) fn depth(&self, base: Pose2, floor_z: f64, cam: &CameraParams, strips: usize) -> DepthImage {
        let (w, h) = (cam.width, cam.height);
        let mut data = vec![1.0 / cam.max_depth as f32; w * h];
        if w > 0 && h > 0 {
            let strips = strips.clamp(1, w);
            let edges: Vec<usize> = (0..=strips).map(|i| i * w / strips).collect();
            let mut parts: Vec<StripRows> = (0..strips).map(|_| StripRows { rows: Vec::with_capacity(h) }).collect();
            for mut row in data.chunks_mut(w) {
                for (i, part) in parts.iter_mut().enumerate() {
                    let (a, rest) = row.split_at_mut(edges[i + 1] - edges[i]);
                    part.rows.push(a);
                    row = rest;
                }
            }
            let draw = |(i, part): (usize, &mut StripRows)| self.depth_strip(&View::new(base, floor_z, cam, edges[i], edges[i + 1]), part);
            if strips == 1 {
                parts.iter_mut().enumerate().for_each(draw);
            } else {
                parts.par_iter_mut().enumerate().for_each(draw);
            }
        }
        DepthImage { width: w, height: h, data }
    }

    /// Draws one strip (its rows holding `1 / max_depth`) and turns its inverse depth into
    /// depth (m, 0 where nothing is hit within `max_depth`).
    fn depth_strip(&self, view: &View, part: &mut StripRows) {
        self.render_view(view, part);
        for row in part.rows.iter_mut() {
            for z in row.iter_mut() {
                *z = depth_of(*z, view.far);
            }
        }
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
