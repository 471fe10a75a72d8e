//! Mip pyramids of base-colour textures and the level of detail a pixel's footprint picks, so
//! that distant textured surfaces neither alias nor read scattered texels: part of the one
//! colour rule of [`super::surface`], mirrored by the wgpu shader ([`super::gpu`]).
//!
//! A pyramid is built once per texture when a renderer is built: level 0 is the image; level
//! `k + 1` halves each side of level `k` (rounding down, at least 1 texel) and each of its
//! texels is the box average, in linear space (texels decoded from sRGB by the shared table),
//! of the 2 x 2 texels of level `k` it covers (3 along an odd side's last texel), encoded back
//! to sRGB bytes; alpha is averaged as stored. Deterministic (fixed summation order).
//!
//! The level of detail of a pixel is `log2` of its footprint in level-0 texels: the pixel's
//! angular size (`1 / fx`, rad) times the ray's length to the hit (m), divided by the cosine
//! of incidence (at least [`MIN_COS`]), times the triangle's texels per metre
//! ([`texel_scale`]: `sqrt(uv area / world area)` times the texture's larger side). Below one
//! texel it is 0 (the image itself, bilinear as before); otherwise it is clamped to the
//! coarsest level. A level of detail `l + f` (`f` its fraction) reads levels `l` and `l + 1`
//! bilinearly and blends them, the weight of level `l + 1` being
//! `clamp((f - (1 - BLEND) / 2) / BLEND, 0, 1)`: only in a band of width [`BLEND`] around each
//! half level are two levels read, elsewhere one (trilinear filtering narrowed to the level
//! changes, as GPUs' "brilinear" filtering: 1.25 bilinear samples per pixel on average instead
//! of 2, with no visible seam where the level changes). Everything is `f32` in the shader's order, and the colour is continuous in the level
//! of detail, so renderers that compute it a few ulps apart still agree to within rounding.

use super::surface::{linear_to_srgb_byte, sample_bilinear_with, srgb_table};
use crate::scene::Texture;
use rayon::prelude::*;
use std::sync::Arc;

/// Width of the band of level-of-detail fractions, centred on one half, where two levels are
/// blended; outside it a pixel reads one level.
pub const BLEND: f32 = 0.25;

/// Smallest cosine of incidence the footprint divides by: grazing surfaces read the level a
/// cosine of 1/1000 gives (in practice the coarsest).
pub const MIN_COS: f32 = 1e-3;

/// A texture with its prefiltered levels, finest first.
#[derive(Clone, Debug)]
pub struct MipChain {
    /// Level 0 is the texture itself; each further level halves both sides (at least 1 texel).
    pub levels: Vec<Texture>,
}

impl MipChain {
    /// The pyramid of `t` down to 1 x 1 (an inconsistent texture keeps its level 0 only).
    pub fn new(t: &Texture) -> MipChain {
        // Level 0 shares the image's texels (no copy).
        let mut levels = vec![t.clone()];
        if !t.is_consistent() {
            return MipChain { levels };
        }
        while let Some(last) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
            let next = downsample(last);
            levels.push(next);
        }
        MipChain { levels }
    }

    /// Linear RGB of the texture at `uv` for level of detail `lod` (in `[0, levels - 1]`, as
    /// [`level_of_detail`] gives it): bilinear in level `floor(lod)`, in the next, or both
    /// blended when the fraction is within [`BLEND`] of one half (see the module).
    #[inline]
    pub fn sample(&self, uv: [f32; 2], lod: f32) -> [f32; 3] {
        let (l, w) = level_weight(lod, self.levels.len());
        self.sample_level(srgb_table(), uv, l, w)
    }

    /// [`MipChain::sample`] given the level `l` and the weight `w` of level `l + 1` that a
    /// level of detail gives ([`level_and_weight`]).
    #[inline(always)]
    pub(crate) fn sample_level(&self, lut: &[f32; 512], uv: [f32; 2], l: usize, w: f32) -> [f32; 3] {
        match self.levels.get(l + 1) {
            Some(next) if w >= 1.0 => sample_bilinear_with(lut, next, uv),
            Some(next) if w > 0.0 => {
                let (a, b) = (sample_bilinear_with(lut, &self.levels[l], uv), sample_bilinear_with(lut, next, uv));
                std::array::from_fn(|k| a[k] * (1.0 - w) + b[k] * w)
            }
            _ => sample_bilinear_with(lut, &self.levels[l], uv),
        }
    }
}

/// The level `l` a level of detail `lod` (in `[0, levels - 1]`) reads and the weight of
/// level `l + 1` ([`next_level_weight`]), for a pyramid of `levels` levels.
#[inline]
pub fn level_weight(lod: f32, levels: usize) -> (usize, f32) {
    let l = (lod as usize).min(levels.saturating_sub(1));
    (l, next_level_weight(lod - l as f32))
}

/// The weight of level `l + 1` for a level of detail `l + f`: 0 up to `(1 - BLEND) / 2`, 1
/// from `(1 + BLEND) / 2`, linear between.
#[inline]
pub fn next_level_weight(f: f32) -> f32 {
    ((f - (1.0 - BLEND) * 0.5) / BLEND).clamp(0.0, 1.0)
}

/// The next level of `t` (both sides halved, rounding down, at least 1): box averages in
/// linear space, see the module.
fn downsample(t: &Texture) -> Texture {
    let lut = srgb_table();
    let (w, h) = (t.width as usize, t.height as usize);
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    // Source texels [lo, hi) covering destination texel i of n along a side of m texels.
    let span = |i: usize, n: usize, m: usize| (i * m / n, ((i + 1) * m).div_ceil(n));
    let mut rgba = vec![0u8; nw * nh * 4];
    rgba.par_chunks_mut(nw * 4).enumerate().for_each(|(y, row)| {
        let (y0, y1) = span(y, nh, h);
        // A texel's decoded channels (alpha as it is), added to a sum.
        let add = |sum: &mut [f32; 4], p: &[u8]| {
            for k in 0..3 {
                sum[k] += lut[p[k] as usize];
            }
            sum[3] += p[3] as f32;
        };
        // The source rows of a 2 x 2 block (the common case: both sides even), as slices.
        let pair = (y1 - y0 == 2).then(|| (&t.rgba[y0 * w * 4..(y0 + 1) * w * 4], &t.rgba[(y0 + 1) * w * 4..(y0 + 2) * w * 4]));
        for x in 0..nw {
            let (x0, x1) = span(x, nw, w);
            let mut sum = [0f32; 4];
            match pair {
                // The same four texels in the same order as the loops below, unrolled.
                Some((r0, r1)) if x1 - x0 == 2 => {
                    let (a, b) = (&r0[x0 * 4..x0 * 4 + 8], &r1[x0 * 4..x0 * 4 + 8]);
                    add(&mut sum, &a[..4]);
                    add(&mut sum, &a[4..]);
                    add(&mut sum, &b[..4]);
                    add(&mut sum, &b[4..]);
                }
                _ => {
                    for sy in y0..y1 {
                        for sx in x0..x1 {
                            add(&mut sum, &t.rgba[(sy * w + sx) * 4..(sy * w + sx) * 4 + 4]);
                        }
                    }
                }
            }
            let n = ((y1 - y0) * (x1 - x0)) as f32;
            let out = &mut row[x * 4..x * 4 + 4];
            for k in 0..3 {
                out[k] = linear_to_srgb_byte(sum[k] / n);
            }
            out[3] = (sum[3] / n + 0.5) as u8;
        }
    });
    Texture { name: t.name.clone(), width: nw as u32, height: nh as u32, rgba: Arc::new(rgba), wrap_s: t.wrap_s, wrap_t: t.wrap_t }
}

/// Level-0 texels per metre on triangle `v` (world, m) with texture coordinates `uv`, for a
/// texture whose larger side is `size` texels: `sqrt(uv area / world area) * size`; 0 for a
/// degenerate triangle or non-finite input (the finest level then).
pub fn texel_scale(v: &[[f32; 3]; 3], uv: &[[f32; 2]; 3], size: u32) -> f32 {
    let d = |a: [f32; 3], b: [f32; 3]| [b[0] as f64 - a[0] as f64, b[1] as f64 - a[1] as f64, b[2] as f64 - a[2] as f64];
    let (e1, e2) = (d(v[0], v[1]), d(v[0], v[2]));
    let n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
    let world = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let (u1, u2) = ([uv[1][0] as f64 - uv[0][0] as f64, uv[1][1] as f64 - uv[0][1] as f64], [uv[2][0] as f64 - uv[0][0] as f64, uv[2][1] as f64 - uv[0][1] as f64]);
    let tex = (u1[0] * u2[1] - u1[1] * u2[0]).abs();
    let s = (tex / world).sqrt() * size as f64;
    // Bounded, so that footprint * scale stays finite in f32.
    if s.is_finite() && s > 0.0 {
        s.min(1e12) as f32
    } else {
        0.0
    }
}

/// A pixel's footprint on a surface (m): the ray's length to the hit `dist` (m) times the
/// pixel's angular size `pixel_angle` (rad), over the cosine of incidence (at least
/// [`MIN_COS`]). In `f32`, as the shader computes it.
#[inline]
pub fn footprint(dist: f32, pixel_angle: f32, cos: f32) -> f32 {
    dist * pixel_angle / cos.max(MIN_COS)
}

/// The level of detail of a footprint of `footprint` metres on a triangle of `scale` level-0
/// texels per metre, for a pyramid of `levels` levels: `log2` of the footprint in texels,
/// 0 below one texel (or for NaN), at most `levels - 1`.
#[inline]
pub fn level_of_detail(footprint: f32, scale: f32, levels: usize) -> f32 {
    let texels = footprint * scale;
    if !(texels > 1.0) {
        return 0.0;
    }
    texels.log2().min(levels.saturating_sub(1) as f32)
}

/// The level `l` and the weight `w` of level `l + 1` that [`MipChain::sample`] reads for the
/// level of detail [`level_of_detail`] gives (`levels` at least 1): the same level and weight,
/// without `log2` where the footprint is not within a hair of a blend band (three pixels in
/// four): there the level read follows from the footprint's binary exponent and mantissa.
#[inline]
pub fn level_and_weight(footprint: f32, scale: f32, levels: usize) -> (usize, f32) {
    let texels = footprint * scale;
    let slow = || level_weight(level_of_detail(footprint, scale, levels), levels);
    if !(texels > 1.0 && texels.is_finite()) {
        return slow();
    }
    // `log2` is exact at powers of two and increasing, so a footprint of 2^e texels or more
    // reads at least level e.
    let e = ((texels.to_bits() >> 23) & 0xff) as usize - 127;
    if e >= levels.saturating_sub(1) {
        return slow();
    }
    // The mantissa as 1 + m in [1, 2): below 2^(3/8) (less a margin far wider than log2's
    // rounding) level e alone; above 2^(5/8) (plus the margin) level e + 1 alone, whether
    // log2 rounds up to e + 1 or not.
    let m = f32::from_bits((texels.to_bits() & 0x7f_ffff) | 0x3f80_0000);
    if m < 1.296_749_6 {
        (e, 0.0)
    } else if m > 1.542_317_8 {
        (e, 1.0)
    } else {
        slow()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Wrap;

    #[test]
    fn level_and_weight_reads_what_the_level_of_detail_reads() {
        // The level read: l + 1 when the weight is 1, else l with the weight.
        let read = |(l, w): (usize, f32)| if w >= 1.0 { (l + 1, 0.0) } else { (l, w) };
        let mut x = 0.3f32;
        while x < 1e7 {
            for levels in [1, 2, 5, 12] {
                for scale in [1.0f32, 3.7, 1e-3] {
                    let lod = level_of_detail(x, scale, levels);
                    let l = (lod as usize).min(levels - 1);
                    let w = next_level_weight(lod - l as f32);
                    // A weight of 1 with no next level reads level l.
                    let want = if l + 1 >= levels { (l, if w >= 1.0 { 0.0 } else { w }) } else { read((l, w)) };
                    let (gl, gw) = level_and_weight(x, scale, levels);
                    let got = if gl + 1 >= levels { (gl, if gw >= 1.0 { 0.0 } else { gw }) } else { read((gl, gw)) };
                    assert_eq!(got, want, "footprint {x}, scale {scale}, levels {levels}");
                }
            }
            x = f32::from_bits(x.to_bits() + 997);
        }
    }

    fn tex(w: u32, h: u32, f: impl Fn(u32, u32) -> u8) -> Texture {
        let rgba = (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).flat_map(|(x, y)| {
            let v = f(x, y);
            [v, v, v, 255]
        });
        Texture { name: "t".into(), width: w, height: h, rgba: Arc::new(rgba.collect()), wrap_s: Wrap::Repeat, wrap_t: Wrap::Repeat }
    }

    #[test]
    fn levels_halve_down_to_one_texel() {
        let c = MipChain::new(&tex(8, 3, |_, _| 10));
        let sizes: Vec<_> = c.levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(8, 3), (4, 1), (2, 1), (1, 1)]);
        assert!(c.levels.iter().all(|l| l.is_consistent()));
        // A flat image stays flat at every level.
        assert!(c.levels.iter().all(|l| l.rgba.chunks(4).all(|p| p == [10, 10, 10, 255])));
        assert_eq!(MipChain::new(&tex(1, 1, |_, _| 0)).levels.len(), 1);
    }

    #[test]
    fn a_checkerboard_averages_to_half_linear_grey() {
        // 1-texel squares: every level above 0 is linear 0.5 (sRGB 188), not 127.
        let c = MipChain::new(&tex(16, 16, |x, y| if (x + y) % 2 == 0 { 255 } else { 0 }));
        assert_eq!(c.levels.len(), 5);
        for l in &c.levels[1..] {
            assert!(l.rgba.chunks(4).all(|p| p[..3] == [188, 188, 188]), "{:?}", &l.rgba[..8]);
        }
        // Between level 0 and 1 the colour moves continuously from the texel to the grey:
        // level 0 alone up to 0.375, level 1 alone from 0.625, blended between.
        let at = |lod: f32| c.sample([0.5 / 16.0, 0.5 / 16.0], lod)[0];
        let g = srgb_table()[188];
        assert_eq!((at(0.0), at(0.375)), (1.0, 1.0));
        assert!((at(0.625) - g).abs() < 1e-6 && (at(1.0) - g).abs() < 1e-6, "{} {}", at(0.625), at(1.0));
        assert!((at(0.5) - (1.0 + g) / 2.0).abs() < 1e-6, "{}", at(0.5));
        let mut last = at(0.0);
        for i in 1..=100 {
            let x = at(i as f32 / 100.0);
            assert!(x <= last && last - x < 0.05, "not continuous at lod {}: {last} -> {x}", i as f32 / 100.0);
            last = x;
        }
        assert_eq!(next_level_weight(0.5), 0.5);
        assert_eq!((next_level_weight(0.0), next_level_weight(0.99)), (0.0, 1.0));
        // The same bytes each time it is built.
        assert_eq!(MipChain::new(&c.levels[0]).levels, c.levels);
    }

    #[test]
    fn two_by_two_blocks_average_as_any_box_does() {
        use rand::{Rng, SeedableRng};
        // Every source texel's box average, as the general loop takes it.
        let reference = |t: &Texture| -> Vec<u8> {
            let lut = srgb_table();
            let (w, h) = (t.width as usize, t.height as usize);
            let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
            let span = |i: usize, n: usize, m: usize| (i * m / n, ((i + 1) * m).div_ceil(n));
            let mut out = Vec::new();
            for y in 0..nh {
                let (y0, y1) = span(y, nh, h);
                for x in 0..nw {
                    let (x0, x1) = span(x, nw, w);
                    let mut sum = [0f32; 4];
                    for sy in y0..y1 {
                        for sx in x0..x1 {
                            let p = &t.rgba[(sy * w + sx) * 4..(sy * w + sx) * 4 + 4];
                            for k in 0..3 {
                                sum[k] += lut[p[k] as usize];
                            }
                            sum[3] += p[3] as f32;
                        }
                    }
                    let n = ((y1 - y0) * (x1 - x0)) as f32;
                    out.extend((0..3).map(|k| linear_to_srgb_byte(sum[k] / n)));
                    out.push((sum[3] / n + 0.5) as u8);
                }
            }
            out
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        for (w, h) in [(8, 6), (7, 5), (6, 3), (3, 6), (1, 4), (4, 1), (2, 2), (64, 32)] {
            let rgba: Vec<u8> = (0..w * h * 4).map(|_| rng.gen()).collect();
            let t = Texture { name: "r".into(), width: w, height: h, rgba: Arc::new(rgba), wrap_s: Wrap::Repeat, wrap_t: Wrap::Repeat };
            assert_eq!(*downsample(&t).rgba, reference(&t), "{w} x {h}");
        }
    }

    #[test]
    fn level_of_detail_follows_the_footprint() {
        assert_eq!(level_of_detail(0.001, 100.0, 8), 0.0);
        assert_eq!(level_of_detail(0.04, 100.0, 8), 2.0);
        assert_eq!(level_of_detail(1.0e6, 100.0, 8), 7.0);
        assert_eq!(level_of_detail(f32::NAN, 100.0, 8), 0.0);
        assert_eq!(level_of_detail(1.0, 0.0, 8), 0.0);
        assert_eq!(level_of_detail(1.0, 100.0, 1), 0.0);
        assert_eq!(footprint(2.0, 0.01, 0.5), 0.04);
        assert_eq!(footprint(2.0, 0.01, 0.0), 2.0 * 0.01 / MIN_COS);
        // A 2 m x 2 m square mapped to the whole of a 256-texel texture: 128 texels per metre.
        let v = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert!((texel_scale(&v, &uv, 256) - 128.0).abs() < 1e-3);
        assert_eq!(texel_scale(&[[0.0; 3]; 3], &uv, 256), 0.0);
        assert_eq!(texel_scale(&v, &[[f32::NAN; 2]; 3], 256), 0.0);
    }
}
