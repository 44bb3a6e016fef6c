//! Boundary handling and interpolation shared by [`Grid2`](crate::Grid2) and
//! [`Grid3`](crate::Grid3) sampling.

use glam::{Vec2, Vec3, Vec4};

/// What a sampler returns for coordinates outside the grid.
///
/// Coordinates are in cell units: sample `i` sits at coordinate `i`, so a grid
/// of width `w` covers `[0, w − 1]` along that axis.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Boundary<T> {
    /// Coordinates are clamped to the grid: the edge value extends outward.
    Clamp,
    /// The grid tiles the plane with period `w` (sample `w` equals sample `0`).
    Wrap,
    /// Every sample outside the grid has this value.
    Constant(T),
}

/// Hermite smoothstep of `x` between edges `a` and `b` (either order): 0 at
/// `a`, 1 at `b`, `3t² − 2t³` between, with `t` clamped to `[0, 1]`.
#[inline]
#[must_use]
pub fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Values that can be linearly interpolated with an `f32` weight.
///
/// Implemented for `f32`, `f64` and the `glam` float vectors; implement it for
/// your own types to sample grids of them.
pub trait Interpolate: Copy {
    /// Returns `a + (b − a)·t`.
    #[must_use]
    fn lerp(a: Self, b: Self, t: f32) -> Self;
}

impl Interpolate for f32 {
    #[inline]
    fn lerp(a: Self, b: Self, t: f32) -> Self {
        a + (b - a) * t
    }
}

impl Interpolate for f64 {
    #[inline]
    fn lerp(a: Self, b: Self, t: f32) -> Self {
        a + (b - a) * f64::from(t)
    }
}

macro_rules! impl_interpolate_vec {
    ($($t:ty),*) => {$(
        impl Interpolate for $t {
            #[inline]
            fn lerp(a: Self, b: Self, t: f32) -> Self {
                a + (b - a) * t
            }
        }
    )*};
}
impl_interpolate_vec!(Vec2, Vec3, Vec4);

/// Resolves integer index `i` along an axis of length `n` under `boundary`.
///
/// Returns `None` when the boundary is [`Boundary::Constant`] and `i` is outside.
#[inline]
pub(crate) fn resolve<T>(i: i64, n: usize, boundary: &Boundary<T>) -> Option<usize> {
    let n = n as i64;
    match boundary {
        Boundary::Clamp => Some(i.clamp(0, n - 1) as usize),
        Boundary::Wrap => Some(i.rem_euclid(n) as usize),
        Boundary::Constant(_) => (0..n).contains(&i).then_some(i as usize),
    }
}

/// `x.floor()` without a call into the C library: the largest integer not
/// above `x`, bit for bit as [`f32::floor`] for every input (NaN, the
/// infinities and `−0.0` included).
///
/// On x86-64 without SSE4.1 (the target's baseline) `f32::floor` compiles
/// to a call to `floorf`, which costs more than the trilinear lookups that
/// use it; this version truncates through an integer instead and stays
/// inline.
///
/// ```
/// use natura_core::floor_f32;
/// for x in [-2.5f32, -1.0, -0.25, -0.0, 0.0, 0.75, 3.0, 1e9, f32::INFINITY] {
///     assert_eq!(floor_f32(x).to_bits(), x.floor().to_bits());
/// }
/// assert!(floor_f32(f32::NAN).is_nan());
/// ```
#[inline(always)]
#[must_use]
pub fn floor_f32(x: f32) -> f32 {
    // At or past 2^23 every f32 is an integer (and NaN and ±∞ are their own floor).
    if x.is_nan() || x.abs() >= 8_388_608.0 {
        return x;
    }
    let t = x as i32 as f32;
    let f = if t > x { t - 1.0 } else { t };
    // Truncation loses the sign of a zero: −0.5 < x ≤ −0.0 floors to −1 or −0.0.
    f32::copysign(f, x)
}

/// Splits a coordinate into its lower lattice index and fractional weight.
///
/// NaN coordinates map to index 0 with weight NaN, so the NaN propagates;
/// infinite ones get weight NaN too. The index is kept within ±2⁶⁰ so that the
/// neighbour `index + 1` never overflows.
#[inline]
pub(crate) fn split(x: f32) -> (i64, f32) {
    const LIMIT: f32 = (1u64 << 60) as f32;
    let f = floor_f32(x);
    // `as` maps NaN to 0; the weight keeps the NaN (and is NaN for ±∞).
    (f.clamp(-LIMIT, LIMIT) as i64, x - f)
}

#[cfg(test)]
mod tests {
    use super::split;

    #[test]
    fn floor_f32_is_floor_bit_for_bit_across_the_bit_patterns() {
        // Every 251st bit pattern (17 million values: every exponent, both
        // signs, NaNs, infinities, subnormals) and the edges near 2^23.
        let edges = [
            8_388_607.5f32,
            8_388_608.0,
            -8_388_607.5,
            -8_388_608.0,
            -0.5,
            0.5,
        ];
        let strided = (0..=u32::MAX).step_by(251).map(f32::from_bits);
        for x in strided.chain(edges) {
            let (a, b) = (super::floor_f32(x), x.floor());
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{x:e}: {a:e} against {b:e}"
            );
        }
    }

    #[test]
    fn split_never_gives_an_index_whose_neighbour_overflows() {
        for x in [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN,
        ] {
            let (i, _) = split(x);
            assert!(
                i.checked_add(1).is_some() && i.checked_sub(1).is_some(),
                "{x}"
            );
        }
        assert!(split(f32::INFINITY).1.is_nan());
        assert_eq!(split(2.25), (2, 0.25));
        assert_eq!(split(-0.5), (-1, 0.5));
    }
}
