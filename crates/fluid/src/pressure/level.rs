//! One grid level of the pressure Poisson operator, stored padded with a
//! ghost layer on every non-flat axis so stencils never branch on borders:
//! the geometry, the coupling masks and diagonals, the work vectors, and the
//! level-wide passes (operator, residual, red–black smoothing, reductions)
//! that run the row equations of [`super::operator`] through the SIMD
//! kernels of [`super::kernels`] over the rows in parallel.

use super::kernels::{ApplyRow, GsRow, ResidualRow};
use super::operator::{self, Real, lane_dot, lane_sum};
use crate::chunks;
use crate::grid::{Boundaries, CellKind, Side};
use natura_core::simd::{self, Simd};

/// Leading guard element so that `row_base − 1` is always a valid index.
pub(crate) const GUARD: usize = 1;

/// A level of the operator: geometry, coupling masks and work vectors.
#[derive(Clone, Debug)]
pub(crate) struct Level {
    /// Cells per axis (unpadded).
    pub n: [usize; 3],
    /// Padded sizes (`n + 2` on active axes, 1 on flat axes).
    pub m: [usize; 3],
    /// Padding per axis (1 on active axes).
    pub pad: [usize; 3],
    /// Strides of the padded array.
    pub stride: [usize; 3],
    /// Active axes in order.
    pub active: Vec<usize>,
    /// Periodic per axis.
    pub periodic: [bool; 3],
    /// Per padded cell: bit `2q`/`2q+1` = coupling to the −/+ neighbour along
    /// the q-th active axis; bits 8.. = diagonal (non-solid neighbour count).
    pub mask: Vec<u16>,
    /// Unpadded cell kinds (for coarsening).
    pub kinds: Vec<CellKind>,
    /// Open sides (Dirichlet outside) `[axis][end]`.
    pub open: [[bool; 2]; 3],
    /// Per padded cell: the diagonal `A_cc` as `f32`, 0 off the unknowns.
    pub diag: Vec<f32>,
    /// Per padded cell: `1 / A_cc`, 0 off the unknowns.
    pub invd: Vec<f32>,
    /// Per colour (`(i + j + k) mod 2`): `1 / A_cc` on that colour's
    /// unknowns, 0 elsewhere — the red–black smoother's update weights.
    pub invc: [Vec<f32>; 2],
    /// Work vectors (padded).
    pub x: Vec<f32>,
    pub b: Vec<f32>,
    pub t: Vec<f32>,
}

impl Level {
    /// Builds a level from unpadded `kinds`.
    pub fn new(
        n: [usize; 3],
        kinds: Vec<CellKind>,
        open: [[bool; 2]; 3],
        periodic: [bool; 3],
    ) -> Self {
        let active: Vec<usize> = (0..3).filter(|&a| n[a] > 1).collect();
        let pad: [usize; 3] = std::array::from_fn(|a| usize::from(n[a] > 1));
        let m: [usize; 3] = std::array::from_fn(|a| n[a] + 2 * pad[a]);
        let stride = [1, m[0], m[0] * m[1]];
        let len = GUARD + m[0] * m[1] * m[2] + GUARD;
        let mut lvl = Self {
            n,
            m,
            pad,
            stride,
            active,
            periodic: std::array::from_fn(|a| periodic[a] && n[a] > 1),
            mask: vec![0; len],
            diag: vec![0.0; len],
            invd: vec![0.0; len],
            invc: [vec![0.0; len], vec![0.0; len]],
            kinds,
            open,
            x: vec![0.0; len],
            b: vec![0.0; len],
            t: vec![0.0; len],
        };
        lvl.build_mask();
        for (p, &m) in lvl.mask.iter().enumerate() {
            if m != 0 {
                let d = f32::from(m >> 8);
                lvl.diag[p] = d;
                lvl.invd[p] = 1.0 / d;
            }
        }
        let mut invc = std::mem::take(&mut lvl.invc);
        lvl.for_each_cell(|c, p| invc[(c[0] + c[1] + c[2]) & 1][p] = lvl.invd[p]);
        lvl.invc = invc;
        lvl
    }

    /// Open flags from boundary sides.
    pub fn open_from(b: &Boundaries) -> [[bool; 2]; 3] {
        std::array::from_fn(|a| std::array::from_fn(|e| b.side(a, e) == Side::Open))
    }

    #[inline]
    pub fn len(&self) -> usize {
        self.mask.len()
    }

    /// Padded index of unpadded cell `(i, j, k)`.
    #[inline]
    pub fn pidx(&self, c: [usize; 3]) -> usize {
        GUARD
            + (c[0] + self.pad[0])
            + (c[1] + self.pad[1]) * self.stride[1]
            + (c[2] + self.pad[2]) * self.stride[2]
    }

    /// Unpadded linear index.
    #[inline]
    pub fn uidx(&self, c: [usize; 3]) -> usize {
        (c[2] * self.n[1] + c[1]) * self.n[0] + c[0]
    }

    fn build_mask(&mut self) {
        let n = self.n;
        for k in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let c = [i, j, k];
                    if self.kinds[self.uidx(c)] != CellKind::Fluid {
                        continue;
                    }
                    let mut bits = 0u16;
                    let mut diag = 0u16;
                    for (q, &a) in self.active.iter().enumerate() {
                        for e in 0..2 {
                            let mut nb = c;
                            let inside = if e == 0 { c[a] > 0 } else { c[a] + 1 < n[a] };
                            if inside {
                                nb[a] = if e == 0 { c[a] - 1 } else { c[a] + 1 };
                            } else if self.periodic[a] {
                                nb[a] = if e == 0 { n[a] - 1 } else { 0 };
                            } else {
                                if self.open[a][e] {
                                    diag += 1;
                                }
                                continue;
                            }
                            match self.kinds[self.uidx(nb)] {
                                CellKind::Fluid => {
                                    bits |= 1 << (2 * q + e);
                                    diag += 1;
                                }
                                CellKind::Air => diag += 1,
                                CellKind::Solid => {}
                            }
                        }
                    }
                    let p = self.pidx(c);
                    self.mask[p] = if diag == 0 { 0 } else { bits | (diag << 8) };
                }
            }
        }
    }

    /// Number of padded rows (x-lines).
    #[inline]
    pub fn rows(&self) -> usize {
        self.m[1] * self.m[2]
    }

    /// If padded row `r` is interior, its base index (padded index of cell x = −pad).
    #[inline]
    pub fn row_base(&self, r: usize) -> Option<usize> {
        let jp = r % self.m[1];
        let kp = r / self.m[1];
        let inside = |p: usize, a: usize| p >= self.pad[a] && p < self.pad[a] + self.n[a];
        (inside(jp, 1) && inside(kp, 2)).then_some(GUARD + r * self.m[0])
    }

    /// Copies wrapped values into the ghost layers of periodic axes.
    pub fn fill_ghosts<T: Copy>(&self, v: &mut [T]) {
        for a in 0..3 {
            if !self.periodic[a] {
                continue;
            }
            let (b, c) = match a {
                0 => (1, 2),
                1 => (0, 2),
                _ => (0, 1),
            };
            for q in 0..self.m[c] {
                for p in 0..self.m[b] {
                    let base = GUARD + p * self.stride[b] + q * self.stride[c];
                    let first = base + self.stride[a];
                    let last = base + self.n[a] * self.stride[a];
                    v[base] = v[last];
                    v[base + (self.n[a] + 1) * self.stride[a]] = v[first];
                }
            }
        }
    }

    /// Runs `f(row_base, out_row)` over interior rows of `out` in parallel;
    /// the out row slice covers the padded row (`m[0]` samples from `row_base`).
    fn rows_par<T: Send>(&self, out: &mut [T], f: impl Fn(usize, usize, &mut [T]) + Sync + Send) {
        let m0 = self.m[0];
        let body = &mut out[GUARD..GUARD + self.rows() * m0];
        chunks::for_chunks(body, m0, |r, row| {
            if let Some(base) = self.row_base(r) {
                f(r, base, row);
            }
        });
    }

    /// `y = A x` on fluid cells (0 elsewhere). `x` ghosts must be filled if periodic.
    pub fn apply<T: Real>(&self, x: &[T], y: &mut [T]) {
        match self.active.len() {
            0 => self.apply_k::<0, T>(x, y),
            1 => self.apply_k::<1, T>(x, y),
            2 => self.apply_k::<2, T>(x, y),
            _ => self.apply_k::<3, T>(x, y),
        }
    }

    /// `y = A x` as [`Level::apply`], returning `x·y` over the interior
    /// cells in `f64`: the same per-row sums, added in the same row order,
    /// as [`Level::dot`]`(x, y)` after `apply` (bit-identical), in one pass.
    pub fn apply_dot(&self, x: &[f32], y: &mut [f32]) -> f64 {
        match self.active.len() {
            0 => self.apply_dot_k::<0>(x, y),
            1 => self.apply_dot_k::<1>(x, y),
            2 => self.apply_dot_k::<2>(x, y),
            _ => self.apply_dot_k::<3>(x, y),
        }
    }

    fn apply_dot_k<const K: usize>(&self, x: &[f32], y: &mut [f32]) -> f64 {
        let st = self.strides::<K>();
        let (p0, n0, m0) = (self.pad[0], self.n[0], self.m[0]);
        let simd = Simd::best();
        let body = &mut y[GUARD..GUARD + self.rows() * m0];
        chunks::for_chunks_sum(body, m0, |r, yrow| {
            let Some(base) = self.row_base(r) else {
                return 0.0;
            };
            let s = base + p0;
            let out = &mut yrow[p0..p0 + n0];
            simd::run(
                simd,
                ApplyRow::<K, f32> {
                    diag: &self.diag,
                    x,
                    s,
                    st,
                    out: &mut *out,
                },
            );
            lane_dot(&x[s..s + n0], out)
        })
    }

    pub(crate) fn strides<const K: usize>(&self) -> [usize; K] {
        std::array::from_fn(|q| self.stride[self.active[q]])
    }

    // The row kernels rely on the zero-padding invariant stated in
    // `super::operator`.

    fn apply_k<const K: usize, T: Real>(&self, x: &[T], y: &mut [T]) {
        let st = self.strides::<K>();
        let (p0, n0) = (self.pad[0], self.n[0]);
        let simd = Simd::best();
        self.rows_par(y, |_, base, yrow| {
            simd::run(
                simd,
                ApplyRow::<K, T> {
                    diag: &self.diag,
                    x,
                    s: base + p0,
                    st,
                    out: &mut yrow[p0..p0 + n0],
                },
            );
        });
    }

    /// One red or black half sweep of Gauss–Seidel, out of place:
    /// `out` = `x` with cells of parity `colour` updated from `b`.
    pub fn gs_half(&self, x: &[f32], b: &[f32], out: &mut [f32], colour: usize) {
        match self.active.len() {
            0 => self.gs_half_k::<0>(x, b, out, colour),
            1 => self.gs_half_k::<1>(x, b, out, colour),
            2 => self.gs_half_k::<2>(x, b, out, colour),
            _ => self.gs_half_k::<3>(x, b, out, colour),
        }
    }

    fn gs_half_k<const K: usize>(&self, x: &[f32], b: &[f32], out: &mut [f32], colour: usize) {
        let st = self.strides::<K>();
        let (p0, n0) = (self.pad[0], self.n[0]);
        // Cells of parity `colour` have a non-zero weight in invc[colour].
        let wc = &self.invc[colour];
        let simd = Simd::best();
        self.rows_par(out, |_, base, orow| {
            simd::run(
                simd,
                GsRow::<K> {
                    x,
                    b,
                    wc,
                    s: base + p0,
                    st,
                    out: &mut orow[p0..p0 + n0],
                },
            );
        });
    }

    /// Mask-decoding form of `apply` (the general per-cell stencil), for tests.
    #[cfg(test)]
    pub fn apply_ref_k<const K: usize, T: Real>(&self, x: &[T], y: &mut [T]) {
        let st = self.strides::<K>();
        let (p0, n0) = (self.pad[0], self.n[0]);
        self.rows_par(y, |_, base, yrow| {
            let s = base + p0;
            let xs = &x[s..s + n0];
            let ms = &self.mask[s..s + n0];
            let lo: [&[T]; K] = std::array::from_fn(|q| &x[s - st[q]..s - st[q] + n0]);
            let hi: [&[T]; K] = std::array::from_fn(|q| &x[s + st[q]..s + st[q] + n0]);
            let out = &mut yrow[p0..p0 + n0];
            for (i, o) in out.iter_mut().enumerate() {
                let l = std::array::from_fn(|q| lo[q][i]);
                let h = std::array::from_fn(|q| hi[q][i]);
                *o = operator::apply_masked::<K, T>(ms[i], xs[i], l, h);
            }
        });
    }

    /// Mask-decoding form of `gs_half`, for tests.
    #[cfg(test)]
    pub fn gs_half_ref_k<const K: usize>(
        &self,
        x: &[f32],
        b: &[f32],
        out: &mut [f32],
        colour: usize,
    ) {
        let st = self.strides::<K>();
        let (p0, n0) = (self.pad[0], self.n[0]);
        self.rows_par(out, |r, base, orow| {
            let s = base + p0;
            let xs = &x[s..s + n0];
            let bs = &b[s..s + n0];
            let ms = &self.mask[s..s + n0];
            let lo: [&[f32]; K] = std::array::from_fn(|q| &x[s - st[q]..s - st[q] + n0]);
            let hi: [&[f32]; K] = std::array::from_fn(|q| &x[s + st[q]..s + st[q] + n0]);
            let o = &mut orow[p0..p0 + n0];
            // Interior cell i is updated when (i + j + k) ≡ colour (mod 2).
            let want = {
                let jp = r % self.m[1] - self.pad[1];
                let kp = r / self.m[1] - self.pad[2];
                (colour + jp + kp) & 1
            };
            for (i, ov) in o.iter_mut().enumerate() {
                let l = std::array::from_fn(|q| lo[q][i]);
                let h = std::array::from_fn(|q| hi[q][i]);
                *ov = operator::gs_masked::<K>(ms[i], xs[i], bs[i], l, h, (i & 1) == want);
            }
        });
    }

    /// One symmetric-ordered red–black sweep pair starting with `first` colour;
    /// result back in `self.x` (uses `self.t`).
    pub fn smooth(&mut self, first: usize) {
        let mut x = std::mem::take(&mut self.x);
        let mut t = std::mem::take(&mut self.t);
        if self.periodic.iter().any(|&p| p) {
            self.fill_ghosts(&mut x);
        }
        self.gs_half(&x, &self.b, &mut t, first);
        if self.periodic.iter().any(|&p| p) {
            self.fill_ghosts(&mut t);
        }
        self.gs_half(&t, &self.b, &mut x, 1 - first);
        self.x = x;
        self.t = t;
    }

    /// `smooth(first)` from a zero iterate, without reading `self.x`: the
    /// first half sweep's neighbour sum is zero, so it is the weighted
    /// right-hand side `(b + 0)·w_first` (bit-identical to `gs_half` on a
    /// zero `x`, signed zeros included). Writes every interior cell of
    /// `self.x`; padding is never written by the smoother, so the caller
    /// need not clear `x` first (periodic ghosts are refilled before reads).
    pub fn smooth_from_zero(&mut self, first: usize) {
        let mut x = std::mem::take(&mut self.x);
        let mut t = std::mem::take(&mut self.t);
        let wc = &self.invc[first];
        let b = &self.b;
        chunks::for_chunks(&mut t, chunks::BLOCK, |bi, tc| {
            let s = bi * chunks::BLOCK;
            let n = tc.len();
            for ((o, &bv), &iv) in tc.iter_mut().zip(&b[s..s + n]).zip(&wc[s..s + n]) {
                // The update with a zero iterate and neighbour sum: `b + 0`
                // turns a −0 right-hand side into +0, as the general sweep's
                // `b + Σ 0` does.
                *o = operator::gs_cell(0.0, bv, iv, 0.0);
            }
        });
        if self.periodic.iter().any(|&p| p) {
            self.fill_ghosts(&mut t);
        }
        self.gs_half(&t, &self.b, &mut x, 1 - first);
        self.x = x;
        self.t = t;
    }

    /// `r = b − A x` on fluid cells; `x` ghosts filled first if periodic.
    pub fn residual<T: Real>(&self, b: &[T], x: &mut [T], r: &mut [T]) {
        if self.periodic.iter().any(|&p| p) {
            self.fill_ghosts(x);
        }
        match self.active.len() {
            0 => self.residual_k::<0, T>(b, x, r),
            1 => self.residual_k::<1, T>(b, x, r),
            2 => self.residual_k::<2, T>(b, x, r),
            _ => self.residual_k::<3, T>(b, x, r),
        }
    }

    fn residual_k<const K: usize, T: Real>(&self, b: &[T], x: &[T], r: &mut [T]) {
        let st = self.strides::<K>();
        let (p0, n0) = (self.pad[0], self.n[0]);
        let simd = Simd::best();
        self.rows_par(r, |_, base, rrow| {
            simd::run(
                simd,
                ResidualRow::<K, T> {
                    x,
                    b,
                    diag: &self.diag,
                    s: base + p0,
                    st,
                    out: &mut rrow[p0..p0 + n0],
                },
            );
        });
    }

    /// `Σ a·b` over interior cells, in `f64`, deterministic: per row
    /// [`lane_dot`], the rows added in order.
    pub fn dot<A: Copy + Into<f64> + Sync, B: Copy + Into<f64> + Sync>(
        &self,
        a: &[A],
        b: &[B],
    ) -> f64 {
        let (p0, n0) = (self.pad[0], self.n[0]);
        chunks::sum_blocks(self.rows(), n0, |r| match self.row_base(r) {
            Some(base) => {
                let s = base + p0;
                lane_dot(&a[s..s + n0], &b[s..s + n0])
            }
            None => 0.0,
        })
    }

    /// `Σ v` over interior cells, in `f64`, deterministic: per row
    /// [`lane_sum`], the rows added in order.
    pub fn sum<T: Copy + Into<f64> + Sync>(&self, v: &[T]) -> f64 {
        let (p0, n0) = (self.pad[0], self.n[0]);
        chunks::sum_blocks(self.rows(), n0, |r| match self.row_base(r) {
            Some(base) => lane_sum(&v[base + p0..base + p0 + n0]),
            None => 0.0,
        })
    }

    /// `v −= m` on the unknowns (other cells keep their zero).
    pub fn sub_on_unknowns<T: Real>(&self, v: &mut [T], m: f64) {
        let (p0, n0) = (self.pad[0], self.n[0]);
        let mt = T::from_f64(m);
        self.rows_par(v, |_, base, row| {
            let ds = &self.diag[base + p0..base + p0 + n0];
            for (o, &d) in row[p0..p0 + n0].iter_mut().zip(ds) {
                let y = *o - mt;
                *o = if d != 0.0 { y } else { *o };
            }
        });
    }

    /// Visits every interior padded index sequentially with its unpadded coordinates.
    pub fn for_each_cell(&self, mut f: impl FnMut([usize; 3], usize)) {
        for k in 0..self.n[2] {
            for j in 0..self.n[1] {
                for i in 0..self.n[0] {
                    let c = [i, j, k];
                    f(c, self.pidx(c));
                }
            }
        }
    }

    /// Number of fluid unknowns.
    pub fn unknowns(&self) -> usize {
        self.mask.iter().filter(|&&m| m != 0).count()
    }
}
