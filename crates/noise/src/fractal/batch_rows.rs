//! Batch evaluation shared by the fractals: octave rows into stack scratch
//! buffers, combined by a per-fractal vectorised kernel.

use glam::{DVec2, DVec3};

use crate::field::{Field, row_len};
use crate::fractal::{CHUNK, Octaves};
use crate::lattice_math::{Simd, run};

/// A row start point of any dimension, scaled by an octave frequency.
pub(crate) trait RowPoint: Copy {
    fn scaled(self, f: f64) -> Self;
    fn advanced(self, dx: f64) -> Self;
    fn fill<B: Field + ?Sized>(self, basis: &B, simd: Simd, step: f64, out: &mut [f32]);
}

impl RowPoint for DVec2 {
    #[inline]
    fn scaled(self, f: f64) -> Self {
        self * f
    }
    #[inline]
    fn advanced(self, dx: f64) -> Self {
        DVec2::new(self.x + dx, self.y)
    }
    #[inline]
    fn fill<B: Field + ?Sized>(self, basis: &B, simd: Simd, step: f64, out: &mut [f32]) {
        basis.fill_row2_with(simd, self, step, out);
    }
}

impl RowPoint for DVec3 {
    #[inline]
    fn scaled(self, f: f64) -> Self {
        self * f
    }
    #[inline]
    fn advanced(self, dx: f64) -> Self {
        DVec3::new(self.x + dx, self.y, self.z)
    }
    #[inline]
    fn fill<B: Field + ?Sized>(self, basis: &B, simd: Simd, step: f64, out: &mut [f32]) {
        basis.fill_row3_with(simd, self, step, out);
    }
}

/// Evaluates every octave of `basis` along the row in chunks and hands each
/// octave's values to `combine(k, basis_values, out_chunk, state_chunk)`.
/// `combine` runs at the `simd` level so its loops vectorise.
pub(crate) fn octave_rows<P: RowPoint, B: Field + ?Sized>(
    basis: &B,
    simd: Simd,
    oct: &Octaves,
    origin: P,
    step: f64,
    out: &mut [f32],
    mut combine: impl FnMut(usize, &[f32], &mut [f32], &mut [f32]),
) {
    let mut tmp = [0.0f32; CHUNK];
    let mut state = [0.0f32; CHUNK];
    for (c, chunk) in out.chunks_mut(CHUNK).enumerate() {
        let m = chunk.len();
        let start = origin.advanced((c * CHUNK) as f64 * step);
        for k in 0..oct.count() {
            let f = oct.frequency(k);
            start.scaled(f).fill(basis, simd, step * f, &mut tmp[..m]);
            run(
                simd,
                #[inline(always)]
                || combine(k, &tmp[..m], chunk, &mut state[..m]),
            );
        }
    }
}

/// What a fractal's batch fill covers: one row from a point (2-D or 3-D),
/// or rows of a 2-D grid ([`GridRows2`]). The fractals write their octave
/// combination once, generic over this.
pub(crate) trait RowSet: Copy {
    /// [`octave_rows`] or [`octave_rows_many`] over these rows.
    fn octave_rows<B: Field + ?Sized>(
        self,
        basis: &B,
        simd: Simd,
        oct: &Octaves,
        step: f64,
        out: &mut [f32],
        combine: impl FnMut(usize, &[f32], &mut [f32], &mut [f32]),
    );
}

/// One row, from a point of either dimension.
impl<P: RowPoint> RowSet for P {
    #[inline(always)]
    fn octave_rows<B: Field + ?Sized>(
        self,
        basis: &B,
        simd: Simd,
        oct: &Octaves,
        step: f64,
        out: &mut [f32],
        combine: impl FnMut(usize, &[f32], &mut [f32], &mut [f32]),
    ) {
        octave_rows(basis, simd, oct, self, step, out, combine);
    }
}

/// Rows of a 2-D grid: from `x0`, row `r` at `ys[r]` (see
/// [`Field::fill_rows2_with`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct GridRows2<'a> {
    pub x0: f64,
    pub ys: &'a [f64],
}

impl RowSet for GridRows2<'_> {
    #[inline(always)]
    fn octave_rows<B: Field + ?Sized>(
        self,
        basis: &B,
        simd: Simd,
        oct: &Octaves,
        step: f64,
        out: &mut [f32],
        combine: impl FnMut(usize, &[f32], &mut [f32], &mut [f32]),
    ) {
        octave_rows_many(basis, simd, oct, self.x0, self.ys, step, out, combine);
    }
}

/// Rows [`octave_rows_many`] evaluates together.
pub(crate) const MANY_ROWS: usize = 8;

/// [`octave_rows`] for rows of a 2-D grid at once: `out` holds `ys.len()`
/// rows of `out.len() / ys.len()` points, row `r` at `y = ys[r]`, and each
/// octave's rows come from one [`Field::fill_rows2_with`] call, so the
/// basis can share its x work between them. `combine` sees every row's
/// chunks in the order [`octave_rows`] gives it one row's, so each row
/// equals [`octave_rows`]'s bit for bit.
#[allow(clippy::too_many_arguments)] // `octave_rows`'s, and the rows' y
pub(crate) fn octave_rows_many<B: Field + ?Sized>(
    basis: &B,
    simd: Simd,
    oct: &Octaves,
    x0: f64,
    ys: &[f64],
    step: f64,
    out: &mut [f32],
    mut combine: impl FnMut(usize, &[f32], &mut [f32], &mut [f32]),
) {
    let Some(n) = row_len(out.len(), ys.len()) else {
        return;
    };
    let mut tmp = [0.0f32; MANY_ROWS * CHUNK];
    let mut state = [0.0f32; MANY_ROWS * CHUNK];
    for (block, ys) in out.chunks_mut(MANY_ROWS * n).zip(ys.chunks(MANY_ROWS)) {
        let rows = ys.len();
        for c in 0..n.div_ceil(CHUNK) {
            let m = CHUNK.min(n - c * CHUNK);
            // As `octave_rows`: the chunk's start advanced along x, then
            // scaled by the octave's frequency.
            let start = DVec2::new(x0, 0.0).advanced((c * CHUNK) as f64 * step);
            for k in 0..oct.count() {
                let f = oct.frequency(k);
                let fy: [f64; MANY_ROWS] =
                    core::array::from_fn(|r| DVec2::new(0.0, ys[r.min(rows - 1)]).scaled(f).y);
                basis.fill_rows2_with(
                    simd,
                    start.scaled(f).x,
                    &fy[..rows],
                    step * f,
                    &mut tmp[..rows * m],
                );
                for r in 0..rows {
                    let chunk = &mut block[r * n + c * CHUNK..][..m];
                    let (vals, st) = (&tmp[r * m..][..m], &mut state[r * m..][..m]);
                    run(
                        simd,
                        #[inline(always)]
                        || combine(k, vals, chunk, st),
                    );
                }
            }
        }
    }
}

/// Point types the fractals are generic over (2-D and 3-D), with basis evaluation.
pub(crate) trait Pt:
    RowPoint
    + core::ops::Mul<f64, Output = Self>
    + core::ops::Add<Output = Self>
    + core::ops::AddAssign
    + core::ops::Sub<Output = Self>
{
    const ZERO: Self;
    fn eval<B: Field + ?Sized>(b: &B, p: Self) -> f64;
    fn eval_grad<B: Field + ?Sized>(b: &B, p: Self) -> (f64, Self);
}

impl Pt for DVec2 {
    const ZERO: Self = DVec2::ZERO;
    #[inline]
    fn eval<B: Field + ?Sized>(b: &B, p: Self) -> f64 {
        b.eval2(p)
    }
    #[inline]
    fn eval_grad<B: Field + ?Sized>(b: &B, p: Self) -> (f64, Self) {
        b.eval_grad2(p)
    }
}

impl Pt for DVec3 {
    const ZERO: Self = DVec3::ZERO;
    #[inline]
    fn eval<B: Field + ?Sized>(b: &B, p: Self) -> f64 {
        b.eval3(p)
    }
    #[inline]
    fn eval_grad<B: Field + ?Sized>(b: &B, p: Self) -> (f64, Self) {
        b.eval_grad3(p)
    }
}

/// Declares a multifractal of the weighted-octave family: the struct (basis,
/// parameters, octave table), its validating constructor and accessors, and
/// its [`Field`] implementation from the type's own generic methods `value<P>`,
/// `value_grad<P>`, `rows<P>`, `bound_impl` and `lipschitz_impl` (which hold
/// the model's arithmetic, in the model's file).
///
/// The constructor validates the parameters, builds the octave table and
/// refuses a field whose bound exceeds [`MAX_BOUND`](crate::MAX_BOUND).
macro_rules! multifractal {
    ($(#[$attr:meta])* $ty:ident($params:ty), $new_doc:literal) => {
        $(#[$attr])*
        #[derive(Clone, Debug, PartialEq)]
        pub struct $ty<B> {
            basis: B,
            params: $params,
            oct: $crate::fractal::Octaves,
        }

        impl<B: $crate::field::Field> $ty<B> {
            #[doc = $new_doc]
            ///
            /// # Errors
            /// As the parameters' `validate`, and
            /// [`NoiseError::Unbounded`](crate::NoiseError::Unbounded) if they let
            /// the field's values exceed [`MAX_BOUND`](crate::MAX_BOUND).
            pub fn new(basis: B, params: $params) -> $crate::error::Result<Self> {
                params.validate()?;
                let oct = params.spectral.octaves_table()?;
                let f = Self { basis, params, oct };
                $crate::error::bounded(stringify!($ty), f.bound_impl())?;
                Ok(f)
            }

            /// The parameters.
            pub fn params(&self) -> &$params {
                &self.params
            }

            /// The basis.
            pub fn basis(&self) -> &B {
                &self.basis
            }

            /// The precomputed octave table.
            pub fn octaves(&self) -> &$crate::fractal::Octaves {
                &self.oct
            }
        }

        impl<B: $crate::field::Field> $crate::field::Field for $ty<B> {
            fn eval2(&self, p: glam::DVec2) -> f64 {
                self.value(p)
            }
            fn eval3(&self, p: glam::DVec3) -> f64 {
                self.value(p)
            }
            fn eval_grad2(&self, p: glam::DVec2) -> (f64, glam::DVec2) {
                self.value_grad(p)
            }
            fn eval_grad3(&self, p: glam::DVec3) -> (f64, glam::DVec3) {
                self.value_grad(p)
            }
            fn bound(&self) -> f64 {
                self.bound_impl()
            }
            fn lipschitz2(&self) -> f64 {
                self.lipschitz_impl(self.basis.lipschitz2())
            }
            fn lipschitz3(&self) -> f64 {
                self.lipschitz_impl(self.basis.lipschitz3())
            }
            fn fill_row2_with(
                &self,
                simd: $crate::lattice_math::Simd,
                origin: glam::DVec2,
                step: f64,
                out: &mut [f32],
            ) {
                self.rows(simd, origin, step, out);
            }
            fn fill_row3_with(
                &self,
                simd: $crate::lattice_math::Simd,
                origin: glam::DVec3,
                step: f64,
                out: &mut [f32],
            ) {
                self.rows(simd, origin, step, out);
            }
            fn fill_rows2_with(
                &self,
                simd: $crate::lattice_math::Simd,
                x0: f64,
                ys: &[f64],
                step: f64,
                out: &mut [f32],
            ) {
                let rows = $crate::fractal::batch_rows::GridRows2 { x0, ys };
                self.rows(simd, rows, step, out);
            }
        }
    };
}
pub(crate) use multifractal;
