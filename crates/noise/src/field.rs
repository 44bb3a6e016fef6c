//! The [`Field`] trait: the seam every basis, fractal and warp plugs into.

use glam::{DVec2, DVec3};

use crate::error::{NoiseError, Result};
use crate::lattice_math::Simd;

/// A deterministic scalar field `R² → R` and `R³ → R`, evaluated at `f64` points.
///
/// Every basis ([`Perlin`](crate::Perlin), [`Simplex`](crate::Simplex),
/// [`Worley`](crate::Worley), …), fractal ([`Fbm`](crate::Fbm),
/// [`HybridMultifractal`](crate::HybridMultifractal), …) and warp implements it.
///
/// # Contract
/// * **Pure**: `&self` evaluation, no interior mutability; the same point gives
///   the same value on every call, thread and run. Implementors are
///   `Send + Sync`, so one field can be shared by rayon workers.
/// * **f64 points** keep planet-scale coordinates precise; values are `f64`.
/// * **NaN in, NaN out**: a non-finite coordinate gives a NaN value (never a panic).
/// * [`bound`](Field::bound) is a true bound on `|f|` and
///   [`lipschitz2`](Field::lipschitz2)/[`lipschitz3`](Field::lipschitz3) true
///   bounds on `|∇f|` (so `|f(p) − f(q)| ≤ L·|p − q|`), which sphere tracers and
///   height-field ray marchers rely on. Discontinuous fields return
///   `f64::INFINITY`.
/// * The batch fills write `f32` values equal to the point evaluation within
///   `1e-5` (relative to [`bound`](Field::bound) for fractals with large sums),
///   identically at every [`Simd`] level, and may be called concurrently on
///   disjoint rows.
///
/// The trait is object safe: `Box<dyn Field>` and `&dyn Field` are fields too.
pub trait Field: Send + Sync {
    /// The value at the 2-D point `p`.
    fn eval2(&self, p: DVec2) -> f64;

    /// The value at the 3-D point `p`.
    fn eval3(&self, p: DVec3) -> f64;

    /// The value and gradient at the 2-D point `p`.
    ///
    /// Analytic wherever the implementor has a closed form (gradient and value
    /// noise, simplex, fBm and the multifractals over them). The default is a
    /// central difference with step `1e-6` (absolute error ≈ 1e-9·L).
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        const H: f64 = 1e-6;
        let gx = (self.eval2(p + DVec2::X * H) - self.eval2(p - DVec2::X * H)) / (2.0 * H);
        let gy = (self.eval2(p + DVec2::Y * H) - self.eval2(p - DVec2::Y * H)) / (2.0 * H);
        (self.eval2(p), DVec2::new(gx, gy))
    }

    /// The value and gradient at the 3-D point `p` (see [`eval_grad2`](Field::eval_grad2)).
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        const H: f64 = 1e-6;
        let d = |e: DVec3| (self.eval3(p + e * H) - self.eval3(p - e * H)) / (2.0 * H);
        (
            self.eval3(p),
            DVec3::new(d(DVec3::X), d(DVec3::Y), d(DVec3::Z)),
        )
    }

    /// The values at `p` scaled by each frequency: `out[k] = eval2(p·freq[k])`
    /// (what a fractal's octave loop asks of its basis).
    ///
    /// The results equal the point evaluations (bit for bit, except that an
    /// implementation may give an exact zero the other sign). The default
    /// evaluates point by point; [`Perlin`](crate::Perlin) noise evaluates
    /// the octaves as SIMD lanes.
    ///
    /// # Panics
    /// If `out` is shorter than `freq` (a programming error).
    fn eval2_scaled(&self, p: DVec2, freq: &[f64], out: &mut [f64]) {
        for (o, &f) in out[..freq.len()].iter_mut().zip(freq) {
            *o = self.eval2(p * f);
        }
    }

    /// The values at the 3-D point `p` scaled by each frequency (see
    /// [`eval2_scaled`](Field::eval2_scaled)).
    ///
    /// # Panics
    /// If `out` is shorter than `freq` (a programming error).
    fn eval3_scaled(&self, p: DVec3, freq: &[f64], out: &mut [f64]) {
        for (o, &f) in out[..freq.len()].iter_mut().zip(freq) {
            *o = self.eval3(p * f);
        }
    }

    /// A bound on `|f|` over all of space.
    fn bound(&self) -> f64;

    /// A Lipschitz constant of the 2-D field: `|f(p) − f(q)| ≤ L·|p − q|`.
    fn lipschitz2(&self) -> f64;

    /// A Lipschitz constant of the 3-D field.
    fn lipschitz3(&self) -> f64;

    /// The larger of the 2-D and 3-D Lipschitz constants.
    fn lipschitz(&self) -> f64 {
        self.lipschitz2().max(self.lipschitz3())
    }

    /// Fills `out[i]` with the value at `origin + i·step·x̂` using `simd`.
    ///
    /// The default evaluates point by point; the bases and fractals override it
    /// with vectorised row kernels.
    fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
        let _ = simd;
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.eval2(DVec2::new(origin.x + i as f64 * step, origin.y)) as f32;
        }
    }

    /// Fills rows of a 2-D grid at once using `simd`: `out` holds
    /// `ys.len()` rows of `n = out.len() / ys.len()` points one after
    /// another, and point `i` of row `r` is the value at `(x0 + i·step,
    /// ys[r])`. Equal, bit for bit, to [`fill_row2_with`](Self::fill_row2_with)
    /// row by row, which is the default; the bases and fBm override it to
    /// share between the rows the work that depends on x alone. Points past
    /// the last whole row are left as they are.
    fn fill_rows2_with(&self, simd: Simd, x0: f64, ys: &[f64], step: f64, out: &mut [f32]) {
        fill_rows2_each(self, simd, x0, ys, step, out);
    }

    /// Fills `out[i]` with the value at `origin + i·step·x̂` (3-D) using `simd`.
    fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
        let _ = simd;
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.eval3(DVec3::new(origin.x + i as f64 * step, origin.y, origin.z)) as f32;
        }
    }

    /// Fills `out[i]` with the value at `origin + i·step·x̂`, at the best SIMD level.
    ///
    /// This is the call a parallel height-field fill makes for each row.
    fn fill_row2(&self, origin: DVec2, step: f64, out: &mut [f32]) {
        self.fill_row2_with(Simd::best(), origin, step, out);
    }

    /// Fills `out[i]` with the value at `origin + i·step·x̂` (3-D), at the best SIMD level.
    fn fill_row3(&self, origin: DVec3, step: f64, out: &mut [f32]) {
        self.fill_row3_with(Simd::best(), origin, step, out);
    }

    /// Fills a row-major 2-D lattice (`out[j·nx + i]` = value at
    /// `origin + (i·step.x, j·step.y)`), checking the buffer length.
    ///
    /// # Errors
    ///
    /// [`NoiseError::InvalidLattice`](crate::NoiseError::InvalidLattice) if `out` does not
    /// hold exactly the lattice's points.
    fn fill_grid2(&self, lattice: &Lattice2, out: &mut [f32]) -> Result<()> {
        lattice.check(out.len())?;
        let simd = Simd::best();
        // Blocks of rows, so fields that share work between rows can.
        for (b, block) in out
            .chunks_mut(GRID_ROWS.saturating_mul(lattice.nx))
            .enumerate()
        {
            let ys: [f64; GRID_ROWS] =
                core::array::from_fn(|r| lattice.row_origin(b * GRID_ROWS + r).y);
            let rows = block.len() / lattice.nx;
            self.fill_rows2_with(simd, lattice.origin.x, &ys[..rows], lattice.step.x, block);
        }
        Ok(())
    }

    /// Fills a 3-D lattice, x fastest then y then z
    /// (`out[(k·ny + j)·nx + i]`), checking the buffer length.
    ///
    /// # Errors
    ///
    /// [`NoiseError::InvalidLattice`](crate::NoiseError::InvalidLattice) if `out` does not
    /// hold exactly the lattice's points.
    fn fill_grid3(&self, lattice: &Lattice3, out: &mut [f32]) -> Result<()> {
        lattice.check(out.len())?;
        let simd = Simd::best();
        for (r, row) in out.chunks_exact_mut(lattice.nx).enumerate() {
            self.fill_row3_with(
                simd,
                lattice.row_origin(r % lattice.ny, r / lattice.ny),
                lattice.step.x,
                row,
            );
        }
        Ok(())
    }
}

/// The points a row of `out` holds when it holds `rows` rows (see
/// [`Field::fill_rows2_with`]); `None` if there are no rows or no points.
#[inline]
pub(crate) fn row_len(out: usize, rows: usize) -> Option<usize> {
    out.checked_div(rows).filter(|&n| n > 0)
}

/// [`Field::fill_rows2_with`] row by row through `fill_row2_with`: its
/// default, and what the overrides do with rows their shared kernels refuse.
pub(crate) fn fill_rows2_each<F: Field + ?Sized>(
    f: &F,
    simd: Simd,
    x0: f64,
    ys: &[f64],
    step: f64,
    out: &mut [f32],
) {
    let Some(n) = row_len(out.len(), ys.len()) else {
        return;
    };
    for (row, &y) in out.chunks_exact_mut(n).zip(ys) {
        f.fill_row2_with(simd, DVec2::new(x0, y), step, row);
    }
}

/// Rows [`Field::fill_grid2`] hands [`Field::fill_rows2_with`] at a time.
const GRID_ROWS: usize = 8;

/// A regular 2-D lattice of sample points: `origin + (i·step.x, j·step.y)` for
/// `i < nx`, `j < ny`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Lattice2 {
    /// The point of sample `(0, 0)`.
    pub origin: DVec2,
    /// Spacing between samples along x and y.
    pub step: DVec2,
    /// Samples along x (row length).
    pub nx: usize,
    /// Samples along y (rows).
    pub ny: usize,
}

impl Lattice2 {
    /// A lattice of `nx × ny` samples; refuses zero counts, an overflowing
    /// point count and non-finite origin or step.
    ///
    /// # Errors
    /// [`NoiseError::InvalidLattice`] for a zero or overflowing point count, or a non-finite origin or step.
    pub fn new(origin: DVec2, step: DVec2, nx: usize, ny: usize) -> Result<Self> {
        let l = Self {
            origin,
            step,
            nx,
            ny,
        };
        l.validate()?;
        Ok(l)
    }

    /// Checks the counts, origin and step.
    ///
    /// # Errors
    /// [`NoiseError::InvalidLattice`] for a zero or overflowing point count, or a non-finite origin or step.
    pub fn validate(&self) -> Result<()> {
        if self.nx == 0 || self.ny == 0 {
            return Err(NoiseError::InvalidLattice {
                what: "zero samples along an axis",
            });
        }
        if self.nx.checked_mul(self.ny).is_none() {
            return Err(NoiseError::InvalidLattice {
                what: "point count overflows usize",
            });
        }
        if !self.origin.is_finite() || !self.step.is_finite() {
            return Err(NoiseError::InvalidLattice {
                what: "origin and step must be finite",
            });
        }
        Ok(())
    }

    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Whether the lattice has no points (never, once validated).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The first point of row `j`.
    #[must_use]
    pub fn row_origin(&self, j: usize) -> DVec2 {
        DVec2::new(self.origin.x, self.origin.y + j as f64 * self.step.y)
    }

    /// The point of sample `(i, j)`.
    #[must_use]
    pub fn point(&self, i: usize, j: usize) -> DVec2 {
        self.origin + DVec2::new(i as f64, j as f64) * self.step
    }

    pub(crate) fn check(&self, len: usize) -> Result<()> {
        self.validate()?;
        if len != self.len() {
            return Err(NoiseError::BufferLength {
                expected: self.len(),
                got: len,
            });
        }
        Ok(())
    }
}

/// A regular 3-D lattice of sample points: `origin + (i, j, k)·step`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Lattice3 {
    /// The point of sample `(0, 0, 0)`.
    pub origin: DVec3,
    /// Spacing between samples along x, y and z.
    pub step: DVec3,
    /// Samples along x (row length).
    pub nx: usize,
    /// Samples along y.
    pub ny: usize,
    /// Samples along z.
    pub nz: usize,
}

impl Lattice3 {
    /// A lattice of `nx × ny × nz` samples; refuses zero counts, an
    /// overflowing point count and non-finite origin or step.
    ///
    /// # Errors
    /// [`NoiseError::InvalidLattice`] for a zero or overflowing point count, or a non-finite origin or step.
    pub fn new(origin: DVec3, step: DVec3, nx: usize, ny: usize, nz: usize) -> Result<Self> {
        let l = Self {
            origin,
            step,
            nx,
            ny,
            nz,
        };
        l.validate()?;
        Ok(l)
    }

    /// Checks the counts, origin and step.
    ///
    /// # Errors
    /// [`NoiseError::InvalidLattice`] for a zero or overflowing point count, or a non-finite origin or step.
    pub fn validate(&self) -> Result<()> {
        if self.nx == 0 || self.ny == 0 || self.nz == 0 {
            return Err(NoiseError::InvalidLattice {
                what: "zero samples along an axis",
            });
        }
        if self
            .nx
            .checked_mul(self.ny)
            .and_then(|v| v.checked_mul(self.nz))
            .is_none()
        {
            return Err(NoiseError::InvalidLattice {
                what: "point count overflows usize",
            });
        }
        if !self.origin.is_finite() || !self.step.is_finite() {
            return Err(NoiseError::InvalidLattice {
                what: "origin and step must be finite",
            });
        }
        Ok(())
    }

    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.nx * self.ny * self.nz
    }

    /// Whether the lattice has no points (never, once validated).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The first point of row `(j, k)`.
    #[must_use]
    pub fn row_origin(&self, j: usize, k: usize) -> DVec3 {
        DVec3::new(
            self.origin.x,
            self.origin.y + j as f64 * self.step.y,
            self.origin.z + k as f64 * self.step.z,
        )
    }

    /// The point of sample `(i, j, k)`.
    #[must_use]
    pub fn point(&self, i: usize, j: usize, k: usize) -> DVec3 {
        self.origin + DVec3::new(i as f64, j as f64, k as f64) * self.step
    }

    pub(crate) fn check(&self, len: usize) -> Result<()> {
        self.validate()?;
        if len != self.len() {
            return Err(NoiseError::BufferLength {
                expected: self.len(),
                got: len,
            });
        }
        Ok(())
    }
}

macro_rules! forward_field {
    ($($ty:ty),*) => {$(
        impl<F: Field + ?Sized> Field for $ty {
            #[inline]
            fn eval2(&self, p: DVec2) -> f64 { (**self).eval2(p) }
            #[inline]
            fn eval3(&self, p: DVec3) -> f64 { (**self).eval3(p) }
            #[inline]
            fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) { (**self).eval_grad2(p) }
            #[inline]
            fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) { (**self).eval_grad3(p) }
            #[inline]
            fn eval2_scaled(&self, p: DVec2, freq: &[f64], out: &mut [f64]) {
                (**self).eval2_scaled(p, freq, out)
            }
            #[inline]
            fn eval3_scaled(&self, p: DVec3, freq: &[f64], out: &mut [f64]) {
                (**self).eval3_scaled(p, freq, out)
            }
            fn bound(&self) -> f64 { (**self).bound() }
            fn lipschitz2(&self) -> f64 { (**self).lipschitz2() }
            fn lipschitz3(&self) -> f64 { (**self).lipschitz3() }
            fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
                (**self).fill_row2_with(simd, origin, step, out)
            }
            fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
                (**self).fill_row3_with(simd, origin, step, out)
            }
            fn fill_rows2_with(&self, simd: Simd, x0: f64, ys: &[f64], step: f64, out: &mut [f32]) {
                (**self).fill_rows2_with(simd, x0, ys, step, out)
            }
        }
    )*};
}

forward_field!(&F);
#[cfg(feature = "alloc")]
forward_field!(alloc::boxed::Box<F>, alloc::sync::Arc<F>);

/// A field that is the same constant everywhere (useful as a parameter field).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Constant(pub f64);

impl Field for Constant {
    fn eval2(&self, _p: DVec2) -> f64 {
        self.0
    }
    fn eval3(&self, _p: DVec3) -> f64 {
        self.0
    }
    fn eval_grad2(&self, _p: DVec2) -> (f64, DVec2) {
        (self.0, DVec2::ZERO)
    }
    fn eval_grad3(&self, _p: DVec3) -> (f64, DVec3) {
        (self.0, DVec3::ZERO)
    }
    fn bound(&self) -> f64 {
        self.0.abs()
    }
    fn lipschitz2(&self) -> f64 {
        0.0
    }
    fn lipschitz3(&self) -> f64 {
        0.0
    }
    fn fill_row2_with(&self, _simd: Simd, _origin: DVec2, _step: f64, out: &mut [f32]) {
        out.fill(self.0 as f32);
    }
    fn fill_row3_with(&self, _simd: Simd, _origin: DVec3, _step: f64, out: &mut [f32]) {
        out.fill(self.0 as f32);
    }
}
