//! The rasterised camera against the ray-cast reference: agreement, near-plane clipping,
//! known depths, determinism.

use crate::common::{room_with_door, GREY};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use xhab_sim::scene::house::default_house;
use xhab_sim::scene::Scene;
use xhab_sim::sensors::{render_depth, render_rgb, CameraParams, RasterScene, RayScene};
use xhab_types::{DepthImage, Pose2};

/// Pixels whose depths differ by less than 1 cm, and the pixels hit in `a`.
fn agree(a: &DepthImage, b: &DepthImage) -> (usize, usize) {
    assert_eq!((a.width, a.height, a.data.len()), (b.width, b.height, b.data.len()));
    let ok = a.data.iter().zip(&b.data).filter(|(x, y)| (**x - **y).abs() < 0.01).count();
    (ok, a.data.iter().filter(|x| **x > 0.0).count())
}

#[test]
fn raster_depth_matches_the_ray_cast_over_random_poses_in_the_house() {
    let scene = default_house(3);
    let (rs, ray) = (RasterScene::new(&scene).unwrap(), RayScene::new(&scene).unwrap());
    let b = scene.bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut ok, mut hit, mut all) = (0, 0, 0);
    for i in 0..60 {
        let cam = CameraParams { mount_height: if i % 2 == 0 { 1.25 } else { 0.6 }, width: 160, height: 120, ..Default::default() };
        let pose = Pose2::new(
            rng.gen_range(b.min[0] as f64 + 0.3..b.max[0] as f64 - 0.3),
            rng.gen_range(b.min[1] as f64 + 0.3..b.max[1] as f64 - 0.3),
            rng.gen_range(-std::f64::consts::PI..std::f64::consts::PI),
        );
        let (o, h) = agree(&rs.render_depth(pose, 0.0, &cam), &render_depth(&ray, pose, 0.0, &cam));
        ok += o;
        hit += h;
        all += cam.width * cam.height;
    }
    let frac = ok as f64 / all as f64;
    eprintln!("procedural house: {:.4}% of {all} pixels within 1 cm ({hit} hit)", 100.0 * frac);
    assert!(frac >= 0.99, "{frac}");
    assert!(hit as f64 > 0.5 * all as f64, "too few pixels hit ({hit} of {all}): the comparison would be vacuous");
}

#[test]
fn a_wall_two_metres_ahead_has_depth_two_across_the_image() {
    let rs = RasterScene::new(&room_with_door()).unwrap();
    let cam = CameraParams::default();
    let img = rs.render_depth(Pose2::new(4.0, 1.0, 0.0), 0.0, &cam);
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
fn walls_closer_than_the_image_edges_are_clipped_not_dropped() {
    let scene = room_with_door();
    let (rs, ray) = (RasterScene::new(&scene).unwrap(), RayScene::new(&scene).unwrap());
    let cam = CameraParams::default();
    // Facing the east wall 5 cm away: it fills the image at depth 0.05.
    let img = rs.render_depth(Pose2::new(5.95, 1.0, 0.0), 0.0, &cam);
    assert!(img.data.iter().all(|d| (d - 0.05).abs() < 1e-4), "{:?}", &img.data[..8]);
    // At an angle to walls 2 cm away, their triangles cross the camera plane.
    for pose in [Pose2::new(5.98, 1.0, 0.7), Pose2::new(0.02, 0.02, 0.785), Pose2::new(2.0, 2.93, 1.2), Pose2::new(3.0, 0.01, -2.0)] {
        let a = rs.render_depth(pose, 0.0, &cam);
        let b = render_depth(&ray, pose, 0.0, &cam);
        let (ok, hit) = agree(&a, &b);
        assert!(ok as f64 >= 0.99 * a.data.len() as f64, "{pose:?}: {ok} of {}", a.data.len());
        assert!(hit as f64 >= 0.5 * a.data.len() as f64, "{pose:?}: only {hit} pixels hit");
    }
}

#[test]
fn rendering_is_deterministic_single_batched_on_one_thread_and_with_colour() {
    let scene = default_house(5);
    let rs = RasterScene::new(&scene).unwrap();
    let cam = CameraParams::default();
    let views: Vec<(Pose2, f64)> = (0..6).map(|i| (Pose2::new(2.0 + i as f64, 1.5 + 0.3 * i as f64, 0.9 * i as f64), 0.0)).collect();
    let bits = |d: &DepthImage| d.data.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let batch = rs.render_depth_batch(&views, &cam);
    let batch_rgb = rs.render_depth_rgb_batch(&views, &cam);
    assert_eq!(batch_rgb.len(), views.len());
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    // A single view draws one buffer per thread and merges them: any count gives the same.
    let four = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap();
    for (i, (&(p, z), b)) in views.iter().zip(&batch).enumerate() {
        let a = rs.render_depth(p, z, &cam);
        assert_eq!(bits(&a), bits(&rs.render_depth(p, z, &cam)));
        assert_eq!(bits(&a), bits(b));
        assert_eq!(bits(&a), bits(&one.install(|| rs.render_depth(p, z, &cam))));
        assert_eq!(bits(&a), bits(&four.install(|| rs.render_depth(p, z, &cam))));
        assert_eq!(rs.render_rgb(p, z, &cam), one.install(|| rs.render_rgb(p, z, &cam)));
        assert_eq!(rs.render_rgb(p, z, &cam), four.install(|| rs.render_rgb(p, z, &cam)));
        // Depth and colour from one rasterisation: the same depth to the bit, the same colour.
        let (d, c) = rs.render_depth_rgb(p, z, &cam);
        assert_eq!(bits(&a), bits(&d));
        assert_eq!(c, rs.render_rgb(p, z, &cam));
        // A batch renders each view on one thread, rows coloured in turn: the same images.
        let (bd, bc) = &batch_rgb[i];
        assert_eq!(bits(&a), bits(bd));
        assert_eq!(&c, bc);
    }
}

#[test]
fn raster_colour_matches_the_ray_cast() {
    // One colour: the ray caster's colour lookup takes the hit's face feature (front/back of
    // the triangle) for a triangle index, so only its shading is comparable on mixed scenes.
    let mut scene = room_with_door();
    scene.add_box("box", [1.0, 1.0, 0.0], [1.5, 1.4, 0.8], GREY);
    let (rs, ray) = (RasterScene::new(&scene).unwrap(), RayScene::new(&scene).unwrap());
    let cam = CameraParams::default();
    let (mut ok, mut lit, mut all) = (0, 0, 0);
    for pose in [Pose2::new(3.0, 1.5, 3.0), Pose2::new(0.5, 0.5, 0.6), Pose2::new(4.0, 4.0, -2.0)] {
        let a = rs.render_rgb(pose, 0.0, &cam);
        let b = render_rgb(&ray, pose, 0.0, &cam);
        assert_eq!(a.len(), 256 * 256 * 3);
        ok += a.chunks(3).zip(b.chunks(3)).filter(|(x, y)| x.iter().zip(y.iter()).all(|(p, q)| p.abs_diff(*q) <= 1)).count();
        lit += a.chunks(3).filter(|x| x.iter().any(|c| *c > 0)).count();
        all += 256 * 256;
    }
    assert!(ok as f64 >= 0.99 * all as f64, "{ok} of {all}");
    assert!(lit as f64 >= 0.5 * all as f64, "{lit} of {all}");
    // Each triangle keeps its mesh's colour: a red box is seen red, shaded by incidence.
    let mut scene = room_with_door();
    scene.add_box("red", [1.0, 1.0, 0.0], [1.5, 1.4, 0.8], [1.0, 0.0, 0.0, 1.0]);
    let rs = RasterScene::new(&scene).unwrap();
    let a = rs.render_rgb(Pose2::new(3.0, 1.2, std::f64::consts::PI), 0.0, &cam);
    // Row 180 looks 0.41 down: the box's face at x = 1.5 (1.5 m ahead), at cos 0.925.
    let p = &a[(180 * 256 + 128) * 3..][..3];
    assert_eq!(p, [(255.0f64 * (0.35 + 0.65 / (1.0f64 + 0.41f64.powi(2)).sqrt())).round() as u8, 0, 0]);
}

#[test]
fn an_empty_scene_has_no_raster_scene_and_a_lone_box_is_seen() {
    assert!(RasterScene::new(&Scene::default()).is_none());
    let mut s = Scene::default();
    s.add_box("b", [2.0, -0.5, 0.0], [3.0, 0.5, 2.0], GREY);
    let rs = RasterScene::new(&s).unwrap();
    let cam = CameraParams { max_depth: 10.0, ..Default::default() };
    let img = rs.render_depth(Pose2::new(0.0, 0.0, 0.0), 0.0, &cam);
    assert!((img.data[128 * 256 + 128] - 2.0).abs() < 1e-4);
    // Beyond max_depth it is gone.
    let far = rs.render_depth(Pose2::new(-8.5, 0.0, 0.0), 0.0, &cam);
    assert!(far.data.iter().all(|d| *d == 0.0));
    // Behind the camera it is not seen.
    let back = rs.render_depth(Pose2::new(0.0, 0.0, std::f64::consts::PI), 0.0, &cam);
    assert!(back.data.iter().all(|d| *d == 0.0));
    // An empty image is empty, not a panic.
    for (w, h) in [(0, 0), (0, 4), (4, 0)] {
        let cam = CameraParams { width: w, height: h, ..Default::default() };
        let (d, c) = rs.render_depth_rgb(Pose2::new(0.0, 0.0, 0.0), 0.0, &cam);
        assert!(d.data.is_empty() && c.is_empty() && rs.render_depth(Pose2::new(0.0, 0.0, 0.0), 0.0, &cam).data.is_empty());
        let ray = RayScene::new(&s).unwrap();
        assert!(render_depth(&ray, Pose2::new(0.0, 0.0, 0.0), 0.0, &cam).data.is_empty() && render_rgb(&ray, Pose2::new(0.0, 0.0, 0.0), 0.0, &cam).is_empty());
    }
    // One pixel works too.
    let one = CameraParams { width: 1, height: 1, ..Default::default() };
    assert!((rs.render_depth(Pose2::new(0.0, 0.0, 0.0), 0.0, &one).data[0] - 2.0).abs() < 1e-4);
    assert!(rs.render_rgb(Pose2::new(0.0, 0.0, 0.0), 0.0, &one).iter().any(|c| *c > 0));
}

#[test]
fn a_batch_of_depth_and_colour_views_is_each_view_rendered_alone() {
    use xhab_sim::sensors::{Renderer, RendererKind};
    let scene = default_house(2);
    let cam = CameraParams { width: 64, height: 48, ..CameraParams::default() };
    let views: Vec<(Pose2, f64)> = (0..5).map(|i| (Pose2::new(1.5 + 0.7 * i as f64, 2.0 + 0.2 * i as f64, 1.3 * i as f64), 0.0)).collect();
    for kind in [RendererKind::Raycast, RendererKind::Raster] {
        let r = Renderer::new(kind, &scene).expect("a CPU renderer");
        let batch = r.depth_rgb_batch(&views, &cam).expect("rendered");
        assert_eq!(batch.len(), views.len());
        for (&(p, z), (d, c)) in views.iter().zip(&batch) {
            let (d1, c1) = r.depth_rgb(p, z, &cam).expect("rendered");
            assert_eq!(d.data.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), d1.data.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), "{kind:?} at {p:?}");
            assert_eq!(c, &c1, "{kind:?} at {p:?}");
            // Something is seen (else the comparison checks nothing).
            assert!(d.data.iter().filter(|x| **x > 0.0).count() > d.data.len() / 2, "{kind:?} at {p:?}");
        }
        assert!(r.depth_rgb_batch(&[], &cam).expect("rendered").is_empty());
    }
}
