//! The colour of a surface point, one rule for every renderer (the wgpu shader mirrors it).
//!
//! A material is glTF's base colour: a linear RGB factor times, when the mesh has a texture,
//! the texture sampled at the point's texture coordinates. Sampling reads the one or two
//! levels of the texture's mip pyramid around the level of detail that the pixel's footprint
//! on the surface gives ([`super::mipmap`], so far textures neither alias nor read scattered
//! texels); within a level,
//! bilinear between the four nearest texels (centres at half-integer texel positions), each
//! wrapped by the texture's wrap modes, after decoding the texels from sRGB to linear (a
//! 256-entry table, shared with the GPU). Up close (a footprint under one texel) that is
//! glTF's default bilinear sampler on the image itself. The product is encoded back to
//! sRGB bytes by where it falls among the 255 linear values half way between consecutive
//! bytes (also shared with the GPU, so no `pow` differs between them; the shader searches
//! them in binary, the CPU starts from a table of bins 1/128 of an octave wide, with the
//! same answer). A pixel is that colour shaded by `0.35 + 0.65 |cos|` of the angle between the camera ray and the
//! surface normal, rounded to bytes. Alpha is ignored (opaque materials).
//! The arithmetic is `f32` in the order the shader uses, so the renderers agree to within a
//! byte wherever they see the same triangle.

use super::mipmap::{level_of_detail, level_weight, texel_scale, MipChain};
use crate::rounding::floor_i32;
use crate::scene::{Scene, Texture, Wrap};
use std::sync::OnceLock;

/// Per-triangle surface data: texture coordinates of the corners and the material (its mesh).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SurfaceTri {
    /// Texture coordinates of the three corners (zero when untextured).
    pub uv: [[f32; 2]; 3],
    /// Index of the material (the mesh) in [`Surfaces`].
    pub material: u32,
    /// Level-0 texels per metre on the triangle ([`texel_scale`]; 0 when untextured).
    pub texel_scale: f32,
}

/// One mesh's material.
#[derive(Clone, Debug)]
pub(crate) struct Material {
    /// Base colour factor, linear RGB in [0, 1].
    pub factor: [f32; 3],
    /// The factor alone as sRGB bytes (the colour when untextured).
    pub flat: [u8; 3],
    /// Index of the texture in [`Surfaces::textures`], when textured.
    pub texture: Option<u32>,
}

/// The materials and textures of a scene, for the CPU renderers.
#[derive(Clone, Debug, Default)]
pub(crate) struct Surfaces {
    /// One per mesh of the scene, in order.
    pub materials: Vec<Material>,
    /// The scene's textures, each with its mip pyramid.
    pub textures: Vec<MipChain>,
}

impl Surfaces {
    /// The materials of `scene`'s meshes (a texture only where [`Scene::texture_of`] gives one).
    pub fn new(scene: &Scene) -> Surfaces {
        let materials = scene
            .meshes
            .iter()
            .map(|m| {
                let factor = [0, 1, 2].map(|i| m.base_color[i].clamp(0.0, 1.0));
                let texture = scene.texture_of(m).and(m.texture);
                Material { factor, flat: factor.map(linear_to_srgb_byte), texture }
            })
            .collect();
        Surfaces { materials, textures: scene.textures.iter().map(MipChain::new).collect() }
    }

    /// Every triangle of `scene`, in the order of [`Scene::triangles`], with its surface data.
    pub fn triangles(scene: &Scene) -> Vec<SurfaceTri> {
        let mut out = Vec::with_capacity(scene.triangle_count());
        for (k, m) in scene.meshes.iter().enumerate() {
            let size = scene.texture_of(m).map(|t| t.width.max(t.height));
            out.extend(m.indices.iter().map(|t| {
                let uv = if size.is_some() { t.map(|i| m.uvs.get(i as usize).copied().unwrap_or_default()) } else { [[0.0; 2]; 3] };
                let scale = match size {
                    Some(n) => texel_scale(&t.map(|i| m.positions.get(i as usize).copied().unwrap_or_default()), &uv, n),
                    None => 0.0,
                };
                SurfaceTri { uv, material: k as u32, texel_scale: scale }
            }));
        }
        out
    }

    /// The base colour (sRGB bytes) of triangle `t` at the barycentric weights of its corners
    /// that `bary` gives (called only for textured triangles), for a pixel whose footprint on
    /// the surface is `footprint` metres ([`super::mipmap::footprint`]).
    #[inline]
    pub fn color(&self, t: &SurfaceTri, bary: impl FnOnce() -> [f64; 3], footprint: f32) -> [u8; 3] {
        match self.paint(t) {
            Paint::Flat(c) => c,
            paint @ Paint::Texture { chain, .. } => paint.textured(Srgb::get(), texture_uv(t, bary()), level_of_detail(footprint, t.texel_scale, chain.levels.len())),
        }
    }

    /// How triangle `t`'s pixels are coloured: a flat colour, or a texture times a factor.
    /// A renderer asks once per run of pixels on one triangle.
    #[inline]
    pub fn paint(&self, t: &SurfaceTri) -> Paint<'_> {
        let Some(m) = self.materials.get(t.material as usize) else { return Paint::Flat([160; 3]) };
        match m.texture.and_then(|i| self.textures.get(i as usize)) {
            Some(chain) => Paint::Texture { chain, factor: m.factor },
            None => Paint::Flat(m.flat),
        }
    }
}

/// How a triangle is coloured ([`Surfaces::paint`]).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Paint<'a> {
    /// An untextured material's colour (sRGB bytes).
    Flat([u8; 3]),
    /// A texture's pyramid times a linear RGB factor.
    Texture { chain: &'a MipChain, factor: [f32; 3] },
}

impl Paint<'_> {
    /// The colour (sRGB bytes) at texture coordinates `uv` and level of detail `lod` (the
    /// flat colour when untextured).
    #[inline(always)]
    pub fn textured(&self, srgb: Srgb, uv: [f32; 2], lod: f32) -> [u8; 3] {
        match *self {
            Paint::Flat(c) => c,
            Paint::Texture { chain, .. } => {
                let (l, w) = level_weight(lod, chain.levels.len());
                self.at_level(srgb, uv, l, w)
            }
        }
    }

    /// [`Paint::textured`] given the level and weight
    /// ([`level_and_weight`](super::mipmap::level_and_weight)) instead of the level of detail.
    #[inline(always)]
    pub fn at_level(&self, srgb: Srgb, uv: [f32; 2], l: usize, w: f32) -> [u8; 3] {
        match *self {
            Paint::Flat(c) => c,
            Paint::Texture { chain, factor } => {
                let s = chain.sample_level(srgb.table, uv, l, w);
                [srgb.encode(s[0] * factor[0]), srgb.encode(s[1] * factor[1]), srgb.encode(s[2] * factor[2])]
            }
        }
    }
}

/// Texture coordinates of triangle `t` at barycentric weights `bary` of its corners.
#[inline(always)]
pub(crate) fn texture_uv(t: &SurfaceTri, bary: [f64; 3]) -> [f32; 2] {
    std::array::from_fn(|k| (bary[0] * t.uv[0][k] as f64 + bary[1] * t.uv[1][k] as f64 + bary[2] * t.uv[2][k] as f64) as f32)
}

/// The sRGB tables the renderers share (the GPU reads the same 512 numbers): entries
/// `0..256` are byte `b` decoded to linear [0, 1]; entries `256 + k`, `k < 255`, the linear
/// value whose sRGB encoding is `(k + 0.5) / 255`, where rounding to bytes steps from `k` to
/// `k + 1`; the last entry is unused (2).
pub(crate) fn srgb_table() -> &'static [f32; 512] {
    static TABLE: OnceLock<[f32; 512]> = OnceLock::new();
    let decode = |c: f64| if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
    TABLE.get_or_init(|| {
        std::array::from_fn(|i| match i {
            0..256 => decode(i as f64 / 255.0) as f32,
            256..511 => decode((i - 256) as f64 / 255.0 + 0.5 / 255.0) as f32,
            _ => 2.0,
        })
    })
}

/// Bins of [`linear_to_srgb_byte`]'s start table over linear [0, 1) (a power of two; 1,792
/// are used, see [`encode_bin`]).
const ENCODE_BINS: usize = 2048;

/// 2^-14's bits shifted right by [`ENCODE_SHIFT`]: the values below the second bin's edge
/// (2^-14 times 129/128), all under the first step (1.5e-4), share the first bin.
const ENCODE_BASE: usize = (127 - 14) << 7;

/// The bits of a linear value dropped to find its bin: all but the exponent and the top seven
/// bits of the mantissa, so that bins are 1/128 of an octave wide (the steps are never closer
/// than 0.8% apart).
const ENCODE_SHIFT: u32 = 16;

/// The bin of [`linear_to_srgb_byte`]'s start table that a linear value in (0, 1) falls in:
/// its exponent and top mantissa bits, counted from [`ENCODE_BASE`] (0 below that). Bins
/// grow with the value, so a bin's lower edge is at most any value in it.
#[inline(always)]
fn encode_bin(x: f32) -> usize {
    ((x.to_bits() >> ENCODE_SHIFT) as usize).saturating_sub(ENCODE_BASE) & (ENCODE_BINS - 1)
}

/// The lower edge of bin `b` ([`encode_bin`]): 0 for the first.
fn encode_bin_edge(b: usize) -> f32 {
    if b == 0 {
        0.0
    } else {
        f32::from_bits(((ENCODE_BASE + b) as u32) << ENCODE_SHIFT)
    }
}

/// For each bin `b` of linear [0, 1) ([`encode_bin`]), the sRGB byte of its lower edge: where
/// the search for any value in the bin starts (255 for bins past 1, which no value reads).
fn encode_start() -> &'static [u8; ENCODE_BINS] {
    static START: OnceLock<[u8; ENCODE_BINS]> = OnceLock::new();
    START.get_or_init(|| std::array::from_fn(|b| encode_by_search(encode_bin_edge(b).min(1.0))))
}

/// A linear value as an sRGB byte (the encoding rounded to the nearest byte; below 0 or NaN
/// reads 0, above 1 reads 255): the byte where the 255 linear values at which rounding steps
/// (the table shared with the GPU) put it, found from a table of starting bytes (at most one
/// step from there, without a branch; the same answer as a binary search of the steps).
#[inline]
pub fn linear_to_srgb_byte(x: f32) -> u8 {
    Srgb::get().encode(x)
}

/// The shared sRGB tables ([`srgb_table`] and the start table of [`linear_to_srgb_byte`]),
/// fetched once for a renderer's loop instead of at every texel and channel.
#[derive(Clone, Copy)]
pub(crate) struct Srgb {
    /// [`srgb_table`].
    pub table: &'static [f32; 512],
    start: &'static [u8; ENCODE_BINS],
}

impl Srgb {
    /// The tables (built on first use).
    #[inline]
    pub fn get() -> Srgb {
        Srgb { table: srgb_table(), start: encode_start() }
    }

    /// [`linear_to_srgb_byte`].
    #[inline(always)]
    pub fn encode(&self, x: f32) -> u8 {
        // Outside (0, 1) (0 and below, NaN, 1 and above) in one unsigned comparison of the bits.
        if x.to_bits().wrapping_sub(1) >= 0x3f7f_ffff {
            return if x >= 1.0 { 255 } else { 0 };
        }
        // The bin's lower edge is <= x and its byte a lower bound. No bin holds two steps (a
        // test checks), so one comparison finishes; entry 511 (2) stands after the last step.
        let c = self.start[encode_bin(x)] as usize;
        (c + (self.table[256 + c] <= x) as usize) as u8
    }
}

/// [`linear_to_srgb_byte`] by a binary search of the 255 linear values where rounding steps.
fn encode_by_search(x: f32) -> u8 {
    let steps = &srgb_table()[256..511];
    let mut c = 0usize;
    for s in [128, 64, 32, 16, 8, 4, 2, 1] {
        if c + s <= 255 && steps[c + s - 1] <= x {
            c += s;
        }
    }
    c as u8
}

/// The texture's (or a mip level's) linear RGB at texture coordinates `uv` (bilinear,
/// wrapped; see the module).
pub fn sample_bilinear(t: &Texture, uv: [f32; 2]) -> [f32; 3] {
    sample_bilinear_with(srgb_table(), t, uv)
}

/// [`sample_bilinear`] with the decoding table `lut` ([`srgb_table`]) at hand.
#[inline(always)]
pub(crate) fn sample_bilinear_with(lut: &[f32; 512], t: &Texture, uv: [f32; 2]) -> [f32; 3] {
    let (w, h) = (t.width as i32, t.height as i32);
    let x = uv[0] * t.width as f32 - 0.5;
    let y = uv[1] * t.height as f32 - 0.5;
    let (i, j) = (floor_i32(x), floor_i32(y));
    let (fx, fy) = (x - i as f32, y - j as f32);
    // Inside the image (the common case) no wrapping is needed.
    let wrap = |m: Wrap, i: i32, n: i32| if i >= 0 && i < n - 1 { [i as u32, i as u32 + 1] } else { [m.apply(i, n) as u32, m.apply(i.saturating_add(1), n) as u32] };
    let (xs, ys) = (wrap(t.wrap_s, i, w), wrap(t.wrap_t, j, h));
    // Four lanes (the fourth unused) so that the blends are one vector operation each.
    let c = |x: u32, y: u32| {
        let i = (y as usize * t.width as usize + x as usize) * 4;
        let p: [u8; 4] = t.rgba[i..i + 4].try_into().unwrap_or_default();
        [lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize], 0.0]
    };
    let (c00, c10, c01, c11) = (c(xs[0], ys[0]), c(xs[1], ys[0]), c(xs[0], ys[1]), c(xs[1], ys[1]));
    let lerp = |a: [f32; 4], b: [f32; 4], f: f32| [a[0] * (1.0 - f) + b[0] * f, a[1] * (1.0 - f) + b[1] * f, a[2] * (1.0 - f) + b[2] * f, a[3] * (1.0 - f) + b[3] * f];
    let v = lerp(lerp(c00, c10, fx), lerp(c01, c11, fx), fy);
    [v[0], v[1], v[2]]
}

/// A triangle's plane seen from a camera origin (world frame, f64), worked out once for the
/// rays from that origin: a ray `origin + t dir` meets it at `t = -n_oa / (n . dir)`, at the
/// point `oa + t dir` relative to corner 0, whose weights of corners 1 and 2 are its dot
/// products with `m1` and `m2`.
pub(crate) struct TrianglePlane {
    /// Normal (not unit, m^2) and its length.
    pub n: [f64; 3],
    pub ln: f64,
    /// The origin relative to corner 0 (m), and `n . oa`.
    oa: [f64; 3],
    n_oa: f64,
    /// `(e2 x n) / |n|^2` and `(n x e1) / |n|^2`, with `e1`, `e2` the edges from corner 0.
    m1: [f64; 3],
    m2: [f64; 3],
}

impl TrianglePlane {
    /// The plane of triangle `v` (world, m) seen from `origin`.
    pub fn new(v: &[[f32; 3]; 3], origin: [f64; 3]) -> TrianglePlane {
        let a = v[0].map(|x| x as f64);
        let sub = |p: [f32; 3]| [p[0] as f64 - a[0], p[1] as f64 - a[1], p[2] as f64 - a[2]];
        let (e1, e2) = (sub(v[1]), sub(v[2]));
        let n = cross(e1, e2);
        let nn = dot(n, n);
        let oa = [origin[0] - a[0], origin[1] - a[1], origin[2] - a[2]];
        TrianglePlane { n, ln: nn.sqrt().max(1e-300), oa, n_oa: dot(n, oa), m1: cross(e2, n).map(|x| x / nn), m2: cross(n, e1).map(|x| x / nn) }
    }

    /// Barycentric weights (of corners 0, 1, 2) where the ray along `dir` meets the plane,
    /// given `denom = n . dir`; the centroid for a ray parallel to the plane or a degenerate
    /// triangle. Perspective-correct by construction.
    #[inline]
    pub fn barycentric(&self, dir: [f64; 3], denom: f64) -> [f64; 3] {
        let t = -self.n_oa / denom;
        let ap = [self.oa[0] + t * dir[0], self.oa[1] + t * dir[1], self.oa[2] + t * dir[2]];
        let (b1, b2) = (dot(ap, self.m1), dot(ap, self.m2));
        if !(b1.is_finite() && b2.is_finite()) {
            return [1.0 / 3.0; 3];
        }
        [1.0 - b1 - b2, b1, b2]
    }

    /// The plane along the rays `d0 + x d1` of one image row (`x` the column's offset from the
    /// principal point over the focal length), for a triangle with texture coordinates `uv`:
    /// where each ray meets the plane and the texture coordinates there, as affine forms in
    /// `x` and one division per pixel ([`RowPlane`]).
    pub fn along(&self, d0: [f64; 3], d1: [f64; 3], uv: &[[f32; 2]; 3]) -> RowPlane {
        let (p1, p2) = (dot(self.oa, self.m1), dot(self.oa, self.m2));
        let (q1, q2) = (dot(d0, self.m1), dot(d0, self.m2));
        let (r1, r2) = (dot(d1, self.m1), dot(d1, self.m2));
        let uv = uv.map(|c| c.map(|x| x as f64));
        let tex = std::array::from_fn(|k| {
            let (d1, d2) = (uv[1][k] - uv[0][k], uv[2][k] - uv[0][k]);
            [uv[0][k] + p1 * d1 + p2 * d2, q1 * d1 + q2 * d2, r1 * d1 + r2 * d2]
        });
        // As the barycentric weights give it: a third of each corner's.
        let centroid = std::array::from_fn(|k| (uv[0][k] * (1.0 / 3.0) + uv[1][k] * (1.0 / 3.0) + uv[2][k] * (1.0 / 3.0)) as f32);
        RowPlane { a: dot(self.n, d0), b: dot(self.n, d1), t_num: -self.n_oa, ln: self.ln, tex, centroid }
    }
}

/// A triangle's plane along one image row ([`TrianglePlane::along`]): for the ray at column
/// offset `x`, `n . dir = a + b x`, the ray meets the plane at `t = t_num / (a + b x)` (in
/// units of the ray direction's length), and the texture coordinates there are
/// `tex[k][0] + t (tex[k][1] + x tex[k][2])`, the same as the barycentric weights give.
pub(crate) struct RowPlane {
    a: f64,
    b: f64,
    t_num: f64,
    /// Length of the plane's (non-unit) normal.
    pub ln: f64,
    tex: [[f64; 3]; 2],
    /// The texture coordinates of the centroid, for a ray parallel to the plane or a
    /// degenerate triangle.
    centroid: [f32; 2],
}

impl RowPlane {
    /// `n . dir` for the ray at column offset `x`.
    #[inline(always)]
    pub fn denom(&self, x: f64) -> f64 {
        self.a + self.b * x
    }

    /// How far along the ray at `x` the plane is, in units of the ray direction's length,
    /// given `denom` ([`RowPlane::denom`]), and the texture coordinates there.
    #[inline(always)]
    pub fn hit(&self, x: f64, denom: f64) -> (f64, [f32; 2]) {
        let t = self.t_num / denom;
        let uv = [self.tex[0][0] + t * (self.tex[0][1] + x * self.tex[0][2]), self.tex[1][0] + t * (self.tex[1][1] + x * self.tex[1][2])];
        let uv = if uv[0].is_finite() && uv[1].is_finite() { uv.map(|c| c as f32) } else { self.centroid };
        (t.abs(), uv)
    }
}

/// Barycentric weights (of corners 0, 1, 2) of the point where the line `origin + t dir` meets
/// the plane of triangle `v` (world, m), as [`TrianglePlane::barycentric`] gives them.
pub(crate) fn barycentric(v: &[[f32; 3]; 3], origin: [f64; 3], dir: [f64; 3]) -> [f64; 3] {
    let p = TrianglePlane::new(v, origin);
    p.barycentric(dir, dot(p.n, dir))
}

/// A base colour (sRGB bytes) shaded by `0.35 + 0.65 cos`, `cos` in [0, 1] the absolute cosine
/// between the camera ray and the surface normal.
#[inline]
pub(crate) fn shade(c: [u8; 3], cos: f64) -> [u8; 3] {
    let s = 0.35 + 0.65 * cos;
    // Rounded half up (the product is in [0, 255]), without a libm call.
    c.map(|v| (v as f64 * s + 0.5) as u8)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// Dot product.
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn checker() -> Texture {
        // 2 x 2: white, black / black, white (sRGB bytes).
        let w = [255, 255, 255, 255];
        let b = [0, 0, 0, 255];
        Texture { name: "c".into(), width: 2, height: 2, rgba: Arc::new([w, b, b, w].concat()), wrap_s: Wrap::Repeat, wrap_t: Wrap::ClampToEdge }
    }

    #[test]
    fn texel_centres_sample_exactly_and_midpoints_average_in_linear() {
        let t = checker();
        assert_eq!(sample_bilinear(&t, [0.25, 0.25]), [1.0; 3]);
        assert_eq!(sample_bilinear(&t, [0.75, 0.25]), [0.0; 3]);
        // Half way between a white and a black texel: linear 0.5, sRGB 188.
        let mid = sample_bilinear(&t, [0.5, 0.25]);
        assert!((mid[0] - 0.5).abs() < 1e-6, "{mid:?}");
        assert_eq!(linear_to_srgb_byte(mid[0]), 188);
        // Repeat along u: u = 1.25 is u = 0.25; clamp along v: v = -3 is the top row.
        assert_eq!(sample_bilinear(&t, [1.25, 0.25]), [1.0; 3]);
        assert_eq!(sample_bilinear(&t, [0.75, -3.0]), [0.0; 3]);
        // Across the repeat seam, u = 0 mixes texels 1 and 0.
        assert!((sample_bilinear(&t, [0.0, 0.25])[0] - 0.5).abs() < 1e-6);
    }

    #[test]
    fn srgb_round_trips_every_byte() {
        for b in 0..=255u8 {
            assert_eq!(linear_to_srgb_byte(srgb_table()[b as usize]), b);
        }
        assert_eq!(linear_to_srgb_byte(f32::NAN), 0);
        assert_eq!(linear_to_srgb_byte(-1.0), 0);
        assert_eq!(linear_to_srgb_byte(2.0), 255);
        // The start table gives the binary search's answer everywhere, steps and bin edges
        // included.
        let mut xs: Vec<f32> = srgb_table()[256..511].iter().flat_map(|&s| [s, f32::from_bits(s.to_bits() - 1), f32::from_bits(s.to_bits() + 1)]).collect();
        xs.extend((0..ENCODE_BINS).flat_map(|b| {
            let e = encode_bin_edge(b);
            [e, f32::from_bits(e.to_bits().saturating_sub(1)), f32::from_bits(e.to_bits() + 1)]
        }));
        xs.extend([f32::MIN_POSITIVE, 1e-45, 1e-30, 1e-5, 0.99999994, 1.0, f32::INFINITY, -0.0, f32::NEG_INFINITY]);
        xs.extend((0..100_000).map(|i| i as f32 / 100_000.0));
        for x in xs {
            assert_eq!(linear_to_srgb_byte(x), encode_by_search(x), "{x}");
        }
        // One comparison after the start table's byte is enough: no bin holds two steps.
        let steps = &srgb_table()[256..511];
        for b in 0..ENCODE_BINS - 1 {
            let (lo, hi) = (encode_bin_edge(b), encode_bin_edge(b + 1));
            assert!(steps.iter().filter(|&&s| s > lo && s < hi).count() <= 1, "bin {b}");
        }
        // Every value in (0, 1) has a bin whose lower edge is at most it, and the bins reach 1.
        assert_eq!(encode_bin(0.99999994), (0x3f7f - ENCODE_BASE));
        assert!(encode_bin_edge(encode_bin(0.99999994) + 1) == 1.0);
        assert_eq!(encode_bin(1e-30), 0);
        // The search agrees with the formula away from the rounding steps.
        for i in 0..=1000 {
            let x = i as f64 / 1000.0;
            let s = if x <= 0.0031308 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 } * 255.0;
            if (s - s.floor() - 0.5).abs() > 1e-3 {
                assert_eq!(linear_to_srgb_byte(x as f32), s.round() as u8, "{x}");
            }
        }
    }

    #[test]
    fn a_row_plane_gives_the_barycentric_texture_coordinates() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let tri = SurfaceTri { uv: [[0.1, 0.2], [3.5, -0.4], [0.7, 2.9]], material: 0, texel_scale: 1.0 };
        for _ in 0..2000 {
            let mut p = || [rng.gen_range(-3.0..3.0f32), rng.gen_range(-3.0..3.0f32), rng.gen_range(-0.5..2.5f32)];
            let v = [p(), p(), p()];
            let origin = [0.3, -0.2, 0.9];
            let (yaw, y): (f64, f64) = (rng.gen_range(-3.2..3.2), rng.gen_range(-1.0..1.0));
            let (s, c) = yaw.sin_cos();
            let (d0, d1) = ([c, s, -y], [s, -c, 0.0]);
            let plane = TrianglePlane::new(&v, origin);
            let row = plane.along(d0, d1, &tri.uv);
            for x in [-1.0, -0.37, 0.0, 0.21, 1.0] {
                let dir = [c + x * s, s - x * c, -y];
                let denom = dot(plane.n, dir);
                if denom.abs() < 1e-6 {
                    continue;
                }
                assert!((row.denom(x) - denom).abs() <= 1e-9 * denom.abs().max(plane.ln), "{} {denom}", row.denom(x));
                let want = texture_uv(&tri, plane.barycentric(dir, denom));
                let (t, got) = row.hit(x, denom);
                assert!((t - (-plane.n_oa / denom).abs()).abs() <= 1e-12 * t.max(1.0), "{t}");
                // Far-off planes magnify rounding in both; compare relative to the hit's reach.
                let tol = 1e-5 * (1.0 + t as f32) * (1.0 + want[0].abs().max(want[1].abs()));
                assert!((got[0] - want[0]).abs() <= tol && (got[1] - want[1]).abs() <= tol, "{got:?} {want:?}");
            }
        }
    }

    #[test]
    fn barycentrics_of_corners_and_centroid() {
        let v = [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]];
        let o = [0.0, 0.0, 0.0];
        let b = barycentric(&v, o, [1.0, 0.0, 1.0]);
        assert!((b[1] - 1.0).abs() < 1e-12 && b[0].abs() < 1e-12, "{b:?}");
        let b = barycentric(&v, o, [1.0 / 3.0, 1.0 / 3.0, 1.0]);
        assert!(b.iter().all(|x| (x - 1.0 / 3.0).abs() < 1e-12), "{b:?}");
        // Parallel to the plane: the centroid, not NaN.
        assert_eq!(barycentric(&v, o, [1.0, 0.0, 0.0]), [1.0 / 3.0; 3]);
    }
}
