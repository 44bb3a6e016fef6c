//! One grid level of the pressure Poisson operator, stored padded with a
//! ghost layer on every non-flat axis so stencils never branch on borders.
//!
//! The operator is the compact (2d+1)-point Laplacian, scaled by `−h²`:
//! `(A x)_c = Σ_{non-solid n} (x_c − x_n)` over the face neighbours `n` of a
//! fluid cell `c`, with `x_n = 0` for air/open neighbours (Dirichlet). It is
//! symmetric positive semi-definite — the negation of the matrix Foster &
//! Fedkiw print (erratum E5: their `a_ii = −#liquid neighbours` makes it
//! negative definite; CG needs the negated form).

use crate::grid::{Boundaries, CellKind, Side};
use crate::par;

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
            kinds,
            open,
            x: vec![0.0; len],
            b: vec![0.0; len],
            t: vec![0.0; len],
        };
        lvl.build_mask();
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

    /// Parity of the first interior cell of row `r` ((j + k) mod 2).
    #[inline]
    fn row_parity(&self, r: usize) -> usize {
        let jp = r % self.m[1] - self.pad[1];
        let kp = r / self.m[1] - self.pad[2];
        (jp + kp) & 1
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

    fn strides<const K: usize>(&self) -> [usize; K] {
        std::array::from_fn(|q| self.st[self.act[q]])
    }

    fn apply_k<const K: usize, T: Real>(&self, x: &[T], y: &mut [T]) {
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
        self.rows_par(out, |r, base, orow| {
            let s = base + p0;
            let xs = &x[s..s + n0];
            let bs = &b[s..s + n0];
            let ms = &self.mask[s..s + n0];
            let lo: [&[f32]; K] = std::array::from_fn(|q| &x[s - st[q]..s - st[q] + n0]);
            let hi: [&[f32]; K] = std::array::from_fn(|q| &x[s + st[q]..s + st[q] + n0]);
            let o = &mut orow[p0..p0 + n0];
            // Interior cell i is updated when (i + j + k) ≡ colour (mod 2).
            let want = (colour + self.row_parity(r)) & 1;
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

    /// `r = b − A x` on fluid cells; `x` ghosts filled first if periodic.
    pub fn residual<T: Real>(&self, b: &[T], x: &mut [T], r: &mut [T]) {
        if self.periodic.iter().any(|&p| p) {
            self.fill_ghosts(x);
        }
        self.apply(x, r);
        let m0 = self.m[0];
        let (p0, n0) = (self.pad[0], self.n[0]);
        self.rows_par(r, |_, base, row| {
            for i in p0..p0 + n0 {
                row[i] = b[base + i] - row[i];
            }
        });
        let _ = m0;
    }

    /// `Σ a·b` over interior cells, in `f64`, deterministic.
    pub fn dot<A: Copy + Into<f64> + Sync, B: Copy + Into<f64> + Sync>(
        &self,
        a: &[A],
        b: &[B],
    ) -> f64 {
        let (p0, n0, m0) = (self.pad[0], self.n[0], self.m[0]);
        par::sum_blocks(self.rows(), n0, |r| match self.row_base(r) {
            Some(base) => {
                let s = base + p0;
                let _ = m0;
                a[s..s + n0]
                    .iter()
                    .zip(&b[s..s + n0])
                    .map(|(&x, &y)| x.into() * y.into())
                    .sum()
            }
            None => 0.0,
        })
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
    pub fn restrict(&self, fine: &Level, r: &[f32], coarse: &mut Level) {
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

    /// `fine.x += P coarse.x` on fine fluid cells.
    pub fn prolong_add(&self, coarse: &Level, fine: &mut Level) {
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
