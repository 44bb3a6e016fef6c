//! A fixed-size vector of `N` channels (RGB or spectral bands) in `f64`.

use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Sub};

/// `N` channel values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Channels<const N: usize>(pub [f64; N]);

impl<const N: usize> Channels<N> {
    pub const ZERO: Self = Channels([0.0; N]);
    pub const ONE: Self = Channels([1.0; N]);

    #[inline]
    pub fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Channels(self.0.map(f))
    }

    #[inline]
    pub fn exp_neg(self) -> Self {
        self.map(|x| (-x).exp())
    }

    #[inline]
    pub fn zip(self, o: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        let mut r = self.0;
        for (a, b) in r.iter_mut().zip(o.0) {
            *a = f(*a, b);
        }
        Channels(r)
    }

    #[inline]
    pub fn to_f32(self) -> [f32; N] {
        self.0.map(|x| x as f32)
    }

    #[inline]
    pub fn from_f32(v: &[f32; N]) -> Self {
        Channels(v.map(f64::from))
    }
}

impl<const N: usize> Add for Channels<N> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        self.zip(o, |a, b| a + b)
    }
}
impl<const N: usize> Sub for Channels<N> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        self.zip(o, |a, b| a - b)
    }
}
impl<const N: usize> Mul for Channels<N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        self.zip(o, |a, b| a * b)
    }
}
impl<const N: usize> Mul<f64> for Channels<N> {
    type Output = Self;
    #[inline]
    fn mul(self, k: f64) -> Self {
        self.map(|a| a * k)
    }
}
impl<const N: usize> Div<f64> for Channels<N> {
    type Output = Self;
    #[inline]
    fn div(self, k: f64) -> Self {
        self.map(|a| a / k)
    }
}
impl<const N: usize> AddAssign for Channels<N> {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}
impl<const N: usize> MulAssign for Channels<N> {
    #[inline]
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}

/// A 2-D table of `N`-channel `f32` texels, sampled bilinearly at
/// normalised coordinates where texel `i` sits at `i/(n − 1)`.
#[derive(Clone, Debug)]
pub(crate) struct Lut2<const N: usize> {
    pub w: usize,
    pub h: usize,
    pub data: Vec<[f32; N]>,
}

impl<const N: usize> Lut2<N> {
    /// Builds the table from `f(x, y)` with `x, y ∈ [0, 1]` (rows in parallel).
    pub fn build(
        w: usize,
        h: usize,
        f: impl Fn(f64, f64) -> Channels<N> + Sync + Send,
        progress: &dyn natura_core::Progress,
    ) -> Self {
        Self::build_rows(w, h, |_| (), |(), x, y| f(x, y), progress)
    }

    /// As [`Self::build`], with what the texels of row `y` share computed
    /// once by `row(y)` and passed to each texel's `f(&row, x, y)`.
    pub fn build_rows<R>(
        w: usize,
        h: usize,
        row: impl Fn(f64) -> R + Sync + Send,
        f: impl Fn(&R, f64, f64) -> Channels<N> + Sync + Send,
        progress: &dyn natura_core::Progress,
    ) -> Self {
        let mut data = vec![[0.0f32; N]; w * h];
        let fill = |j: usize, out: &mut [[f32; N]]| {
            let y = j as f64 / (h - 1) as f64;
            let shared = row(y);
            for (i, t) in out.iter_mut().enumerate() {
                *t = f(&shared, i as f64 / (w - 1) as f64, y).to_f32();
            }
            progress.advance(1);
        };
        #[cfg(feature = "parallel")]
        {
            use rayon::prelude::*;
            data.par_chunks_mut(w)
                .enumerate()
                .for_each(|(j, out)| fill(j, out));
        }
        #[cfg(not(feature = "parallel"))]
        data.chunks_mut(w)
            .enumerate()
            .for_each(|(j, out)| fill(j, out));
        Self { w, h, data }
    }

    /// Bilinear sample at `x, y ∈ [0, 1]` (clamped).
    #[inline]
    pub fn sample(&self, x: f64, y: f64) -> Channels<N> {
        let fx = (x.clamp(0.0, 1.0) * (self.w - 1) as f64).min((self.w - 1) as f64);
        let fy = (y.clamp(0.0, 1.0) * (self.h - 1) as f64).min((self.h - 1) as f64);
        let (i, j) = ((fx as usize).min(self.w - 2), (fy as usize).min(self.h - 2));
        let (tx, ty) = (fx - i as f64, fy - j as f64);
        let at = |i: usize, j: usize| Channels::from_f32(&self.data[j * self.w + i]);
        let a = at(i, j) * (1.0 - tx) + at(i + 1, j) * tx;
        let b = at(i, j + 1) * (1.0 - tx) + at(i + 1, j + 1) * tx;
        a * (1.0 - ty) + b * ty
    }
}
