//! The wgpu camera against the ray-cast reference and the CPU rasteriser: agreement, known
//! depths, clipping, batches. Without a Vulkan adapter the GPU tests print SKIPPED and pass,
//! unless `XHAB_REQUIRE_GPU=1`.

use crate::common::{room_with_door, GREY};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use xhab_sim::scene::house::default_house;
use xhab_sim::scene::Scene;
use xhab_sim::sensors::{render_depth, CameraParams, GpuAdapter, GpuError, GpuRenderer, RasterScene, RayScene, Renderer};
use xhab_types::{DepthImage, Pose2};

/// The renderer for `scene`, or `None` (after a loud SKIPPED line) when no adapter can be had
/// and `XHAB_REQUIRE_GPU` is not 1.
pub fn gpu(test: &str, scene: &Scene) -> Option<GpuRenderer> {
    match GpuRenderer::new(scene) {
        Ok(g) => {
            eprintln!("{test}: adapter {}", g.adapter_info());
            Some(g)
        }
        Err(e) if std::env::var("XHAB_REQUIRE_GPU").as_deref() == Ok("1") => {
            panic!("{test}: XHAB_REQUIRE_GPU=1 but the GPU renderer is unavailable: {e}")
        }
        Err(e) => {
            crate::data::skipped(test, &format!("no GPU renderer ({e})"));
            None
        }
    }
}

/// Pixels whose depths differ by less than 1 cm, and the pixels hit in `a`.
fn agree(a: &DepthImage, b: &DepthImage) -> (usize, usize) {
    assert_eq!((a.width, a.height, a.data.len()), (b.width, b.height, b.data.len()));
    let ok = a.data.iter().zip(&b.data).filter(|(x, y)| (**x - **y).abs() < 0.01).count();
    (ok, a.data.iter().filter(|x| **x > 0.0).count())
}

fn bits(d: &DepthImage) -> Vec<u32> {
    d.data.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn gpu_depth_matches_the_ray_cast_over_random_poses_in_the_house() {
    let scene = default_house(3);
    let Some(g) = gpu("gpu_depth_matches_the_ray_cast_over_random_poses_in_the_house", &scene) else { return };
    let ray = RayScene::new(&scene).unwrap();
    let b = scene.bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut ok, mut hit, mut all) = (0, 0, 0);
    for i in 0..60 {
        // Odd and even sizes: the principal point (W-1)/2 must land on the same pixels.
        let (width, height) = [(160, 120), (101, 77), (256, 256)][i % 3];
        let cam = CameraParams { mount_height: if i % 2 == 0 { 1.25 } else { 0.6 }, width, height, ..Default::default() };
        let pose = Pose2::new(
            rng.gen_range(b.min[0] as f64 + 0.3..b.max[0] as f64 - 0.3),
            rng.gen_range(b.min[1] as f64 + 0.3..b.max[1] as f64 - 0.3),
            rng.gen_range(-std::f64::consts::PI..std::f64::consts::PI),
        );
        let (o, h) = agree(&g.render_depth(pose, 0.0, &cam).unwrap(), &render_depth(&ray, pose, 0.0, &cam));
        ok += o;
        hit += h;
        all += cam.width * cam.height;
    }
    let frac = ok as f64 / all as f64;
    eprintln!("procedural house: gpu depth within 1 cm of the ray cast on {:.4}% of {all} pixels ({hit} hit)", 100.0 * frac);
    assert!(frac >= 0.99, "{frac}");
    assert!(hit as f64 > 0.5 * all as f64, "too few pixels hit ({hit} of {all}): the comparison would be vacuous");
}

#[test]
fn gpu_wall_two_metres_ahead_has_depth_two_across_the_image() {
    let Some(g) = gpu("gpu_wall_two_metres_ahead_has_depth_two_across_the_image", &room_with_door()) else { return };
    let cam = CameraParams::default();
    let img = g.render_depth(Pose2::new(4.0, 1.0, 0.0), 0.0, &cam).unwrap();
    assert_eq!((img.width, img.height, img.data.len()), (256, 256, 256 * 256));
    for px in [128 * 256 + 128, 127 * 256 + 127, 128 * 256 + 20, 140 * 256 + 180] {
        assert!((img.data[px] - 2.0).abs() < 1e-4, "pixel {px}: {}", img.data[px]);
    }
    // The top row looks above the 2.5 m wall top: nothing there.
    assert_eq!(img.data[128], 0.0);
    // The bottom row sees the floor nearer than the wall.
    let floor = img.data[255 * 256 + 128];
    assert!(floor > 0.0 && floor < 2.0, "{floor}");
}

#[test]
fn gpu_near_walls_are_clipped_not_dropped_and_far_or_hidden_things_read_zero() {
    let scene = room_with_door();
    let Some(g) = gpu("gpu_near_walls_are_clipped_not_dropped_and_far_or_hidden_things_read_zero", &scene) else { return };
    let ray = RayScene::new(&scene).unwrap();
    let cam = CameraParams::default();
    // Facing the east wall 5 cm away: it fills the image at depth 0.05.
    let img = g.render_depth(Pose2::new(5.95, 1.0, 0.0), 0.0, &cam).unwrap();
    assert!(img.data.iter().all(|d| (d - 0.05).abs() < 1e-4), "{:?}", &img.data[..8]);
    for pose in [Pose2::new(5.98, 1.0, 0.7), Pose2::new(0.02, 0.02, 0.785), Pose2::new(2.0, 2.93, 1.2), Pose2::new(3.0, 0.02, -2.0)] {
        let a = g.render_depth(pose, 0.0, &cam).unwrap();
        let (ok, hit) = agree(&a, &render_depth(&ray, pose, 0.0, &cam));
        assert!(ok as f64 >= 0.99 * a.data.len() as f64, "{pose:?}: {ok} of {}", a.data.len());
        assert!(hit as f64 >= 0.5 * a.data.len() as f64, "{pose:?}: only {hit} pixels hit");
    }
    // A lone box: seen at 2 m, gone beyond max_depth and behind the camera.
    let mut s = Scene::default();
    s.add_box("b", [2.0, -0.5, 0.0], [3.0, 0.5, 2.0], GREY);
    let Some(g) = gpu("gpu_lone_box", &s) else { return };
    let img = g.render_depth(Pose2::new(0.0, 0.0, 0.0), 0.0, &cam).unwrap();
    assert!((img.data[128 * 256 + 128] - 2.0).abs() < 1e-4, "{}", img.data[128 * 256 + 128]);
    assert!(g.render_depth(Pose2::new(-8.5, 0.0, 0.0), 0.0, &cam).unwrap().data.iter().all(|d| *d == 0.0));
    let back = g.render_depth(Pose2::new(0.0, 0.0, std::f64::consts::PI), 0.0, &cam).unwrap();
    assert!(back.data.iter().all(|d| *d == 0.0));
}

#[test]
fn gpu_batch_of_eight_equals_eight_single_renders() {
    let scene = default_house(5);
    let Some(g) = gpu("gpu_batch_of_eight_equals_eight_single_renders", &scene) else { return };
    let cam = CameraParams::default();
    let views: Vec<(Pose2, f64)> = (0..8).map(|i| (Pose2::new(2.0 + 0.8 * i as f64, 1.5 + 0.3 * i as f64, 0.9 * i as f64), 0.0)).collect();
    let batch = g.render_depth_batch(&views, &cam).unwrap();
    assert_eq!(batch.len(), 8);
    let rgb_batch = g.render_rgb_batch(&views, &cam).unwrap();
    for (i, (&(p, z), b)) in views.iter().zip(&batch).enumerate() {
        let a = g.render_depth(p, z, &cam).unwrap();
        assert!(a.data.iter().filter(|d| **d > 0.0).count() > 1000, "view {i} sees almost nothing");
        assert_eq!(bits(&a), bits(b), "view {i}");
        assert_eq!(g.render_rgb(p, z, &cam).unwrap(), rgb_batch[i], "rgb view {i}");
    }
    // Views differ (a mix-up of atlas cells would show), and a repeat is identical.
    assert_ne!(bits(&batch[0]), bits(&batch[1]));
    let again = g.render_depth_batch(&views, &cam).unwrap();
    assert!(again.iter().zip(&batch).all(|(a, b)| bits(a) == bits(b)));
    assert!(g.render_depth_batch(&[], &cam).unwrap().is_empty());
}

#[test]
fn gpu_colour_matches_the_rasteriser() {
    let scene = default_house(7);
    let Some(g) = gpu("gpu_colour_matches_the_rasteriser", &scene) else { return };
    let rs = RasterScene::new(&scene).unwrap();
    let cam = CameraParams::default();
    let b = scene.bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut ok, mut lit, mut all) = (0, 0, 0);
    for _ in 0..12 {
        let pose = Pose2::new(
            rng.gen_range(b.min[0] as f64 + 0.3..b.max[0] as f64 - 0.3),
            rng.gen_range(b.min[1] as f64 + 0.3..b.max[1] as f64 - 0.3),
            rng.gen_range(-std::f64::consts::PI..std::f64::consts::PI),
        );
        let a = g.render_rgb(pose, 0.0, &cam).unwrap();
        let r = rs.render_rgb(pose, 0.0, &cam);
        assert_eq!(a.len(), 256 * 256 * 3);
        ok += a.chunks(3).zip(r.chunks(3)).filter(|(x, y)| x.iter().zip(y.iter()).all(|(p, q)| p.abs_diff(*q) <= 1)).count();
        lit += a.chunks(3).filter(|x| x.iter().any(|c| *c > 0)).count();
        all += 256 * 256;
    }
    let frac = ok as f64 / all as f64;
    eprintln!("procedural house: gpu rgb within 1 of the rasteriser on {:.4}% of {all} pixels ({lit} lit)", 100.0 * frac);
    assert!(frac >= 0.98, "{frac}");
    assert!(lit as f64 >= 0.5 * all as f64, "{lit} of {all}");
    // Each triangle keeps its mesh's colour: a red box is seen red, shaded by incidence.
    let mut scene = room_with_door();
    scene.add_box("red", [1.0, 1.0, 0.0], [1.5, 1.4, 0.8], [1.0, 0.0, 0.0, 1.0]);
    let Some(g) = gpu("gpu_red_box", &scene) else { return };
    let a = g.render_rgb(Pose2::new(3.0, 1.2, std::f64::consts::PI), 0.0, &cam).unwrap();
    // Row 180 looks 0.41 down: the box's face at x = 1.5 (1.5 m ahead), at cos 0.925.
    let p = &a[(180 * 256 + 128) * 3..][..3];
    assert_eq!(p, [(255.0f64 * (0.35 + 0.65 / (1.0f64 + 0.41f64.powi(2)).sqrt())).round() as u8, 0, 0]);
}

#[test]
fn gpu_depth_and_colour_from_one_pass_are_the_two_renders_to_the_bit() {
    // The procedural house (flat colours, odd image sizes), then a textured shared scene.
    let mut scenes = vec![("procedural house", default_house(5))];
    if let Some(dir) = crate::data::data_dir("gpu_depth_and_colour_from_one_pass textured") {
        let path = dir.join("scenes/aws_small_house.glb");
        scenes.push(("aws_small_house", xhab_sim::scene::load(&path, &Default::default()).unwrap_or_else(|e| panic!("{}: {e}", path.display()))));
    }
    for (name, scene) in scenes {
        let Some(g) = gpu("gpu_depth_and_colour_from_one_pass_are_the_two_renders_to_the_bit", &scene) else { return };
        let b = scene.bounds();
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let mut views = Vec::new();
        for _ in 0..6 {
            let pose = Pose2::new(
                rng.gen_range(b.min[0] as f64 + 0.3..b.max[0] as f64 - 0.3),
                rng.gen_range(b.min[1] as f64 + 0.3..b.max[1] as f64 - 0.3),
                rng.gen_range(-std::f64::consts::PI..std::f64::consts::PI),
            );
            views.push((pose, b.min[2] as f64));
        }
        let mut lit = 0;
        for cam in [CameraParams::default(), CameraParams { width: 101, height: 77, ..Default::default() }] {
            let both = g.render_depth_rgb_batch(&views, &cam).unwrap();
            assert_eq!(both.len(), views.len());
            for (&(pose, z), (d, c)) in views.iter().zip(&both) {
                assert_eq!((d.width, d.height, c.len()), (cam.width, cam.height, cam.width * cam.height * 3));
                assert!(bits(d) == bits(&g.render_depth(pose, z, &cam).unwrap()), "{name}: depth differs from the depth pass at {pose:?}");
                assert!(*c == g.render_rgb(pose, z, &cam).unwrap(), "{name}: colour differs from the colour pass at {pose:?}");
                lit += c.chunks(3).filter(|p| p.iter().any(|&x| x > 0)).count();
            }
            let (d, c) = g.render_depth_rgb(views[0].0, views[0].1, &cam).unwrap();
            assert!(bits(&d) == bits(&both[0].0) && c == both[0].1, "{name}: a view alone differs from the same view in a batch");
        }
        assert!(lit > 10_000, "{name}: {lit} pixels lit: the comparison would be vacuous");
        eprintln!("{name}: one-pass depth and colour equal the two passes on {} views", 2 * views.len());
    }
}

#[test]
fn gpu_renderer_errors_are_named() {
    fn shareable<T: Send + Sync>() {}
    shareable::<GpuRenderer>();
    // No triangles: refused before any device is asked for.
    assert!(matches!(GpuRenderer::new(&Scene::default()), Err(GpuError::EmptyScene)));
    assert!(GpuError::NoAdapter.to_string().contains("mesa-vulkan-drivers"));
    let Some(g) = gpu("gpu_renderer_errors_are_named", &room_with_door()) else { return };
    let bad = CameraParams { width: 0, ..Default::default() };
    assert!(matches!(g.render_depth(Pose2::new(1.0, 1.0, 0.0), 0.0, &bad), Err(GpuError::Camera(_))));
    let huge = CameraParams { width: 1 << 20, ..Default::default() };
    assert!(matches!(g.render_depth(Pose2::new(1.0, 1.0, 0.0), 0.0, &huge), Err(GpuError::Camera(_))));
}

#[test]
fn auto_builds_the_gpu_renderer_only_on_a_real_gpu() {
    let scene = room_with_door();
    let (r, why) = Renderer::auto(&scene).expect("a renderer");
    match GpuAdapter::find() {
        Ok(a) if a.is_software() => {
            // No device was opened for the software adapter: the rasteriser, and why.
            assert_eq!(r.name(), "raster", "{why}");
            assert!(why.contains("only a software adapter") && why.contains(&a.describe()), "{why}");
        }
        Ok(a) => {
            assert_eq!(r.name(), "wgpu", "{why}");
            assert!(why.contains(&a.describe()), "{why}");
            // The renderer built on the adapter found beforehand draws what `new` draws.
            let g = GpuRenderer::with_adapter(&scene, GpuAdapter::find().expect("the same adapter")).expect("renderer");
            let n = gpu("auto_builds_the_gpu_renderer_only_on_a_real_gpu", &scene).expect("renderer");
            let cam = CameraParams::default();
            let pose = Pose2::new(1.0, 1.0, 0.3);
            assert_eq!(bits(&g.render_depth(pose, 0.0, &cam).unwrap()), bits(&n.render_depth(pose, 0.0, &cam).unwrap()));
            assert_eq!(g.render_rgb(pose, 0.0, &cam).unwrap(), n.render_rgb(pose, 0.0, &cam).unwrap());
        }
        Err(e) => {
            if std::env::var("XHAB_REQUIRE_GPU").as_deref() == Ok("1") {
                panic!("XHAB_REQUIRE_GPU=1 but no Vulkan adapter: {e}");
            }
            assert_eq!(r.name(), "raster", "{why}");
            assert!(why.contains("no GPU renderer"), "{why}");
        }
    }
    // An empty scene: no renderer, whatever the adapter.
    assert!(Renderer::auto(&Scene::default()).is_err());
}
