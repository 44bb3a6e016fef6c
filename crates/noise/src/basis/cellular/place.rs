//! Where Worley noise's feature points lie and how distances to them are
//! kept and sorted: the arithmetic the point search and the batch kernels
//! share, in `f64` and `f32`.

use crate::hash::rehash;
use crate::lattice_math::{Real, max_fast, min_fast};

/// Where the cells' feature points lie: relative to its cell's corner, a
/// feature point is at `margin + jitter·u` on each axis, `margin = (1 −
/// jitter)/2` and `u` uniform in `[0, 1)` from the cell's hash (16 bits
/// each: the hash's low half, its high half, and the high half of a second
/// draw for z), i.e. `½ + jitter·(u − ½)`: jitter 0 is the cell centre.
///
/// The point search and the batch kernels all place feature points through
/// this one type, in f64 and f32; they subtract the margin once per cell
/// column and row and the displacement ([`disp`](Self::disp)) per cell.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Placement<T> {
    /// `(1 − jitter)/2`.
    pub(crate) margin: T,
    /// `jitter / 2¹⁶`: one step of the hash's 16-bit uniforms.
    scale: T,
}

impl<T: Real> Placement<T> {
    /// The placement for `jitter ∈ [0, 1]`.
    #[inline(always)]
    pub(crate) fn new(jitter: f64) -> Self {
        Self {
            margin: T::of_f64(0.5 - 0.5 * jitter),
            scale: T::of_f64(jitter * (1.0 / 65_536.0)),
        }
    }

    /// The displacement `jitter·u` of the feature point of the cell hashed
    /// `h`, beyond the margin, on each axis.
    #[inline(always)]
    pub(crate) fn disp(&self, h: u32) -> [T; 3] {
        [
            T::of_u32(h & 0xFFFF) * self.scale,
            T::of_u32(h >> 16) * self.scale,
            T::of_u32(rehash(h) >> 16) * self.scale,
        ]
    }

    /// The feature point of the cell hashed `h`, relative to its corner.
    #[inline(always)]
    pub(crate) fn point(&self, h: u32) -> [T; 3] {
        self.disp(h).map(|d| self.margin + d)
    }
}

/// Inserts `d` into the `K` smallest distances so far, kept sorted: a
/// branch-free min/max network.
#[inline(always)]
pub(crate) fn insert_k<T: Real, const K: usize>(best: &mut [T; K], d: T) {
    let mut d = d;
    for b in best.iter_mut() {
        let lo = min_fast(*b, d);
        d = max_fast(*b, d);
        *b = lo;
    }
}

/// A metric's arithmetic on lane type `T`, written once for the point search
/// (`f64`) and the batch kernels (`f32`). A distance is kept in a cheap form
/// while the nearest are sorted (squared for the Euclidean metrics) and turned
/// into the metric's value at the end.
pub(crate) trait Dist<T: Real> {
    /// The term of one axis offset (`x²`, or `|x|`).
    fn axis(x: T) -> T;
    /// How two terms combine (`+`, or `max` for Chebyshev).
    fn comb(a: T, b: T) -> T;
    /// A lower bound on the largest axis distance, in the kept form.
    fn kept(b: T) -> T;
    /// A kept distance as the metric's value.
    fn value(d: T) -> T;
}

/// [`Metric::Euclidean`]'s arithmetic (kept squared, rooted at the end).
pub(crate) struct Euclid;
/// [`Metric::EuclideanSquared`]'s arithmetic.
pub(crate) struct EuclidSq;
/// [`Metric::Manhattan`]'s arithmetic.
pub(crate) struct Taxicab;
/// [`Metric::Chebyshev`]'s arithmetic.
pub(crate) struct Cheb;

macro_rules! impl_dist {
    ($t:ty, $root:path) => {
        impl Dist<$t> for Euclid {
            #[inline(always)]
            fn axis(x: $t) -> $t {
                x * x
            }
            #[inline(always)]
            fn comb(a: $t, b: $t) -> $t {
                a + b
            }
            #[inline(always)]
            fn kept(b: $t) -> $t {
                b * b
            }
            #[inline(always)]
            fn value(d: $t) -> $t {
                $root(d)
            }
        }
        impl Dist<$t> for EuclidSq {
            #[inline(always)]
            fn axis(x: $t) -> $t {
                x * x
            }
            #[inline(always)]
            fn comb(a: $t, b: $t) -> $t {
                a + b
            }
            #[inline(always)]
            fn kept(b: $t) -> $t {
                b * b
            }
            #[inline(always)]
            fn value(d: $t) -> $t {
                d
            }
        }
        impl Dist<$t> for Taxicab {
            #[inline(always)]
            fn axis(x: $t) -> $t {
                x.abs()
            }
            #[inline(always)]
            fn comb(a: $t, b: $t) -> $t {
                a + b
            }
            #[inline(always)]
            fn kept(b: $t) -> $t {
                b
            }
            #[inline(always)]
            fn value(d: $t) -> $t {
                d
            }
        }
        impl Dist<$t> for Cheb {
            #[inline(always)]
            fn axis(x: $t) -> $t {
                x.abs()
            }
            #[inline(always)]
            fn comb(a: $t, b: $t) -> $t {
                max_fast(a, b)
            }
            #[inline(always)]
            fn kept(b: $t) -> $t {
                b
            }
            #[inline(always)]
            fn value(d: $t) -> $t {
                d
            }
        }
    };
}
impl_dist!(f64, libm::sqrt);
impl_dist!(f32, crate::basis::cellular_rows::sqrt32);
