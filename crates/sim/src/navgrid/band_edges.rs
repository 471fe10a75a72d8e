//! The obstacle edges of the agent's body band: each scene triangle clipped to the band's
//! heights and projected onto the ground plane gives a convex piece, whose edges are the 2D
//! segments that [`super::clearance`] measures distances to.
//!
//! Most of a furnished scene's pieces tile larger surfaces (a table top, a shelf, a sofa's
//! seat), and the edges they share lie inside the obstacles. [`boundary_edges`] drops an edge
//! that pieces cover on both sides, and duplicates: no point off the obstacles is nearest to
//! such an edge (a point outside a union of pieces is nearest to the union's boundary, and an
//! edge's ends belong to the boundary's edges too), so every distance and nearest point from
//! the region is what it was with all the edges. On aws_small_house the band's 320k edges
//! leave 133k distinct ones and 49k on the boundary.

use super::clearance::Seg;
use super::raster;

/// Adds the edges of the part of `tri` between heights `lo` and `hi`, projected to 2D.
pub(crate) fn band_segments(tri: &[[f64; 3]; 3], lo: f64, hi: f64, out: &mut Vec<Seg>) {
    band_segments_with(tri, lo, hi, &mut Vec::with_capacity(5), &mut Vec::with_capacity(5), out);
}

/// [`band_segments`] with buffers for the clipped polygon and the clip in between.
pub(crate) fn band_segments_with(tri: &[[f64; 3]; 3], lo: f64, hi: f64, poly: &mut raster::Poly, tmp: &mut raster::Poly, out: &mut Vec<Seg>) {
    raster::clip_slab_with(tri, 2, lo, hi, tmp, poly);
    let n = poly.len();
    if n == 0 {
        return;
    }
    for i in 0..n {
        let a = [poly[i][0], poly[i][1]];
        let b = [poly[(i + 1) % n][0], poly[(i + 1) % n][1]];
        out.push([a, b]);
    }
    if n == 1 {
        out.push([[poly[0][0], poly[0][1]]; 2]);
    }
}

/// Adds the edges of the part of `tri` between heights `lo` and `hi`, projected to 2D, each
/// with the height range (m) of the piece it bounds. A sloped triangle is cut into slices of
/// [`SLICE`] so that a cell sees only the part of it within its own body band (to a slice);
/// an upright one projects to the same line at every height and is kept whole.
pub(crate) fn band_segments_sliced(tri: &[[f64; 3]; 3], lo: f64, hi: f64, out: &mut Vec<(Seg, [f32; 2])>) {
    let zlo = tri[0][2].min(tri[1][2]).min(tri[2][2]).max(lo);
    let zhi = tri[0][2].max(tri[1][2]).max(tri[2][2]).min(hi);
    if zhi < zlo {
        return;
    }
    let upright = raster::abs_normal_z(tri).is_none_or(|nz| nz < 1e-3);
    let mut edges = Vec::new();
    let mut a = zlo;
    loop {
        let b = if upright { zhi } else { (a + SLICE).min(zhi) };
        edges.clear();
        band_segments(tri, a, b, &mut edges);
        out.extend(edges.iter().map(|s| (*s, [a as f32, b as f32])));
        if b >= zhi {
            break;
        }
        a = b;
    }
}

/// Height of the slices a sloped obstacle is cut into on a storey with stairs (m).
pub(crate) const SLICE: f64 = 0.1;

/// [`band_segments_with`], also giving each new edge the side of it that its piece covers,
/// in `sides`: +1 when the piece, in projection, turns counter-clockwise (it lies left of the
/// edge as emitted), -1 clockwise, 0 when it is thinner than [`SIDED_WIDTH`] (an upright
/// triangle's piece has no area in projection: it covers neither side).
pub(crate) fn band_edges_with(tri: &[[f64; 3]; 3], lo: f64, hi: f64, poly: &mut raster::Poly, tmp: &mut raster::Poly, out: &mut Vec<Seg>, sides: &mut Vec<i8>) {
    debug_assert_eq!(out.len(), sides.len());
    band_segments_with(tri, lo, hi, poly, tmp, out);
    let n = poly.len();
    // Twice the signed area (about the first corner) and the longest edge, squared.
    let (mut twice_area, mut longest2) = (0.0f64, 0.0f64);
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        twice_area += (a[0] - poly[0][0]) * (b[1] - poly[0][1]) - (a[1] - poly[0][1]) * (b[0] - poly[0][0]);
        longest2 = longest2.max((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2));
    }
    // |twice area| <= width * longest edge, squared (no libm call).
    let side = if twice_area * twice_area <= SIDED_WIDTH * SIDED_WIDTH * longest2 {
        0
    } else if twice_area > 0.0 {
        1
    } else {
        -1
    };
    sides.resize(out.len(), side);
}

/// Width (m) of a piece across its longest edge, in projection, below which it covers no side
/// of its edges ([`band_edges_with`]): ten times the quantum of [`boundary_edges`]' keys, so
/// that a sliver's two long edges, which the quantum could make one edge run both ways, never
/// read as an edge covered on both sides.
pub(crate) const SIDED_WIDTH: f64 = 1e-4;

/// The band's edges less duplicates (equal to 10 micrometres, the first kept) and less those
/// that pieces cover on both sides (`sides` from [`band_edges_with`], one per edge): see the
/// module. Kept in a canonical order (by end points), the same for any thread count.
pub(crate) fn boundary_edges(segs: &[Seg], sides: &[i8]) -> Vec<Seg> {
    use rayon::prelude::*;
    // Each edge's key (its ends quantised to 10 micrometres, smaller first), its position, and
    // which side of the key's direction its piece covers (bit 0 left, bit 1 right, none for an
    // upright piece). Sorted by key and then position, so the first of equal keys came first.
    let keyed = |i: usize| {
        let (s, side) = (&segs[i], sides[i]);
        let (a, b) = (quantum(s[0]), quantum(s[1]));
        let covers = match (side, a <= b) {
            (0, _) => 0u8,
            (1, true) | (-1, false) => 1,
            _ => 2,
        };
        (if a <= b { (a, b) } else { (b, a) }, covers)
    };
    // Of each group of equal keys, the first edge unless its pieces cover both sides.
    let kept = |first: usize, covers: u8| (covers != 3).then(|| segs[first]);
    match packing(segs) {
        Some(pack) => {
            // One 128-bit number per edge, in the order of (key, position): the four
            // coordinates less their minimum, `pack.bits` each, then the position and sides.
            let mut packed: Vec<u128> = (0..segs.len())
                .into_par_iter()
                .map(|i| {
                    let ((a, b), covers) = keyed(i);
                    let key = [a[0] - pack.min[0], a[1] - pack.min[1], b[0] - pack.min[0], b[1] - pack.min[1]]
                        .iter()
                        .fold(0u128, |k, &v| k << pack.bits | v as u128);
                    key << pack.low | (i as u128) << 2 | covers as u128
                })
                .collect();
            packed.par_sort_unstable();
            let index = (1u128 << (pack.low - 2)) - 1;
            packed.chunk_by(|x, y| x >> pack.low == y >> pack.low).filter_map(|g| kept((g[0] >> 2 & index) as usize, g.iter().fold(0, |c, &k| c | (k & 3) as u8))).collect()
        }
        None => {
            let mut keyed: Vec<_> = (0..segs.len()).into_par_iter().map(|i| (keyed(i), i)).collect();
            keyed.par_sort_unstable_by_key(|k| (k.0 .0, k.1));
            keyed.chunk_by(|x, y| x.0 .0 == y.0 .0).filter_map(|g| kept(g[0].1, g.iter().fold(0, |c, k| c | k.0 .1))).collect()
        }
    }
}

/// A point's coordinates (m) in units of 10 micrometres, rounded half away from zero as
/// `f64::round` rounds, without its library call where the fraction `v - trunc(v)` is exact.
#[inline]
fn quantum(p: [f64; 2]) -> [i64; 2] {
    p.map(|x| {
        let v = x * 1e5;
        if !(v.abs() < 4e15) {
            return v.round() as i64;
        }
        let t = v as i64;
        let f = v - t as f64;
        t + (f >= 0.5) as i64 - (f <= -0.5) as i64
    })
}

/// How [`boundary_edges`] packs an edge into one 128-bit number: its key's four quantised
/// coordinates less the smallest (x and y apart), `bits` bits each, above `low` bits holding
/// its position and (the lowest two) the sides its piece covers.
struct Packing {
    min: [i64; 2],
    bits: u32,
    low: u32,
}

/// The packing of `segs`' keys; `None` when they do not fit 128 bits (a span under 2^26
/// quanta, 671 m, fits with up to 2^20 edges).
fn packing(segs: &[Seg]) -> Option<Packing> {
    use rayon::prelude::*;
    if segs.is_empty() || segs.len() > u32::MAX as usize {
        return None;
    }
    // `quantum` never decreases as a coordinate grows, so the extreme keys are the extreme
    // coordinates' (a NaN coordinate, whose key is 0, is counted apart).
    let (lo, hi, nan) = segs
        .par_iter()
        .fold(
            || ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2], false),
            |(mut lo, mut hi, mut nan), s| {
                for p in s {
                    for k in 0..2 {
                        (lo[k], hi[k]) = (lo[k].min(p[k]), hi[k].max(p[k]));
                        nan |= p[k].is_nan();
                    }
                }
                (lo, hi, nan)
            },
        )
        .reduce(
            || ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2], false),
            |(a, b, n), (c, d, m)| ([a[0].min(c[0]), a[1].min(c[1])], [b[0].max(d[0]), b[1].max(d[1])], n | m),
        );
    let (mut lo, mut hi) = (quantum(lo), quantum(hi));
    if nan {
        (lo, hi) = (lo.map(|v| v.min(0)), hi.map(|v| v.max(0)));
    }
    let span = (hi[0] as i128 - lo[0] as i128).max(hi[1] as i128 - lo[1] as i128);
    let bits = (128 - (span as u128).leading_zeros()).max(1);
    let low = 2 + (usize::BITS - (segs.len() - 1).leading_zeros());
    (4 * bits + low <= 128).then_some(Packing { min: lo, bits, low })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::navgrid::clearance::closest_on_segment;

    /// The band's edges and their sides for triangles (world, m) in a band of 0..1 m.
    fn edges(tris: &[[[f64; 3]; 3]]) -> (Vec<Seg>, Vec<i8>) {
        let (mut out, mut sides, mut poly, mut tmp) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for t in tris {
            band_edges_with(t, 0.0, 1.0, &mut poly, &mut tmp, &mut out, &mut sides);
        }
        (out, sides)
    }

    /// A grid of `n` x `n` unit squares at height 0.5, each cut along a diagonal, the triangles
    /// wound alternately counter-clockwise and clockwise (meshes do both).
    fn tiled(n: usize) -> Vec<[[f64; 3]; 3]> {
        let mut tris = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let p = |dx: usize, dy: usize| [(i + dx) as f64, (j + dy) as f64, 0.5];
                let (a, b) = ([p(0, 0), p(1, 0), p(1, 1)], [p(0, 0), p(1, 1), p(0, 1)]);
                let flip = |t: [[f64; 3]; 3]| [t[0], t[2], t[1]];
                tris.push(if (i + j) % 2 == 0 { a } else { flip(a) });
                tris.push(if (i + j) % 3 == 0 { flip(b) } else { b });
            }
        }
        tris
    }

    #[test]
    fn a_tiled_top_keeps_its_outline_only() {
        let (segs, sides) = edges(&tiled(3));
        assert_eq!(segs.len(), 54);
        assert!(sides.iter().all(|&s| s != 0));
        let kept = boundary_edges(&segs, &sides);
        // The outline: 3 unit edges per side.
        assert_eq!(kept.len(), 12, "{kept:?}");
        let on_outline = |p: [f64; 2]| p[0] == 0.0 || p[0] == 3.0 || p[1] == 0.0 || p[1] == 3.0;
        assert!(kept.iter().all(|s| on_outline(s[0]) && on_outline(s[1]) && (s[0][0] == s[1][0] || s[0][1] == s[1][1])));
        // The same edges whatever order the triangles come in (a canonical order).
        let mut rev = tiled(3);
        rev.reverse();
        let (segs2, sides2) = edges(&rev);
        let mut a: Vec<_> = kept.iter().map(|s| format!("{s:?}")).collect();
        let mut b: Vec<_> = boundary_edges(&segs2, &sides2).iter().map(|s| format!("{s:?}")).collect();
        a.sort();
        b.sort();
        assert_eq!(a, b);
    }

    #[test]
    fn scenes_too_wide_to_pack_keep_the_same_edges() {
        // Two tiled tops 100 km apart: a span of 10^10 quanta (34 bits, four times) does not
        // pack into 128 bits, so the tuples are sorted; each top alone packs. The edges kept
        // are the same.
        let shift = |t: [[f64; 3]; 3]| t.map(|p| [p[0] + 1e5, p[1] - 0.37, p[2]]);
        let (near, far): (Vec<_>, Vec<_>) = (tiled(3), tiled(3).into_iter().map(shift).collect());
        let both: Vec<_> = near.iter().chain(&far).copied().collect();
        let (segs, sides) = edges(&both);
        assert!(packing(&segs).is_none());
        let (s1, d1) = edges(&near);
        let (s2, d2) = edges(&far);
        assert!(packing(&s1).is_some() && packing(&s2).is_some());
        let mut apart = boundary_edges(&s1, &d1);
        apart.extend(boundary_edges(&s2, &d2));
        let kept = boundary_edges(&segs, &sides);
        assert_eq!(kept.len(), 24);
        let sorted = |v: &[Seg]| {
            let mut v: Vec<String> = v.iter().map(|s| format!("{s:?}")).collect();
            v.sort();
            v
        };
        assert_eq!(sorted(&kept), sorted(&apart));
    }

    #[test]
    fn quanta_round_as_the_library_rounds() {
        let mut xs = vec![0.0, -0.0, 1e-5, 5e-6, -5e-6, 1.5e-5, -2.5e-5, 0.49999999999999994e-5, 123.456785, -123.456785, 4e10, -4e10, 1e11, f64::NAN];
        let mut k = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..100_000 {
            k ^= k << 13;
            k ^= k >> 7;
            k ^= k << 17;
            // Random metres, and random multiples of half a quantum (the ties).
            xs.push((k >> 11) as f64 / (1u64 << 53) as f64 * 400.0 - 200.0);
            xs.push(((k >> 40) as f64 - 8_388_608.0) * 0.5e-5);
        }
        for x in xs {
            assert_eq!(quantum([x, -x]), [(x * 1e5).round() as i64, (-x * 1e5).round() as i64], "{x}");
        }
    }

    #[test]
    fn distances_from_outside_are_those_to_every_edge() {
        // The tiled top, a wall crossing it and sticking out, and a triangle overlapping the
        // top's corner from the same side as the top (its shared edge stays).
        let mut tris = tiled(4);
        tris.push([[2.0, -1.0, 0.0], [2.0, 6.0, 0.0], [2.0, 6.0, 1.0]]);
        tris.push([[4.0, 4.0, 0.5], [3.0, 4.0, 0.5], [4.0, 3.0, 0.5]]);
        let (segs, sides) = edges(&tris);
        let kept = boundary_edges(&segs, &sides);
        assert!(kept.len() < segs.len() / 2, "{} of {}", kept.len(), segs.len());
        let dist = |p: [f64; 2], set: &[Seg]| set.iter().map(|s| {
            let c = closest_on_segment(p, s);
            (c[0] - p[0]).hypot(c[1] - p[1])
        }).fold(f64::INFINITY, f64::min);
        let inside = |p: [f64; 2]| (0.0..=4.0).contains(&p[0]) && (0.0..=4.0).contains(&p[1]);
        let mut checked = 0;
        for i in 0..=80 {
            for j in 0..=80 {
                let p = [-2.0 + 0.1 * i as f64 + 0.013, -2.0 + 0.1 * j as f64 + 0.007];
                if inside(p) {
                    continue;
                }
                assert_eq!(dist(p, &kept), dist(p, &segs), "at {p:?}");
                checked += 1;
            }
        }
        assert!(checked > 4000, "{checked}");
        // The wall's edges (an upright piece covers no side) stay where they leave the top.
        assert!(kept.iter().any(|s| s[0][0] == 2.0 && s[1][0] == 2.0 && s[0][1].max(s[1][1]) > 5.0));
    }

    #[test]
    fn slivers_and_upright_pieces_cover_no_side() {
        let (_, sides) = edges(&[[[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 0.0, 1.0]]]);
        assert!(sides.iter().all(|&s| s == 0), "{sides:?}");
        // Twenty micrometres wide: its long edges share a key at the quantum, run both ways.
        let sliver = [[0.0, 0.0, 0.5], [3.0, 0.0, 0.5], [3.0, 2e-5, 0.5]];
        let (segs, sides) = edges(&[sliver]);
        assert!(sides.iter().all(|&s| s == 0), "{sides:?}");
        assert!(!boundary_edges(&segs, &sides).is_empty());
        // A thick piece does.
        let (_, sides) = edges(&[[[0.0, 0.0, 0.5], [3.0, 0.0, 0.5], [3.0, 1e-3, 0.5]]]);
        assert!(sides.iter().all(|&s| s == 1), "{sides:?}");
    }

    #[test]
    fn quantum_never_decreases_so_the_packing_reads_the_extreme_coordinates() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
        // Around half quanta (where rounding steps), across zero and far out.
        let mut xs: Vec<f64> = (0..20_000).map(|_| (rng.gen_range(-2000..2000) as f64 + 0.5) * 1e-5 + rng.gen_range(-3..=3) as f64 * 1e-20).collect();
        xs.extend((0..20_000).map(|_| rng.gen_range(-1e3..1e3)));
        xs.extend([0.0, -0.0, 5e-6, -5e-6, 4e10, -4e10, 1e300]);
        xs.sort_by(f64::total_cmp);
        for w in xs.windows(2) {
            assert!(quantum([w[0], 0.0])[0] <= quantum([w[1], 0.0])[0], "{} {}", w[0], w[1]);
        }
        // The packing's smallest key is the smallest point's, coordinate by coordinate.
        // (Within a kilometre, so that the keys fit.)
        xs.retain(|x| x.abs() <= 1e3);
        let segs: Vec<Seg> = xs.chunks(4).filter(|c| c.len() == 4).map(|c| [[c[0], c[3]], [c[2], c[1]]]).collect();
        let pack = packing(&segs).expect("fits");
        let all = segs.iter().flatten().map(|&p| quantum(p));
        assert_eq!(pack.min, all.fold([i64::MAX; 2], |m, q| [m[0].min(q[0]), m[1].min(q[1])]));
    }
}
