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
pub(crate) fn diffuse(data: &mut [f32], n: [usize; 3], coef: f32, role: &[u8]) -> u32 {
    if coef == 0.0 {
        return 0;
    }
    let len = data.len();
    let n0 = n[0];
    // Diagonal (0 on fixed samples) and right-hand side (Dirichlet
    // neighbours' values moved to it), row by row.
    let mut dg = vec![0.0f32; len];
    let mut b = vec![0.0f32; len];
    {
        let data: &[f32] = data;
        par::for_chunks2(&mut dg, &mut b, n0, |r, drow, brow| {
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
            for i in 0..n0 {
                let s = s0 + i;
                if role[s] != FREE {
                    continue;
                }
                let mut d = 1.0f32;
                let mut rhs = data[s];
                let mut visit = |nb: usize| {
                    if role[nb] != EXCLUDED {
                        d += coef;
                        if role[nb] == DIRICHLET {
                            rhs += coef * data[nb];
                        }
                    }
                };
                if n0 > 1 {
                    if i > 0 {
                        visit(s - 1);
                    }
                    if i + 1 < n0 {
                        visit(s + 1);
                    }
                }
                for nb in nbs.iter().flatten() {
                    visit(nb + i);
                }
                drow[i] = d;
                brow[i] = rhs;
            }
        });
    }
    // y = A x for x zero on fixed samples.
    let apply = |x: &[f32], y: &mut [f32]| {
        par::for_chunks(y, n0, |r, yrow| {
            let s0 = r * n0;
            let (j, k) = (r % n[1], r / n[1]);
            let xr = &x[s0..s0 + n0];
            let mut acc = vec![0.0f32; n0];
            if n0 > 1 {
                for (a, &v) in acc[1..].iter_mut().zip(&xr[..n0 - 1]) {
                    *a += v;
                }
                for (a, &v) in acc[..n0 - 1].iter_mut().zip(&xr[1..]) {
                    *a += v;
                }
            }
            let mut add_row = |start: usize| {
                for (a, &v) in acc.iter_mut().zip(&x[start..start + n0]) {
                    *a += v;
                }
            };
            if n[1] > 1 {
                if j > 0 {
                    add_row(s0 - n0);
                }
                if j + 1 < n[1] {
                    add_row(s0 + n0);
                }
            }
            if n[2] > 1 {
                if k > 0 {
                    add_row(s0 - n0 * n[1]);
                }
                if k + 1 < n[2] {
                    add_row(s0 + n0 * n[1]);
                }
            }
            let ds = &dg[s0..s0 + n0];
            for (((o, &xv), &d), &a) in yrow.iter_mut().zip(xr).zip(ds).zip(&acc) {
                let v = d * xv - coef * a;
                *o = if d != 0.0 { v } else { 0.0 };
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
        .zip(&dg)
        .map(|(&v, &d)| if d != 0.0 { v } else { 0.0 })
        .collect();
    let mut r = vec![0.0f32; len];
    apply(&x, &mut r);
    par::for_chunks(&mut r, par::BLOCK, |bi, rc| {
        let s0 = bi * par::BLOCK;
        for (o, (&bv, &d)) in rc.iter_mut().zip(b[s0..].iter().zip(&dg[s0..])) {
            *o = if d != 0.0 { bv - *o } else { 0.0 };
        }
    });
    // b is zero on fixed samples, so ‖b‖ is over the free ones.
    let bn = dot(&b, &b).sqrt();
    let inv: Vec<f32> = dg
        .iter()
        .map(|&d| if d != 0.0 { 1.0 / d } else { 0.0 })
        .collect();
    let mut z: Vec<f32> = r.iter().zip(&inv).map(|(&v, &d)| v * d).collect();
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
        {
            let (p, q) = (&p, &q);
            par::for_chunks2(&mut x, &mut r, par::BLOCK, |bi, xc, rc| {
                let s0 = bi * par::BLOCK;
                let m = xc.len();
                for (((xv, rv), &pv), &qv) in xc
                    .iter_mut()
                    .zip(rc.iter_mut())
                    .zip(&p[s0..s0 + m])
                    .zip(&q[s0..s0 + m])
                {
                    *xv += alpha * pv;
                    *rv -= alpha * qv;
                }
            });
            let r = &r;
            par::for_chunks(&mut z, par::BLOCK, |bi, zc| {
                let s0 = bi * par::BLOCK;
                let m = zc.len();
                for ((zv, &rv), &iv) in zc.iter_mut().zip(&r[s0..s0 + m]).zip(&inv[s0..s0 + m]) {
                    *zv = rv * iv;
                }
            });
        }
        let rz2 = dot(&r, &z);
        let beta = (rz2 / rz) as f32;
        rz = rz2;
        let z = &z;
        par::for_chunks(&mut p, par::BLOCK, |bi, pc| {
            let s0 = bi * par::BLOCK;
            let m = pc.len();
            for (pv, &zv) in pc.iter_mut().zip(&z[s0..s0 + m]) {
                *pv = zv + beta * *pv;
            }
        });
    }
    for ((o, &xv), &d) in data.iter_mut().zip(&x).zip(&dg) {
        if d != 0.0 {
            *o = xv;
        }
    }
    it
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
