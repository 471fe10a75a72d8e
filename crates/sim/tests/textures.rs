//! Base-colour textures: loading (glTF views, data URIs, files; OBJ map_Kd), bad references,
//! the GLB round trip, and the same texels on screen in all three renderers.

use crate::gpu::gpu;
use base64::Engine;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use xhab_sim::scene::{load, to_glb_bytes, LoadOptions, Mesh, Scene, SceneError, Texture, Wrap};
use xhab_sim::sensors::surface::linear_to_srgb_byte;
use xhab_sim::sensors::{render_rgb, CameraParams, RasterScene, RayScene};
use xhab_types::Pose2;

/// A fresh folder `name` for this test run.
fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("xhab-textures-{}", std::process::id())).join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

const WHITE: [u8; 4] = [255, 255, 255, 255];
const BLACK: [u8; 4] = [0, 0, 0, 255];
const RED: [u8; 4] = [255, 0, 0, 255];
const BLUE: [u8; 4] = [0, 0, 255, 255];

/// A 64 x 64 checkerboard of 8 x 8 cells of 8 x 8 texels, white at (0, 0) except that the
/// top-left cell is red (so an upside-down or mirrored texture shows).
fn checker() -> Texture {
    let mut rgba = Vec::new();
    for y in 0..64 {
        for x in 0..64 {
            let (cx, cy) = (x / 8, y / 8);
            rgba.extend_from_slice(&if (cx, cy) == (0, 0) { RED } else if (cx + cy) % 2 == 0 { WHITE } else { BLACK });
        }
    }
    Texture { name: "checker".into(), width: 64, height: 64, rgba: Arc::new(rgba), wrap_s: Wrap::Repeat, wrap_t: Wrap::Repeat }
}

/// A wall at x = 2 (m) facing the origin, y in [-2, 2], z in [0, 2.5], textured with `tex`:
/// u runs from `u0` at y = 2 (the image's left) to `u1` at y = -2, v from 0 at the top to 1 at
/// the floor.
fn wall(tex: Texture, u0: f32, u1: f32) -> Scene {
    let mut m = Mesh::new("wall", vec![[2.0, 2.0, 0.0], [2.0, -2.0, 0.0], [2.0, -2.0, 2.5], [2.0, 2.0, 2.5]], vec![[0, 1, 2], [0, 2, 3]], [1.0; 4]);
    m.uvs = vec![[u0, 1.0], [u1, 1.0], [u1, 0.0], [u0, 0.0]];
    m.texture = Some(0);
    Scene { meshes: vec![m], textures: vec![tex] }
}

/// The camera at the origin looking along +x, 1.25 m up, 256 x 256, 90 degrees.
const POSE: Pose2 = Pose2 { x: 0.0, y: 0.0, yaw: 0.0 };

/// The pixel (column, row) that sees the wall point at lateral `y`, height `z` (m).
fn pixel_of(y: f64, z: f64) -> (usize, usize) {
    let k = CameraParams::default().intrinsics();
    let u = k.cx - y / 2.0 * k.fx;
    let v = k.cy - (z - 1.25) / 2.0 * k.fy;
    (u.round() as usize, v.round() as usize)
}

/// The wall point's texture coordinate under `wall(_, u0, u1)`.
fn wall_point(u: f64, v: f64, u0: f64, u1: f64) -> (f64, f64) {
    (2.0 - 4.0 * (u - u0) / (u1 - u0), 2.5 * (1.0 - v))
}

/// The RGB images of `scene` from [`POSE`] by every renderer available: ray cast, raster and,
/// when an adapter exists, wgpu.
fn render_all(test: &str, scene: &Scene) -> Vec<(&'static str, Vec<u8>)> {
    let cam = CameraParams::default();
    let mut out = vec![
        ("raycast", render_rgb(&RayScene::new(scene).unwrap(), POSE, 0.0, &cam)),
        ("raster", RasterScene::new(scene).unwrap().render_rgb(POSE, 0.0, &cam)),
    ];
    if let Some(g) = gpu(test, scene) {
        out.push(("wgpu", g.render_rgb(POSE, 0.0, &cam).unwrap()));
    }
    out
}

fn px(img: &[u8], (u, v): (usize, usize)) -> [u8; 3] {
    let i = (v * 256 + u) * 3;
    [img[i], img[i + 1], img[i + 2]]
}

/// `c` shaded as the renderers shade the pixel (u, v) of a wall facing the camera squarely.
fn shaded(c: [u8; 4], (u, v): (usize, usize)) -> [u8; 3] {
    let k = CameraParams::default().intrinsics();
    let (x, y) = ((u as f64 - k.cx) / k.fx, (v as f64 - k.cy) / k.fy);
    let cos = 1.0 / (1.0 + x * x + y * y).sqrt();
    [0, 1, 2].map(|i| (c[i] as f64 * (0.35 + 0.65 * cos)).round() as u8)
}

#[test]
fn a_checkerboard_wall_shows_its_cells_upright_in_every_renderer() {
    let scene = wall(checker(), 0.0, 1.0);
    for (name, img) in render_all("a_checkerboard_wall_shows_its_cells_upright_in_every_renderer", &scene) {
        // The centre of every cell of the 8 x 8 board, on screen.
        for cy in 0..8 {
            for cx in 0..8 {
                let (y, z) = wall_point((cx as f64 + 0.5) / 8.0, (cy as f64 + 0.5) / 8.0, 0.0, 1.0);
                let p = pixel_of(y, z);
                let want = if (cx, cy) == (0, 0) { RED } else if (cx + cy) % 2 == 0 { WHITE } else { BLACK };
                let got = px(&img, p);
                let exp = shaded(want, p);
                assert!(got.iter().zip(exp).all(|(a, b)| a.abs_diff(b) <= 1), "{name}: cell ({cx}, {cy}) at pixel {p:?}: {got:?}, want {exp:?}");
            }
        }
    }
}

#[test]
fn the_base_colour_factor_multiplies_the_texture_in_linear_space() {
    let mut scene = wall(checker(), 0.0, 1.0);
    scene.meshes[0].base_color = [0.5, 0.25, 1.0, 1.0];
    let (y, z) = wall_point(1.5 / 8.0, 0.5 / 8.0, 0.0, 1.0);
    let p = pixel_of(y, z); // a black cell
    let q = pixel_of(wall_point(2.5 / 8.0, 0.5 / 8.0, 0.0, 1.0).0, z); // a white cell
    let white = [linear_to_srgb_byte(0.5), linear_to_srgb_byte(0.25), 255, 255];
    for (name, img) in render_all("the_base_colour_factor_multiplies_the_texture_in_linear_space", &scene) {
        assert_eq!(px(&img, p), [0, 0, 0], "{name}");
        let (got, exp) = (px(&img, q), shaded(white, q));
        assert!(got.iter().zip(exp).all(|(a, b)| a.abs_diff(b) <= 1), "{name}: {got:?}, want {exp:?}");
    }
}

#[test]
fn wrap_modes_repeat_clamp_and_mirror_in_every_renderer() {
    // Two texels, red then blue; u runs from -1 to 2 across the wall.
    let two = |w: Wrap| Texture { name: "two".into(), width: 2, height: 1, rgba: Arc::new([RED, BLUE].concat()), wrap_s: w, wrap_t: Wrap::Repeat };
    // At u = -0.75, -0.25, ..., 1.75 (texel centres and their images): red or blue.
    let cases = [
        (Wrap::Repeat, [RED, BLUE, RED, BLUE, RED, BLUE]),
        (Wrap::ClampToEdge, [RED, RED, RED, BLUE, BLUE, BLUE]),
        (Wrap::MirroredRepeat, [BLUE, RED, RED, BLUE, BLUE, RED]),
    ];
    for (mode, want) in cases {
        let scene = wall(two(mode), -1.0, 2.0);
        for (name, img) in render_all("wrap_modes_repeat_clamp_and_mirror_in_every_renderer", &scene) {
            for (i, w) in want.iter().enumerate() {
                let u = -0.75 + 0.5 * i as f64;
                let p = pixel_of(wall_point(u, 0.5, -1.0, 2.0).0, 1.25);
                let c = px(&img, p);
                // Pixel centres miss the texel centre by up to half a pixel: mostly one colour.
                let ok = if *w == RED { c[0] > 150 && c[2] < 40 } else { c[2] > 150 && c[0] < 40 };
                assert!(ok, "{name} {mode:?}: u = {u} at pixel {p:?} is {c:?}, want {w:?}");
            }
        }
    }
}

/// A 2 x 2 PNG (red, blue / blue, red).
fn png() -> Vec<u8> {
    let mut out = Vec::new();
    let img = image::RgbaImage::from_raw(2, 2, [RED, BLUE, BLUE, RED].concat()).unwrap();
    img.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png).unwrap();
    out
}

/// A .gltf quad "quad" whose material's base colour texture reads image `image` (a JSON
/// object) with texture coordinate set `set`; `uvs` texture coordinates are stored.
fn gltf_quad(dir: &Path, file: &str, image: serde_json::Value, set: u32, uvs: usize) -> PathBuf {
    let mut bin = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]] {
        p.iter().for_each(|v| bin.extend_from_slice(&v.to_le_bytes()));
    }
    for uv in [[0.0f32, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0], [0.5, 0.5]].iter().take(uvs) {
        uv.iter().for_each(|v| bin.extend_from_slice(&v.to_le_bytes()));
    }
    for i in [0u32, 1, 2, 0, 2, 3] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let uri = format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bin));
    let json = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"name": "quad", "mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": set}}}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"wrapS": 33071, "wrapT": 33648}],
        "images": [image],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": uvs, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 8 * uvs},
            {"buffer": 0, "byteOffset": 48 + 8 * uvs, "byteLength": 24},
        ],
        "buffers": [{"byteLength": bin.len(), "uri": uri}],
    });
    let p = dir.join(file);
    std::fs::write(&p, serde_json::to_vec_pretty(&json).unwrap()).unwrap();
    p
}

fn load_err(p: &Path) -> String {
    match load(p, &LoadOptions::default()) {
        Err(e @ SceneError::Texture { .. }) => e.to_string(),
        other => panic!("{}: want a texture error, got {other:?}", p.display()),
    }
}

#[test]
fn gltf_textures_load_from_files_and_data_uris_with_their_sampler() {
    let dir = tmp("gltf");
    std::fs::write(dir.join("tex 1.png"), png()).unwrap();
    let data = format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(png()));
    for image in [serde_json::json!({"uri": "tex%201.png"}), serde_json::json!({"uri": data})] {
        let p = gltf_quad(&dir, "quad.gltf", image.clone(), 0, 4);
        let s = load(&p, &LoadOptions::default()).unwrap_or_else(|e| panic!("{image}: {e}"));
        assert_eq!(s.textures.len(), 1);
        let t = &s.textures[0];
        assert_eq!((t.width, t.height, t.wrap_s, t.wrap_t), (2, 2, Wrap::ClampToEdge, Wrap::MirroredRepeat));
        assert_eq!(*t.rgba, [RED, BLUE, BLUE, RED].concat());
        assert_eq!(s.meshes[0].texture, Some(0));
        assert_eq!(s.meshes[0].uvs, [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    }
}

#[test]
fn bad_texture_references_are_errors_or_warnings_never_panics() {
    let dir = tmp("bad");
    // A missing image file: an error naming the scene file, the mesh and the image.
    let p = gltf_quad(&dir, "missing.gltf", serde_json::json!({"uri": "nowhere.png"}), 0, 4);
    let e = load_err(&p);
    assert!(e.contains("missing.gltf") && e.contains("'quad'") && e.contains("nowhere.png"), "{e}");
    // Bytes that are no image.
    std::fs::write(dir.join("junk.png"), b"this is not a png").unwrap();
    let e = load_err(&gltf_quad(&dir, "junk.gltf", serde_json::json!({"uri": "junk.png"}), 0, 4));
    assert!(e.contains("junk.png") && e.contains("decode"), "{e}");
    // A bad data URI and a network URI.
    let e = load_err(&gltf_quad(&dir, "b64.gltf", serde_json::json!({"uri": "data:image/png;base64,@@@"}), 0, 4));
    assert!(e.contains("base64"), "{e}");
    let e = load_err(&gltf_quad(&dir, "net.gltf", serde_json::json!({"uri": "http://example.invalid/a.png"}), 0, 4));
    assert!(e.contains("network"), "{e}");
    // An image in a buffer view that holds no image.
    let e = load_err(&gltf_quad(&dir, "view.gltf", serde_json::json!({"bufferView": 1, "mimeType": "image/png"}), 0, 4));
    assert!(e.contains("image 0") && e.contains("decode"), "{e}");
    // TEXCOORD_1 absent, or fewer texture coordinates than vertices: drawn with the factor.
    std::fs::write(dir.join("ok.png"), png()).unwrap();
    for (file, set, n) in [("set1.gltf", 1, 4), ("short.gltf", 0, 3), ("long.gltf", 0, 5)] {
        let s = load(&gltf_quad(&dir, file, serde_json::json!({"uri": "ok.png"}), set, n), &LoadOptions::default()).unwrap();
        assert_eq!(s.meshes[0].texture, None, "{file}");
        assert!(RasterScene::new(&s).is_some());
    }
}

#[test]
fn obj_map_kd_loads_with_flipped_vt() {
    let dir = tmp("obj");
    std::fs::write(dir.join("wood.png"), png()).unwrap();
    std::fs::write(dir.join("a.mtl"), "newmtl wood\nKd 0.2 0.2 0.2\nmap_Kd wood.png\nnewmtl bad\nmap_Kd gone.png\n").unwrap();
    let obj = "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 0.25\nusemtl wood\nf 1/1 2/2 3/3\n";
    std::fs::write(dir.join("a.obj"), obj).unwrap();
    let s = load(&dir.join("a.obj"), &LoadOptions::default()).unwrap();
    assert_eq!(s.textures.len(), 1);
    let m = &s.meshes[0];
    assert_eq!(m.texture, Some(0));
    assert_eq!(m.base_color, [1.0; 4]);
    // OBJ's v points up, glTF's down.
    assert_eq!(m.uvs, [[0.0, 1.0], [1.0, 1.0], [1.0, 0.75]]);
    std::fs::write(dir.join("b.obj"), obj.replace("usemtl wood", "usemtl bad")).unwrap();
    let e = load_err(&dir.join("b.obj"));
    assert!(e.contains("b.obj") && e.contains("gone.png"), "{e}");
}

#[test]
fn glb_round_trip_keeps_textures_and_texture_coordinates() {
    let mut scene = wall(checker(), -0.5, 1.5);
    scene.textures[0].wrap_t = Wrap::MirroredRepeat;
    scene.add_box("plain", [3.0, 0.0, 0.0], [4.0, 1.0, 1.0], [0.2, 0.4, 0.6, 1.0]);
    let bytes = to_glb_bytes(&scene);
    assert_eq!(bytes, to_glb_bytes(&scene));
    let p = tmp("round").join("round.glb");
    std::fs::write(&p, &bytes).unwrap();
    let back = load(&p, &LoadOptions::default()).unwrap();
    assert_eq!(back.textures.len(), 1);
    let (a, b) = (&scene.textures[0], &back.textures[0]);
    assert_eq!((a.width, a.height, &a.rgba, a.wrap_s, a.wrap_t), (b.width, b.height, &b.rgba, b.wrap_s, b.wrap_t));
    assert_eq!(back.meshes[0].uvs, scene.meshes[0].uvs);
    assert_eq!(back.meshes[0].texture, Some(0));
    assert_eq!((back.meshes[1].texture, back.meshes[1].uvs.len()), (None, 0));
}

#[test]
fn without_textures_a_scene_loads_the_same_geometry_and_reads_no_image() {
    let no_textures = LoadOptions { textures: false, ..LoadOptions::default() };
    // glTF: a wall with its texture in the GLB; the geometry is the same to the bit.
    let p = tmp("geometry").join("wall.glb");
    std::fs::write(&p, to_glb_bytes(&wall(checker(), -0.5, 1.5))).unwrap();
    let (full, bare) = (load(&p, &LoadOptions::default()).unwrap(), load(&p, &no_textures).unwrap());
    assert_eq!((full.textures.len(), bare.textures.len()), (1, 0));
    assert_eq!(full.meshes.len(), bare.meshes.len());
    for (a, b) in full.meshes.iter().zip(&bare.meshes) {
        assert_eq!((&a.positions, &a.indices, a.base_color), (&b.positions, &b.indices, b.base_color));
        assert_eq!((b.texture, b.uvs.len()), (None, 0));
    }
    assert!(RasterScene::new(&bare).is_some());
    // An image that is missing, or no image at all, is never read, so it is no error.
    let dir = tmp("geometry_missing");
    let p = gltf_quad(&dir, "missing.gltf", serde_json::json!({"uri": "nowhere.png"}), 0, 4);
    assert!(load(&p, &LoadOptions::default()).is_err());
    assert_eq!(load(&p, &no_textures).unwrap().meshes[0].texture, None);
    std::fs::write(dir.join("a.mtl"), "newmtl bad\nKd 0.2 0.3 0.4\nmap_Kd gone.png\n").unwrap();
    std::fs::write(dir.join("a.obj"), "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl bad\nf 1/1 2/2 3/3\n").unwrap();
    assert!(load(&dir.join("a.obj"), &LoadOptions::default()).is_err());
    let s = load(&dir.join("a.obj"), &no_textures).unwrap();
    assert_eq!((s.textures.len(), s.meshes[0].texture, s.meshes[0].base_color), (0, None, [0.2, 0.3, 0.4, 1.0]));
}

/// Texels per metre of [`far_floor`]'s checkerboard.
const FLOOR_TEXELS_PER_M: f64 = 50.0;

/// A 256 x 256 checkerboard of 1-texel squares (white at (0, 0)), repeating.
fn fine_checker() -> Texture {
    let rgba = (0..256u32).flat_map(|y| (0..256u32).map(move |x| if (x + y) % 2 == 0 { WHITE } else { BLACK })).flatten().collect();
    Texture { name: "fine checker".into(), width: 256, height: 256, rgba: Arc::new(rgba), wrap_s: Wrap::Repeat, wrap_t: Wrap::Repeat }
}

/// A floor at z = 0, x in [0.5, 40] (m) ahead of the camera, y in [-31, 31], covered with
/// [`fine_checker`] at [`FLOOR_TEXELS_PER_M`] (u along x, v along y).
fn far_floor() -> Scene {
    let corners = [[0.5f32, 31.0], [40.0, 31.0], [40.0, -31.0], [0.5, -31.0]];
    let mut m = Mesh::new("floor", corners.iter().map(|c| [c[0], c[1], 0.0]).collect(), vec![[0, 1, 2], [0, 2, 3]], [1.0; 4]);
    let s = (FLOOR_TEXELS_PER_M / 256.0) as f32;
    m.uvs = corners.iter().map(|c| [c[0] * s, c[1] * s]).collect();
    m.texture = Some(0);
    Scene { meshes: vec![m], textures: vec![fine_checker()] }
}

/// sRGB byte to linear.
fn decode(b: u8) -> f64 {
    let c = b as f64 / 255.0;
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// What a renderer without mipmaps shows along the ray `(1, -x, -y)` from 1.25 m above
/// [`far_floor`]: the texture sampled bilinearly from the image itself at the hit, encoded and
/// shaded as the renderers do (RGB bytes, all equal here).
fn bilinear_ray(tex: &Texture, x: f64, y: f64) -> u8 {
    let t = 1.25 / y;
    let s = FLOOR_TEXELS_PER_M / 256.0;
    let lin = xhab_sim::sensors::surface::sample_bilinear(tex, [(t * s) as f32, (-x * t * s) as f32]);
    let cos = y / (1.0 + x * x + y * y).sqrt();
    (linear_to_srgb_byte(lin[0]) as f64 * (0.35 + 0.65 * cos) + 0.5) as u8
}

#[test]
fn a_distant_fine_checkerboard_floor_is_grey_not_a_moire() {
    let test = "a_distant_fine_checkerboard_floor_is_grey_not_a_moire";
    let scene = far_floor();
    let tex = fine_checker();
    let cam = CameraParams { max_depth: 30.0, ..Default::default() };
    let k = cam.intrinsics();
    // Floor pixels whose centre ray meets the floor within 25 m (so every sub-ray does within
    // the camera's 30 m), with the distance along the optical axis.
    let floor: Vec<(usize, usize, f64)> = (0..cam.height)
        .flat_map(|v| (0..cam.width).map(move |u| (u, v)))
        .filter_map(|(u, v)| {
            let y = (v as f64 - k.cy) / k.fy;
            (y > 0.0 && 1.25 / y < 25.0).then_some((u, v, 1.25 / y))
        })
        .collect();
    // The reference: 8 x 8 sub-rays per pixel, averaged in linear space; and what the
    // renderers showed before mipmaps: the centre ray alone.
    let n = 8;
    let reference: Vec<f64> = floor
        .iter()
        .map(|&(u, v, _)| {
            let mut sum = 0.0;
            for j in 0..n {
                for i in 0..n {
                    let x = (u as f64 - 0.5 + (i as f64 + 0.5) / n as f64 - k.cx) / k.fx;
                    let y = (v as f64 - 0.5 + (j as f64 + 0.5) / n as f64 - k.cy) / k.fy;
                    sum += decode(bilinear_ray(&tex, x, y));
                }
            }
            linear_to_srgb_byte((sum / (n * n) as f64) as f32) as f64
        })
        .collect();
    let single: Vec<f64> = floor.iter().map(|&(u, v, _)| bilinear_ray(&tex, (u as f64 - k.cx) / k.fx, (v as f64 - k.cy) / k.fy) as f64).collect();
    // Mean absolute error (bytes) over the floor, and over its far part (beyond 8 m), where
    // a pixel spans many texels.
    let far: Vec<bool> = floor.iter().map(|p| p.2 > 8.0).collect();
    let errors = |img: &[f64]| {
        let e: Vec<f64> = img.iter().zip(&reference).map(|(a, b)| (a - b).abs()).collect();
        let far_e: Vec<f64> = e.iter().zip(&far).filter(|(_, f)| **f).map(|(e, _)| *e).collect();
        (e.iter().sum::<f64>() / e.len() as f64, far_e.iter().sum::<f64>() / far_e.len() as f64, far_e.iter().cloned().fold(0.0, f64::max))
    };
    let (old_mae, old_far, old_max) = errors(&single);
    eprintln!("{test}: {} floor pixels ({} beyond 8 m); without mipmaps: mean error {old_mae:.2}, far {old_far:.2}, far max {old_max}", floor.len(), far.iter().filter(|f| **f).count());
    assert!(old_far > 4.0, "the view should alias without mipmaps (far mean error {old_far:.2})");
    let mut renders = vec![
        ("raycast", render_rgb(&RayScene::new(&scene).unwrap(), POSE, 0.0, &cam)),
        ("raster", RasterScene::new(&scene).unwrap().render_rgb(POSE, 0.0, &cam)),
    ];
    if let Some(g) = gpu(test, &scene) {
        renders.push(("wgpu", g.render_rgb(POSE, 0.0, &cam).unwrap()));
    }
    for (name, img) in renders {
        let got: Vec<f64> = floor.iter().map(|&(u, v, _)| img[(v * cam.width + u) * 3] as f64).collect();
        let (mae, far_mae, far_max) = errors(&got);
        eprintln!("{test}: {name}: mean error {mae:.2}, far {far_mae:.2}, far max {far_max}");
        assert!(mae < 0.5 * old_mae, "{name}: mean error {mae:.2} vs {old_mae:.2} without mipmaps");
        // No moire: far away the floor is an even grey, close to the reference everywhere.
        assert!(far_mae < 0.25 * old_far && far_max < 0.5 * old_max, "{name}: far mean error {far_mae:.2}, max {far_max} (without mipmaps {old_far:.2}, {old_max})");
    }
}
