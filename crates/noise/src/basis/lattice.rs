//! Shared lattice machinery for gradient and value noise: corner hashes and
//! the generic n-D point evaluator (value and analytic gradient, in f64).

use crate::hash::{corner, row1, row2, row3, row4};
use crate::lattice_math::split;

/// The hash of lattice corner `idx` (1 to 4 dimensions) under `seed`.
#[inline(always)]
pub(crate) fn corner_hash<const N: usize>(idx: [u32; N], seed: u32) -> u32 {
    match N {
        1 => corner(idx[0], row1(seed)),
        2 => corner(idx[0], row2(idx[1], seed)),
        3 => corner(idx[0], row3(idx[1], idx[2], seed)),
        _ => corner(idx[0], row4(idx[1], idx[2], idx[3], seed)),
    }
}

/// Sum over the 2ⁿ cell corners of `W_c(p)·φ_c(d)` with multilinear fade
/// weights `W_c`, where `φ_c(d)` and its gradient come from `corner_fn(hash, d)`
/// with `d = p − c`. Returns the value and analytic gradient.
#[inline(always)]
pub(crate) fn lattice_sum<const N: usize>(
    seed: u32,
    interp: impl Fn(f64) -> (f64, f64),
    p: [f64; N],
    corner_fn: impl Fn(u32, [f64; N]) -> (f64, [f64; N]),
) -> (f64, [f64; N]) {
    let mut base = [0u32; N];
    let mut f = [0.0; N];
    let mut u = [0.0; N];
    let mut du = [0.0; N];
    for a in 0..N {
        let (i, t) = split(p[a]);
        base[a] = i;
        f[a] = t;
        let (w, dw) = interp(t);
        u[a] = w;
        du[a] = dw;
    }
    let mut value = 0.0;
    let mut grad = [0.0; N];
    for c in 0..(1usize << N) {
        let mut idx = base;
        let mut d = f;
        let mut w = [0.0; N];
        let mut dw = [0.0; N];
        for a in 0..N {
            if c >> a & 1 == 1 {
                idx[a] = idx[a].wrapping_add(1);
                d[a] -= 1.0;
                w[a] = u[a];
                dw[a] = du[a];
            } else {
                w[a] = 1.0 - u[a];
                dw[a] = -du[a];
            }
        }
        let (phi, dphi) = corner_fn(corner_hash(idx, seed), d);
        let weight: f64 = w.iter().product();
        value += weight * phi;
        for a in 0..N {
            let mut dwa = dw[a];
            for (b, wb) in w.iter().enumerate() {
                if b != a {
                    dwa *= wb;
                }
            }
            grad[a] += weight * dphi[a] + dwa * phi;
        }
    }
    (value, grad)
}
