//! Implicit diffusion `(I − ν dt ∇²) w3 = w2` (Stam 1999, §2.2).
//!
//! The system is the FISHPAK discretisation of App. B (Stam 1999, App. B): diagonal
//! `1 + ν dt Σ 1/h²` per neighbour, off-diagonals `−ν dt/h²`. It is an
//! M-matrix, so the solution never exceeds the data's range and its energy
//! never grows. Samples marked fixed keep their values and act
//! as Dirichlet data; neighbours beyond the grid edge are omitted (zero-flux
//! Neumann), so the sum is conserved in a closed box. Solved by Chebyshev
//! iteration on the Gershgorin bounds of the spectrum to a relative residual
//! of 1e-6 (the general-form conjugate-gradient solve is kept as the test
//! oracle).

use crate::chunks;
use natura_core::simd::{self, Kernel, Simd};

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
/// (keeps its value, acts as a zero-flux wall). Returns the iteration count.
///
/// Same system and stopping rule as [`diffuse_ref`] (relative residual
/// `‖b − A x‖₂ ≤ 1e-6 ‖b‖₂`), solved by Chebyshev iteration instead of
/// conjugate gradients; see [`diffuse_in`].
#[cfg(test)]
pub(crate) fn diffuse(data: &mut [f32], n: [usize; 3], coef: f32, role: &[u8]) -> u32 {
    diffuse_in(&mut Scratch::default(), data, n, coef, role)
}

/// Work vectors of [`diffuse_in`], kept between calls so that a solver
/// step does not allocate (and page-fault) its grids per component.
#[derive(Clone, Debug, Default)]
pub(crate) struct Scratch {
    v: [Vec<f32>; 3],
}

/// Relative residual the diffusion solve reaches.
const TOL: f64 = 1e-6;
/// Iteration cap (never reached for `coef` below ≈ 10⁴ in 3-D).
const MAX_ITER: u32 = 10_000;

/// [`diffuse`] with caller-owned work vectors.
///
/// **Chebyshev iteration** (Saad, *Iterative Methods for Sparse Linear
/// Systems*, Alg. 12.1) on `A x = b`, `A = I + coef·L` restricted to the free
/// samples. By Gershgorin every eigenvalue lies in `[1, 1 + 2·coef·deg]`
/// (`deg` = neighbours per sample, 2 per active axis): the diagonal is
/// `1 + coef·(non-excluded neighbours)`, the off-diagonal row sum at most
/// `coef·(free neighbours)`. With these bounds the residual after `m` steps
/// obeys `‖r_m‖ ≤ ‖r_0‖ / T_m(σ)`, `σ = (λmax + λmin)/(λmax − λmin)`, so
/// the iteration stops as soon as that bound (with a factor 2 margin for
/// round-off) or the residual measured in the pass is below `1e-6 ‖b‖` —
/// the conjugate-gradient solve's tolerance. Each step is one fused pass
/// (no inner products but the residual norm, which the pass sums on the
/// fly): it computes the true residual `r_m = b − A x_m` from `x_m`, the
/// correction `d_m = a_m d_{m−1} + g_m r_m` and `x_{m+1} = x_m + d_m`.
/// The iterate holds the data on fixed samples, so the operator is the
/// plain neighbour difference `b_s − x_s + coef Σ (x_nb − x_s)` over
/// non-excluded in-grid neighbours and nothing has to be set up per call.
pub(crate) fn diffuse_in(
    scratch: &mut Scratch,
    data: &mut [f32],
    n: [usize; 3],
    coef: f32,
    role: &[u8],
) -> u32 {
    let deg = 2 * n.iter().filter(|&&m| m > 1).count();
    if coef == 0.0 || deg == 0 || data.is_empty() {
        return 0;
    }
    let len = data.len();
    let n0 = n[0];
    let masked = role.contains(&EXCLUDED);
    let (lmin, lmax) = (1.0f64, 1.0 + 2.0 * f64::from(coef) * deg as f64);
    let theta = 0.5 * (lmax + lmin);
    let delta = 0.5 * (lmax - lmin);
    let sigma = theta / delta;
    // Every element of each work vector is written before it is read.
    let mut take = |k: usize| {
        let mut v = std::mem::take(&mut scratch.v[k]);
        v.resize(len, 0.0);
        v
    };
    let (mut xa, mut xb, mut d) = (take(0), take(1), take(2));
    let simd = Simd::best();
    let pass = |x: &[f32], xo: &mut [f32], d: &mut [f32], first: bool, a: f32, g: f32| {
        let p = Pass {
            x,
            b: data,
            role,
            n,
            coef,
            first,
            a,
            g,
        };
        chunks::for_chunks2_sum2(xo, d, n0, |r, xo, d| {
            if masked {
                simd::run(simd, PassRow::<true> { p: &p, r, xo, d })
            } else {
                simd::run(simd, PassRow::<false> { p: &p, r, xo, d })
            }
        })
    };
    // Step 0 reads the data as x_0 and writes x_1 = x_0 + r_0/θ.
    let (rr0, bb) = pass(data, &mut xa, &mut d, true, 0.0, (1.0 / theta) as f32);
    let tol = TOL * bb.sqrt();
    let r0 = rr0.sqrt();
    let mut it = 0;
    if bb > 0.0 && r0 > tol {
        // x_m lives in `xa`; T_{m−1}, T_m of the bound.
        let (mut t_prev, mut t) = (1.0f64, sigma);
        let mut rho_prev = 1.0 / sigma;
        it = 1;
        while r0 / t > 0.5 * tol && it < MAX_ITER {
            let rho = 1.0 / (2.0 * sigma - rho_prev);
            let (a, g) = ((rho * rho_prev) as f32, (2.0 * rho / delta) as f32);
            let (rr, _) = pass(&xa, &mut xb, &mut d, false, a, g);
            if rr.sqrt() <= tol {
                break;
            }
            std::mem::swap(&mut xa, &mut xb);
            rho_prev = rho;
            (t_prev, t) = (t, 2.0 * sigma * t - t_prev);
            it += 1;
        }
        data.copy_from_slice(&xa);
    }
    scratch.v = [xa, xb, d];
    it
}

/// One Chebyshev step over the rows (see [`diffuse_in`]).
struct Pass<'a> {
    /// The iterate `x_m` (data on fixed samples).
    x: &'a [f32],
    /// The data: the right-hand side on free samples.
    b: &'a [f32],
    role: &'a [u8],
    n: [usize; 3],
    coef: f32,
    /// Step 0: `d_{−1}` is not read, and `‖b‖²` is summed.
    first: bool,
    /// `d_m = a d_{m−1} + g r_m`.
    a: f32,
    g: f32,
}

/// Row `r` of a [`Pass`] as a SIMD-dispatched kernel (`MASKED`: some
/// neighbours may be excluded).
struct PassRow<'a, const MASKED: bool> {
    p: &'a Pass<'a>,
    r: usize,
    xo: &'a mut [f32],
    d: &'a mut [f32],
}

impl<const MASKED: bool> Kernel for PassRow<'_, MASKED> {
    type Out = (f64, f64);

    /// Writes `x_{m+1}` and `d_m` of the row; returns `(‖r_m‖², ‖b‖²)` of
    /// the row (the latter on the first step only), in lane sums.
    #[inline(always)]
    fn call(self) -> (f64, f64) {
        let Self { p: this, r, xo, d } = self;
        this.row::<MASKED>(r, xo, d)
    }
}

impl Pass<'_> {
    /// Body of [`PassRow`].
    #[inline(always)]
    fn row<const MASKED: bool>(&self, r: usize, xo: &mut [f32], d: &mut [f32]) -> (f64, f64) {
        let (n, x, role) = (self.n, self.x, self.role);
        let n0 = n[0];
        let s0 = r * n0;
        let nbs = self.row_neighbours(r);
        let xr = &x[s0..s0 + n0];
        let (mut rr, mut bb) = (0.0f64, 0.0f64);
        let mut acc = [0.0f32; CH];
        let mut bacc = [0.0f32; CH];
        let mut res = [0.0f32; CH];
        for c0 in (0..n0).step_by(CH) {
            let w = CH.min(n0 - c0);
            let block = Block { s0, c0, w, nbs };
            let a = &mut acc[..w];
            self.neighbour_differences::<MASKED>(&block, a);
            if self.first {
                let ba = &mut bacc[..w];
                self.right_hand_side(&block, ba);
                bb += lane_dot(ba, ba);
            }
            // r = b − x + coef·acc on free samples (0 on fixed ones),
            // d = a d + g r (d = g r on the first step), x' = x + d.
            let rs = &mut res[..w];
            let (coef, g, a_) = (self.coef, self.g, self.a);
            let xs = &xr[c0..c0 + w];
            let bs = &self.b[s0 + c0..s0 + c0 + w];
            let ms = &role[s0 + c0..s0 + c0 + w];
            let (ds, xos) = (&mut d[c0..c0 + w], &mut xo[c0..c0 + w]);
            for ((((rv, &av), (&bv, &m)), &xv), (dv, xov)) in rs
                .iter_mut()
                .zip(a.iter())
                .zip(bs.iter().zip(ms))
                .zip(xs)
                .zip(ds.iter_mut().zip(xos.iter_mut()))
            {
                let t = bv - xv + coef * av;
                *rv = if m == FREE { t } else { 0.0 };
                let dn = if self.first {
                    g * *rv
                } else {
                    a_ * *dv + g * *rv
                };
                *dv = dn;
                *xov = xv + dn;
            }
            rr += lane_dot(rs, rs);
        }
        (rr, bb)
    }

    /// Starts of the rows beside row `r` that exist: below and above in y,
    /// then in z.
    #[inline(always)]
    fn row_neighbours(&self, r: usize) -> [Option<usize>; 4] {
        let n = self.n;
        let n0 = n[0];
        let s0 = r * n0;
        let (j, k) = (r % n[1], r / n[1]);
        let mut nbs: [Option<usize>; 4] = [None; 4];
        if n[1] > 1 {
            nbs[0] = (j > 0).then(|| s0 - n0);
            nbs[1] = (j + 1 < n[1]).then(|| s0 + n0);
        }
        if n[2] > 1 {
            let sz = n0 * n[1];
            nbs[2] = (k > 0).then(|| s0 - sz);
            nbs[3] = (k + 1 < n[2]).then(|| s0 + sz);
        }
        nbs
    }

    /// `a = Σ w_nb (x_nb − x_s)` over the block's samples: left, right,
    /// then the y and z rows (`w_nb` 0 for excluded neighbours when
    /// `MASKED`, else 1).
    #[inline(always)]
    fn neighbour_differences<const MASKED: bool>(&self, blk: &Block, a: &mut [f32]) {
        let (x, role, n0) = (self.x, self.role, self.n[0]);
        let Block { s0, c0, w, nbs } = *blk;
        let w_of = |m: u8| {
            if MASKED {
                f32::from(u8::from(m != EXCLUDED))
            } else {
                1.0
            }
        };
        let xr = &x[s0..s0 + n0];
        let xs = &xr[c0..c0 + w];
        a.fill(0.0);
        if n0 > 1 {
            let lo = c0.max(1);
            for ((av, &xn), (&xv, &m)) in a[lo - c0..].iter_mut().zip(&xr[lo - 1..c0 + w - 1]).zip(
                xr[lo..c0 + w]
                    .iter()
                    .zip(&role[s0 + lo - 1..s0 + c0 + w - 1]),
            ) {
                *av += w_of(m) * (xn - xv);
            }
            let hi = (c0 + w).min(n0 - 1);
            for ((av, &xn), (&xv, &m)) in a[..hi - c0]
                .iter_mut()
                .zip(&xr[c0 + 1..hi + 1])
                .zip(xr[c0..hi].iter().zip(&role[s0 + c0 + 1..s0 + hi + 1]))
            {
                *av += w_of(m) * (xn - xv);
            }
        }
        for &o in nbs.iter().flatten() {
            let (xn, rn) = (&x[o + c0..o + c0 + w], &role[o + c0..o + c0 + w]);
            for ((av, (&xn, &m)), &xv) in a.iter_mut().zip(xn.iter().zip(rn)).zip(xs) {
                *av += w_of(m) * (xn - xv);
            }
        }
    }

    /// The first step's right-hand side over the block:
    /// `b_s = data_s + coef Σ data_nb` over Dirichlet neighbours on free
    /// samples, 0 on fixed ones (`x_0` is the data).
    #[inline(always)]
    fn right_hand_side(&self, blk: &Block, ba: &mut [f32]) {
        let (x, role, n0) = (self.x, self.role, self.n[0]);
        let Block { s0, c0, w, nbs } = *blk;
        let xr = &x[s0..s0 + n0];
        ba.fill(0.0);
        let dir = |m: u8| f32::from(u8::from(m == DIRICHLET));
        if n0 > 1 {
            let lo = c0.max(1);
            for ((bv, &xn), &m) in ba[lo - c0..]
                .iter_mut()
                .zip(&xr[lo - 1..c0 + w - 1])
                .zip(&role[s0 + lo - 1..s0 + c0 + w - 1])
            {
                *bv += dir(m) * xn;
            }
            let hi = (c0 + w).min(n0 - 1);
            for ((bv, &xn), &m) in ba[..hi - c0]
                .iter_mut()
                .zip(&xr[c0 + 1..hi + 1])
                .zip(&role[s0 + c0 + 1..s0 + hi + 1])
            {
                *bv += dir(m) * xn;
            }
        }
        for &o in nbs.iter().flatten() {
            let (xn, rn) = (&x[o + c0..o + c0 + w], &role[o + c0..o + c0 + w]);
            for ((bv, &xn), &m) in ba.iter_mut().zip(xn).zip(rn) {
                *bv += dir(m) * xn;
            }
        }
        for ((bv, &v), &m) in ba
            .iter_mut()
            .zip(&self.b[s0 + c0..s0 + c0 + w])
            .zip(&role[s0 + c0..s0 + c0 + w])
        {
            let t = v + self.coef * *bv;
            *bv = if m == FREE { t } else { 0.0 };
        }
    }
}

/// One block of a row in [`Pass::row`]: the row's start `s0`, the block's
/// first column `c0` and width `w`, and the starts of the neighbouring rows.
#[derive(Clone, Copy)]
struct Block {
    s0: usize,
    c0: usize,
    w: usize,
    nbs: [Option<usize>; 4],
}

/// Row block length of the operator (stack accumulator).
const CH: usize = 256;

/// `Σ a·b` in `f64`, in eight lane sums added in a fixed order (so the
/// loop vectorises; deterministic).
#[inline(always)]
pub(crate) fn lane_dot(a: &[f32], b: &[f32]) -> f64 {
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
        chunks::for_chunks(y, chunks::BLOCK, |bi, yc| {
            let s0 = bi * chunks::BLOCK;
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
        chunks::sum_blocks(len.div_ceil(chunks::BLOCK), chunks::BLOCK, |bi| {
            let r = bi * chunks::BLOCK..((bi + 1) * chunks::BLOCK).min(len);
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
