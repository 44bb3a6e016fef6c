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
/// NaN coordinates map to index 0 with weight NaN, so the NaN propagates.
#[inline]
pub(crate) fn split(x: f32) -> (i64, f32) {
    let f = x.floor();
    // `as` saturates for huge values and maps NaN to 0; the weight keeps the NaN.
    (f as i64, x - f)
}
