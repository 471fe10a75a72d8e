//! Rounding without libm calls (the build targets plain x86-64, where `floor` is a call), for
//! the renderers' inner loops and the map build's raster.

/// Largest whole number <= `x` for `|x| < 2^23`, without a libm call (saturating beyond the
/// `i32` range, 0 for NaN).
#[inline(always)]
pub(crate) fn floor_i32(x: f32) -> i32 {
    let i = x as i32;
    i - ((i as f32) > x) as i32
}

/// Smallest whole number >= `x`, for `x` in [-1, 2^23].
#[inline(always)]
pub(crate) fn ceil_small(x: f32) -> i32 {
    let i = x as i32;
    i + ((i as f32) < x) as i32
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
