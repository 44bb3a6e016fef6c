//! Value noise: random values at the lattice points, interpolated.
//!
//! MojoWorld's "Linear" basis (Musgrave 2001, "Linear") is value noise with
//! linear interpolation ("linear interpolation of random offsets"): continuous
//! but creased along the lattice lines (not C¹). The smooth variants
//! interpolate with a fade. Unlike gradient noise it is not zero on the
//! lattice, and it adds the low-frequency power Lewis' variant is criticised
//! for (Musgrave 1993, §2.3.1). Lattice values are uniform in `[-1, 1)`, so the
//! values are within `[-1, 1]`.

use glam::{DVec2, DVec3, DVec4};
use natura_simd::multiversion;

use crate::basis::SPAN_MAX_STEP;
use crate::basis::lattice::lattice_sum;
use crate::basis::window::{
    WINDOW, WINDOW_COLUMNS, Window, row_windows, rows_windows, takes_windows, window_at,
};
use crate::basis::{Fade, row_in_fast_range};
use crate::field::{Field, fill_rows2_each, row_len};
use crate::hash::{corner, row2, row3, seed32, signed_unit};
use crate::lattice_math::{Simd, split_fast};
use natura_simd::lookup16;

/// How value noise interpolates across a cell.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum ValueInterp {
    /// Multilinear: MojoWorld's "Linear" basis, creased at cell faces. The default.
    #[default]
    Linear,
    /// Cubic fade (C¹).
    Cubic,
    /// Quintic fade (C²).
    Quintic,
}

impl ValueInterp {
    #[inline(always)]
    fn eval(self, t: f64) -> (f64, f64) {
        match self {
            ValueInterp::Linear => (t, 1.0),
            ValueInterp::Cubic => (Fade::Cubic.eval(t), Fade::Cubic.deriv(t)),
            ValueInterp::Quintic => (Fade::Quintic.eval(t), Fade::Quintic.deriv(t)),
        }
    }

    /// sup of the interpolant's derivative.
    fn max_slope(self) -> f64 {
        match self {
            ValueInterp::Linear => 1.0,
            ValueInterp::Cubic => 1.5,
            ValueInterp::Quintic => 1.875,
        }
    }
}

const SALT: u64 = 0x5641_4C55; // "VALU"

/// Value noise; unit lattice, values in `[-1, 1]`.
///
/// Lipschitz constant `2·√n·max fade'` (each axis' derivative is at most the
/// largest difference of two lattice values, 2, times the fade's slope).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Value {
    seed: u64,
    s: u32,
    interp: ValueInterp,
}

impl Default for Value {
    fn default() -> Self {
        Value::new(0)
    }
}

impl Value {
    /// Linearly interpolated value noise ("Linear" basis).
    #[must_use]
    pub const fn new(seed: u64) -> Self {
        Self::with_interp(seed, ValueInterp::Linear)
    }

    /// Value noise with the given interpolation.
    #[must_use]
    pub const fn with_interp(seed: u64, interp: ValueInterp) -> Self {
        Self {
            seed,
            s: seed32(seed, SALT),
            interp,
        }
    }

    /// The seed.
    #[must_use]
    pub const fn seed(&self) -> u64 {
        self.seed
    }

    fn sum<const N: usize>(&self, p: [f64; N]) -> (f64, [f64; N]) {
        let i = self.interp;
        lattice_sum::<N>(
            self.s,
            move |t| i.eval(t),
            p,
            |h, _| (f64::from(signed_unit(h)), [0.0; N]),
        )
    }

    /// The value and derivative at the 1-D point `x`.
    #[must_use]
    pub fn eval_grad1(&self, x: f64) -> (f64, f64) {
        let (v, g) = self.sum::<1>([x]);
        (v, g[0])
    }

    /// The value and gradient at the 4-D point `p`.
    #[must_use]
    pub fn eval_grad4(&self, p: DVec4) -> (f64, DVec4) {
        let (v, g) = self.sum::<4>(p.to_array());
        (v, DVec4::from_array(g))
    }

    fn lipschitz_n(&self, n: f64) -> f64 {
        2.0 * libm::sqrt(n) * self.interp.max_slope()
    }
}

impl Field for Value {
    fn eval2(&self, p: DVec2) -> f64 {
        self.sum::<2>(p.to_array()).0
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.sum::<3>(p.to_array()).0
    }
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        let (v, g) = self.sum::<2>(p.to_array());
        (v, DVec2::from_array(g))
    }
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        let (v, g) = self.sum::<3>(p.to_array());
        (v, DVec3::from_array(g))
    }
    fn bound(&self) -> f64 {
        1.0
    }
    fn lipschitz2(&self) -> f64 {
        self.lipschitz_n(2.0)
    }
    fn lipschitz3(&self) -> f64 {
        self.lipschitz_n(3.0)
    }

    fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
        if !fast_row2(origin.x, step, out.len(), origin.y) {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval2(DVec2::new(origin.x + i as f64 * step, origin.y)) as f32;
            }
            return;
        }
        let (rows, w) = self.row2_terms(origin.y);
        self.fill_row(simd, origin.x, step, out, &rows, &w);
    }

    fn fill_rows2_with(&self, simd: Simd, x0: f64, ys: &[f64], step: f64, out: &mut [f32]) {
        let Some(n) = row_len(out.len(), ys.len()) else {
            return;
        };
        // Rows on the window kernel share their groups' cells and fractions
        // (`rows_windows`); any other row is `fill_row2_with`'s.
        if !takes_windows(step, VALUE_WINDOW_MIN_STEP)
            || !ys.iter().all(|&y| fast_row2(x0, step, n, y))
        {
            fill_rows2_each(self, simd, x0, ys, step, out);
            return;
        }
        for (block, ys) in out.chunks_mut(MANY_ROWS * n).zip(ys.chunks(MANY_ROWS)) {
            // Each row's lattice rows and weights as `fill_row2_with` takes
            // them, the weights in f32 as `value_row_at` gives its windows.
            let terms: [([u32; 2], [f64; 2]); MANY_ROWS] =
                core::array::from_fn(|r| self.row2_terms(ys[r.min(ys.len() - 1)]));
            let rows = terms.map(|t| t.0);
            let w = terms.map(|(_, [a, b])| [a as f32, b as f32, 0.0, 0.0]);
            let m = ys.len();
            value_rows_at(
                simd,
                &rows[..m],
                &w[..m],
                self.interp,
                x0,
                step,
                &mut block[..m * n],
            );
        }
    }

    fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
        let yz_ok = origin.y.is_finite()
            && origin.z.is_finite()
            && origin.y.abs().max(origin.z.abs()) < 1e15;
        if !(row_in_fast_range(origin.x, step, out.len()) && yz_ok) {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval3(DVec3::new(origin.x + i as f64 * step, origin.y, origin.z)) as f32;
            }
            return;
        }
        let (iy, fy) = split_fast(origin.y);
        let (iz, fz) = split_fast(origin.z);
        let (v, w) = (self.interp.eval(fy).0, self.interp.eval(fz).0);
        let mut rows = [0u32; 4];
        for (c, r) in rows.iter_mut().enumerate() {
            *r = row3(
                iy.wrapping_add((c & 1) as u32),
                iz.wrapping_add((c >> 1) as u32),
                self.s,
            );
        }
        let wts = [(1.0 - v) * (1.0 - w), v * (1.0 - w), (1.0 - v) * w, v * w];
        self.fill_row(simd, origin.x, step, out, &rows, &wts);
    }
}

/// Whether the 2-D row of `n` points from `(x0, y)` at `step` takes the row
/// kernels (else the point path), for a row alone or in a grid's block.
#[inline]
fn fast_row2(x0: f64, step: f64, n: usize, y: f64) -> bool {
    row_in_fast_range(x0, step, n) && y.is_finite() && y.abs() < 1e15
}

impl Value {
    /// A 2-D row's two lattice rows (their hashes) and their weights at `y`.
    #[inline]
    fn row2_terms(&self, y: f64) -> ([u32; 2], [f64; 2]) {
        let (iy, fy) = split_fast(y);
        let v = self.interp.eval(fy).0;
        (
            [row2(iy, self.s), row2(iy.wrapping_add(1), self.s)],
            [1.0 - v, v],
        )
    }

    /// Row kernel: `N(fx) = A + interp(fx)·B` with per-cell `A`, `B` (the
    /// row-weighted lattice values of the cell's two x columns).
    fn fill_row(&self, simd: Simd, x0: f64, step: f64, out: &mut [f32], rows: &[u32], w: &[f64]) {
        value_row_at(simd, rows, w, self.interp, x0, step, out);
    }
}

multiversion! {
    /// [`Value::fill_row`]'s kernel compiled for `simd`'s instruction set (a
    /// named function: a closure handed to `run` is not always inlined into
    /// the level's `#[target_feature]` function).
    fn value_row_at<'a>(
        simd: Simd,
        rows: &'a [u32],
        w: &'a [f64],
        interp: ValueInterp,
        x0: f64,
        step: f64,
        out: &'a mut [f32],
    ) {
        // Span by span up to 1/32 cell a point (measured faster there than
        // the windows), window by window to 1 cell, then lane by lane.
        if takes_windows(step, VALUE_WINDOW_MIN_STEP) {
            let w32: [f32; 4] = core::array::from_fn(|k| w.get(k).copied().unwrap_or(0.0) as f32);
            match interp {
                ValueInterp::Linear => {
                    let v = ValueWindow { rows, w: w32, interp: linear32 };
                    row_windows(simd, &v, x0, step, out);
                }
                ValueInterp::Cubic => {
                    let v = ValueWindow { rows, w: w32, interp: crate::lattice_math::cubic32 };
                    row_windows(simd, &v, x0, step, out);
                }
                ValueInterp::Quintic => {
                    let v = ValueWindow { rows, w: w32, interp: crate::lattice_math::quintic32 };
                    row_windows(simd, &v, x0, step, out);
                }
            }
            return;
        }
        let cell = |ix: u32| {
            let (mut a, mut b) = (0.0, 0.0);
            for (r, wt) in rows.iter().zip(w) {
                a += wt * f64::from(signed_unit(corner(ix, *r)));
                b += wt * f64::from(signed_unit(corner(ix.wrapping_add(1), *r)));
            }
            (a, b - a)
        };
        if step > 0.0 && step <= SPAN_MAX_STEP {
            let n = out.len();
            let s32 = step as f32;
            let mut i = 0;
            while i < n {
                let (ix, fx) = split_fast(x0 + i as f64 * step);
                let count = (libm::ceil((1.0 - fx) / step) as usize).clamp(1, n - i);
                let (a, b) = cell(ix);
                let (a, b, t0) = (a as f32, b as f32, fx as f32);
                let span = &mut out[i..i + count];
                match interp {
                    ValueInterp::Linear => {
                        for (k, o) in span.iter_mut().enumerate() {
                            *o = a + b * (t0 + (k as i32) as f32 * s32);
                        }
                    }
                    ValueInterp::Cubic => {
                        for (k, o) in span.iter_mut().enumerate() {
                            *o = a + b * crate::lattice_math::cubic32(t0 + (k as i32) as f32 * s32);
                        }
                    }
                    ValueInterp::Quintic => {
                        for (k, o) in span.iter_mut().enumerate() {
                            *o = a + b * crate::lattice_math::quintic32(t0 + (k as i32) as f32 * s32);
                        }
                    }
                }
                i += count;
            }
        } else {
            let w32: [f32; 4] = core::array::from_fn(|k| w.get(k).copied().unwrap_or(0.0) as f32);
            let nr = rows.len();
            for (i, o) in out.iter_mut().enumerate() {
                let (ix, fx) = split_fast(x0 + (i as i32) as f64 * step);
                let fx = fx as f32;
                let u = match interp {
                    ValueInterp::Linear => fx,
                    ValueInterp::Cubic => crate::lattice_math::cubic32(fx),
                    ValueInterp::Quintic => crate::lattice_math::quintic32(fx),
                };
                let mut acc = 0.0f32;
                for r in 0..nr {
                    let a = signed_unit(corner(ix, rows[r]));
                    let b = signed_unit(corner(ix.wrapping_add(1), rows[r]));
                    acc += w32[r] * (a + u * (b - a));
                }
                *o = acc;
            }
        }
    }
}

/// Value noise rows go window by window above this step (cells a point).
const VALUE_WINDOW_MIN_STEP: f64 = 1.0 / 32.0;

/// Rows [`Value`]'s `fill_rows2_with` evaluates together.
const MANY_ROWS: usize = 8;

multiversion! {
    /// Rows of a 2-D grid window by window (`WINDOW_MIN_STEP < step ≤ 1`,
    /// from [`VALUE_WINDOW_MIN_STEP`]), row `r` from its lattice rows'
    /// hashes `rows[r]` and weights `w[r]` (at most [`MANY_ROWS`] rows),
    /// their groups' cells and fractions shared.
    fn value_rows_at<'a>(
        simd: Simd,
        rows: &'a [[u32; 2]],
        w: &'a [[f32; 4]],
        interp: ValueInterp,
        x0: f64,
        step: f64,
        out: &'a mut [f32],
    ) {
        let m = rows.len();
        let window = |r: usize| (&rows[r.min(m - 1)][..], w[r.min(m - 1)]);
        match interp {
            ValueInterp::Linear => {
                let ws: [ValueWindow<'_, _>; MANY_ROWS] = core::array::from_fn(|r| {
                    let (rows, w) = window(r);
                    ValueWindow { rows, w, interp: linear32 }
                });
                rows_windows(simd, &ws[..m], x0, step, out);
            }
            ValueInterp::Cubic => {
                let ws: [ValueWindow<'_, _>; MANY_ROWS] = core::array::from_fn(|r| {
                    let (rows, w) = window(r);
                    ValueWindow { rows, w, interp: crate::lattice_math::cubic32 }
                });
                rows_windows(simd, &ws[..m], x0, step, out);
            }
            ValueInterp::Quintic => {
                let ws: [ValueWindow<'_, _>; MANY_ROWS] = core::array::from_fn(|r| {
                    let (rows, w) = window(r);
                    ValueWindow { rows, w, interp: crate::lattice_math::quintic32 }
                });
                rows_windows(simd, &ws[..m], x0, step, out);
            }
        }
    }
}

/// The linear interpolation's weight: the fraction itself.
#[inline(always)]
fn linear32(t: f32) -> f32 {
    t
}

/// Value noise's side of [`row_windows`]: each lattice column's value, the
/// row-weighted lattice values of its corner rows; a lane interpolates
/// between its cell's two columns (the same function as the lane kernel's,
/// re-associated).
struct ValueWindow<'a, F> {
    rows: &'a [u32],
    w: [f32; 4],
    interp: F,
}

/// The one table: each column's value.
impl<F: Fn(f32) -> f32> Window<1> for ValueWindow<'_, F> {
    type Shared = ();

    #[inline(always)]
    fn shared(&self) {}

    #[inline(always)]
    fn columns(&self, first: u32, n: usize, tables: &mut [[f32; WINDOW_COLUMNS]; 1]) {
        let v = &mut tables[0][..n];
        v.fill(0.0);
        // One pass per corner row: plain loops that vectorise.
        for (&r, &w) in self.rows.iter().zip(&self.w) {
            for (i, v) in v.iter_mut().enumerate() {
                *v += w * signed_unit(corner(first.wrapping_add(i as u32), r));
            }
        }
    }

    #[inline(always)]
    fn group(
        &self,
        simd: Simd,
        tables: &[[f32; WINDOW_COLUMNS]; 1],
        cell: usize,
        index: &[u32; WINDOW],
        t: &[f32; WINDOW],
    ) -> [f32; WINDOW] {
        let (l, r) = (window_at(&tables[0], cell), window_at(&tables[0], cell + 1));
        let [a, b] = lookup16(simd, [&l, &r], index);
        let mut v = [0.0f32; WINDOW];
        for k in 0..WINDOW {
            v[k] = a[k] + (self.interp)(t[k]) * (b[k] - a[k]);
        }
        v
    }
}
