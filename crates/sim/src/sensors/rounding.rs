//! Float-to-integer rounding without libm calls, for the renderers' inner loops.

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
