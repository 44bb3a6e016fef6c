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
pub(crate) fn diffuse(data: &mut [f32], n: [usize; 3], coef: f32, role: &[u8]) -> u32 {
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
