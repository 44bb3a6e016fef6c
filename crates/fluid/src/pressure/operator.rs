//! The discrete pressure Poisson operator's equations, written once: the
//! stencil, the residual, the red–black Gauss–Seidel update and the row
//! reductions. Every path calls these functions — the level's sweeps
//! ([`super::level`]), the SIMD row kernels ([`super::kernels`]) and the
//! test oracles.
//!
//! The operator is the compact (2d+1)-point Laplacian, scaled by `−h²`:
//! `(A x)_c = Σ_{non-solid n} (x_c − x_n)` over the face neighbours `n` of a
//! fluid cell `c`, with `x_n = 0` for air/open neighbours (Dirichlet). It is
//! symmetric positive semi-definite — the negation of the matrix Foster &
//! Fedkiw print (an erratum in Foster & Fedkiw 2001, §8: their
//! `a_ii = −#liquid neighbours` makes it negative definite; CG needs the
//! negated form).
//!
//! The row functions rely on one invariant of every vector they read: values
//! are zero on padded cells that are not unknowns (solid, air, isolated
//! fluid, non-periodic ghosts), and periodic ghosts hold wrapped copies. Then
//! the coupling `Σ_n x_n` over the coupled neighbours equals the plain sum
//! over all 2K face neighbours (solid and Dirichlet neighbours contribute
//! zero), so the stencil needs no per-cell mask decoding and the loops
//! vectorise. Padding the right-hand side, the restriction and prolongation,
//! and the smoother all preserve the invariant.

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

/// Row block length of the stencil rows (even, so colour parity is per block).
pub(crate) const CH: usize = 256;

/// Lane count of the row reductions.
pub(crate) const LANES: usize = 8;

/// `acc[k] = Σ_q x[c + k − st_q] + x[c + k + st_q]` for `k < acc.len()`:
/// the sum of the 2K face neighbours along the active axes with strides `st`.
#[inline(always)]
pub(crate) fn neighbour_sum<const K: usize, T: Real>(
    x: &[T],
    c: usize,
    st: [usize; K],
    acc: &mut [T],
) {
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
pub(crate) fn neighbour_sum_wide<const K: usize, T: Real>(
    x: &[T],
    c: usize,
    st: [usize; K],
    acc: &mut [f64],
) {
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

/// `(A x)_c` of one cell from its diagonal `d`, value `xv` and neighbour
/// sum `off` (in `f64`), rounded once; zero off the unknowns (`d = 0`).
#[inline(always)]
pub(crate) fn apply_cell<T: Real>(d: f32, xv: T, off: f64) -> T {
    let v = f64::from(d) * xv.into() - off;
    if d != 0.0 {
        T::from_f64(v)
    } else {
        T::default()
    }
}

/// `out` = (A x) over the row of unknowns starting at padded index `s`
/// (diagonal `diag`, active-axis strides `st`).
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
pub(crate) fn apply_row<const K: usize, T: Real>(
    diag: &[f32],
    x: &[T],
    s: usize,
    st: [usize; K],
    out: &mut [T],
) {
    let n0 = out.len();
    let mut acc = [0.0f64; CH];
    for i0 in (0..n0).step_by(CH) {
        let w = CH.min(n0 - i0);
        let a = &mut acc[..w];
        let c = s + i0;
        neighbour_sum_wide::<K, T>(x, c, st, a);
        let xs = &x[c..c + w];
        let ds = &diag[c..c + w];
        for (((o, &xv), &d), &off) in out[i0..i0 + w].iter_mut().zip(xs).zip(ds).zip(&*a) {
            *o = apply_cell(d, xv, off);
        }
    }
}

/// The Gauss–Seidel update of one cell: `(b + Σ neighbours)·w` where the
/// colour's weight `w = 1/A_cc` is non-zero, else the old value `xv`.
#[inline(always)]
pub(crate) fn gs_cell(xv: f32, bv: f32, w: f32, off: f32) -> f32 {
    let v = (bv + off) * w;
    // A select, not a branch, so the loop vectorises.
    if w != 0.0 { v } else { xv }
}

/// One row of a red–black half sweep: `out` = `x` with the cells of
/// non-zero weight `wc` replaced by [`gs_cell`].
#[inline(always)]
pub(crate) fn gs_row<const K: usize>(
    x: &[f32],
    b: &[f32],
    wc: &[f32],
    s: usize,
    st: [usize; K],
    out: &mut [f32],
) {
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
            *ov = gs_cell(xv, bv, iv, off);
        }
    }
}

/// The residual `b − A x` of one cell (zero off the unknowns).
#[inline(always)]
pub(crate) fn residual_cell<T: Real>(d: f32, xv: T, bv: T, off: T) -> T {
    let v = bv - (T::from(d) * xv - off);
    if d != 0.0 { v } else { T::default() }
}

/// One row of the residual `r = b − A x`, in `T` throughout.
#[inline(always)]
pub(crate) fn residual_row<const K: usize, T: Real>(
    x: &[T],
    b: &[T],
    diag: &[f32],
    s: usize,
    st: [usize; K],
    out: &mut [T],
) {
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
            *o = residual_cell(d, xv, bv, off);
        }
    }
}

/// `Σ a·b` in `f64` over one row: element `i` goes to lane `i mod 8` for
/// the full groups of eight, the lanes are added in order and the tail
/// elements after them. Eight independent sums instead of one running sum:
/// a single `f64` chain is latency-bound (one add per four cycles), which
/// would make it the dominant cost of the CG's dot products; the fixed
/// grouping keeps the result deterministic and identical at every SIMD level.
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

/// `Σ v` in `f64` over one row, in [`LANES`] lane sums as [`lane_dot`].
#[inline(always)]
pub(crate) fn lane_sum<T: Copy + Into<f64>>(row: &[T]) -> f64 {
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

/// The operator's general per-cell form, decoding the coupling mask
/// (bit `2q`/`2q+1` = coupled to the −/+ neighbour along the q-th active
/// axis, bits 8.. = the diagonal): the test oracle of [`apply_row`].
#[cfg(test)]
pub(crate) fn apply_masked<const K: usize, T: Real>(m: u16, xv: T, lo: [T; K], hi: [T; K]) -> T {
    let mut off = T::default();
    for q in 0..K {
        off = off
            + T::from(f32::from((m >> (2 * q)) & 1)) * lo[q]
            + T::from(f32::from((m >> (2 * q + 1)) & 1)) * hi[q];
    }
    T::from(f32::from(m >> 8)) * xv - off
}

/// The Gauss–Seidel update in the general per-cell form (mask decoding, a
/// division, an arithmetic blend with `update` ∈ {0, 1}): the test oracle
/// of [`gs_row`].
#[cfg(test)]
pub(crate) fn gs_masked<const K: usize>(
    m: u16,
    xv: f32,
    bv: f32,
    lo: [f32; K],
    hi: [f32; K],
    update: bool,
) -> f32 {
    let mut off = 0.0f32;
    for q in 0..K {
        off += f32::from((m >> (2 * q)) & 1) * lo[q] + f32::from((m >> (2 * q + 1)) & 1) * hi[q];
    }
    let d = f32::from((m >> 8).max(1));
    let w = f32::from(u8::from(update) & u8::from(m != 0));
    let v = (bv + off) / d;
    xv + w * (v - xv)
}
