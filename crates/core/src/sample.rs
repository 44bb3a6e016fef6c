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

/// Splits a coordinate into its lower lattice index and fractional weight.
///
/// NaN coordinates map to index 0 with weight NaN, so the NaN propagates;
/// infinite ones get weight NaN too. The index is kept within ±2⁶⁰ so that the
/// neighbour `index + 1` never overflows.
#[inline]
pub(crate) fn split(x: f32) -> (i64, f32) {
    const LIMIT: f32 = (1u64 << 60) as f32;
    let f = x.floor();
    // `as` maps NaN to 0; the weight keeps the NaN (and is NaN for ±∞).
    (f.clamp(-LIMIT, LIMIT) as i64, x - f)
}

#[cfg(test)]
mod tests {
    use super::split;

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
