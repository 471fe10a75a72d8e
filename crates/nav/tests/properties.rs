//! Property tests (proptest) of the navigation stack's grid code against ROS's rules, each
//! checked by an independent reference written here from the ROS sources' semantics:
//! - map_server (noetic image_loader.cpp): any PGM/PNG image, any thresholds, `negate`, mode;
//! - map_saver round trips: a saved map loads back as map_saver's three classes;
//! - costmap_2d's inflation: every cell's cost from the brute-force distance to the nearest
//!   lethal cell (or the map's edge);
//! - the exact squared distance transform the layered costmaps update in pieces.

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use xhab_nav::costmap::{inflation_cost, Costmap, CostmapParams, FREE, INSCRIBED, LETHAL, UNKNOWN};
use xhab_nav::distance_field::{squared_edt, FAR};
use xhab_nav::map_server::{decode_map_image, load_map, save_map, MapMetadata, MapMode};
use xhab_types::{OccupancyGrid, Pose2, GRID_UNKNOWN};

/// An image as map_server's SDL sees it: rows top first, `channels` bytes per pixel (1 grey,
/// 3 RGB, 4 RGBA with alpha last).
#[derive(Debug, Clone)]
struct Image {
    w: usize,
    h: usize,
    channels: usize,
    px: Vec<u8>,
}

fn image() -> impl Strategy<Value = Image> {
    (1usize..7, 1usize..7, prop::sample::select(vec![1usize, 3, 4])).prop_flat_map(|(w, h, channels)| {
        // Pixel values near the thresholds and the extremes, and anything else.
        let value = prop_oneof![Just(0u8), Just(254u8), Just(255u8), Just(205u8), Just(0u8), any::<u8>()];
        prop::collection::vec(value, w * h * channels).prop_map(move |px| Image { w, h, channels, px })
    })
}

fn metadata() -> impl Strategy<Value = MapMetadata> {
    (0.0..0.6f64, 0.0..1.0f64, any::<bool>(), prop::sample::select(vec![MapMode::Trinary, MapMode::Scale, MapMode::Raw])).prop_map(
        |(free, span, negate, mode)| MapMetadata {
            image: PathBuf::from("map.png"),
            resolution: 0.05,
            origin: [-1.0, 2.0, 0.0],
            negate,
            occupied_thresh: free + 1e-3 + span * (1.0 - free),
            free_thresh: free,
            mode,
        },
    )
}

/// map_server's conversion of one pixel (noetic image_loader.cpp), written from its rules.
fn ros_value(p: &[u8], m: &MapMetadata) -> i8 {
    let n = p.len();
    let has_alpha = n == 4;
    // Trinary mode averages alpha in with the colours; the other modes leave it out.
    let avg_channels = if m.mode == MapMode::Trinary || !has_alpha { n } else { n - 1 };
    let mut avg = p[..avg_channels].iter().map(|&v| v as u32).sum::<u32>() as f64 / avg_channels as f64;
    let alpha = if n == 1 { 1.0 } else { p[n - 1] as f64 };
    if m.negate {
        avg = 255.0 - avg;
    }
    if m.mode == MapMode::Raw {
        return avg as u8 as i8;
    }
    let occ = (255.0 - avg) / 255.0;
    if occ > m.occupied_thresh {
        100
    } else if occ < m.free_thresh {
        0
    } else if m.mode == MapMode::Trinary || alpha < 1.0 {
        -1
    } else {
        (1.0 + 98.0 * (occ - m.free_thresh) / (m.occupied_thresh - m.free_thresh)) as u8 as i8
    }
}

/// The image's bytes as a file: PGM (P5 or P2) for grey, PNG otherwise.
fn encode(img: &Image, ascii: bool) -> Vec<u8> {
    match img.channels {
        1 if ascii => {
            let mut s = format!("P2\n{} {}\n255\n", img.w, img.h);
            for v in &img.px {
                s += &format!("{v} ");
            }
            s.into_bytes()
        }
        1 => {
            let mut b = format!("P5\n{} {}\n255\n", img.w, img.h).into_bytes();
            b.extend_from_slice(&img.px);
            b
        }
        c => {
            let color = if c == 3 { image::ExtendedColorType::Rgb8 } else { image::ExtendedColorType::Rgba8 };
            let mut out = Vec::new();
            image::ImageEncoder::write_image(image::codecs::png::PngEncoder::new(&mut out), &img.px, img.w as u32, img.h as u32, color).unwrap();
            out
        }
    }
}

fn temp_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("xhab-nav-properties-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A random occupancy grid (values anywhere in -1..=100, unknown and the extremes often).
fn grid() -> impl Strategy<Value = OccupancyGrid> {
    (1usize..24, 1usize..24, prop::sample::select(vec![0.01, 0.05, 0.1, 0.3]), -5.0..5.0f64, -5.0..5.0f64).prop_flat_map(|(w, h, res, x, y)| {
        let value = prop_oneof![Just(-1i8), Just(0i8), Just(100i8), -1i8..=100];
        prop::collection::vec(value, w * h).prop_map(move |data| OccupancyGrid { width: w, height: h, resolution: res, origin: Pose2::new(x, y, 0.0), data })
    })
}

/// A random map of lethal cells and free and unknown ones, 1–40 cells a side.
fn obstacle_map() -> impl Strategy<Value = OccupancyGrid> {
    (1usize..40, 1usize..40, 0u32..30).prop_flat_map(|(w, h, percent)| {
        let value = prop_oneof![100 - percent => prop_oneof![Just(0i8), Just(-1i8)], percent => Just(100i8)];
        prop::collection::vec(value, w * h).prop_map(move |data| OccupancyGrid { width: w, height: h, resolution: 0.05, origin: Pose2::new(0.3, -0.7, 0.0), data })
    })
}

fn costmap_params() -> impl Strategy<Value = CostmapParams> {
    (0.0..0.4f64, 0.0..1.0f64, 0.5..15.0f64, any::<bool>()).prop_map(|(radius, inflation, scaling, track_unknown)| CostmapParams {
        robot_radius: radius,
        inflation_radius: inflation,
        cost_scaling_factor: scaling,
        track_unknown_space: track_unknown,
        ..CostmapParams::default()
    })
}

/// The cases' seed: `$PROPTEST_RNG_SEED`, else a fixed one.
fn rng_seed() -> u64 {
    std::env::var("PROPTEST_RNG_SEED").ok().and_then(|s| s.parse().ok()).unwrap_or(20261125)
}

proptest! {
    // A fixed seed: the suite is deterministic like every other test (set PROPTEST_RNG_SEED
    // to explore other cases).
    #![proptest_config(ProptestConfig { cases: 128, rng_seed: proptest::test_runner::RngSeed::Fixed(rng_seed()), ..ProptestConfig::default() })]

    #[test]
    fn map_images_decode_as_map_server_decodes_them(img in image(), meta in metadata(), ascii in any::<bool>()) {
        let bytes = encode(&img, ascii);
        let g = decode_map_image(&bytes, Path::new("map.png"), &meta).expect("a well-formed image decodes");
        prop_assert_eq!((g.width, g.height), (img.w, img.h));
        for j in 0..img.h {
            for i in 0..img.w {
                let k = (j * img.w + i) * img.channels;
                let want = ros_value(&img.px[k..k + img.channels], &meta);
                // Image row j (top first) is grid row h-1-j (bottom first).
                prop_assert_eq!(g.get(i, img.h - 1 - j), want, "pixel ({}, {}) {:?}", i, j, &img.px[k..k + img.channels]);
            }
        }
    }

    #[test]
    fn a_saved_map_loads_back_as_map_savers_three_classes(g in grid()) {
        let yaml = temp_dir().join(format!("m{}.yaml", g.data.len()));
        save_map(&g, &yaml).unwrap();
        let (back, _) = load_map(&yaml).unwrap();
        prop_assert_eq!((back.width, back.height, back.resolution), (g.width, g.height, g.resolution));
        prop_assert_eq!(back.origin, g.origin);
        for (k, (&v, &b)) in g.data.iter().zip(&back.data).enumerate() {
            // map_saver: 0..=25 free, >= 65 occupied, the rest (and -1) unknown.
            let want = if (0..=25).contains(&v) { 0 } else if v >= 65 { 100 } else { GRID_UNKNOWN };
            prop_assert_eq!(b, want, "cell {} was {}", k, v);
        }
    }

    #[test]
    fn inflation_follows_costmap_2d_from_the_nearest_lethal_cell(map in obstacle_map(), p in costmap_params()) {
        let cm = Costmap::from_map(&map, &p);
        let (w, h) = (map.width, map.height);
        let lethal: Vec<(usize, usize)> = (0..w * h).filter(|&i| map.data[i] >= p.lethal_cost_threshold).map(|i| (i % w, i / w)).collect();
        for r in 0..h {
            for c in 0..w {
                let i = r * w + c;
                // Cells to the nearest lethal cell centre, or straight across the nearest edge
                // (the map's outside counts as an obstacle).
                let to_lethal = lethal.iter().map(|&(lc, lr)| ((lc as f64 - c as f64).powi(2) + (lr as f64 - r as f64).powi(2)).sqrt()).fold(f64::INFINITY, f64::min);
                let to_edge = (c + 1).min(r + 1).min(w - c).min(h - r) as f64;
                let d = to_lethal.min(to_edge) * map.resolution;
                let want = if map.data[i] >= p.lethal_cost_threshold {
                    LETHAL
                } else {
                    let c = inflation_cost(d, &p);
                    if p.track_unknown_space && map.data[i] == GRID_UNKNOWN && c < INSCRIBED { UNKNOWN } else { c }
                };
                prop_assert_eq!(cm.cost[i], want, "cell ({}, {}) at {} m", c, r, d);
            }
        }
    }

    #[test]
    fn the_inflation_cost_is_costmap_2ds_and_never_rises_with_distance(p in costmap_params(), d in 0.0..2.0f64, step in 0.0..0.5f64) {
        let (near, far) = (inflation_cost(d, &p), inflation_cost(d + step, &p));
        prop_assert!(far <= near, "{} at {} m but {} at {} m", near, d, far, d + step);
        let inscribed = p.inscribed_radius();
        let want = if d <= 0.0 { LETHAL } else if d <= inscribed { INSCRIBED } else if d > p.inflation_radius { FREE } else {
            // costmap_2d: (INSCRIBED - 1) * exp(-factor * (d - inscribed)), truncated.
            ((INSCRIBED - 1) as f64 * (-p.cost_scaling_factor * (d - inscribed)).exp()) as u8
        };
        prop_assert_eq!(near, want);
    }

    #[test]
    fn the_squared_distance_transform_is_exact_up_to_its_cap(w in 1usize..30, h in 1usize..30, seed in any::<u64>(), density in 0.0..0.2f64, cap in 0u32..200) {
        let blocked: Vec<bool> = (0..w * h).map(|i| {
            let x = (seed ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            ((x >> 11) as f64 / (1u64 << 53) as f64) < density
        }).collect();
        let mut out = Vec::new();
        squared_edt(w, h, |c, r| blocked[r * w + c], cap, &mut out);
        for r in 0..h {
            for c in 0..w {
                let exact = (0..w * h).filter(|&j| blocked[j]).map(|j| {
                    let (dc, dr) = ((j % w).abs_diff(c) as u32, (j / w).abs_diff(r) as u32);
                    dc * dc + dr * dr
                }).min().unwrap_or(FAR);
                let got = out[r * w + c];
                if exact <= cap {
                    prop_assert_eq!(got, exact, "cell ({}, {})", c, r);
                } else {
                    prop_assert!(got > cap, "cell ({}, {}): {} within the cap {} but the nearest is {}", c, r, got, cap, exact);
                }
            }
        }
    }
}
