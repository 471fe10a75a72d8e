//! Rounding without libm calls (the build targets plain x86-64, where `floor` is a call), for
//! the renderers' inner loops and the map build's raster.

/// Largest whole number <= `x` for `|x| < 2^23`, without a libm call (saturating beyond the
/// `i32` range, 0 for NaN).
#[inline(always)]
pub(crate) fn floor_i32(x: f32) -> i32 {
    let i = x as i32;
    i - ((i as f32) > x) as i32
}

/// 1.5 * 2^23: an `f32` of magnitude under 2^22 plus this is rounded to a whole number (to
/// nearest, ties to even), which the sum's low mantissa bits hold.
const ROUND_MAGIC: f32 = 12_582_912.0;

/// `x` rounded to the nearest whole number, as a float and as an integer, for `|x| <= 2^22`
/// (not NaN): an addition and a subtraction, no conversion instruction, so that loops over
/// many values run as vector operations.
#[inline(always)]
fn round_small(x: f32) -> (f32, i32) {
    let y = x + ROUND_MAGIC;
    (y - ROUND_MAGIC, y.to_bits() as i32 - ROUND_MAGIC.to_bits() as i32)
}

/// [`floor_i32`] for `|x| <= 2^22`, not NaN (a clamped pixel coordinate), without a
/// conversion instruction ([`round_small`]).
#[inline(always)]
pub(crate) fn floor_bounded(x: f32) -> i32 {
    let (r, i) = round_small(x);
    i - (r > x) as i32
}

/// Smallest whole number >= `x`, for `|x| <= 2^22`, not NaN (a clamped pixel coordinate),
/// without a conversion instruction ([`round_small`]).
#[inline(always)]
pub(crate) fn ceil_bounded(x: f32) -> i32 {
    let (r, i) = round_small(x);
    i + (r < x) as i32
}

/// `x.floor()` without a libm call: the same value, signed zero, infinities and NaN included.
#[inline(always)]
pub(crate) fn floor_f64(x: f64) -> f64 {
    if !(x.abs() < 4.5e15) {
        // Whole already (or infinite, or NaN).
        return x;
    }
    let t = x as i64 as f64;
    if t > x {
        t - 1.0
    } else if t == x {
        x
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn bounded_floor_and_ceil_are_the_conversions() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        // Whole numbers, halves (the ties of rounding to nearest) and their neighbours, the
        // range's ends, and random values at every scale.
        let mut xs = vec![0.0f32, -0.0, 4_194_304.0, -4_194_304.0, 4_194_303.5, -4_194_303.5, 1e-40, -1e-40];
        for k in -3000..3000 {
            for x in [k as f32, k as f32 + 0.5, k as f32 * 1397.0, k as f32 * 1397.0 + 0.5] {
                xs.extend([x, f32::from_bits(x.to_bits().wrapping_add(1)), f32::from_bits(x.to_bits().wrapping_sub(1))]);
            }
        }
        xs.extend((0..200_000).map(|_| rng.gen_range(-300.0f32..300.0)));
        xs.extend((0..200_000).map(|_| rng.gen_range(-4_194_304.0f32..4_194_304.0)));
        for x in xs.into_iter().filter(|x| x.abs() <= 4_194_304.0) {
            assert_eq!(super::floor_bounded(x), super::floor_i32(x), "{x}");
            // (The ceiling by conversion, as `floor_i32` takes the floor.)
            let ceil_by_conversion = (x as i32) + (((x as i32) as f32) < x) as i32;
            assert_eq!(super::ceil_bounded(x), ceil_by_conversion, "{x}");
            assert_eq!(super::floor_bounded(x), x.floor() as i32, "{x}");
            assert_eq!(super::ceil_bounded(x), x.ceil() as i32, "{x}");
        }
    }

    #[test]
    fn floor_f64_is_the_library_floor() {
        let mut xs = vec![0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.5e-300, -2.5e-300, 4.4e15 + 0.5, -4.4e15 - 0.5, 4.6e15, -4.6e15, 1e300, f64::INFINITY, f64::NEG_INFINITY, f64::NAN];
        xs.extend((0..10_000).map(|i| (i as f64 - 5000.0) * 0.0137 + 1e-9 * (i % 7) as f64));
        xs.extend((0..2000).map(|i| (i as f64 - 1000.0) * 0.25));
        for x in xs {
            let (want, got) = (x.floor(), super::floor_f64(x));
            assert!(got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()), "{x}: {got} vs {want}");
        }
    }
}
