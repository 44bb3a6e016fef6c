//! Grid transfers of the multigrid hierarchy: cell-kind coarsening, the
//! restriction `scale · Pᵀ` and the prolongation `P` (trilinear, ¾ ¼ weights
//! per axis), written once. [`Transfer::restrict`] and
//! [`Transfer::prolong_add`] run the row equations [`Transfer::restrict_row`]
//! and [`Transfer::prolong_row`] through the SIMD kernels of
//! [`super::kernels`]; the general per-cell forms below are their test
//! oracles.
//!
//! The hierarchy follows McAdams et al. 2010: cell-type-aware coarsening,
//! trilinear interpolation and its scaled transpose as restriction.

use super::kernels::{ProlongRow, RestrictRow};
use super::level::{GUARD, Level};
use crate::chunks;
use crate::grid::CellKind;
use natura_core::simd::{self, Simd};

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
        let d = fine.active.len() as i32;
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
        let body = &mut cb[GUARD..GUARD + cl.rows() * m0];
        // Coarse x cells whose four fine children 2c−1..=2c+2 are interior
        // with the standard weights.
        let (lo_c, hi_c) = interior_range(n0, nf0, fine.n[0] > 1);
        let simd = Simd::best();
        chunks::for_chunks(body, m0, |row_i, row| {
            simd::run(
                simd,
                RestrictRow {
                    tr: self,
                    fine,
                    r,
                    cl,
                    interior: (lo_c, hi_c),
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
        let body = &mut fx[GUARD..GUARD + fl.rows() * m0];
        let simd = Simd::best();
        chunks::for_chunks(body, m0, |row_i, row| {
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
        let body = &mut cb[GUARD..GUARD + cl.rows() * m0];
        chunks::for_chunks(body, m0, |row_i, row| {
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
        let body = &mut fx[GUARD..GUARD + fl.rows() * m0];
        chunks::for_chunks(body, m0, |row_i, row| {
            let Some((base, rows)) = self.coarse_rows(coarse, fl, row_i) else {
                return;
            };
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

    /// One coarse row `row_i` of [`Transfer::restrict`]: the contributing
    /// fine rows of `r` restricted along x (coarse cells `interior.0 ..
    /// interior.1` with the fixed ¼ ¾ ¾ ¼ weights, the others from the
    /// general weight lists) and summed with their y/z weights and the
    /// scale; zero off the coarse unknowns.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn restrict_row(
        &self,
        fine: &Level,
        r: &[f32],
        cl: &Level,
        interior: (usize, usize),
        row_i: usize,
        row: &mut [f32],
    ) {
        let tr = self;
        let (lo_c, hi_c) = interior;
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

    /// The coarse rows that fine row `row_i` interpolates from: the fine row's
    /// base index and the (up to four) coarse row starts with their y/z
    /// weights (¾ ¼ on an active axis, 1 0 on a flat one); `None` off the
    /// fine unknowns.
    #[inline(always)]
    fn coarse_rows(
        &self,
        coarse: &Level,
        fl: &Level,
        row_i: usize,
    ) -> Option<(usize, [(usize, f32); 4])> {
        let base = fl.row_base(row_i)?;
        let jf = row_i % fl.m[1] - fl.pad[1];
        let kf = row_i / fl.m[1] - fl.pad[2];
        let (jp, jn) = self.up[1][jf];
        let (kp, kn) = self.up[2][kf];
        let weights = |active: bool| if active { (0.75, 0.25) } else { (1.0, 0.0) };
        let (wjp, wjn) = weights(fl.n[1] > 1);
        let (wkp, wkn) = weights(fl.n[2] > 1);
        Some((
            base,
            [
                (coarse.pidx([0, jp, kp]), wjp * wkp),
                (coarse.pidx([0, jn, kp]), wjn * wkp),
                (coarse.pidx([0, jp, kn]), wjp * wkn),
                (coarse.pidx([0, jn, kn]), wjn * wkn),
            ],
        ))
    }

    /// One fine row `row_i` of [`Transfer::prolong_add`]: the (up to four)
    /// contributing coarse rows of `coarse.x` combined with their y/z
    /// weights, interpolated along x (¾ ¼ weights; the ends from the general
    /// lists) and added to the fine unknowns of `row`.
    #[inline(always)]
    pub(crate) fn prolong_row(&self, coarse: &Level, fl: &Level, row_i: usize, row: &mut [f32]) {
        let tr = self;
        let (p0, n0) = (fl.pad[0], fl.n[0]);
        let nc0 = coarse.n[0];
        let cx = &coarse.x;
        let active_x = fl.n[0] > 1;
        let Some((base, rows)) = tr.coarse_rows(coarse, fl, row_i) else {
            return;
        };
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
        // Each fine cell's value is added where the cell is an unknown
        // (every fine cell has a value: 2·nc0 ≥ n0 on an active axis).
        let mut put = |i: usize, a: f32| {
            if ds[i] != 0.0 {
                out[i] += a;
            }
        };
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
            put(i, even);
            if i + 1 < n0 {
                put(
                    i + 1,
                    if q + 1 < nc0 {
                        0.75 * c[q] + 0.25 * c[q + 1]
                    } else {
                        general(i + 1)
                    },
                );
            }
        }
    }
}

/// Coarse x cells `lo..hi` whose fine children `2c−1 ..= 2c+2` all exist
/// and carry the standard ¼ ¾ ¾ ¼ restriction weights (`nc` coarse and `nf`
/// fine cells; `(0, 0)` on a flat axis).
pub(crate) fn interior_range(nc: usize, nf: usize, active: bool) -> (usize, usize) {
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
