//! `xhab render`: what the robot's camera sees, depth colour-mapped beside RGB.

use crate::cli::{CameraOpts, RenderArgs, RendererArg};
use crate::scene_arg::load_scene;
use anyhow::{bail, Context, Result};
use image::{Rgb, RgbImage};
use std::process::ExitCode;
use xhab_bridge::setup::{self, CameraOptions};
use xhab_sim::sensors::{CameraParams, Renderer, RendererKind};
use xhab_types::Pose2;

/// The library's camera options from the command line's.
pub fn camera_options(o: &CameraOpts) -> CameraOptions {
    CameraOptions {
        renderer: match o.renderer {
            RendererArg::Auto => None,
            RendererArg::Raycast => Some(RendererKind::Raycast),
            RendererArg::Raster => Some(RendererKind::Raster),
            RendererArg::Wgpu => Some(RendererKind::Wgpu),
        },
        resolution: o.resolution,
        hfov: o.hfov,
        camera_height: o.camera_height,
    }
}

/// Camera parameters from the options; `--camera-height` or else `default_height` (m).
pub fn camera(o: &CameraOpts, default_height: f64) -> Result<CameraParams> {
    Ok(setup::camera_params(&camera_options(o), default_height)?)
}

/// The renderer `--renderer` asks for, built for `scene`; `auto` takes wgpu on a real GPU and
/// the CPU rasteriser otherwise (with a warning when the GPU path failed). A line says which.
pub fn renderer(o: &CameraOpts, scene: &xhab_sim::scene::Scene) -> Result<Renderer> {
    let (r, why) = setup::build_renderer(camera_options(o).renderer, scene)?;
    print_renderer_note(&format!("{}{why}", r.name()));
    Ok(r)
}

/// Prints which renderer renders and why (`NAME (auto: ...)`), warning when the GPU path failed.
pub fn print_renderer_note(note: &str) {
    if note.contains("no GPU renderer") {
        tracing::warn!("renderer: {note}");
    }
    eprintln!("xhab: renderer {note}");
}

/// A depth colour map: near = yellow, far = dark blue, no return = black.
fn depth_color(d: f32, max: f64) -> Rgb<u8> {
    if d <= 0.0 {
        return Rgb([0, 0, 0]);
    }
    let t = (d as f64 / max).clamp(0.0, 1.0);
    let r = (255.0 * (1.0 - t).powf(1.5)) as u8;
    let g = (230.0 * (1.0 - t)) as u8;
    let b = (90.0 + 120.0 * t) as u8;
    Rgb([r, g, b])
}

pub fn run(a: &RenderArgs) -> Result<ExitCode> {
    let v: Vec<f64> = a.pose.split(',').map(|t| t.trim().parse::<f64>()).collect::<std::result::Result<_, _>>().map_err(|_| anyhow::anyhow!("bad --pose '{}': expected X,Y,Z,YAW", a.pose))?;
    if v.len() != 4 || v.iter().any(|x| !x.is_finite()) {
        bail!("bad --pose '{}': expected four finite numbers X,Y,Z,YAW", a.pose);
    }
    let cam = camera(&a.camera, CameraParams::default().mount_height)?;
    let scene = load_scene(&a.scene, &a.scene_opts)?;
    let r = renderer(&a.camera, &scene)?;
    let pose = Pose2::new(v[0], v[1], v[3]);
    let depth = r.depth(pose, v[2], &cam)?;
    let rgb = r.rgb(pose, v[2], &cam)?;
    let (w, h) = (cam.width as u32, cam.height as u32);
    let mut img = RgbImage::new(2 * w + 4, h);
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            img.put_pixel(x, y, depth_color(depth.data[i], cam.max_depth));
            img.put_pixel(w + 4 + x, y, Rgb([rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]]));
        }
    }
    super::ensure_parent(&a.out)?;
    img.save(&a.out).with_context(|| format!("writing {}", a.out.display()))?;
    let valid: Vec<f32> = depth.data.iter().copied().filter(|&d| d > 0.0).collect();
    let mean = valid.iter().map(|&d| d as f64).sum::<f64>() / valid.len().max(1) as f64;
    eprintln!("xhab: wrote {} (depth | rgb, {}x{}; {:.0}% of pixels hit, mean depth {:.2} m)", a.out.display(), w, h, 100.0 * valid.len() as f64 / depth.data.len() as f64, mean);
    Ok(ExitCode::SUCCESS)
}
