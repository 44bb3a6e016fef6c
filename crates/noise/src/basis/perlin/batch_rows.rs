//! Batch rows of [`Perlin`] noise (f32 lanes, compiled per SIMD level
//! through natura-simd's dispatch).
//!
//! Three kernels by the row's step (lattice cells per point):
//!
//! - up to 1/64, span by span: four coefficients per cell, each lattice
//!   column hashed once per row, whole 16-lane groups (the 3-D grid fill
//!   caches the columns' gradients across rows);
//! - up to 1, window by window ([`row_windows`], with [`PerlinWindow`]):
//!   each lattice column hashed once per row into two terms, and every
//!   16-point group, which spans at most 16 cells, looks its lanes' columns
//!   up by permutes (`natura_simd::lookup16`);
//! - beyond, a per-lane kernel whose 32-point blocks are rebased to a local
//!   origin (one f64 split per block, then f32/u32 lanes from precomputed
//!   lane offsets), so lattice indices stay exact at planet-scale
//!   coordinates while every lane runs at the full f32 width.
//!
//! All equal the f64 point path within 1e-5. The corner hashes and
//! gradients are the point path's ([`corner`], [`grad2`], [`grad3`]).

use glam::{DVec2, DVec3};
use natura_simd::multiversion;

use super::Perlin;
use crate::basis::window::{
    WINDOW, WINDOW_COLUMNS, WINDOW_MIN_STEP, Window, row_windows, rows_windows, takes_windows,
    window_at,
};
use crate::basis::{Fade, SPAN_MAX_STEP, row_in_fast_range, with_fade32};
use crate::field::{Field, Lattice3, fill_rows2_each, row_len};
use crate::hash::{corner, grad2, grad3, row2, row3};
use crate::lattice_math::{BLOCK, LaneOffsets, Real, Simd, rebase, split_fast};
use natura_simd::lookup16;

impl Perlin {
    /// The 2-D row fill behind [`Field::fill_row2_with`].
    pub(crate) fn rows2(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
        if !fast_row2(origin.x, step, out.len(), origin.y) {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval2(DVec2::new(origin.x + i as f64 * step, origin.y)) as f32;
            }
            return;
        }
        let rows = RowCoeffs::new2(self.lattice_seed(), self.fade(), origin.y);
        let k = self.scale(2);
        let fade = self.fade();
        row_at::<false>(simd, &rows, fade, origin.x, step, k, out);
    }

    /// The 2-D rows fill behind [`Field::fill_rows2_with`]: rows that take
    /// the window kernel share their groups' cells and fractions
    /// ([`rows_windows`]); any other row is [`Perlin::rows2`]'s.
    pub(crate) fn rows2_many(&self, simd: Simd, x0: f64, ys: &[f64], step: f64, out: &mut [f32]) {
        let Some(n) = row_len(out.len(), ys.len()) else {
            return;
        };
        if RowKernel::of(step) != RowKernel::Windows
            || !ys.iter().all(|&y| fast_row2(x0, step, n, y))
        {
            fill_rows2_each(self, simd, x0, ys, step, out);
            return;
        }
        let (seed, fade, k) = (self.lattice_seed(), self.fade(), self.scale(2));
        for (block, ys) in out.chunks_mut(MANY_ROWS * n).zip(ys.chunks(MANY_ROWS)) {
            let coeffs: [RowCoeffs; MANY_ROWS] =
                core::array::from_fn(|r| RowCoeffs::new2(seed, fade, ys[r.min(ys.len() - 1)]));
            let rows = ys.len();
            rows2_windows_at(
                simd,
                &coeffs[..rows],
                fade,
                x0,
                step,
                k,
                &mut block[..rows * n],
            );
        }
    }

    /// The 3-D row fill behind [`Field::fill_row3_with`].
    pub(crate) fn rows3(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
        let bad_yz = !origin.y.is_finite()
            || !origin.z.is_finite()
            || origin.y.abs() > 1e15
            || origin.z.abs() > 1e15;
        if !row_in_fast_range(origin.x, step, out.len()) || bad_yz {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval3(DVec3::new(origin.x + i as f64 * step, origin.y, origin.z)) as f32;
            }
            return;
        }
        let rows = RowCoeffs::new3(self.lattice_seed(), self.fade(), origin.y, origin.z);
        let k = self.scale(3);
        let fade = self.fade();
        row_at::<true>(simd, &rows, fade, origin.x, step, k, out);
    }
}

// The row kernels compiled per SIMD level. Named functions rather than
// closures: a closure handed to `run` is not always inlined into the
// level's `#[target_feature]` function (it depends on the build's inlining
// budget), and then it runs at the baseline level.

multiversion! {
    /// A 2-D (`D3` false) or 3-D row from its row constants: span by span
    /// for small steps, else lane by lane.
    fn row_at<'a, const D3: bool>(
        simd: Simd,
        rows: &'a RowCoeffs,
        fade: Fade,
        x0: f64,
        step: f64,
        k: f64,
        out: &'a mut [f32],
    ) {
        match (RowKernel::of(step), D3) {
            (RowKernel::Windows, false) => with_fade32!(fade, |f| {
                let w = PerlinWindow::<false, _> { rows, k: k as f32, fade: f };
                row_windows(simd, &w, x0, step, out);
            }),
            (RowKernel::Windows, true) => with_fade32!(fade, |f| {
                let w = PerlinWindow::<true, _> { rows, k: k as f32, fade: f };
                row_windows(simd, &w, x0, step, out);
            }),
            (RowKernel::Spans, false) => row_spans(fade, x0, step, k, out, |ix| rows.column2(ix)),
            (RowKernel::Spans, true) => row_spans(fade, x0, step, k, out, |ix| rows.column3(ix)),
            (RowKernel::Lanes, false) => {
                with_fade32!(fade, |f| perlin2_row(f, rows, x0, step, k as f32, out));
            }
            (RowKernel::Lanes, true) => {
                with_fade32!(fade, |f| perlin3_row(f, rows, x0, step, k as f32, out));
            }
        }
    }
}

multiversion! {
    /// A 3-D grid row span by span, its columns from `cache`.
    #[allow(clippy::too_many_arguments)]
    fn grid3_row_at<'a>(
        simd: Simd,
        cache: &'a ColumnCache3,
        rows: &'a RowCoeffs,
        fade: Fade,
        x0: f64,
        step: f64,
        k: f64,
        out: &'a mut [f32],
    ) {
        row_spans(fade, x0, step, k, out, |ix| cache.column(rows, ix));
    }
}

/// Whether the 2-D row of `n` points from `(x0, y)` at `step` takes the row
/// kernels (else the point path): the one test [`Perlin::rows2`] and
/// [`Perlin::rows2_many`] share, so a grid's rows equal the row fill.
#[inline]
fn fast_row2(x0: f64, step: f64, n: usize, y: f64) -> bool {
    row_in_fast_range(x0, step, n) && y.is_finite() && y.abs() <= 1e15
}

multiversion! {
    /// Rows of a 2-D grid window by window, one row per entry of `coeffs`
    /// (at most [`MANY_ROWS`]), their groups' cells and fractions shared.
    fn rows2_windows_at<'a>(
        simd: Simd,
        coeffs: &'a [RowCoeffs],
        fade: Fade,
        x0: f64,
        step: f64,
        k: f64,
        out: &'a mut [f32],
    ) {
        with_fade32!(fade, |f| {
            let windows: [PerlinWindow<'_, false, _>; MANY_ROWS] =
                core::array::from_fn(|r| PerlinWindow {
                    rows: &coeffs[r.min(coeffs.len() - 1)],
                    k: k as f32,
                    fade: f,
                });
            rows_windows(simd, &windows[..coeffs.len()], x0, step, out);
        });
    }
}

/// Rows [`Perlin::rows2_many`] evaluates together.
const MANY_ROWS: usize = 8;

/// The kernel a row of spacing `step` (lattice cells per point) takes, the
/// one decision [`row_at`] and the 3-D grid fill's column cache share.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RowKernel {
    /// [`row_spans`]: up to [`WINDOW_MIN_STEP`].
    Spans,
    /// [`row_windows`]: up to `WINDOW_MAX_STEP`.
    Windows,
    /// [`perlin2_row`] or [`perlin3_row`]: beyond.
    Lanes,
}

impl RowKernel {
    #[inline(always)]
    fn of(step: f64) -> Self {
        if takes_windows(step, WINDOW_MIN_STEP) {
            Self::Windows
        } else if step > 0.0 && step <= SPAN_MAX_STEP {
            Self::Spans
        } else {
            Self::Lanes
        }
    }
}

/// Per-row constants of a 2-D or 3-D gradient-noise row: the fractional y/z,
/// their fade weights and the row hashes of the 2 (2-D) or 4 (3-D) lattice rows.
pub(crate) struct RowCoeffs {
    /// Fractional y and z.
    fy: f64,
    fz: f64,
    /// Fade weights of the corner rows, ordered (cy, cz) = (0,0), (1,0), (0,1), (1,1).
    w: [f64; 4],
    /// Row hashes in the same order.
    r: [u32; 4],
    /// f32 copies for the lane kernels.
    fy32: f32,
    fz32: f32,
    w32: [f32; 4],
}

impl RowCoeffs {
    pub(crate) fn new2(seed: u32, fade: Fade, y: f64) -> Self {
        let (iy, fy) = split_fast(y);
        let v = fade.eval(fy);
        let w = [1.0 - v, v, 0.0, 0.0];
        let r = [row2(iy, seed), row2(iy.wrapping_add(1), seed), 0, 0];
        Self {
            fy,
            fz: 0.0,
            w,
            r,
            fy32: fy as f32,
            fz32: 0.0,
            w32: w.map(|x| x as f32),
        }
    }

    pub(crate) fn new3(seed: u32, fade: Fade, y: f64, z: f64) -> Self {
        let (iy, fy) = split_fast(y);
        let (iz, fz) = split_fast(z);
        let v = fade.eval(fy);
        let ww = fade.eval(fz);
        let w = [
            (1.0 - v) * (1.0 - ww),
            v * (1.0 - ww),
            (1.0 - v) * ww,
            v * ww,
        ];
        let mut r = [0u32; 4];
        for (c, rc) in r.iter_mut().enumerate() {
            *rc = row3(
                iy.wrapping_add((c & 1) as u32),
                iz.wrapping_add((c >> 1) as u32),
                seed,
            );
        }
        Self {
            fy,
            fz,
            w,
            r,
            fy32: fy as f32,
            fz32: fz as f32,
            w32: w.map(|x| x as f32),
        }
    }

    /// The lattice column `ix` of a 2-D row: `[Σ w·g_y·dy, Σ w·g_x]` over the
    /// two corner rows (unscaled). A cell's span coefficients follow from its
    /// two columns ([`span_coeffs`]), so each column is hashed once per row.
    #[inline(always)]
    fn column2(&self, ix: u32) -> [f64; 2] {
        let mut c = [0.0; 2];
        for cy in 0..2 {
            let dy = self.fy - cy as f64;
            let w = self.w[cy];
            let (gx, gy) = grad2(corner(ix, self.r[cy]));
            c[1] += w * f64::from(gx);
            c[0] += w * f64::from(gy) * dy;
        }
        c
    }

    /// [`column2`](Self::column2) in `f32`, scaled by `k`.
    #[inline(always)]
    fn column2_32(&self, ix: u32, k: f32) -> [f32; 2] {
        let (w, fy) = (self.w32, self.fy32);
        let (gx0, gy0) = grad2(corner(ix, self.r[0]));
        let (gx1, gy1) = grad2(corner(ix, self.r[1]));
        [
            (w[0] * (gy0 * fy) + w[1] * (gy1 * (fy - 1.0))) * k,
            (w[0] * gx0 + w[1] * gx1) * k,
        ]
    }

    /// [`column3`](Self::column3) in `f32`, scaled by `k`, for the lattice
    /// columns `first, first + 1, …` into `a` (the fraction-independent
    /// terms) and `b` (the x-gradient terms): one pass over the columns per
    /// corner row, each a plain loop that vectorises.
    #[inline(always)]
    fn columns3_32(&self, first: u32, k: f32, a: &mut [f32], b: &mut [f32]) {
        let (w, fy, fz) = (self.w32, self.fy32, self.fz32);
        a.fill(0.0);
        b.fill(0.0);
        for (j, (&wj, &r)) in w.iter().zip(&self.r).enumerate() {
            let dy = fy - (j & 1) as f32;
            let dz = fz - (j >> 1) as f32;
            for (i, (a, b)) in a.iter_mut().zip(b.iter_mut()).enumerate() {
                let (gx, gy, gz) = grad3(corner(first.wrapping_add(i as u32), r));
                *b += wj * gx;
                *a += wj * (gy * dy + gz * dz);
            }
        }
        for (a, b) in a.iter_mut().zip(b.iter_mut()) {
            *a *= k;
            *b *= k;
        }
    }

    /// As [`column2`](Self::column2) for the 3-D row (four corner rows).
    #[inline(always)]
    fn column3(&self, ix: u32) -> [f64; 2] {
        self.column3_from(|k| grad3(corner(ix, self.r[k])))
    }

    /// [`column3`](Self::column3) with the four corner gradients (corner row
    /// `k`) supplied by `grad`, e.g. from a [`ColumnCache3`].
    #[inline(always)]
    fn column3_from(&self, grad: impl Fn(usize) -> (f32, f32, f32)) -> [f64; 2] {
        let mut c = [0.0; 2];
        for k in 0..4 {
            let dy = self.fy - (k & 1) as f64;
            let dz = self.fz - (k >> 1) as f64;
            let w = self.w[k];
            let (gx, gy, gz) = grad(k);
            c[1] += w * f64::from(gx);
            c[0] += w * (f64::from(gy) * dy + f64::from(gz) * dz);
        }
        c
    }
}

/// Most lattice columns a row may span for [`Perlin`]'s 3-D grid fill to
/// cache their gradients (wider rows are filled row by row).
const CACHE_COLUMNS: usize = 64;

/// The corner gradients of a 3-D grid row's lattice columns, kept while
/// successive rows share the same four corner rows: at low frequency many
/// rows (20 × 20 at 0.05 cells per sample) fall between the same lattice
/// planes, so their columns are hashed once instead of once per row.
struct ColumnCache3 {
    /// Row hashes the gradients belong to (`None`: empty).
    key: Option<[u32; 4]>,
    /// Lattice index of column 0.
    first: u32,
    /// Columns held.
    len: usize,
    /// `grads[c][k]`: gradient of column `first + c` on corner row `k`.
    grads: [[(f32, f32, f32); 4]; CACHE_COLUMNS],
}

impl ColumnCache3 {
    /// Makes the cache hold the columns of `rows`, rehashing only when the
    /// corner rows changed.
    fn update(&mut self, rows: &RowCoeffs) {
        if self.key != Some(rows.r) {
            for (c, g) in self.grads[..self.len].iter_mut().enumerate() {
                let ix = self.first.wrapping_add(c as u32);
                *g = core::array::from_fn(|k| grad3(corner(ix, rows.r[k])));
            }
            self.key = Some(rows.r);
        }
    }

    /// The column `ix` of the row `rows` (as [`RowCoeffs::column3`]), from the
    /// cache when it holds it.
    #[inline(always)]
    fn column(&self, rows: &RowCoeffs, ix: u32) -> [f64; 2] {
        match self.grads[..self.len].get(ix.wrapping_sub(self.first) as usize) {
            Some(g) => rows.column3_from(|k| g[k]),
            None => rows.column3(ix),
        }
    }
}

impl Perlin {
    /// The 3-D lattice fill behind [`Field::fill_grid3`]: low-frequency rows
    /// go span by span with their column gradients cached across rows
    /// ([`ColumnCache3`]); the values are bit-identical to filling each row
    /// with [`Field::fill_row3_with`].
    pub(crate) fn grid3(
        &self,
        simd: Simd,
        lattice: &Lattice3,
        out: &mut [f32],
    ) -> crate::Result<()> {
        lattice.check(out.len())?;
        let (x0, step, nx) = (lattice.origin.x, lattice.step.x, lattice.nx);
        let spans = RowKernel::of(step) == RowKernel::Spans;
        let columns = if spans && row_in_fast_range(x0, step, nx) {
            let (first, _) = split_fast(x0);
            let (last, _) = split_fast(x0 + (nx - 1) as f64 * step);
            Some((first, last.wrapping_sub(first) as usize + 2))
        } else {
            None
        };
        let Some((first, len)) = columns.filter(|&(_, len)| len <= CACHE_COLUMNS) else {
            for (r, row) in out.chunks_exact_mut(nx).enumerate() {
                self.fill_row3_with(
                    simd,
                    lattice.row_origin(r % lattice.ny, r / lattice.ny),
                    step,
                    row,
                );
            }
            return Ok(());
        };
        let mut cache = ColumnCache3 {
            key: None,
            first,
            len,
            grads: [[(0.0, 0.0, 0.0); 4]; CACHE_COLUMNS],
        };
        let k = self.scale(3);
        let fade = self.fade();
        for (r, row) in out.chunks_exact_mut(nx).enumerate() {
            let origin = lattice.row_origin(r % lattice.ny, r / lattice.ny);
            if !origin.y.is_finite()
                || !origin.z.is_finite()
                || origin.y.abs() > 1e15
                || origin.z.abs() > 1e15
            {
                self.fill_row3_with(simd, origin, step, row);
                continue;
            }
            let rows = RowCoeffs::new3(self.lattice_seed(), fade, origin.y, origin.z);
            cache.update(&rows);
            grid3_row_at(simd, &cache, &rows, fade, x0, step, k, row);
        }
        Ok(())
    }
}

/// Coefficients `(a0, a1, b0, b1)` with `N(fx) = a0 + a1·fx + fade(fx)·(b0 + b1·fx)`
/// over the cell between lattice columns `left` and `right` (see
/// [`RowCoeffs::column2`]): the left corners give `a0 + a1·fx`, the right ones
/// `c1·(fx − 1) + c0`, and the fade blends them.
/// In `f64` for the spans, in `f32` for the windows' lanes.
#[inline(always)]
fn span_coeffs<R: Real>(left: [R; 2], right: [R; 2]) -> [R; 4] {
    let c0 = right[0] - right[1];
    [left[0], left[1], c0 - left[0], right[1] - left[1]]
}

/// Evaluates a low-frequency row cell by cell: within one lattice cell the row
/// is `a0 + a1·t + fade(t)·(b0 + b1·t)` in the fractional coordinate `t`, with
/// the four coefficients computed once per cell (hoisting all hashing out of
/// the per-point loop). The same function as the point path, re-associated.
///
/// The lattice columns of up to [`SPAN_CELLS`] consecutive cells are hashed
/// once each (`column(ix)`, shared by the two cells they bound), and each cell's points are
/// written in whole groups of [`SPAN_GROUP`] lanes: a group that runs past the
/// cell's end writes values the next cell then overwrites, so no scalar
/// remainder loop runs per cell.
#[inline(always)]
pub(crate) fn row_spans(
    fade: Fade,
    x0: f64,
    step: f64,
    scale: f64,
    out: &mut [f32],
    column: impl Fn(u32) -> [f64; 2],
) {
    let n = out.len();
    let s32 = step as f32;
    // The row's last cell (the batch kernels only run on rows inside the
    // fast-split range, so this index arithmetic is exact).
    let (last, _) = split_fast(x0 + (n - 1) as f64 * step);
    let mut table = [[0.0f32; 4]; SPAN_CELLS];
    let mut base = 0u32;
    let mut filled = 0usize;
    with_fade32!(fade, |f| {
        let mut i = 0usize;
        while i < n {
            let x = x0 + i as f64 * step;
            let (ix, fx) = split_fast(x);
            let count = (libm::ceil((1.0 - fx) / step) as usize).clamp(1, n - i);
            let mut slot = ix.wrapping_sub(base) as usize;
            if slot >= filled {
                base = ix;
                slot = 0;
                filled = (last.wrapping_sub(ix) as usize)
                    .saturating_add(1)
                    .min(SPAN_CELLS);
                let mut cols = [[0.0f64; 2]; SPAN_CELLS + 1];
                for (c, col) in cols[..=filled].iter_mut().enumerate() {
                    *col = column(ix.wrapping_add(c as u32));
                }
                for (c, t) in table[..filled].iter_mut().enumerate() {
                    *t = span_coeffs(cols[c], cols[c + 1]).map(|v| (v * scale) as f32);
                }
            }
            let c = table[slot];
            let t0 = fx as f32;
            let poly = |k: usize| {
                let t = t0 + (k as i32) as f32 * s32;
                (c[0] + c[1] * t) + f(t) * (c[2] + c[3] * t)
            };
            let mut g = 0usize;
            while g < count {
                let at = i + g;
                if at + SPAN_GROUP <= n {
                    let group: &mut [f32; SPAN_GROUP] =
                        (&mut out[at..at + SPAN_GROUP]).try_into().unwrap();
                    for (k, o) in group.iter_mut().enumerate() {
                        *o = poly(g + k);
                    }
                } else {
                    for (k, o) in out[at..].iter_mut().enumerate() {
                        *o = poly(g + k);
                    }
                }
                g += SPAN_GROUP;
            }
            i += count;
        }
    });
}

/// Cells whose span coefficients [`row_spans`] computes in one batch.
const SPAN_CELLS: usize = 32;

/// Points [`row_spans`] writes per group (one AVX-512 vector, two AVX2 ones).
const SPAN_GROUP: usize = 16;

/// Perlin noise's side of [`row_windows`]: the two terms of each lattice
/// column of a 2-D (`D3` false) or 3-D row ([`RowCoeffs::column2`] or
/// [`RowCoeffs::column3`], scaled by `k`, in `f32`); a lane forms its cell's
/// [`span_coeffs`] from its two columns and evaluates the cell's polynomial
/// at its fraction.
struct PerlinWindow<'a, const D3: bool, F> {
    rows: &'a RowCoeffs,
    k: f32,
    fade: F,
}

/// Tables: per column, the fraction-independent term and the x-gradient term.
impl<const D3: bool, F: Fn(f32) -> f32> Window<2> for PerlinWindow<'_, D3, F> {
    type Shared = LatticeRows;

    #[inline(always)]
    fn shared(&self) -> LatticeRows {
        LatticeRows {
            key: [None; 2],
            g: [[[0.0; WINDOW_COLUMNS]; 2]; 2],
        }
    }

    /// 2-D: a row's two lattice rows' corner gradients, kept for the next
    /// rows of the grid (a row's upper lattice row is often the next row's
    /// lower one, or both are the same), then combined with the row's own
    /// fraction and weights exactly as [`RowCoeffs::column2_32`] does.
    #[inline(always)]
    fn columns_shared(
        &self,
        first: u32,
        n: usize,
        shared: &mut LatticeRows,
        tables: &mut [[f32; WINDOW_COLUMNS]; 2],
    ) {
        if D3 {
            self.columns(first, n, tables);
            return;
        }
        let rows = [self.rows.r[0], self.rows.r[1]];
        let slot = shared.fill(rows, first, n);
        let (w, fy, k) = (self.rows.w32, self.rows.fy32, self.k);
        let [g0, g1] = [&shared.g[slot[0]], &shared.g[slot[1]]];
        let [a, b] = tables;
        for i in 0..n {
            let (gx0, gy0, gx1, gy1) = (g0[0][i], g0[1][i], g1[0][i], g1[1][i]);
            a[i] = (w[0] * (gy0 * fy) + w[1] * (gy1 * (fy - 1.0))) * k;
            b[i] = (w[0] * gx0 + w[1] * gx1) * k;
        }
    }

    #[inline(always)]
    fn columns(&self, first: u32, n: usize, tables: &mut [[f32; WINDOW_COLUMNS]; 2]) {
        let [a, b] = tables;
        let (a, b) = (&mut a[..n], &mut b[..n]);
        if D3 {
            self.rows.columns3_32(first, self.k, a, b);
        } else {
            for (i, (a, b)) in a.iter_mut().zip(b).enumerate() {
                [*a, *b] = self.rows.column2_32(first.wrapping_add(i as u32), self.k);
            }
        }
    }

    #[inline(always)]
    fn group(
        &self,
        simd: Simd,
        tables: &[[f32; WINDOW_COLUMNS]; 2],
        cell: usize,
        index: &[u32; WINDOW],
        t: &[f32; WINDOW],
    ) -> [f32; WINDOW] {
        let [a, b] = tables;
        let (a0, b0) = (window_at(a, cell), window_at(b, cell));
        let (a1, b1) = (window_at(a, cell + 1), window_at(b, cell + 1));
        let [la, lb, ra, rb] = lookup16(simd, [&a0, &b0, &a1, &b1], index);
        let mut v = [0.0f32; WINDOW];
        for l in 0..WINDOW {
            let c = span_coeffs([la[l], lb[l]], [ra[l], rb[l]]);
            let t = t[l];
            v[l] = (c[0] + c[1] * t) + (self.fade)(t) * (c[2] + c[3] * t);
        }
        v
    }
}

/// Two lattice rows' corner gradients along a chunk's columns: slot `s`
/// holds row hash `key[s]`'s `(gx, gy)` for columns `first..first + n`.
pub(crate) struct LatticeRows {
    key: [Option<u32>; 2],
    g: [[[f32; WINDOW_COLUMNS]; 2]; 2],
}

impl LatticeRows {
    /// The slots holding lattice rows `rows` (hashes), computing those not
    /// held (into the slot the other row does not need).
    #[inline(always)]
    fn fill(&mut self, rows: [u32; 2], first: u32, n: usize) -> [usize; 2] {
        let mut slot = [0usize; 2];
        for (j, &r) in rows.iter().enumerate() {
            let held = self.key.iter().position(|&k| k == Some(r));
            slot[j] = match held {
                Some(s) => s,
                None => {
                    // Not the slot the pair's other row sits in (or will).
                    let s = if j == 1 {
                        1 - slot[0]
                    } else {
                        usize::from(self.key[0] == Some(rows[1]))
                    };
                    let [gx, gy] = &mut self.g[s];
                    for i in 0..n {
                        (gx[i], gy[i]) = grad2(corner(first.wrapping_add(i as u32), r));
                    }
                    self.key[s] = Some(r);
                    s
                }
            };
        }
        slot
    }
}

/// The general 2-D row kernel: every lane finds its own cell.
#[inline(always)]
fn perlin2_row(
    fade: impl Fn(f32) -> f32,
    rows: &RowCoeffs,
    x0: f64,
    step: f64,
    k: f32,
    out: &mut [f32],
) {
    let (r0, r1) = (rows.r[0], rows.r[1]);
    let fy = rows.fy32;
    let fy1 = fy - 1.0;
    let v = rows.w32[1];
    let lanes = LaneOffsets::new(step);
    for (b, block) in out.chunks_mut(BLOCK).enumerate() {
        let (bi, bf) = LaneOffsets::base(x0 + (b * BLOCK) as f64 * step);
        for ((o, &cell), &frac) in block.iter_mut().zip(&lanes.cell).zip(&lanes.frac) {
            let (ix, fx) = rebase(bi, bf, cell, frac);
            let fx1 = fx - 1.0;
            let ix1 = ix.wrapping_add(1);
            let d = |h: u32, x: f32, y: f32| {
                let (gx, gy) = grad2(h);
                gx * x + gy * y
            };
            let n00 = d(corner(ix, r0), fx, fy);
            let n10 = d(corner(ix1, r0), fx1, fy);
            let n01 = d(corner(ix, r1), fx, fy1);
            let n11 = d(corner(ix1, r1), fx1, fy1);
            let u = fade(fx);
            let a = n00 + u * (n10 - n00);
            let b = n01 + u * (n11 - n01);
            *o = (a + v * (b - a)) * k;
        }
    }
}

/// The general 3-D row kernel.
#[inline(always)]
fn perlin3_row(
    fade: impl Fn(f32) -> f32,
    rows: &RowCoeffs,
    x0: f64,
    step: f64,
    k: f32,
    out: &mut [f32],
) {
    let (fy, fz) = (rows.fy32, rows.fz32);
    let dy = [fy, fy - 1.0, fy, fy - 1.0];
    let dz = [fz, fz, fz - 1.0, fz - 1.0];
    let w = rows.w32;
    let r = rows.r;
    let lanes = LaneOffsets::new(step);
    for (b, block) in out.chunks_mut(BLOCK).enumerate() {
        let (bi, bf) = LaneOffsets::base(x0 + (b * BLOCK) as f64 * step);
        for ((o, &cell), &frac) in block.iter_mut().zip(&lanes.cell).zip(&lanes.frac) {
            let (ix, fx) = rebase(bi, bf, cell, frac);
            let fx1 = fx - 1.0;
            let ix1 = ix.wrapping_add(1);
            let u = fade(fx);
            let mut acc = 0.0f32;
            for c in 0..4 {
                let (ax, ay, az) = grad3(corner(ix, r[c]));
                let (bx, by, bz) = grad3(corner(ix1, r[c]));
                let n0 = ax * fx + ay * dy[c] + az * dz[c];
                let n1 = bx * fx1 + by * dy[c] + bz * dz[c];
                acc += w[c] * (n0 + u * (n1 - n0));
            }
            *o = acc * k;
        }
    }
}
