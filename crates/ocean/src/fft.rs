//! The fast path of [`crate::Ocean::evaluate_into`]: eight real fields from
//! five half-spectrum column passes and four paired row passes.
//!
//! Every field f is the inverse DFT of h̃(k,t) times a factor of k. Three
//! observations cut the work of eight complex 2-D FFTs to about four:
//!
//! 1. The fields are real, so F(−k_x, y) = F(k_x, y)* after the first (k_y)
//!    pass; only the columns 0 ≤ n < N/2 are transformed (the Nyquist column
//!    is zero).
//! 2. Factors that depend on k_x alone commute with the k_y pass, so the
//!    eight fields need only five column transforms: h̃, i k_y h̃, λh̃/k,
//!    iλk_y h̃/k and −λk_y² h̃/k; the k_x factors are applied afterwards.
//! 3. Two real fields a and b share one complex row transform of a + i b.
//!
//! The spectrum is built a group of 16 columns at a time, right before its
//! transforms, in the layout those transforms read (no transpose on the way
//! in). The one transpose between the passes happens while the group is
//! still in cache: it writes each row's 16 values contiguously. The row pass
//! then reads its rows sequentially, unfolds and pairs them in SIMD lanes,
//! transforms each row and unpacks it while it is in L1. The lane loops are
//! compiled for the widest instruction set the CPU has (natura-core's
//! run-time dispatch). Work is split over column groups and rows; each column
//! and row is transformed the same way whatever thread runs it, so results do
//! not depend on the thread count or the instruction set.

use natura_core::fft::Complex;
use natura_core::simd::{self, Kernel, Simd};

use crate::fastmath::{phase, sin_cos};
use crate::frame::{Frame, Workspace};
use crate::patch::Ocean;

type C32 = Complex<f32>;

/// Number of column sources.
pub(crate) const SOURCES: usize = 5;

/// Number of paired row transforms (eight real fields).
pub(crate) const PAIRS: usize = 4;

pub(crate) fn evaluate(ocean: &Ocean, t: f64, frame: &mut Frame) {
    // The spectrum, transpose and unpack loops are compiled for the widest
    // instruction set the CPU has (the FFTs dispatch on their own).
    evaluate_with(ocean, t, frame, Simd::best());
}

/// [`evaluate`] with the lane loops compiled for `simd` (every level gives
/// bit-identical fields).
pub(crate) fn evaluate_with(ocean: &Ocean, t: f64, frame: &mut Frame, simd: Simd) {
    let Frame {
        fields, work, time, ..
    } = frame;
    *time = t;
    let Workspace { cols, slots } = work;
    let [c0, c1, c2, c3, c4] = cols;
    let cols = [
        c0.as_mut_slice(),
        c1.as_mut_slice(),
        c2.as_mut_slice(),
        c3.as_mut_slice(),
        c4.as_mut_slice(),
    ];
    column_pass(ocean, t, cols, 0, slots, simd);
    let cols = [
        c0.as_slice(),
        c1.as_slice(),
        c2.as_slice(),
        c3.as_slice(),
        c4.as_slice(),
    ];
    let [f0, f1, f2, f3, f4, f5, f6, f7] = fields;
    let outs = [
        f0.as_mut_slice(),
        f1.as_mut_slice(),
        f2.as_mut_slice(),
        f3.as_mut_slice(),
        f4.as_mut_slice(),
        f5.as_mut_slice(),
        f6.as_mut_slice(),
        f7.as_mut_slice(),
    ];
    row_pass(ocean, &cols, outs, 0, slots, simd);
}

/// Whether the choppy fields need computing (with zero choppiness they are
/// exactly 0 and the identity, and only two column sources and two row pairs
/// are transformed).
#[inline]
fn choppy(ocean: &Ocean) -> bool {
    ocean.params.choppiness != 0.0
}

/// Splits `slices` at element `at` (each), returning the heads and tails.
#[cfg(feature = "parallel")]
fn split_all<'a, const K: usize, T>(
    slices: [&'a mut [T]; K],
    at: usize,
) -> ([&'a mut [T]; K], [&'a mut [T]; K]) {
    let mut heads: [&'a mut [T]; K] = std::array::from_fn(|_| <&mut [T]>::default());
    let mut tails: [&'a mut [T]; K] = std::array::from_fn(|_| <&mut [T]>::default());
    for (i, s) in slices.into_iter().enumerate() {
        let (a, b) = s.split_at_mut(at);
        heads[i] = a;
        tails[i] = b;
    }
    (heads, tails)
}

/// Columns per group of the column pass.
#[inline]
pub(crate) fn group_width(nx: usize) -> usize {
    (nx / 2).min(16)
}

/// Padding (complex values) after each column group of the intermediate
/// planes. Unpadded, a group spans `ny · 16` values (64 KiB at 512²), so
/// the 16 groups' values of one row all fell into the same L1 and L2 cache
/// sets, and the row pass's reads of a row evicted each other.
const GROUP_PAD: usize = 16;

/// Distance (complex values) between column groups in the intermediate
/// planes: the group's `ny` rows of `gw` values, then [`GROUP_PAD`].
pub(crate) fn group_stride(nx: usize, ny: usize) -> usize {
    ny * group_width(nx) + GROUP_PAD
}

/// Length of each intermediate plane: every column group with its padding.
pub(crate) fn plane_len(nx: usize, ny: usize) -> usize {
    nx / 2 / group_width(nx) * group_stride(nx, ny)
}

/// Padding (complex values) after each column of a slot's group buffer, so
/// the columns of a group do not all map to the same L1 sets.
const COL_PAD: usize = 8;

/// Length of a slot's group buffer: every source's columns of one group.
pub(crate) fn group_buffer_len(nx: usize, ny: usize) -> usize {
    SOURCES * group_width(nx) * (ny + COL_PAD)
}

/// Length of a slot's row buffer: one row.
pub(crate) fn row_buffer_len(nx: usize) -> usize {
    nx
}

/// Builds and transforms the columns of groups `g0 ..` covered by `cols`.
///
/// `cols` is laid out [group of `gw` columns][row][column in group]: a group
/// is contiguous (so threads split at group boundaries) and so is each
/// row's run of `gw` values in it (so the row pass reads sequentially).
fn column_pass(
    ocean: &Ocean,
    t: f64,
    cols: [&mut [C32]; SOURCES],
    g0: usize,
    slots: &mut [crate::frame::Slot],
    simd: Simd,
) {
    #[cfg(feature = "parallel")]
    if slots.len() > 1 {
        let stride = group_stride(ocean.params.nx, ocean.params.ny);
        let groups = cols[0].len() / stride;
        let left_slots = slots.len() / 2;
        let left = groups * left_slots / slots.len();
        if left > 0 && left < groups {
            let (sa, sb) = slots.split_at_mut(left_slots);
            let (ca, cb) = split_all(cols, left * stride);
            rayon::join(
                || column_pass(ocean, t, ca, g0, sa, simd),
                || column_pass(ocean, t, cb, g0 + left, sb, simd),
            );
            return;
        }
    }
    simd::run(
        simd,
        ColumnLeaf {
            ocean,
            t,
            cols,
            g0,
            slot: &mut slots[0],
        },
    );
}

/// The serial part of [`column_pass`], compiled per instruction set.
struct ColumnLeaf<'a, 'b> {
    ocean: &'a Ocean,
    t: f64,
    cols: [&'b mut [C32]; SOURCES],
    g0: usize,
    slot: &'b mut crate::frame::Slot,
}

impl Kernel for ColumnLeaf<'_, '_> {
    type Out = ();
    #[inline(always)]
    fn call(self) {
        let ColumnLeaf {
            ocean,
            t,
            mut cols,
            g0,
            slot,
        } = self;
        let (nx, ny) = (ocean.params.nx, ocean.params.ny);
        let gw = group_width(nx);
        let cs = ny + COL_PAD;
        let stride = group_stride(nx, ny);
        let groups = cols[0].len() / stride;
        let lam = ocean.params.choppiness as f32;
        let chop = choppy(ocean);
        let used = if chop { SOURCES } else { 2 };
        let buf = &mut slot.col[..SOURCES * gw * cs];
        for g in 0..groups {
            // Fill and transform the group's columns, source-major.
            for c in 0..gw {
                let n = (g0 + g) * gw + c;
                let mut parts = buf
                    .chunks_exact_mut(gw * cs)
                    .map(|b| &mut b[c * cs..c * cs + ny]);
                let out: [&mut [C32]; SOURCES] =
                    std::array::from_fn(|_| parts.next().expect("one buffer per source"));
                fill_column(ocean, t, lam, chop, n * ny, out);
            }
            for s in 0..used {
                for c in 0..gw {
                    let at = (s * gw + c) * cs;
                    ocean
                        .col_fft
                        .process_with_scratch(&mut buf[at..at + ny], &mut slot.scratch);
                }
            }
            // Transpose into [row][column in group].
            for (s, dst) in cols.iter_mut().enumerate().take(used) {
                let src = &buf[s * gw * cs..(s + 1) * gw * cs];
                let dst = &mut dst[g * stride..g * stride + ny * gw];
                transpose_group(src, dst, gw, cs, ny);
            }
        }
    }
}

/// Writes `dst[y·gw + c] = src[c·cs + y]` for `c < gw`, `y < ny`.
#[inline(always)]
fn transpose_group(src: &[C32], dst: &mut [C32], gw: usize, cs: usize, ny: usize) {
    /// Rows per register block.
    const R: usize = 8;
    if gw == 16 && ny.is_multiple_of(R) {
        // 16 × 8 blocks: contiguous loads of 8 rows per column, then
        // contiguous stores of 16 columns per row (no gathers).
        for y0 in (0..ny).step_by(R) {
            let mut tile = [[C32::new(0.0, 0.0); R]; 16];
            for (c, t) in tile.iter_mut().enumerate() {
                t.copy_from_slice(&src[c * cs + y0..c * cs + y0 + R]);
            }
            let out = &mut dst[y0 * 16..(y0 + R) * 16];
            for (y, row) in out.chunks_exact_mut(16).enumerate() {
                for (c, v) in row.iter_mut().enumerate() {
                    *v = tile[c][y];
                }
            }
        }
    } else {
        for (y, row) in dst.chunks_exact_mut(gw).enumerate().take(ny) {
            for (c, v) in row.iter_mut().enumerate() {
                *v = src[c * cs + y];
            }
        }
    }
}

/// Writes the five source spectra of column `base / M` at time `t`.
#[inline(always)]
fn fill_column(
    ocean: &Ocean,
    t: f64,
    lam: f32,
    chop: bool,
    base: usize,
    out: [&mut [C32]; SOURCES],
) {
    /// Lanes per chunk: the phase and the sine/cosine run on plain arrays
    /// (which vectorise), the complex stores after them.
    const L: usize = 16;
    let ny = ocean.params.ny;
    let [o0, o1, o2, o3, o4] = out;
    let nu = &ocean.nu[base..base + ny];
    let pr = &ocean.p_re[base..base + ny];
    let pi = &ocean.p_im[base..base + ny];
    let qr = &ocean.q_re[base..base + ny];
    let qi = &ocean.q_im[base..base + ny];
    let ik = &ocean.inv_k[base..base + ny];
    let kys = &ocean.ky[..ny];
    // `ny` is a power of two ≥ 16, so every chunk is full: fixed-length
    // loops over arrays, which vectorise (complex stores included).
    debug_assert_eq!(ny % L, 0);
    for m0 in (0..ny).step_by(L) {
        // Fixed-length views, so the loop below has no bounds checks: with
        // them the compiler vectorised only 8 of the 16 lanes and ran the
        // other 8 as scalar code (the checks' panics must stay in order).
        let nu: &[f64; L] = nu[m0..m0 + L].try_into().expect("L frequencies");
        let pr: &[f32; L] = pr[m0..m0 + L].try_into().expect("L values");
        let pi: &[f32; L] = pi[m0..m0 + L].try_into().expect("L values");
        let qr: &[f32; L] = qr[m0..m0 + L].try_into().expect("L values");
        let qi: &[f32; L] = qi[m0..m0 + L].try_into().expect("L values");
        let mut hr = [0.0f32; L];
        let mut hi = [0.0f32; L];
        for j in 0..L {
            let (s, c) = sin_cos(phase(nu[j] * t));
            // h̃ = h̃₀(k) e^{−iθ} + h̃₀*(−k) e^{iθ} = p cos θ − i q sin θ.
            hr[j] = pr[j] * c + qi[j] * s;
            hi[j] = pi[j] * c - qr[j] * s;
        }
        let ky: &[f32; L] = kys[m0..m0 + L].try_into().expect("L wavenumbers");
        let o0: &mut [C32; L] = (&mut o0[m0..m0 + L]).try_into().expect("L values");
        let o1: &mut [C32; L] = (&mut o1[m0..m0 + L]).try_into().expect("L values");
        for j in 0..L {
            o0[j] = C32::new(hr[j], hi[j]);
            o1[j] = C32::new(-ky[j] * hi[j], ky[j] * hr[j]);
        }
        if chop {
            let ik: &[f32; L] = ik[m0..m0 + L].try_into().expect("L values");
            let o2: &mut [C32; L] = (&mut o2[m0..m0 + L]).try_into().expect("L values");
            let o3: &mut [C32; L] = (&mut o3[m0..m0 + L]).try_into().expect("L values");
            let o4: &mut [C32; L] = (&mut o4[m0..m0 + L]).try_into().expect("L values");
            for j in 0..L {
                let l = lam * ik[j];
                let (lr, li) = (l * hr[j], l * hi[j]);
                o2[j] = C32::new(lr, li);
                o3[j] = C32::new(-ky[j] * li, ky[j] * lr);
                o4[j] = C32::new(-ky[j] * ky[j] * lr, -ky[j] * ky[j] * li);
            }
        }
    }
}

/// Unfolds, pairs, row-transforms and unpacks rows `y0 .. y0 + outs[0].len()/N`.
fn row_pass(
    ocean: &Ocean,
    cols: &[&[C32]; SOURCES],
    outs: [&mut [f32]; 8],
    y0: usize,
    slots: &mut [crate::frame::Slot],
    simd: Simd,
) {
    #[cfg(feature = "parallel")]
    if slots.len() > 1 {
        let nx = ocean.params.nx;
        let nrows = outs[0].len() / nx;
        let left_slots = slots.len() / 2;
        let left_rows = nrows * left_slots / slots.len();
        if left_rows > 0 && left_rows < nrows {
            let (sa, sb) = slots.split_at_mut(left_slots);
            let (oa, ob) = split_all(outs, left_rows * nx);
            rayon::join(
                || row_pass(ocean, cols, oa, y0, sa, simd),
                || row_pass(ocean, cols, ob, y0 + left_rows, sb, simd),
            );
            return;
        }
    }
    simd::run(
        simd,
        RowLeaf {
            ocean,
            cols,
            outs,
            y0,
            slot: &mut slots[0],
        },
    );
}

/// The serial part of [`row_pass`], compiled per instruction set.
struct RowLeaf<'a, 'b> {
    ocean: &'a Ocean,
    cols: &'a [&'a [C32]; SOURCES],
    outs: [&'b mut [f32]; 8],
    y0: usize,
    slot: &'b mut crate::frame::Slot,
}

impl Kernel for RowLeaf<'_, '_> {
    type Out = ();
    #[inline(always)]
    fn call(self) {
        let RowLeaf {
            ocean,
            cols,
            mut outs,
            y0,
            slot,
        } = self;
        let nx = ocean.params.nx;
        let nrows = outs[0].len() / nx;
        for r in 0..nrows {
            row(ocean, cols, &mut outs, y0 + r, r, slot);
        }
    }
}

/// Field pairs of the row transforms: (source of a, factor of a, source of
/// b, factor of b), each field a real part and b the imaginary part.
const PLAN: [(usize, u8, usize, u8); PAIRS] = [
    (0, F_ONE, 0, F_IKX),     // h, ε_x
    (1, F_ONE, 3, F_ONE),     // ε_y, d_y
    (2, F_IKX, 2, F_NEG_KX2), // d_x, ∂d_x/∂x
    (4, F_ONE, 3, F_IKX),     // ∂d_y/∂y, ∂d_x/∂y
];

/// Output fields of each pair and what is added to them (the diagonal
/// Jacobian terms get their identity).
const OUT: [(usize, f32, usize, f32); PAIRS] = [
    (0, 0.0, 1, 0.0),
    (2, 0.0, 4, 0.0),
    (3, 0.0, 5, 1.0),
    (6, 1.0, 7, 0.0),
];

/// Global row `gy` (local row `ly` of `outs`): every pair's unfolding,
/// transform and unpacking.
#[inline(always)]
fn row(
    ocean: &Ocean,
    cols: &[&[C32]; SOURCES],
    outs: &mut [&mut [f32]; 8],
    gy: usize,
    ly: usize,
    slot: &mut crate::frame::Slot,
) {
    let nx = ocean.params.nx;
    let half = nx / 2;
    let gw = group_width(nx);
    let chop = choppy(ocean);
    let pairs = if chop { PAIRS } else { 2 };
    let g = &mut slot.rows[..nx];
    for (p, &(sa, fa, sb, fb)) in PLAN.iter().enumerate() {
        let (ia, oa, ib, ob) = OUT[p];
        let (da, db) = two_mut(outs, ia, ib);
        let (da, db) = (
            &mut da[ly * nx..(ly + 1) * nx],
            &mut db[ly * nx..(ly + 1) * nx],
        );
        if p >= pairs {
            // Without choppiness d_x and the Jacobian are exactly 0 and 1.
            da.fill(oa);
            db.fill(ob);
            continue;
        }
        // Without choppiness d_y (source 3) is exactly 0 and not transformed.
        let b_zero = !chop && sb == 3;
        let (ca, cb) = (cols[sa], cols[sb]);
        match (fa, fb, b_zero) {
            (_, _, true) => unfold::<F_ONE, F_ZERO>(ocean, ca, cb, g, gy),
            (F_ONE, F_IKX, _) => unfold::<F_ONE, F_IKX>(ocean, ca, cb, g, gy),
            (F_ONE, F_ONE, _) => unfold::<F_ONE, F_ONE>(ocean, ca, cb, g, gy),
            (F_IKX, F_NEG_KX2, _) => {
                unfold::<F_IKX, F_NEG_KX2>(ocean, ca, cb, g, gy);
            }
            _ => unreachable!("every pair of the plan has a kernel"),
        }
        // k_x = 0: the column of a real field is real; the Nyquist bin is 0.
        {
            let at = gy * gw;
            let a = apply_code(fa, cols[sa][at], 0.0);
            let bb = if b_zero {
                C32::new(0.0, 0.0)
            } else {
                apply_code(fb, cols[sb][at], 0.0)
            };
            g[0] = C32::new(a.re, bb.re);
            g[half] = C32::new(0.0, 0.0);
        }
        ocean
            .row_fft
            .process_with_scratch(&mut g[..nx], &mut slot.scratch);
        // Unpack: real parts are field a, imaginary parts field b.
        if b_zero {
            for (x, a) in g[..nx].iter().zip(da.iter_mut()) {
                *a = x.re + oa;
            }
            db.fill(0.0);
            continue;
        }
        for ((x, a), b) in g[..nx].iter().zip(da.iter_mut()).zip(db.iter_mut()) {
            *a = x.re + oa;
            *b = x.im + ob;
        }
    }
}

/// Factor codes for [`unfold`] (const generics keep its loop branch-free).
const F_ZERO: u8 = 0;
const F_ONE: u8 = 1;
const F_IKX: u8 = 2;
const F_NEG_KX2: u8 = 3;

/// Multiplies `v` by the factor with code `F` at wavenumber `kx`.
#[inline(always)]
fn apply<const F: u8>(v: C32, kx: f32) -> C32 {
    match F {
        F_ZERO => C32::new(0.0, 0.0),
        F_ONE => v,
        F_IKX => C32::new(-kx * v.im, kx * v.re),
        _ => {
            let s = -kx * kx;
            C32::new(s * v.re, s * v.im)
        }
    }
}

/// Unfolds the half spectra `ca`, `cb` of row `gy` (times their factors) into
/// the full row `g` of G = A + iB: G(n) = A + iB, G(N−n) = A* + iB* for
/// 0 < n < N/2 (bins 0 and N/2 are left to the caller).
#[inline(always)]
fn unfold<const FA: u8, const FB: u8>(
    ocean: &Ocean,
    ca: &[C32],
    cb: &[C32],
    g: &mut [C32],
    gy: usize,
) {
    let (nx, ny) = (ocean.params.nx, ocean.params.ny);
    let gw = group_width(nx);
    let stride = group_stride(nx, ny);
    if gw != 16 {
        for n in 1..nx / 2 {
            let at = (n / gw) * stride + gy * gw + n % gw;
            let a = apply::<FA>(ca[at], ocean.kx[n]);
            let b = apply::<FB>(cb[at], ocean.kx[n]);
            g[n] = C32::new(a.re - b.im, a.im + b.re);
            g[nx - n] = C32::new(a.re + b.im, b.re - a.im);
        }
        return;
    }
    for grp in 0..nx / 2 / 16 {
        let at = grp * stride + gy * 16;
        let va: &[C32; 16] = ca[at..at + 16].try_into().expect("16 values");
        let vb: &[C32; 16] = cb[at..at + 16].try_into().expect("16 values");
        let kx: &[f32; 16] = ocean.kx[grp * 16..grp * 16 + 16]
            .try_into()
            .expect("16 wavenumbers");
        let mut fwd = [C32::new(0.0, 0.0); 16];
        let mut rev = [C32::new(0.0, 0.0); 16];
        for c in 0..16 {
            let a = apply::<FA>(va[c], kx[c]);
            let b = apply::<FB>(vb[c], kx[c]);
            fwd[c] = C32::new(a.re - b.im, a.im + b.re);
            rev[15 - c] = C32::new(a.re + b.im, b.re - a.im);
        }
        let n0 = grp * 16;
        if n0 > 0 {
            g[n0..n0 + 16].copy_from_slice(&fwd);
            g[nx - n0 - 15..=nx - n0].copy_from_slice(&rev);
        } else {
            // Bin 0 is the caller's; its mirror would be bin N.
            g[1..16].copy_from_slice(&fwd[1..]);
            g[nx - 15..nx].copy_from_slice(&rev[..15]);
        }
    }
}

/// Borrows two distinct elements of `outs` mutably.
fn two_mut<'a>(
    outs: &'a mut [&mut [f32]; 8],
    i: usize,
    j: usize,
) -> (&'a mut [f32], &'a mut [f32]) {
    debug_assert!(i < j);
    let (lo, hi) = outs.split_at_mut(j);
    (&mut *lo[i], &mut *hi[0])
}

/// [`apply`] with the factor code known only at run time (bin 0).
#[inline(always)]
fn apply_code(code: u8, v: C32, kx: f32) -> C32 {
    match code {
        F_ZERO => apply::<F_ZERO>(v, kx),
        F_ONE => apply::<F_ONE>(v, kx),
        F_IKX => apply::<F_IKX>(v, kx),
        _ => apply::<F_NEG_KX2>(v, kx),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{OceanParams, Phillips, Seed};

    /// Every instruction set gives bit-identical fields, for a size with
    /// 16-column groups and one with narrower groups, with and without chop.
    #[test]
    fn every_simd_level_gives_identical_fields() {
        for (n, m, chop) in [(64, 32, 1.3), (16, 32, 0.8), (32, 16, 0.0)] {
            let params = OceanParams {
                nx: n,
                ny: m,
                lx: 80.0,
                ly: 40.0,
                choppiness: chop,
                ..OceanParams::default()
            };
            let o = Ocean::new(&params, &Phillips::default(), Seed(9)).expect("ocean");
            let mut want = Frame::new(&o).expect("frame");
            evaluate_with(&o, 3.7, &mut want, Simd::baseline());
            for simd in Simd::supported() {
                let mut got = Frame::new(&o).expect("frame");
                evaluate_with(&o, 3.7, &mut got, simd);
                for (a, b) in got.fields.iter().zip(&want.fields) {
                    let same = a
                        .as_slice()
                        .iter()
                        .zip(b.as_slice())
                        .all(|(x, y)| x.to_bits() == y.to_bits());
                    assert!(same, "{:?} differs at n = {n}", simd.level());
                }
            }
        }
    }
}
