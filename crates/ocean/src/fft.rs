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
//! The spectrum is built column by column, right before its transforms, in
//! the layout those transforms read (no transpose on the way in). The
//! transpose between the passes is blocked by 16 rows and fused with the
//! unfolding of the half spectrum and the pairing. Work is split over
//! columns and row blocks; each column and row is transformed the same way
//! whatever thread runs it, so results do not depend on the thread count.

use rustfft::num_complex::Complex;

use crate::fastmath::{phase, sin_cos};
use crate::frame::{Frame, Workspace};
use crate::patch::Ocean;

type C32 = Complex<f32>;

/// Rows per block of the row pass.
pub(crate) const BLOCK: usize = 16;

/// Number of column sources.
pub(crate) const SOURCES: usize = 5;

/// Number of paired row transforms (eight real fields).
pub(crate) const PAIRS: usize = 4;

pub(crate) fn evaluate(ocean: &Ocean, t: f64, frame: &mut Frame) {
    let ny = ocean.params.ny;
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
    column_pass(ocean, t, cols, 0, slots);
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
    let _ = ny;
    row_pass(ocean, &cols, outs, 0, slots);
}

/// Whether the choppy fields need computing (with zero choppiness they are
/// exactly 0 and the identity, and only two column sources and two row pairs
/// are transformed).
#[inline]
fn choppy(ocean: &Ocean) -> bool {
    ocean.params.choppiness != 0.0
}

/// Splits `slices` at element `at` (each), returning the heads and tails.
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

/// Columns per group of the tiled column-pass output.
#[inline]
pub(crate) fn group_width(nx: usize) -> usize {
    (nx / 2).min(16)
}

/// Index in a tiled column buffer of column `n`, rows `y0 .. y0 + BLOCK`.
///
/// The buffer is laid out [group of `gw` columns][block of BLOCK rows]
/// [column in group][row in block], so the row pass reads each block of
/// rows as a few long contiguous runs (a plain column-major layout would
/// touch one page per column and thrash the TLB), and the column pass can
/// be split between threads at group boundaries.
#[inline]
fn tile_index(n: usize, y0: usize, ny: usize, gw: usize) -> usize {
    (n / gw) * ny * gw + (y0 / BLOCK) * gw * BLOCK + (n % gw) * BLOCK
}

/// Builds and transforms the columns of groups `g0 ..` covered by `cols`.
fn column_pass(
    ocean: &Ocean,
    t: f64,
    cols: [&mut [C32]; SOURCES],
    g0: usize,
    slots: &mut [crate::frame::Slot],
) {
    let (nx, ny) = (ocean.params.nx, ocean.params.ny);
    let gw = group_width(nx);
    let groups = cols[0].len() / (ny * gw);
    #[cfg(feature = "parallel")]
    if slots.len() > 1 && groups > 1 {
        let left_slots = slots.len() / 2;
        let left = groups * left_slots / slots.len();
        if left > 0 {
            let (sa, sb) = slots.split_at_mut(left_slots);
            let (ca, cb) = split_all(cols, left * ny * gw);
            rayon::join(
                || column_pass(ocean, t, ca, g0, sa),
                || column_pass(ocean, t, cb, g0 + left, sb),
            );
            return;
        }
    }
    let slot = &mut slots[0];
    let lam = ocean.params.choppiness as f32;
    let chop = choppy(ocean);
    let used = if chop { SOURCES } else { 2 };
    let mut cols = cols;
    for c in 0..groups * gw {
        let n = g0 * gw + c;
        {
            let (c0, rest) = slot.col.split_at_mut(ny);
            let (c1, rest) = rest.split_at_mut(ny);
            let (c2, rest) = rest.split_at_mut(ny);
            let (c3, c4) = rest.split_at_mut(ny);
            fill_column(ocean, t, lam, chop, n * ny, [c0, c1, c2, c3, c4]);
        }
        // One call transforms every length-M chunk (the `used` columns).
        ocean
            .col_fft
            .process_with_scratch(&mut slot.col[..used * ny], &mut slot.scratch);
        // Scatter into the tiled layout, relative to this range's first group.
        for (s, dst) in cols.iter_mut().enumerate().take(used) {
            let src = &slot.col[s * ny..(s + 1) * ny];
            for y0 in (0..ny).step_by(BLOCK) {
                let at = tile_index(c, y0, ny, gw);
                dst[at..at + BLOCK].copy_from_slice(&src[y0..y0 + BLOCK]);
            }
        }
    }
}

/// Writes the five source spectra of column `base / M` at time `t`.
#[inline]
fn fill_column(
    ocean: &Ocean,
    t: f64,
    lam: f32,
    chop: bool,
    base: usize,
    out: [&mut [C32]; SOURCES],
) {
    let ny = ocean.params.ny;
    let [o0, o1, o2, o3, o4] = out;
    let nu = &ocean.nu[base..base + ny];
    let pr = &ocean.p_re[base..base + ny];
    let pi = &ocean.p_im[base..base + ny];
    let qr = &ocean.q_re[base..base + ny];
    let qi = &ocean.q_im[base..base + ny];
    let ik = &ocean.inv_k[base..base + ny];
    let kys = &ocean.ky[..ny];
    let (o0, o1) = (&mut o0[..ny], &mut o1[..ny]);
    if !chop {
        for m in 0..ny {
            let (s, c) = sin_cos(phase(nu[m] * t));
            let hr = pr[m] * c + qi[m] * s;
            let hi = pi[m] * c - qr[m] * s;
            let ky = kys[m];
            o0[m] = C32::new(hr, hi);
            o1[m] = C32::new(-ky * hi, ky * hr);
        }
        return;
    }
    let (o2, o3, o4) = (&mut o2[..ny], &mut o3[..ny], &mut o4[..ny]);
    for m in 0..ny {
        let (s, c) = sin_cos(phase(nu[m] * t));
        // h̃ = h̃₀(k) e^{−iθ} + h̃₀*(−k) e^{iθ} = p cos θ − i q sin θ.
        let hr = pr[m] * c + qi[m] * s;
        let hi = pi[m] * c - qr[m] * s;
        let ky = kys[m];
        let l = lam * ik[m];
        let (lr, li) = (l * hr, l * hi);
        o0[m] = C32::new(hr, hi);
        o1[m] = C32::new(-ky * hi, ky * hr);
        o2[m] = C32::new(lr, li);
        o3[m] = C32::new(-ky * li, ky * lr);
        o4[m] = C32::new(-ky * ky * lr, -ky * ky * li);
    }
}

/// Unfolds, pairs and row-transforms rows `y0 .. y0 + outs[0].len()/N`.
fn row_pass(
    ocean: &Ocean,
    cols: &[&[C32]; SOURCES],
    outs: [&mut [f32]; 8],
    y0: usize,
    slots: &mut [crate::frame::Slot],
) {
    let nx = ocean.params.nx;
    let nrows = outs[0].len() / nx;
    #[cfg(feature = "parallel")]
    if slots.len() > 1 && nrows > BLOCK {
        let left_slots = slots.len() / 2;
        let blocks = nrows.div_ceil(BLOCK);
        let left_rows = (blocks * left_slots / slots.len()) * BLOCK;
        if left_rows > 0 && left_rows < nrows {
            let (sa, sb) = slots.split_at_mut(left_slots);
            let (oa, ob) = split_all(outs, left_rows * nx);
            rayon::join(
                || row_pass(ocean, cols, oa, y0, sa),
                || row_pass(ocean, cols, ob, y0 + left_rows, sb),
            );
            return;
        }
    }
    let slot = &mut slots[0];
    let mut outs = outs;
    let mut y = 0;
    while y < nrows {
        let b = BLOCK.min(nrows - y);
        row_block(ocean, cols, &mut outs, y0 + y, y, b, slot);
        y += b;
    }
}

/// One block of `b` rows starting at global row `gy` (local row `ly` of `outs`).
fn row_block(
    ocean: &Ocean,
    cols: &[&[C32]; SOURCES],
    outs: &mut [&mut [f32]; 8],
    gy: usize,
    ly: usize,
    b: usize,
    slot: &mut crate::frame::Slot,
) {
    let nx = ocean.params.nx;
    let ny = ocean.params.ny;
    let half = nx / 2;
    // Rows are padded so the b rows of a block do not all map to the same
    // cache sets (a power-of-two stride would make the unfolding below
    // thrash L1).
    let stride = row_stride(nx);
    let rows = &mut slot.rows[..PAIRS * b * stride];
    // (source of a, factor of a, source of b, factor of b).
    const PLAN: [(usize, Factor, usize, Factor); PAIRS] = [
        (0, Factor::One, 0, Factor::IKx),    // h, ε_x
        (1, Factor::One, 3, Factor::One),    // ε_y, d_y
        (2, Factor::IKx, 2, Factor::NegKx2), // d_x, ∂d_x/∂x
        (4, Factor::One, 3, Factor::IKx),    // ∂d_y/∂y, ∂d_x/∂y
    ];
    let chop = choppy(ocean);
    let pairs = if chop { PAIRS } else { 2 };
    for (p, &(sa, fa, sb, fb)) in PLAN.iter().enumerate().take(pairs) {
        let g = &mut rows[p * b * stride..(p + 1) * b * stride];
        let (ca, cb) = (cols[sa], cols[sb]);
        // k_x = 0: the column of a real field is real; the Nyquist bin is 0.
        let gw = group_width(nx);
        {
            let at = tile_index(0, gy, ny, gw);
            let va = &ca[at..at + b];
            let vb = &cb[at..at + b];
            let (ma, mb) = (fa.multiplier(0.0), fb.multiplier(0.0));
            for r in 0..b {
                let row = &mut g[r * stride..r * stride + nx];
                row[0] = C32::new((va[r] * ma).re, (vb[r] * mb).re);
                row[half] = C32::new(0.0, 0.0);
            }
        }
        for n in 1..half {
            let kx = ocean.kx[n];
            let (ma, mb) = (fa.multiplier(kx), fb.multiplier(kx));
            let at = tile_index(n, gy, ny, gw);
            let va = &ca[at..at + b];
            let vb = &cb[at..at + b];
            for r in 0..b {
                let a = va[r] * ma;
                let bb = vb[r] * mb;
                let o = r * stride;
                // G(n) = A + iB, G(N−n) = A* + iB*.
                g[o + n] = C32::new(a.re - bb.im, a.im + bb.re);
                g[o + nx - n] = C32::new(a.re + bb.im, bb.re - a.im);
            }
        }
        for r in 0..b {
            ocean
                .row_fft
                .process_with_scratch(&mut g[r * stride..r * stride + nx], &mut slot.scratch);
        }
    }
    // Unpack: real parts are field a, imaginary parts field b; the diagonal
    // Jacobian terms get their identity added.
    const OUT: [(usize, f32, usize, f32); PAIRS] = [
        (0, 0.0, 1, 0.0),
        (2, 0.0, 4, 0.0),
        (3, 0.0, 5, 1.0),
        (6, 1.0, 7, 0.0),
    ];
    for (p, &(ia, oa, ib, ob)) in OUT.iter().enumerate() {
        let (fa, fb) = two_mut(outs, ia, ib);
        for r in 0..b {
            let range = (ly + r) * nx..(ly + r + 1) * nx;
            let (da, db) = (&mut fa[range.clone()], &mut fb[range]);
            if p >= pairs {
                da.fill(oa);
                db.fill(ob);
                continue;
            }
            let o = p * b * stride + r * stride;
            let g = &rows[o..o + nx];
            if p == 1 && !chop {
                // d_y shares a transform with ε_y; without chop it is exactly 0.
                for (x, a) in g.iter().zip(da.iter_mut()) {
                    *a = x.re;
                }
                db.fill(0.0);
                continue;
            }
            for ((x, a), bb) in g.iter().zip(da.iter_mut()).zip(db.iter_mut()) {
                *a = x.re + oa;
                *bb = x.im + ob;
            }
        }
    }
}

/// Padded row length (complex values) of the row-pass buffers.
#[inline]
pub(crate) fn row_stride(nx: usize) -> usize {
    nx + 16
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

#[derive(Clone, Copy)]
enum Factor {
    One,
    IKx,
    NegKx2,
}

impl Factor {
    /// Returns the complex factor for wavenumber `kx`.
    #[inline(always)]
    fn multiplier(self, kx: f32) -> C32 {
        match self {
            Factor::One => C32::new(1.0, 0.0),
            Factor::IKx => C32::new(0.0, kx),
            Factor::NegKx2 => C32::new(-kx * kx, 0.0),
        }
    }
}
