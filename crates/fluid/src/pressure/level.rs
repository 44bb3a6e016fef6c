//! One grid level of the pressure Poisson operator, stored padded with a
//! ghost layer on every non-flat axis so stencils never branch on borders.
//!
//! The operator is the compact (2d+1)-point Laplacian, scaled by `−h²`:
//! `(A x)_c = Σ_{non-solid n} (x_c − x_n)` over the face neighbours `n` of a
//! fluid cell `c`, with `x_n = 0` for air/open neighbours (Dirichlet). It is
//! symmetric positive semi-definite — the negation of the matrix Foster &
//! Fedkiw print (an erratum in Foster & Fedkiw 2001, §8: their `a_ii = −#liquid neighbours` makes it
//! negative definite; CG needs the negated form).

use crate::grid::{Boundaries, CellKind, Side};
use crate::par;
use natura_core::simd::{self, Kernel, Simd};

/// The float types the operator is applied to (f32 work vectors, f64 CG iterate).
pub(crate) trait Real:
    Copy
    + Send
    + Sync
    + Default
    + From<f32>
    + Into<f64>
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
{
    /// Rounds from `f64`.
    fn from_f64(v: f64) -> Self;
}
impl Real for f32 {
    fn from_f64(v: f64) -> Self {
        v as f32
    }
}
impl Real for f64 {
    fn from_f64(v: f64) -> Self {
        v
    }
}

/// Leading guard element so that `row_base − 1` is always a valid index.
pub(crate) const G: usize = 1;

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
    pub st: [usize; 3],
    /// Active axes in order.
    pub act: Vec<usize>,
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
        let act: Vec<usize> = (0..3).filter(|&a| n[a] > 1).collect();
        let pad: [usize; 3] = std::array::from_fn(|a| usize::from(n[a] > 1));
        let m: [usize; 3] = std::array::from_fn(|a| n[a] + 2 * pad[a]);
        let st = [1, m[0], m[0] * m[1]];
        let len = G + m[0] * m[1] * m[2] + G;
        let mut lvl = Self {
            n,
            m,
            pad,
            st,
            act,
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
        G + (c[0] + self.pad[0])
            + (c[1] + self.pad[1]) * self.st[1]
            + (c[2] + self.pad[2]) * self.st[2]
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
                    for (q, &a) in self.act.iter().enumerate() {
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
        (inside(jp, 1) && inside(kp, 2)).then_some(G + r * self.m[0])
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
                    let base = G + p * self.st[b] + q * self.st[c];
                    let first = base + self.st[a];
                    let last = base + self.n[a] * self.st[a];
                    v[base] = v[last];
                    v[base + (self.n[a] + 1) * self.st[a]] = v[first];
                }
            }
        }
    }

    /// Runs `f(row_base, out_row)` over interior rows of `out` in parallel;
    /// the out row slice covers the padded row (`m[0]` samples from `row_base`).
    fn rows_par<T: Send>(&self, out: &mut [T], f: impl Fn(usize, usize, &mut [T]) + Sync + Send) {
        let m0 = self.m[0];
        let body = &mut out[G..G + self.rows() * m0];
        par::for_chunks(body, m0, |r, row| {
            if let Some(base) = self.row_base(r) {
                f(r, base, row);
            }
        });
    }

    /// `y = A x` on fluid cells (0 elsewhere). `x` ghosts must be filled if periodic.
    pub fn apply<T: Real>(&self, x: &[T], y: &mut [T]) {
        match self.act.len() {
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
        match self.act.len() {
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
        let body = &mut y[G..G + self.rows() * m0];
        par::for_chunks_sum(body, m0, |r, yrow| {
            let Some(base) = self.row_base(r) else {
                return 0.0;
            };
            let s = base + p0;
            let out = &mut yrow[p0..p0 + n0];
            simd::run(
                simd,
                ApplyRow::<K, f32> {
                    lvl: self,
                    x,
                    s,
                    st,
                    out: &mut *out,
                },
            );
            lane_dot(&x[s..s + n0], out)
        })
    }

    fn strides<const K: usize>(&self) -> [usize; K] {
        std::array::from_fn(|q| self.st[self.act[q]])
    }

    // The row kernels below rely on one invariant of every vector they read:
    // values are zero on padded cells that are not unknowns (solid, air,
    // isolated fluid, non-periodic ghosts), and periodic ghosts hold wrapped
    // copies. Then the coupling `Σ_n x_n` over the coupled neighbours equals
    // the plain sum over all 2K face neighbours (solid and Dirichlet
    // neighbours contribute zero), so the stencil needs no per-cell mask
    // decoding and the loops vectorise. `pad_into`, the restriction and
    // prolongation, and the smoother all preserve the invariant.

    fn apply_k<const K: usize, T: Real>(&self, x: &[T], y: &mut [T]) {
        let st = self.strides::<K>();
        let (p0, n0) = (self.pad[0], self.n[0]);
        let simd = Simd::best();
        self.rows_par(y, |_, base, yrow| {
            simd::run(
                simd,
                ApplyRow::<K, T> {
                    lvl: self,
                    x,
                    s: base + p0,
                    st,
                    out: &mut yrow[p0..p0 + n0],
                },
            );
        });
    }

    /// `out` = (A x) over the row of unknowns starting at padded index `s`.
    ///
    /// The stencil is evaluated in `f64` whatever `T` is and rounded once.
    /// For `f32` vectors this matters: a smooth CG search direction `d` is
    /// orders of magnitude larger than `A d`, so an `f32` evaluation loses
    /// most of `A d`'s digits to cancellation, and the CG residual updated
    /// with it (`r −= α A d`) drifts from the true residual `b − A x` by
    /// about 1e-5 relative on a 512² pressure problem — the stopping
    /// tolerance — after which CG stagnates. Every input is an exact `f32`,
    /// so the `f64` sum of the five (seven) terms is exact or nearly so and
    /// the only error left is the final rounding, relative to `A d` itself.
    #[inline(always)]
    fn apply_row<const K: usize, T: Real>(&self, x: &[T], s: usize, st: [usize; K], out: &mut [T]) {
        let n0 = out.len();
        let mut acc = [0.0f64; CH];
        for i0 in (0..n0).step_by(CH) {
            let w = CH.min(n0 - i0);
            let a = &mut acc[..w];
            let c = s + i0;
            neighbour_sum_wide::<K, T>(x, c, st, a);
            let xs = &x[c..c + w];
            let ds = &self.diag[c..c + w];
            for (((o, &xv), &d), &off) in out[i0..i0 + w].iter_mut().zip(xs).zip(ds).zip(&*a) {
                let v = f64::from(d) * xv.into() - off;
                *o = if d != 0.0 {
                    T::from_f64(v)
                } else {
                    T::default()
                };
            }
        }
    }

    /// One red or black half sweep of Gauss–Seidel, out of place:
    /// `out` = `x` with cells of parity `colour` updated from `b`.
    pub fn gs_half(&self, x: &[f32], b: &[f32], out: &mut [f32], colour: usize) {
        match self.act.len() {
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
                let m = ms[i];
                let mut off = T::default();
                for q in 0..K {
                    off = off
                        + T::from(f32::from((m >> (2 * q)) & 1)) * lo[q][i]
                        + T::from(f32::from((m >> (2 * q + 1)) & 1)) * hi[q][i];
                }
                *o = T::from(f32::from(m >> 8)) * xs[i] - off;
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
                let m = ms[i];
                let mut off = 0.0f32;
                for q in 0..K {
                    off += f32::from((m >> (2 * q)) & 1) * lo[q][i]
                        + f32::from((m >> (2 * q + 1)) & 1) * hi[q][i];
                }
                let d = f32::from((m >> 8).max(1));
                // Arithmetic blend instead of a branch so the loop vectorises.
                let w = f32::from(u8::from((i & 1) == want) & u8::from(m != 0));
                let v = (bs[i] + off) / d;
                *ov = xs[i] + w * (v - xs[i]);
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
        par::for_chunks(&mut t, par::BLOCK, |bi, tc| {
            let s = bi * par::BLOCK;
            let n = tc.len();
            for ((o, &bv), &iv) in tc.iter_mut().zip(&b[s..s + n]).zip(&wc[s..s + n]) {
                // `+ 0.0` turns a −0 right-hand side into +0, as the
                // general sweep's `b + Σ 0` does.
                let v = (bv + 0.0) * iv;
                *o = if iv != 0.0 { v } else { 0.0 };
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
        match self.act.len() {
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
        par::sum_blocks(self.rows(), n0, |r| match self.row_base(r) {
            Some(base) => {
                let s = base + p0;
                lane_dot(&a[s..s + n0], &b[s..s + n0])
            }
            None => 0.0,
        })
    }

    /// `Σ v` over interior cells, in `f64`, deterministic: per row in
    /// [`LANES`] lane sums (as [`lane_dot`]), the rows added in order.
    pub fn sum<T: Copy + Into<f64> + Sync>(&self, v: &[T]) -> f64 {
        let (p0, n0) = (self.pad[0], self.n[0]);
        par::sum_blocks(self.rows(), n0, |r| match self.row_base(r) {
            Some(base) => {
                let row = &v[base + p0..base + p0 + n0];
                let mut lanes = [0.0f64; LANES];
                let it = row.chunks_exact(LANES);
                let tail = it.remainder();
                for c in it {
                    for (l, &x) in lanes.iter_mut().zip(c) {
                        *l += x.into();
                    }
                }
                fold_lanes(lanes, tail.iter().map(|&x| x.into()))
            }
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

/// Per-axis transfer weights between a fine and a coarse level.
#[derive(Clone, Debug)]
pub(crate) struct Transfer {
    /// For each fine index along each axis: (parent, neighbour) coarse
    /// indices (unpadded); weights 0.75 / 0.25.
    pub up: [Vec<(usize, usize)>; 3],
    /// For each coarse index along each axis: fine (index, weight) pairs.
    pub down: [Vec<Vec<(usize, f32)>>; 3],
    /// `4 / 2^d`: restriction scale making the coarse system consistent.
    pub scale: f32,
}

impl Transfer {
    pub fn new(fine: &Level, coarse: &Level) -> Self {
        let mut up: [Vec<(usize, usize)>; 3] = Default::default();
        let mut down: [Vec<Vec<(usize, f32)>>; 3] = Default::default();
        for a in 0..3 {
            let nf = fine.n[a];
            let nc = coarse.n[a];
            if nf == 1 {
                up[a] = vec![(0, 0)];
                down[a] = vec![vec![(0, 1.0)]];
                continue;
            }
            let per = fine.periodic[a];
            let fix = |i: i64| -> usize {
                if per {
                    i.rem_euclid(nc as i64) as usize
                } else {
                    i.clamp(0, nc as i64 - 1) as usize
                }
            };
            up[a] = (0..nf)
                .map(|f| {
                    let p = f / 2;
                    let nb = if f % 2 == 0 {
                        p as i64 - 1
                    } else {
                        p as i64 + 1
                    };
                    (p, fix(nb))
                })
                .collect();
            down[a] = (0..nc)
                .map(|c| {
                    let mut v = Vec::with_capacity(4);
                    for d in -1i64..=2 {
                        let f = 2 * c as i64 + d;
                        let f = if per {
                            f.rem_euclid(nf as i64)
                        } else if f < 0 || f >= nf as i64 {
                            continue;
                        } else {
                            f
                        } as usize;
                        let (p, nb) = up[a][f];
                        let w = if p == c { 0.75 } else { 0.0 } + if nb == c { 0.25 } else { 0.0 };
                        if w > 0.0 && !v.iter().any(|&(g, _)| g == f) {
                            v.push((f, w));
                        }
                    }
                    v
                })
                .collect();
        }
        let d = fine.act.len() as i32;
        Self {
            up,
            down,
            scale: 4.0 / 2f32.powi(d),
        }
    }

    /// `coarse.b = scale · Pᵀ r` (fine residual `r`), on coarse fluid cells.
    ///
    /// Separable: each contributing fine row is first restricted along x
    /// (interior coarse cells with the fixed ¼ ¾ ¾ ¼ weights, the two ends
    /// from the general weight lists), then the rows are summed with their
    /// y/z weights.
    pub fn restrict(&self, fine: &Level, r: &[f32], coarse: &mut Level) {
        let mut cb = std::mem::take(&mut coarse.b);
        let m0 = coarse.m[0];
        let n0 = coarse.n[0];
        let nf0 = fine.n[0];
        let cl: &Level = coarse;
        let body = &mut cb[G..G + cl.rows() * m0];
        // Coarse x cells whose four fine children 2c−1..=2c+2 are interior
        // with the standard weights.
        let (lo_c, hi_c) = interior_range(n0, nf0, fine.n[0] > 1);
        let simd = Simd::best();
        par::for_chunks(body, m0, |row_i, row| {
            simd::run(
                simd,
                RestrictRow {
                    tr: self,
                    fine,
                    r,
                    cl,
                    lo_c,
                    hi_c,
                    row_i,
                    row,
                },
            );
        });
        coarse.b = cb;
    }

    /// `fine.x += P coarse.x` on fine fluid cells.
    ///
    /// Separable: the (up to four) contributing coarse rows are first
    /// combined with their y/z weights into one coarse row, which is then
    /// interpolated along x (¾ ¼ weights; the ends from the general lists).
    pub fn prolong_add(&self, coarse: &Level, fine: &mut Level) {
        let mut fx = std::mem::take(&mut fine.x);
        let m0 = fine.m[0];
        let fl: &Level = fine;
        let body = &mut fx[G..G + fl.rows() * m0];
        let simd = Simd::best();
        par::for_chunks(body, m0, |row_i, row| {
            simd::run(
                simd,
                ProlongRow {
                    tr: self,
                    coarse,
                    fl,
                    row_i,
                    row,
                },
            );
        });
        fine.x = fx;
    }

    /// Reference restriction (the general per-cell form), for tests.
    #[cfg(test)]
    pub fn restrict_ref(&self, fine: &Level, r: &[f32], coarse: &mut Level) {
        let cb = std::mem::take(&mut coarse.b);
        let mut cb = cb;
        let m0 = coarse.m[0];
        let (p0, n0) = (coarse.pad[0], coarse.n[0]);
        let cl: &Level = coarse;
        let body = &mut cb[G..G + cl.rows() * m0];
        par::for_chunks(body, m0, |row_i, row| {
            let Some(base) = cl.row_base(row_i) else {
                return;
            };
            let jc = row_i % cl.m[1] - cl.pad[1];
            let kc = row_i / cl.m[1] - cl.pad[2];
            for ic in 0..n0 {
                let pi = base + p0 + ic;
                if cl.mask[pi] == 0 {
                    row[p0 + ic] = 0.0;
                    continue;
                }
                let mut s = 0.0f32;
                for &(fk, wk) in &self.down[2][kc] {
                    for &(fj, wj) in &self.down[1][jc] {
                        let wjk = wj * wk;
                        let fb = fine.pidx([0, fj, fk]);
                        for &(fi, wi) in &self.down[0][ic] {
                            s += wi * wjk * r[fb + fi];
                        }
                    }
                }
                row[p0 + ic] = self.scale * s;
            }
        });
        coarse.b = cb;
    }

    /// Reference prolongation (the general per-cell form), for tests.
    #[cfg(test)]
    pub fn prolong_add_ref(&self, coarse: &Level, fine: &mut Level) {
        let mut fx = std::mem::take(&mut fine.x);
        let m0 = fine.m[0];
        let (p0, n0) = (fine.pad[0], fine.n[0]);
        let fl: &Level = fine;
        let cx = &coarse.x;
        let body = &mut fx[G..G + fl.rows() * m0];
        par::for_chunks(body, m0, |row_i, row| {
            let Some(base) = fl.row_base(row_i) else {
                return;
            };
            let jf = row_i % fl.m[1] - fl.pad[1];
            let kf = row_i / fl.m[1] - fl.pad[2];
            let (jp, jn) = self.up[1][jf];
            let (kp, kn) = self.up[2][kf];
            let (wjp, wjn) = if fl.n[1] > 1 {
                (0.75, 0.25)
            } else {
                (1.0, 0.0)
            };
            let (wkp, wkn) = if fl.n[2] > 1 {
                (0.75, 0.25)
            } else {
                (1.0, 0.0)
            };
            let rows = [
                (coarse.pidx([0, jp, kp]), wjp * wkp),
                (coarse.pidx([0, jn, kp]), wjn * wkp),
                (coarse.pidx([0, jp, kn]), wjp * wkn),
                (coarse.pidx([0, jn, kn]), wjn * wkn),
            ];
            let (wip, win) = if fl.n[0] > 1 {
                (0.75f32, 0.25f32)
            } else {
                (1.0, 0.0)
            };
            for i in 0..n0 {
                if fl.mask[base + p0 + i] == 0 {
                    continue;
                }
                let (ip, inb) = self.up[0][i];
                let mut s = 0.0f32;
                for &(rb, w) in &rows {
                    if w != 0.0 {
                        s += w * (wip * cx[rb + ip] + win * cx[rb + inb]);
                    }
                }
                row[p0 + i] += s;
            }
        });
        fine.x = fx;
    }
}

/// One row of [`Level::apply`] as a SIMD-dispatched kernel (the same
/// element-wise arithmetic at every width, so bit-identical results).
struct ApplyRow<'a, const K: usize, T> {
    lvl: &'a Level,
    x: &'a [T],
    s: usize,
    st: [usize; K],
    out: &'a mut [T],
}

impl<const K: usize, T: Real> Kernel for ApplyRow<'_, K, T> {
    type Out = ();

    #[inline(always)]
    fn call(self) {
        self.lvl
            .apply_row::<K, T>(self.x, self.s, self.st, self.out);
    }
}

/// One row of a red–black half sweep ([`Level::gs_half`]) as a
/// SIMD-dispatched kernel: `out` = `x` with the cells of non-zero weight
/// `wc` replaced by `(b + Σ neighbours)·wc`.
struct GsRow<'a, const K: usize> {
    x: &'a [f32],
    b: &'a [f32],
    wc: &'a [f32],
    s: usize,
    st: [usize; K],
    out: &'a mut [f32],
}

impl<const K: usize> Kernel for GsRow<'_, K> {
    type Out = ();

    #[inline(always)]
    fn call(self) {
        let Self {
            x,
            b,
            wc,
            s,
            st,
            out,
        } = self;
        let n0 = out.len();
        let mut acc = [0.0f32; CH];
        for i0 in (0..n0).step_by(CH) {
            let w = CH.min(n0 - i0);
            let a = &mut acc[..w];
            let c = s + i0;
            neighbour_sum::<K, f32>(x, c, st, a);
            let xs = &x[c..c + w];
            let bs = &b[c..c + w];
            let ws = &wc[c..c + w];
            for ((((ov, &xv), &bv), &iv), &off) in
                out[i0..i0 + w].iter_mut().zip(xs).zip(bs).zip(ws).zip(&*a)
            {
                let v = (bv + off) * iv;
                // A select, not a branch, so the loop vectorises.
                *ov = if iv != 0.0 { v } else { xv };
            }
        }
    }
}

/// One row of [`Level::residual`] as a SIMD-dispatched kernel.
struct ResidualRow<'a, const K: usize, T> {
    x: &'a [T],
    b: &'a [T],
    diag: &'a [f32],
    s: usize,
    st: [usize; K],
    out: &'a mut [T],
}

impl<const K: usize, T: Real> Kernel for ResidualRow<'_, K, T> {
    type Out = ();

    #[inline(always)]
    fn call(self) {
        let Self {
            x,
            b,
            diag,
            s,
            st,
            out,
        } = self;
        let n0 = out.len();
        let mut acc = [T::default(); CH];
        for i0 in (0..n0).step_by(CH) {
            let w = CH.min(n0 - i0);
            let a = &mut acc[..w];
            let c = s + i0;
            neighbour_sum::<K, T>(x, c, st, a);
            let xs = &x[c..c + w];
            let bs = &b[c..c + w];
            let ds = &diag[c..c + w];
            for ((((o, &xv), &bv), &d), &off) in
                out[i0..i0 + w].iter_mut().zip(xs).zip(bs).zip(ds).zip(&*a)
            {
                let v = bv - (T::from(d) * xv - off);
                *o = if d != 0.0 { v } else { T::default() };
            }
        }
    }
}

/// One coarse row of [`Transfer::restrict`] as a SIMD-dispatched kernel.
struct RestrictRow<'a> {
    tr: &'a Transfer,
    fine: &'a Level,
    r: &'a [f32],
    cl: &'a Level,
    lo_c: usize,
    hi_c: usize,
    row_i: usize,
    row: &'a mut [f32],
}

impl Kernel for RestrictRow<'_> {
    type Out = ();

    #[inline(always)]
    #[allow(clippy::needless_range_loop)]
    fn call(self) {
        let Self {
            tr,
            fine,
            r,
            cl,
            lo_c,
            hi_c,
            row_i,
            row,
        } = self;
        let (p0, n0) = (cl.pad[0], cl.n[0]);
        let nf0 = fine.n[0];
        let Some(base) = cl.row_base(row_i) else {
            return;
        };
        let jc = row_i % cl.m[1] - cl.pad[1];
        let kc = row_i / cl.m[1] - cl.pad[2];
        let out = &mut row[p0..p0 + n0];
        out.fill(0.0);
        for &(fk, wk) in &tr.down[2][kc] {
            for &(fj, wj) in &tr.down[1][jc] {
                let w = wj * wk * tr.scale;
                let fb = fine.pidx([0, fj, fk]);
                let fr = &r[fb..fb + nf0];
                for ic in 0..lo_c.min(n0) {
                    let mut v = 0.0f32;
                    for &(fi, wi) in &tr.down[0][ic] {
                        v += wi * fr[fi];
                    }
                    out[ic] += w * v;
                }
                if hi_c > lo_c {
                    // Fine cells 2c−1 ..= 2c+2 for c in lo_c..hi_c.
                    let span = &fr[2 * lo_c - 1..2 * hi_c + 1];
                    for (k, o) in out[lo_c..hi_c].iter_mut().enumerate() {
                        let q = &span[2 * k..2 * k + 4];
                        *o += w * (0.25 * (q[0] + q[3]) + 0.75 * (q[1] + q[2]));
                    }
                }
                for ic in hi_c.max(lo_c)..n0 {
                    let mut v = 0.0f32;
                    for &(fi, wi) in &tr.down[0][ic] {
                        v += wi * fr[fi];
                    }
                    out[ic] += w * v;
                }
            }
        }
        let ds = &cl.diag[base + p0..base + p0 + n0];
        for (o, &d) in out.iter_mut().zip(ds) {
            if d == 0.0 {
                *o = 0.0;
            }
        }
    }
}

/// One fine row of [`Transfer::prolong_add`] as a SIMD-dispatched kernel.
struct ProlongRow<'a> {
    tr: &'a Transfer,
    coarse: &'a Level,
    fl: &'a Level,
    row_i: usize,
    row: &'a mut [f32],
}

impl Kernel for ProlongRow<'_> {
    type Out = ();

    #[inline(always)]
    fn call(self) {
        let Self {
            tr,
            coarse,
            fl,
            row_i,
            row,
        } = self;
        let (p0, n0) = (fl.pad[0], fl.n[0]);
        let nc0 = coarse.n[0];
        let cx = &coarse.x;
        let (wjp, wjn) = if fl.n[1] > 1 {
            (0.75, 0.25)
        } else {
            (1.0, 0.0)
        };
        let (wkp, wkn) = if fl.n[2] > 1 {
            (0.75, 0.25)
        } else {
            (1.0, 0.0)
        };
        let active_x = fl.n[0] > 1;
        let Some(base) = fl.row_base(row_i) else {
            return;
        };
        let jf = row_i % fl.m[1] - fl.pad[1];
        let kf = row_i / fl.m[1] - fl.pad[2];
        let (jp, jn) = tr.up[1][jf];
        let (kp, kn) = tr.up[2][kf];
        let rows = [
            (coarse.pidx([0, jp, kp]), wjp * wkp),
            (coarse.pidx([0, jn, kp]), wjn * wkp),
            (coarse.pidx([0, jp, kn]), wjp * wkn),
            (coarse.pidx([0, jn, kn]), wjn * wkn),
        ];
        // Combined coarse row c[0..nc0].
        let mut c = vec![0.0f32; nc0];
        for &(rb, w) in &rows {
            if w != 0.0 {
                for (o, &v) in c.iter_mut().zip(&cx[rb..rb + nc0]) {
                    *o += w * v;
                }
            }
        }
        let ds = &fl.diag[base + p0..base + p0 + n0];
        let out = &mut row[p0..p0 + n0];
        if !active_x {
            for (i, o) in out.iter_mut().enumerate() {
                if ds[i] != 0.0 {
                    *o += c[tr.up[0][i].0];
                }
            }
            return;
        }
        // Fine i = 2q (q ≥ 1) takes ¾ c[q] + ¼ c[q−1]; i = 2q+1 (q + 1 < nc0)
        // takes ¾ c[q] + ¼ c[q+1]. The ends use the general lists.
        let general = |i: usize| {
            let (ip, inb) = tr.up[0][i];
            0.75 * c[ip] + 0.25 * c[inb]
        };
        let mut add = vec![0.0f32; n0];
        for q in 0..nc0 {
            let i = 2 * q;
            if i >= n0 {
                break;
            }
            let even = if q >= 1 {
                0.75 * c[q] + 0.25 * c[q - 1]
            } else {
                general(i)
            };
            add[i] = even;
            if i + 1 < n0 {
                add[i + 1] = if q + 1 < nc0 {
                    0.75 * c[q] + 0.25 * c[q + 1]
                } else {
                    general(i + 1)
                };
            }
        }
        for ((o, &a), &d) in out.iter_mut().zip(&add).zip(ds) {
            if d != 0.0 {
                *o += a;
            }
        }
    }
}

/// Row block length of the stencil kernels (even, so colour parity is per block).
const CH: usize = 256;

/// Lane count of the row reductions.
pub(crate) const LANES: usize = 8;

/// `Σ a·b` in `f64` over one row: element `i` goes to lane `i mod 8` for
/// the full groups of eight, the lanes are added in order and the tail
/// elements after them. Eight independent sums instead of one running sum:
/// a single `f64` chain is latency-bound (one add per four cycles) and was
/// the dominant cost of the CG's dot products; the fixed grouping keeps the
/// result deterministic and identical at every SIMD level.
#[inline(always)]
pub(crate) fn lane_dot<A: Copy + Into<f64>, B: Copy + Into<f64>>(a: &[A], b: &[B]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut lanes = [0.0f64; LANES];
    let (a8, b8) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    let (at, bt) = (a8.remainder(), b8.remainder());
    for (x, y) in a8.zip(b8) {
        for l in 0..LANES {
            lanes[l] += x[l].into() * y[l].into();
        }
    }
    fold_lanes(lanes, at.iter().zip(bt).map(|(&x, &y)| x.into() * y.into()))
}

/// Adds the lane sums in lane order, then the tail terms in order.
#[inline(always)]
fn fold_lanes(lanes: [f64; LANES], tail: impl Iterator<Item = f64>) -> f64 {
    let mut s = 0.0f64;
    for l in lanes {
        s += l;
    }
    for t in tail {
        s += t;
    }
    s
}

/// `acc[k] = Σ_q x[c + k − st_q] + x[c + k + st_q]` for `k < acc.len()`:
/// the sum of the 2K face neighbours along the active axes with strides `st`.
#[inline(always)]
fn neighbour_sum<const K: usize, T: Real>(x: &[T], c: usize, st: [usize; K], acc: &mut [T]) {
    let w = acc.len();
    if K == 0 {
        acc.fill(T::default());
    }
    for q in 0..K {
        let lo = &x[c - st[q]..c - st[q] + w];
        let hi = &x[c + st[q]..c + st[q] + w];
        // The first axis starts the sum from `+0` in registers (`0 + y`,
        // which turns −0 into +0) instead of clearing `acc` first: the
        // same additions without a memset per block.
        let first = q == 0;
        for ((a, &l), &h) in acc.iter_mut().zip(lo).zip(hi) {
            let prev = if first { T::default() } else { *a };
            *a = prev + (l + h);
        }
    }
}

/// [`neighbour_sum`] accumulated in `f64` (the same order of additions:
/// for `T = f64` it is the same sum bit for bit).
#[inline(always)]
fn neighbour_sum_wide<const K: usize, T: Real>(x: &[T], c: usize, st: [usize; K], acc: &mut [f64]) {
    let w = acc.len();
    if K == 0 {
        acc.fill(0.0);
    }
    for q in 0..K {
        let lo = &x[c - st[q]..c - st[q] + w];
        let hi = &x[c + st[q]..c + st[q] + w];
        let first = q == 0;
        for ((a, &l), &h) in acc.iter_mut().zip(lo).zip(hi) {
            let prev = if first { 0.0 } else { *a };
            *a = prev + (l.into() + h.into());
        }
    }
}

/// Coarse x cells `lo..hi` whose fine children `2c−1 ..= 2c+2` all exist
/// and carry the standard ¼ ¾ ¾ ¼ restriction weights (`nc` coarse and `nf`
/// fine cells; `(0, 0)` on a flat axis).
fn interior_range(nc: usize, nf: usize, active: bool) -> (usize, usize) {
    if !active || nc < 2 {
        return (0, 0);
    }
    let hi = (nc - 1).min((nf - 1) / 2).max(1);
    (1, hi)
}

/// Coarsens cell kinds by 2 along active axes: air wins, then fluid, then solid.
pub(crate) fn coarsen(fine: &Level) -> ([usize; 3], Vec<CellKind>) {
    let nc: [usize; 3] = std::array::from_fn(|a| {
        if fine.n[a] > 1 {
            fine.n[a].div_ceil(2)
        } else {
            1
        }
    });
    // 0 = solid, 1 = fluid, 2 = air: the coarse kind is the max over children.
    let rank = |k: CellKind| match k {
        CellKind::Solid => 0u8,
        CellKind::Fluid => 1,
        CellKind::Air => 2,
    };
    let mut best = vec![0u8; nc[0] * nc[1] * nc[2]];
    let n = fine.n;
    let half = |a: usize, i: usize| if n[a] > 1 { i / 2 } else { 0 };
    for k in 0..n[2] {
        let kc = half(2, k);
        for j in 0..n[1] {
            let jc = half(1, j);
            let frow = (k * n[1] + j) * n[0];
            let crow = (kc * nc[1] + jc) * nc[0];
            for i in 0..n[0] {
                let c = crow + half(0, i);
                best[c] = best[c].max(rank(fine.kinds[frow + i]));
            }
        }
    }
    let kinds = best
        .into_iter()
        .map(|r| match r {
            0 => CellKind::Solid,
            1 => CellKind::Fluid,
            _ => CellKind::Air,
        })
        .collect();
    (nc, kinds)
}

#[cfg(test)]
mod simd_tests {
    use super::*;

    fn level(n: [usize; 3], periodic: [bool; 3]) -> Level {
        let kinds: Vec<CellKind> = (0..n[0] * n[1] * n[2])
            .map(|c| match natura_core::mix64(c as u64 ^ 0x51d) % 11 {
                0 => CellKind::Solid,
                1 => CellKind::Air,
                _ => CellKind::Fluid,
            })
            .collect();
        Level::new(n, kinds, [[false; 2]; 3], periodic)
    }

    fn random(l: &Level, seed: u64) -> Vec<f32> {
        let mut v: Vec<f32> = (0..l.len())
            .map(|p| {
                if l.mask[p] != 0 {
                    (natura_core::mix64(seed ^ p as u64) % 2001) as f32 / 997.0 - 1.0
                } else {
                    0.0
                }
            })
            .collect();
        l.fill_ghosts(&mut v);
        v
    }

    /// Runs `row(simd, s, out)` over every interior row at every supported
    /// SIMD level and checks each level's output equals the baseline's bit
    /// for bit.
    fn same_at_every_level<T: Real + PartialEq + std::fmt::Debug>(
        l: &Level,
        row: impl Fn(Simd, usize, &mut [T]),
    ) {
        let (p0, n0) = (l.pad[0], l.n[0]);
        for r in 0..l.rows() {
            let Some(base) = l.row_base(r) else { continue };
            let s = base + p0;
            let mut want = vec![T::default(); n0];
            row(Simd::baseline(), s, &mut want);
            for simd in Simd::supported() {
                let mut got = vec![T::default(); n0];
                row(simd, s, &mut got);
                for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                    let (g, w): (f64, f64) = ((*g).into(), (*w).into());
                    assert_eq!(g.to_bits(), w.to_bits(), "{:?} row {r} [{i}]", simd.level());
                }
            }
        }
    }

    fn check<const K: usize>(l: &Level) {
        let st = l.strides::<K>();
        let x = random(l, 1);
        let b = random(l, 2);
        let x64: Vec<f64> = x.iter().map(|&v| f64::from(v) * 3.0 + 1e3).collect();
        let b64: Vec<f64> = b.iter().map(|&v| f64::from(v)).collect();
        for colour in 0..2 {
            same_at_every_level::<f32>(l, |simd, s, out| {
                simd::run(
                    simd,
                    GsRow::<K> {
                        x: &x,
                        b: &b,
                        wc: &l.invc[colour],
                        s,
                        st,
                        out,
                    },
                )
            });
        }
        same_at_every_level::<f32>(l, |simd, s, out| {
            simd::run(
                simd,
                ResidualRow::<K, f32> {
                    x: &x,
                    b: &b,
                    diag: &l.diag,
                    s,
                    st,
                    out,
                },
            )
        });
        same_at_every_level::<f64>(l, |simd, s, out| {
            simd::run(
                simd,
                ResidualRow::<K, f64> {
                    x: &x64,
                    b: &b64,
                    diag: &l.diag,
                    s,
                    st,
                    out,
                },
            )
        });
        same_at_every_level::<f32>(l, |simd, s, out| {
            simd::run(
                simd,
                ApplyRow::<K, f32> {
                    lvl: l,
                    x: &x,
                    s,
                    st,
                    out,
                },
            )
        });
        same_at_every_level::<f64>(l, |simd, s, out| {
            simd::run(
                simd,
                ApplyRow::<K, f64> {
                    lvl: l,
                    x: &x64,
                    s,
                    st,
                    out,
                },
            )
        });
    }

    /// Restriction and prolongation rows at every SIMD level against the
    /// baseline, bit for bit.
    fn check_transfers(fine: &Level) {
        let (nc, ck) = coarsen(fine);
        let mut coarse = Level::new(nc, ck, fine.open, fine.periodic);
        coarse.x = random(&coarse, 5);
        let tr = Transfer::new(fine, &coarse);
        let r = random(fine, 6);
        let (lo_c, hi_c) = interior_range(coarse.n[0], fine.n[0], fine.n[0] > 1);
        let restrict = |simd: Simd| -> Vec<f32> {
            let mut out = vec![0.0f32; coarse.len()];
            let m0 = coarse.m[0];
            for (row_i, row) in out[G..G + coarse.rows() * m0].chunks_mut(m0).enumerate() {
                simd::run(
                    simd,
                    RestrictRow {
                        tr: &tr,
                        fine,
                        r: &r,
                        cl: &coarse,
                        lo_c,
                        hi_c,
                        row_i,
                        row,
                    },
                );
            }
            out
        };
        let prolong = |simd: Simd| -> Vec<f32> {
            let mut out = random(fine, 7);
            let m0 = fine.m[0];
            for (row_i, row) in out[G..G + fine.rows() * m0].chunks_mut(m0).enumerate() {
                simd::run(
                    simd,
                    ProlongRow {
                        tr: &tr,
                        coarse: &coarse,
                        fl: fine,
                        row_i,
                        row,
                    },
                );
            }
            out
        };
        let (rw, pw) = (restrict(Simd::baseline()), prolong(Simd::baseline()));
        for simd in Simd::supported() {
            let (rg, pg) = (restrict(simd), prolong(simd));
            assert!(rg.iter().zip(&rw).all(|(a, b)| a.to_bits() == b.to_bits()));
            assert!(pg.iter().zip(&pw).all(|(a, b)| a.to_bits() == b.to_bits()));
        }
    }

    /// The neighbour sums (which start from `+0` in registers) equal the
    /// earlier form that cleared the accumulator first and added every axis
    /// into it, bit for bit: `f32` and `f64` sums and the `f64` sum of `f32`
    /// data, signed zeros included, full and partial blocks.
    #[test]
    fn neighbour_sums_equal_the_cleared_accumulator_form() {
        fn cleared<T: Real>(x: &[T], c: usize, st: &[usize], acc: &mut [T]) {
            acc.fill(T::default());
            for &s in st {
                for (k, a) in acc.iter_mut().enumerate() {
                    *a = *a + (x[c + k - s] + x[c + k + s]);
                }
            }
        }
        fn check_k<const K: usize>(l: &Level) {
            let st = l.strides::<K>();
            let mut x = random(l, 9);
            // Negative zeros, so `+0 + (−0 + −0)` is exercised.
            for (p, v) in x.iter_mut().enumerate() {
                if p % 7 == 0 {
                    *v = -0.0;
                }
            }
            let x64: Vec<f64> = x.iter().map(|&v| f64::from(v)).collect();
            let (p0, n0) = (l.pad[0], l.n[0]);
            for r in 0..l.rows() {
                let Some(base) = l.row_base(r) else { continue };
                let s = base + p0;
                for w in [n0, n0 / 2 + 1, 1] {
                    let (mut got, mut want) = (vec![1.0f32; w], vec![2.0f32; w]);
                    neighbour_sum::<K, f32>(&x, s, st, &mut got);
                    cleared(&x, s, &st, &mut want);
                    assert!(
                        got.iter()
                            .zip(&want)
                            .all(|(a, b)| a.to_bits() == b.to_bits())
                    );
                    let (mut got, mut want) = (vec![1.0f64; w], vec![2.0f64; w]);
                    neighbour_sum::<K, f64>(&x64, s, st, &mut got);
                    cleared(&x64, s, &st, &mut want);
                    assert!(
                        got.iter()
                            .zip(&want)
                            .all(|(a, b)| a.to_bits() == b.to_bits())
                    );
                    let mut wide = vec![3.0f64; w];
                    neighbour_sum_wide::<K, f32>(&x, s, st, &mut wide);
                    assert!(
                        wide.iter()
                            .zip(&want)
                            .all(|(a, b)| a.to_bits() == b.to_bits())
                    );
                }
            }
        }
        check_k::<2>(&level([300, 1, 37], [false; 3]));
        check_k::<2>(&level([64, 1, 40], [true, false, false]));
        check_k::<3>(&level([21, 13, 9], [false; 3]));
        check_k::<3>(&level([16, 8, 12], [true, true, false]));
    }

    /// The dispatched row kernels (smoother half sweep, residual, operator,
    /// restriction, prolongation) give the same bits at every SIMD level as
    /// the baseline build.
    #[test]
    fn row_kernels_are_bit_identical_at_every_simd_level() {
        for (l, three) in [
            (level([300, 1, 37], [false; 3]), false),
            (level([64, 1, 40], [true, false, false]), false),
            (level([21, 13, 9], [false; 3]), true),
            (level([16, 8, 12], [true, true, false]), true),
        ] {
            if three {
                check::<3>(&l);
            } else {
                check::<2>(&l);
            }
            check_transfers(&l);
        }
    }
}
