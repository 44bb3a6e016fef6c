//! Scalar helpers that compile to one instruction per lane: the tracers'
//! models are written with these so that the same function serves a single
//! ray and a loop over lanes that LLVM vectorises.

/// `min` without NaN handling (operands are never NaN here): one instruction.
#[inline(always)]
pub(crate) fn fmin(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// `max` without NaN handling.
#[inline(always)]
pub(crate) fn fmax(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// `max(v, lo)` for a whole number `lo`, returning `lo` when `v` is NaN (as
/// `f32::max` does), in a form that vectorises to one compare and blend.
#[inline(always)]
pub(crate) fn fmax_nan_lo(v: f32, lo: f32) -> f32 {
    if v > lo { v } else { lo }
}

/// A cell or node coordinate (below 2²⁴, [`crate::MAX_SAMPLES_PER_AXIS`])
/// as `f32`, exactly. Converting through `i32` vectorises (there is no
/// packed unsigned conversion before AVX-512) and gives the same value.
#[inline(always)]
pub(crate) fn coord(v: u32) -> f32 {
    v as i32 as f32
}

/// `v as u32` for `v` in `[0, 2²⁴)` (a clamped cell coordinate).
#[inline(always)]
pub(crate) fn trunc(v: f32) -> u32 {
    debug_assert!((0.0..16_777_216.0).contains(&v));
    #[allow(unsafe_code)]
    // SAFETY: every caller clamps `v` between two cell coordinates, whole
    // numbers in `[0, 2²⁴)` (`MAX_SAMPLES_PER_AXIS`), so it is finite and its
    // truncation fits an `i32`.
    let i = unsafe { v.to_int_unchecked::<i32>() };
    i as u32
}

/// The cell holding coordinate `v` along an axis of cells `0..=hi`: `⌊v⌋`
/// clamped to `[0, hi]` (NaN goes to 0). Clamping before the truncation is
/// the same as after it, the bounds being whole numbers.
#[inline(always)]
pub(crate) fn cell_of(v: f32, hi: f32) -> u32 {
    trunc(fmin(fmax(v, 0.0), hi))
}
