//! Implicit diffusion `(I − ν dt ∇²) w3 = w2` (Stable Fluids L1780-1788).
//!
//! The system is the FISHPAK discretisation of App. B (L1958-1960): diagonal
//! `1 + ν dt Σ 1/h²` per neighbour, off-diagonals `−ν dt/h²`. It is an
//! M-matrix, so the solution never exceeds the data's range and its energy
//! never grows (spec §6.4 S2). Samples marked fixed keep their values and act
//! as Dirichlet data; neighbours beyond the grid edge are omitted (zero-flux
//! Neumann), so the sum is conserved in a closed box. Solved by
//! Jacobi-preconditioned conjugate gradient to a relative residual of 1e-6.

use crate::par;

/// An unknown sample.
pub(crate) const FREE: u8 = 0;
/// A fixed sample that acts as Dirichlet data for its neighbours.
pub(crate) const DIRICHLET: u8 = 1;
/// A fixed sample that acts as a zero-flux wall.
pub(crate) const EXCLUDED: u8 = 2;

/// Solves the implicit diffusion of one gridded component in place.
///
/// `n`: sample counts; `coef = ν dt / h²`; `role[s]` is [`FREE`],
/// [`DIRICHLET`] (keeps its value, feeds neighbours) or [`EXCLUDED`]
/// (keeps its value, acts as a zero-flux wall). Returns the CG iteration count.
///
/// Row-wise form of [`diffuse_ref`] (same system, same stopping rule): every
/// CG vector is kept zero on fixed samples, so the coupling of a free sample
/// is the plain sum of its in-grid neighbours and the operator runs over
/// contiguous rows without per-sample branching.
#[cfg(test)]
pub(crate) fn diffuse(data: &mut [f32], n: [usize; 3], coef: f32, role: &[u8]) -> u32 {
    diffuse_in(&mut Scratch::default(), data, n, coef, role)
}

/// Work vectors of [`diffuse_in`], kept between calls so that a solver
/// step does not allocate (and page-fault) seven grids per component.
#[derive(Clone, Debug, Default)]
pub(crate) struct Scratch {
    v: [Vec<f32>; 7],
}

/// [`diffuse`] with caller-owned work vectors.
pub(crate) fn diffuse_in(
    scratch: &mut Scratch,
    data: &mut [f32],
    n: [usize; 3],
    coef: f32,
    role: &[u8],
) -> u32 {
    if coef == 0.0 {
        return 0;
    }
    let len = data.len();
    let n0 = n[0];
    // Every element of each work vector is written before it is read.
    let mut take = |k: usize| {
        let mut v = std::mem::take(&mut scratch.v[k]);
        v.resize(len, 0.0);
        v
    };
    let (mut dg, mut b, mut x, mut r, mut inv, mut p, mut q) = (
        take(0),
        take(1),
        take(2),
        take(3),
        take(4),
        take(5),
        take(6),
    );
    // Diagonal (0 on fixed samples), right-hand side (Dirichlet
    // neighbours' values moved to it), the initial iterate (the data on
    // free samples, 0 on fixed ones) and the Jacobi weights `1/A_ss` (0 on
    // fixed samples), row by row in one parallel pass.
    {
        let data: &[f32] = data;
        let mut vs: [&mut [f32]; 4] = [&mut dg, &mut b, &mut x, &mut inv];
        par::for_bands(&mut vs, n0, |r, rows| {
            let [drow, brow, xrow, irow] = rows else {
                unreachable!("four vectors per band")
            };
            let s0 = r * n0;
            let (j, k) = (r % n[1], r / n[1]);
            let mut nbs: [Option<usize>; 4] = [None; 4];
            if n[1] > 1 {
                nbs[0] = (j > 0).then(|| s0 - n0);
                nbs[1] = (j + 1 < n[1]).then(|| s0 + n0);
            }
            if n[2] > 1 {
                nbs[2] = (k > 0).then(|| s0 - n0 * n[1]);
                nbs[3] = (k + 1 < n[2]).then(|| s0 + n0 * n[1]);
            }
            // Neighbour by neighbour in the general form's order (left,
            // right, then the y and z rows), over contiguous slices.
            for ((dv, bv), &v) in drow.iter_mut().zip(brow.iter_mut()).zip(&data[s0..s0 + n0]) {
                *dv = 1.0;
                *bv = v;
            }
            let add = |drow: &mut [f32], brow: &mut [f32], nr: &[u8], nd: &[f32]| {
                for ((dv, bv), (&m, &v)) in
                    drow.iter_mut().zip(brow.iter_mut()).zip(nr.iter().zip(nd))
                {
                    // Selects, not branches (conditional stores), so the
                    // loop vectorises; the same values.
                    let (d1, b1) = (*dv + coef, *bv + coef * v);
                    *dv = if m != EXCLUDED { d1 } else { *dv };
                    *bv = if m == DIRICHLET { b1 } else { *bv };
                }
            };
            if n0 > 1 {
                let (l, h) = (s0..s0 + n0 - 1, s0 + 1..s0 + n0);
                add(&mut drow[1..], &mut brow[1..], &role[l.clone()], &data[l]);
                add(
                    &mut drow[..n0 - 1],
                    &mut brow[..n0 - 1],
                    &role[h.clone()],
                    &data[h],
                );
            }
            for &nb in nbs.iter().flatten() {
                add(drow, brow, &role[nb..nb + n0], &data[nb..nb + n0]);
            }
            for ((dv, bv), &m) in drow.iter_mut().zip(brow.iter_mut()).zip(&role[s0..s0 + n0]) {
                let free = m == FREE;
                *dv = if free { *dv } else { 0.0 };
                *bv = if free { *bv } else { 0.0 };
            }
            for (((xv, iv), &d), &v) in xrow
                .iter_mut()
                .zip(irow.iter_mut())
                .zip(drow.iter())
                .zip(&data[s0..s0 + n0])
            {
                *xv = if d != 0.0 { v } else { 0.0 };
                *iv = if d != 0.0 { 1.0 / d } else { 0.0 };
            }
        });
    }
    // `y = A x` row by row (x zero on fixed samples); returns `Σ x·y` in
    // `f64`, summed per row and the rows in order (deterministic).
    let apply = |x: &[f32], y: &mut [f32]| -> f64 {
        par::for_chunks_sum(y, n0, |r, yrow| {
            let s0 = r * n0;
            let (j, k) = (r % n[1], r / n[1]);
            let xr = &x[s0..s0 + n0];
            let mut nb: [Option<&[f32]>; 4] = [None; 4];
            if n[1] > 1 {
                nb[0] = (j > 0).then(|| &x[s0 - n0..s0]);
                nb[1] = (j + 1 < n[1]).then(|| &x[s0 + n0..s0 + 2 * n0]);
            }
            if n[2] > 1 {
                let sz = n0 * n[1];
                nb[2] = (k > 0).then(|| &x[s0 - sz..s0 - sz + n0]);
                nb[3] = (k + 1 < n[2]).then(|| &x[s0 + sz..s0 + sz + n0]);
            }
            let ds = &dg[s0..s0 + n0];
            let mut acc = [0.0f32; CH];
            let mut dot = 0.0f64;
            for c0 in (0..n0).step_by(CH) {
                let w = CH.min(n0 - c0);
                let a = &mut acc[..w];
                a.fill(0.0);
                // The same summation order as the general form: left, right,
                // then the y and z neighbour rows.
                if n0 > 1 {
                    let lo = c0.max(1);
                    for (av, &v) in a[lo - c0..].iter_mut().zip(&xr[lo - 1..c0 + w - 1]) {
                        *av += v;
                    }
                    let hi = (c0 + w).min(n0 - 1);
                    for (av, &v) in a[..hi - c0].iter_mut().zip(&xr[c0 + 1..hi + 1]) {
                        *av += v;
                    }
                }
                for row in nb.iter().flatten() {
                    for (av, &v) in a.iter_mut().zip(&row[c0..c0 + w]) {
                        *av += v;
                    }
                }
                for (((o, &xv), &d), &av) in yrow[c0..c0 + w]
                    .iter_mut()
                    .zip(&xr[c0..c0 + w])
                    .zip(&ds[c0..c0 + w])
                    .zip(a.iter())
                {
                    let v = d * xv - coef * av;
                    *o = if d != 0.0 { v } else { 0.0 };
                }
                dot += lane_dot(&xr[c0..c0 + w], &yrow[c0..c0 + w]);
            }
            dot
        })
    };
    let dot = |a: &[f32], b: &[f32]| {
        par::sum_blocks(len.div_ceil(par::BLOCK), par::BLOCK, |bi| {
            let r = bi * par::BLOCK..((bi + 1) * par::BLOCK).min(len);
            lane_dot(&a[r.clone()], &b[r])
        })
    };
    // r = b − A x, then p = z = M⁻¹ r with the Jacobi preconditioner
    // `M = diag(A)`.
    apply(&x, &mut r);
    let (mut rz, mut rr) = par::for_chunks2_sum2(&mut r, &mut p, par::BLOCK, |bi, rc, pc| {
        let s0 = bi * par::BLOCK;
        let m = rc.len();
        for (((rv, pv), &bv), &iv) in rc
            .iter_mut()
            .zip(pc.iter_mut())
            .zip(&b[s0..s0 + m])
            .zip(&inv[s0..s0 + m])
        {
            *rv = if iv != 0.0 { bv - *rv } else { 0.0 };
            *pv = *rv * iv;
        }
        // r·z and r·r in lane sums (as in the iteration below).
        (lane_dot(rc, pc), lane_dot(rc, rc))
    });
    let bn = dot(&b, &b).sqrt();
    let mut it = 0;
    while it < 200 && bn > 0.0 && rr.sqrt() > 1e-6 * bn {
        it += 1;
        let pq = apply(&p, &mut q);
        if pq <= 0.0 {
            break;
        }
        let alpha = (rz / pq) as f32;
        // x += αp, r −= αq, and the new r·z and r·r (z = M⁻¹r not stored).
        let (p_ref, q_ref) = (&p, &q);
        let (rz2, rr2) = par::for_chunks2_sum2(&mut x, &mut r, par::BLOCK, |bi, xc, rc| {
            let s0 = bi * par::BLOCK;
            let m = xc.len();
            for (((xv, rv), &pv), &qv) in xc
                .iter_mut()
                .zip(rc.iter_mut())
                .zip(&p_ref[s0..s0 + m])
                .zip(&q_ref[s0..s0 + m])
            {
                *xv += alpha * pv;
                *rv -= alpha * qv;
            }
            // r·z (z = r/A_ss, rounded to f32 as before) and r·r of the
            // block while it is in cache, in eight lane sums so that both
            // loops vectorise (a single running sum keeps them scalar).
            let rc: &[f32] = rc;
            let iv = &inv[s0..s0 + m];
            let (mut lz, mut lr) = ([0.0f64; 8], [0.0f64; 8]);
            let (r8, i8) = (rc.chunks_exact(8), iv.chunks_exact(8));
            let (rt, it) = (r8.remainder(), i8.remainder());
            for (rs, is) in r8.zip(i8) {
                for l in 0..8 {
                    let rv = f64::from(rs[l]);
                    lz[l] += rv * f64::from(rs[l] * is[l]);
                    lr[l] += rv * rv;
                }
            }
            let (mut rz, mut rr) = (lz.iter().sum::<f64>(), lr.iter().sum::<f64>());
            for (&r, &i) in rt.iter().zip(it) {
                rz += f64::from(r) * f64::from(r * i);
                rr += f64::from(r) * f64::from(r);
            }
            (rz, rr)
        });
        rr = rr2;
        let unconverged = rr.sqrt() > 1e-6 * bn;
        if !unconverged {
            break;
        }
        let beta = (rz2 / rz) as f32;
        rz = rz2;
        let r_ref = &r;
        par::for_chunks(&mut p, par::BLOCK, |bi, pc| {
            let s0 = bi * par::BLOCK;
            let m = pc.len();
            for ((pv, &rv), &iv) in pc.iter_mut().zip(&r_ref[s0..s0 + m]).zip(&inv[s0..s0 + m]) {
                *pv = rv * iv + beta * *pv;
            }
        });
    }
    for ((o, &xv), &d) in data.iter_mut().zip(&x).zip(&dg) {
        if d != 0.0 {
            *o = xv;
        }
    }
    scratch.v = [dg, b, x, r, inv, p, q];
    it
}

/// Row block length of the operator (stack accumulator).
const CH: usize = 256;

/// `Σ a·b` in `f64`, in eight lane sums added in a fixed order (so the
/// loop vectorises; deterministic).
#[inline(always)]
fn lane_dot(a: &[f32], b: &[f32]) -> f64 {
    let mut lanes = [0.0f64; 8];
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let (at, bt) = (a8.remainder(), b8.remainder());
    for (x, y) in a8.zip(b8) {
        for l in 0..8 {
            lanes[l] += f64::from(x[l]) * f64::from(y[l]);
        }
    }
    let mut s = lanes.iter().sum::<f64>();
    for (&x, &y) in at.iter().zip(bt) {
        s += f64::from(x) * f64::from(y);
    }
    s
}

/// The general per-sample form of [`diffuse`], kept as its test oracle.
#[cfg(test)]
pub(crate) fn diffuse_ref(data: &mut [f32], n: [usize; 3], coef: f32, role: &[u8]) -> u32 {
    let fixed: Vec<bool> = role.iter().map(|&r| r != FREE).collect();
    let excluded = |s: usize| role[s] == EXCLUDED;
    if coef == 0.0 {
        return 0;
    }
    let len = data.len();
    let st = [1usize, n[0], n[0] * n[1]];
    let coord = |s: usize| [s % n[0], (s / n[0]) % n[1], s / (n[0] * n[1])];
    // Diagonal and right-hand side (fixed neighbours move to the RHS).
    let mut diag = vec![1.0f32; len];
    let mut b = data.to_vec();
    for s in 0..len {
        if fixed[s] {
            continue;
        }
        let c = coord(s);
        for a in 0..3 {
            if n[a] == 1 {
                continue;
            }
            for (ok, nb) in [
                (c[a] > 0, s.wrapping_sub(st[a])),
                (c[a] + 1 < n[a], s + st[a]),
            ] {
                if ok && !excluded(nb) {
                    diag[s] += coef;
                    if fixed[nb] {
                        b[s] += coef * data[nb];
                    }
                }
            }
        }
    }
    let apply = |x: &[f32], y: &mut [f32]| {
        par::for_chunks(y, par::BLOCK, |bi, yc| {
            let s0 = bi * par::BLOCK;
            for (o, yv) in yc.iter_mut().enumerate() {
                let s = s0 + o;
                if fixed[s] {
                    *yv = 0.0;
                    continue;
                }
                let c = coord(s);
                let mut off = 0.0f32;
                for a in 0..3 {
                    if n[a] == 1 {
                        continue;
                    }
                    if c[a] > 0 && !fixed[s - st[a]] {
                        off += x[s - st[a]];
                    }
                    if c[a] + 1 < n[a] && !fixed[s + st[a]] {
                        off += x[s + st[a]];
                    }
                }
                *yv = diag[s] * x[s] - coef * off;
            }
        });
    };
    let dot = |a: &[f32], b: &[f32]| {
        par::sum_blocks(len.div_ceil(par::BLOCK), par::BLOCK, |bi| {
            let r = bi * par::BLOCK..((bi + 1) * par::BLOCK).min(len);
            a[r.clone()]
                .iter()
                .zip(&b[r])
                .map(|(&x, &y)| f64::from(x) * f64::from(y))
                .sum()
        })
    };
    let mut x: Vec<f32> = data
        .iter()
        .zip(&fixed)
        .map(|(&v, &f)| if f { 0.0 } else { v })
        .collect();
    let mut r = vec![0.0f32; len];
    apply(&x, &mut r);
    for s in 0..len {
        r[s] = if fixed[s] { 0.0 } else { b[s] - r[s] };
    }
    let bn = dot(
        &b.iter()
            .zip(&fixed)
            .map(|(&v, &f)| if f { 0.0 } else { v })
            .collect::<Vec<_>>(),
        &b,
    )
    .abs()
    .sqrt();
    let mut z: Vec<f32> = r.iter().zip(&diag).map(|(&v, &d)| v / d).collect();
    let mut p = z.clone();
    let mut q = vec![0.0f32; len];
    let mut rz = dot(&r, &z);
    let mut it = 0;
    while it < 200 && bn > 0.0 && dot(&r, &r).sqrt() > 1e-6 * bn {
        it += 1;
        apply(&p, &mut q);
        let pq = dot(&p, &q);
        if pq <= 0.0 {
            break;
        }
        let alpha = (rz / pq) as f32;
        for s in 0..len {
            x[s] += alpha * p[s];
            r[s] -= alpha * q[s];
        }
        for s in 0..len {
            z[s] = r[s] / diag[s];
        }
        let rz2 = dot(&r, &z);
        let beta = (rz2 / rz) as f32;
        rz = rz2;
        for s in 0..len {
            p[s] = z[s] + beta * p[s];
        }
    }
    for s in 0..len {
        if !fixed[s] {
            data[s] = x[s];
        }
    }
    it
}
