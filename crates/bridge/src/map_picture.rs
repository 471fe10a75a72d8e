//! Pictures: top-down maps with trajectories, as PNG.

use crate::runner::Outcome;
use image::{Rgb, RgbImage};
use std::path::{Path, PathBuf};
use xhab_sim::episode::Dataset;
use xhab_sim::navgrid::NavGridError;
use xhab_sim::world::World;
use xhab_types::{OccupancyGrid, Point2, GRID_FREE, GRID_UNKNOWN};

/// A picture that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("writing {}", path.display())]
pub struct PictureError {
    /// The file.
    pub path: PathBuf,
    /// Why.
    #[source]
    pub source: image::ImageError,
}

/// A top-down picture of a map, at `scale` pixels per cell, north (+y) up.
pub struct MapPicture<'a> {
    grid: &'a OccupancyGrid,
    scale: u32,
    img: RgbImage,
}

impl<'a> MapPicture<'a> {
    /// Draws the map: free white, occupied black, unknown grey; a 1 m scale bar bottom left.
    pub fn new(grid: &'a OccupancyGrid) -> Self {
        let scale = (900 / grid.width.max(grid.height).max(1)).clamp(1, 8) as u32;
        let (w, h) = (grid.width as u32 * scale, grid.height as u32 * scale);
        let mut img = RgbImage::new(w.max(1), h.max(1));
        for row in 0..grid.height {
            for col in 0..grid.width {
                let v = grid.get(col, row);
                let c = match v {
                    GRID_UNKNOWN => Rgb([205, 205, 205]),
                    GRID_FREE => Rgb([255, 255, 255]),
                    v if v >= 65 => Rgb([20, 20, 20]),
                    v => {
                        let g = 255 - (v as u16 * 255 / 100) as u8;
                        Rgb([g, g, g])
                    }
                };
                let y0 = (grid.height - 1 - row) as u32 * scale;
                for dy in 0..scale {
                    for dx in 0..scale {
                        img.put_pixel(col as u32 * scale + dx, y0 + dy, c);
                    }
                }
            }
        }
        let mut p = MapPicture { grid, scale, img };
        p.scale_bar();
        p
    }

    fn to_px(&self, q: Point2) -> (f64, f64) {
        let s = self.scale as f64 / self.grid.resolution;
        let x = (q.x - self.grid.origin.x) * s;
        let y = self.img.height() as f64 - (q.y - self.grid.origin.y) * s;
        (x, y)
    }

    fn scale_bar(&mut self) {
        let px = (self.scale as f64 / self.grid.resolution).round() as i64; // one metre
        let y = self.img.height() as i64 - 8;
        for x in 8..8 + px {
            for t in 0..3 {
                self.put(x, y - t, Rgb([200, 30, 30]));
            }
        }
    }

    fn put(&mut self, x: i64, y: i64, c: Rgb<u8>) {
        if x >= 0 && y >= 0 && (x as u32) < self.img.width() && (y as u32) < self.img.height() {
            self.img.put_pixel(x as u32, y as u32, c);
        }
    }

    /// Draws a polyline (m, world frame) in colour `c`.
    pub fn polyline(&mut self, pts: &[Point2], c: [u8; 3]) {
        for w in pts.windows(2) {
            let (x0, y0) = self.to_px(w[0]);
            let (x1, y1) = self.to_px(w[1]);
            let n = ((x1 - x0).abs().max((y1 - y0).abs()).ceil() as i64).max(1);
            for k in 0..=n {
                let t = k as f64 / n as f64;
                let (x, y) = ((x0 + t * (x1 - x0)).round() as i64, (y0 + t * (y1 - y0)).round() as i64);
                self.put(x, y, Rgb(c));
                if self.scale >= 3 {
                    self.put(x + 1, y, Rgb(c));
                    self.put(x, y + 1, Rgb(c));
                }
            }
        }
    }

    /// Draws a filled disc of radius `r_px` pixels at `q` (m).
    pub fn dot(&mut self, q: Point2, r_px: i64, c: [u8; 3]) {
        let (x, y) = self.to_px(q);
        let (x, y) = (x.round() as i64, y.round() as i64);
        for dy in -r_px..=r_px {
            for dx in -r_px..=r_px {
                if dx * dx + dy * dy <= r_px * r_px {
                    self.put(x + dx, y + dy, Rgb(c));
                }
            }
        }
    }

    /// Writes the picture as PNG.
    pub fn save(&self, path: &Path) -> Result<(), PictureError> {
        self.img.save(path).map_err(|source| PictureError { path: path.to_path_buf(), source })
    }

    /// The picture's pixels (RGB, rows top to bottom).
    pub fn image(&self) -> &RgbImage {
        &self.img
    }
}

/// Writes the pictures of `maps` (a building's storeys, lowest first) side by side, left to
/// right, 16 pixels apart, as one PNG.
pub fn save_side_by_side(maps: &[OccupancyGrid], path: &Path) -> Result<(), PictureError> {
    const GAP: u32 = 16;
    let pics: Vec<MapPicture> = maps.iter().map(MapPicture::new).collect();
    let w = pics.iter().map(|p| p.img.width()).sum::<u32>() + GAP * pics.len().saturating_sub(1) as u32;
    let h = pics.iter().map(|p| p.img.height()).max().unwrap_or(1);
    let mut img = RgbImage::from_pixel(w.max(1), h.max(1), Rgb([255, 255, 255]));
    let mut x = 0;
    for p in &pics {
        image::imageops::replace(&mut img, &p.img, x as i64, 0);
        x += p.img.width() + GAP;
    }
    img.save(path).map_err(|source| PictureError { path: path.to_path_buf(), source })
}

/// Why the trajectory pictures could not be drawn.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TrajectoriesError {
    /// The folder could not be created.
    #[error("creating {}", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The grid of an episode's floor could not be built.
    #[error(transparent)]
    Grid(#[from] NavGridError),
    /// A picture could not be written.
    #[error(transparent)]
    Picture(#[from] PictureError),
}

/// Draws each episode's trajectory (recorded in `outcomes`, one per episode of `ds`) over its
/// floor's map into `dir/EPISODE_ID.png`, with the shortest path as the metrics measure it,
/// the start and the goals; episodes without a trajectory are passed over.
pub fn draw_trajectories(world: &World, ds: &Dataset, outcomes: &[Outcome], dir: &Path) -> Result<(), TrajectoriesError> {
    std::fs::create_dir_all(dir).map_err(|source| TrajectoriesError::Folder { path: dir.to_path_buf(), source })?;
    for (ep, o) in ds.episodes.iter().zip(outcomes) {
        let Outcome::Ran(r) = o else { continue };
        let Some(traj) = &r.trajectory else { continue };
        let grid = world.grid_at(ep.start_position.z)?;
        let map = grid.occupancy_grid();
        let mut pic = MapPicture::new(&map);
        let goals: Vec<Point2> = ep.goals.iter().map(|g| g.position.xy()).collect();
        // The shortest path as the metrics measure it (the episode's goal field, cached).
        pic.polyline(&grid.field(&goals).path(&grid, ep.start_position.xy()), [60, 160, 255]);
        let pts: Vec<Point2> = traj.iter().map(|p| p.position()).collect();
        pic.polyline(&pts, [230, 120, 0]);
        pic.dot(ep.start_position.xy(), 4, [0, 170, 0]);
        for g in &goals {
            pic.dot(*g, 4, [220, 0, 0]);
        }
        let name: String = r.episode_id.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect();
        pic.save(&dir.join(format!("{name}.png")))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::agents::AgentKind;
    use crate::runner::{run_dataset, RunConfig};
    use xhab_sim::env::TaskConfig;

    #[test]
    fn one_picture_per_recorded_trajectory() {
        let world = crate::setup::load_world("procedural:3", &Default::default()).unwrap();
        let ds = crate::setup::generate(&world, "procedural:3", "auto", 3, 1, "procedural:3").unwrap();
        let mut cfg = RunConfig { agent: AgentKind::Oracle, task: TaskConfig::default(), threads: 1, record_trajectories: true, physics: None, seed: 0, nav: None, sensors: None, episode_indices: None };
        let dir = std::env::temp_dir().join(format!("xhab-trajectories-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let outcomes = run_dataset(&world, &ds, &cfg, &|| {});
        draw_trajectories(&world, &ds, &outcomes, &dir).unwrap();
        for ep in &ds.episodes {
            let img = image::open(dir.join(format!("{}.png", ep.episode_id))).unwrap();
            assert!(img.width() > 1 && img.height() > 1);
        }
        // Without recorded trajectories: nothing drawn.
        cfg.record_trajectories = false;
        let empty = dir.join("none");
        draw_trajectories(&world, &ds, &run_dataset(&world, &ds, &cfg, &|| {}), &empty).unwrap();
        assert_eq!(std::fs::read_dir(&empty).unwrap().count(), 0);
        // A folder that cannot be made is named.
        let e = draw_trajectories(&world, &ds, &outcomes, &dir.join(format!("{}.png", ds.episodes[0].episode_id)).join("x")).unwrap_err();
        assert!(e.to_string().starts_with("creating "), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
