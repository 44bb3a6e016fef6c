//! The row kernels: each pass of the step over one row, the grid's two edge
//! cells through the per-cell reference functions and the interior cells
//! through plain loops over `f32` slices (or fixed-size lane arrays) that
//! call the model's per-cell equations ([`super::model`]) and are compiled
//! for each instruction set with natura-simd's `multiversion!`. Nothing here
//! restates the model's arithmetic: the loops only gather a cell's
//! neighbours and store its results.

// The kernels index many parallel row slices with one counter (the form that vectorises).
#![allow(clippy::needless_range_loop)]

use natura_core::simd::Simd;

use super::grid::{Around, B, L, Outflows, R, Rows, Step, opt_rows};
use super::model::{CellIn, Coefficients, bilinear};
use super::reference::{flux_cell, semi_lagrangian_cell, transport_cell, update_cell};
use crate::erosion::Edges;

/// Steps 1 and 2 over a row: `d₁` and the in-place update of the row's
/// fluxes; the interior cells through [`flux_kernel`] unless `c.simd` is
/// `None`.
pub(super) fn flux_pass_row(
    c: &Step,
    w: Rows<'_>,
    bed: Rows<'_>,
    f: [&mut [f32]; 4],
    d1o: &mut [f32],
) {
    let nx = c.nx;
    let [fl, fr, fb, ft] = f;
    if let (Some(simd), Some(wa), Some(ba)) = (c.simd, w.around(), bed.around()) {
        for x in [0, nx - 1] {
            d1o[x] = flux_cell(
                c,
                x,
                w,
                bed,
                [&mut fl[x], &mut fr[x], &mut fb[x], &mut ft[x]],
            );
        }
        let m = 1..nx - 1;
        flux_kernel(
            simd,
            &c.k,
            wa,
            ba,
            [
                &mut d1o[m.clone()],
                &mut fl[m.clone()],
                &mut fr[m.clone()],
                &mut fb[m.clone()],
                &mut ft[m],
            ],
        );
    } else {
        for x in 0..nx {
            d1o[x] = flux_cell(
                c,
                x,
                w,
                bed,
                [&mut fl[x], &mut fr[x], &mut fb[x], &mut ft[x]],
            );
        }
    }
}

/// The inputs of steps 3, 4 and 6 for one row.
#[derive(Clone, Copy)]
pub(super) struct UpdateRows<'a> {
    /// `d₁` of the row.
    pub d1: &'a [f32],
    /// The four flux planes around the row.
    pub f: [Rows<'a>; 4],
    /// Sediment of the row before erosion.
    pub s0: &'a [f32],
    /// The bed around the row.
    pub bed: Rows<'a>,
    /// Erodibility of the row, if any.
    pub erod: Option<&'a [f32]>,
}

/// Steps 3, 4 and 6 over row `y`: writes water, bed, post-erosion sediment and
/// (unless their slices are empty) u and v; returns the water evaporated and
/// appends each cell's outflow through open edges to `out`.
pub(super) fn update_pass_row(
    c: &Step,
    ins: &UpdateRows<'_>,
    outs: [&mut [f32]; 5],
    y: usize,
    out: &mut Outflows,
) -> f64 {
    let nx = c.nx;
    let [wo, bo, so, uo, vo] = outs;
    let vel = !uo.is_empty();
    let mut evaporated = 0.0f64;
    let mut cell = |x: usize| {
        let (lost, o, [u, v]) = update_cell(c, x, ins, [&mut wo[x], &mut bo[x], &mut so[x]]);
        if vel {
            (uo[x], vo[x]) = (u, v);
        }
        evaporated += f64::from(lost);
        if o != 0.0 {
            out.push((y, o));
        }
    };
    let f = ins.f.map(Rows::around);
    if let (Some(simd), [Some(fl), Some(fr), Some(fb), Some(ft)], Some(bed)) =
        (c.simd, f, ins.bed.around())
    {
        cell(0);
        cell(nx - 1);
        let m = 1..nx - 1;
        let ui = InteriorUpdate {
            d1: &ins.d1[m.clone()],
            f: [fl, fr, fb, ft],
            s0: &ins.s0[m.clone()],
            bed,
        };
        let outs = [
            &mut wo[m.clone()],
            &mut bo[m.clone()],
            &mut so[m.clone()],
            opt_rows(uo, m.clone()),
            opt_rows(vo, m.clone()),
        ];
        evaporated += match ins.erod {
            Some(e) => update_kernel_erodible(simd, &c.k, &ui, &e[m], outs),
            None => update_kernel_uniform(simd, &c.k, &ui, outs),
        };
    } else {
        (0..nx).for_each(cell);
    }
    evaporated
}

/// Conservative transport over row `y`; appends each cell's sediment
/// outflow through open edges to `out`.
#[allow(clippy::too_many_arguments)]
pub(super) fn transport_pass_row(
    c: &Step,
    d1: Rows<'_>,
    f: [Rows<'_>; 4],
    s1: Rows<'_>,
    so: &mut [f32],
    y: usize,
    out: &mut Outflows,
) {
    let nx = c.nx;
    let mut cell = |x: usize| {
        let (s, o) = transport_cell(c, x, d1, &f, s1);
        so[x] = s;
        if o != 0.0 {
            out.push((y, o));
        }
    };
    let fa = f.map(Rows::around);
    if let (Some(simd), Some(da), [Some(fl), Some(fr), Some(fb), Some(ft)], Some(sa)) =
        (c.simd, d1.around(), fa, s1.around())
    {
        cell(0);
        cell(nx - 1);
        transport_kernel(simd, &c.k, da, [fl, fr, fb, ft], sa, &mut so[1..nx - 1]);
    } else {
        (0..nx).for_each(cell);
    }
}

/// Semi-Lagrangian transport over row `y` (interior cells of interior rows
/// through [`semi_lagrangian_kernel`]).
pub(super) fn semi_lagrangian_pass_row(
    c: &Step,
    u: &[f32],
    v: &[f32],
    s1: &[f32],
    y: usize,
    so: &mut [f32],
) {
    let (nx, ny) = (c.nx, c.ny);
    if let (Some(simd), true) = (c.simd, y > 0 && y + 1 < ny) {
        for x in [0, nx - 1] {
            so[x] = semi_lagrangian_cell(c, u, v, s1, x, y);
        }
        let i0 = y * nx + 1;
        let m = nx - 2;
        semi_lagrangian_kernel(
            simd,
            c,
            &u[i0..i0 + m],
            &v[i0..i0 + m],
            s1,
            y,
            &mut so[1..nx - 1],
        );
    } else {
        for x in 0..nx {
            so[x] = semi_lagrangian_cell(c, u, v, s1, x, y);
        }
    }
}

natura_core::simd::multiversion! {
/// Steps 1 and 2 over the interior cells of a row (every neighbour exists).
fn flux_kernel<'a>(simd: Simd, c: &'a Coefficients, w: Around<'a>, bd: Around<'a>, outs: [&'a mut [f32]; 5]) {
    let [d1o, fl, fr, fb, ft] = outs;
    let m = d1o.len();
    let (fl, fr, fb, ft) = (&mut fl[..m], &mut fr[..m], &mut fb[..m], &mut ft[..m]);
    let (wc, wl, wr, wb, wt) = (&w.c[..m], &w.l[..m], &w.r[..m], &w.b[..m], &w.t[..m]);
    let (bc, bl, br, bb, bt) = (&bd.c[..m], &bd.l[..m], &bd.r[..m], &bd.b[..m], &bd.t[..m]);
    for k in 0..m {
        let hn = |j| match j {
            L => c.head(bl[k], wl[k]),
            R => c.head(br[k], wr[k]),
            B => c.head(bb[k], wb[k]),
            _ => c.head(bt[k], wt[k]),
        };
        let (d1, [vl, vr, vb, vt]) = c.outflow(wc[k], bc[k], [fl[k], fr[k], fb[k], ft[k]], hn);
        fl[k] = vl;
        fr[k] = vr;
        fb[k] = vb;
        ft[k] = vt;
        d1o[k] = d1;
    }
}
}

/// The inputs of steps 3, 4 and 6 for the interior cells of one row.
struct InteriorUpdate<'a> {
    d1: &'a [f32],
    f: [Around<'a>; 4],
    s0: &'a [f32],
    bed: Around<'a>,
}

/// Cells per block of [`update_lanes`] (the evaporation of a block is summed on the stack).
const BLOCK: usize = 128;

natura_core::simd::multiversion! {
/// Steps 3, 4 and 6 over the interior cells of a row (uniform `K_s`); returns the water evaporated.
fn update_kernel_uniform<'a>(simd: Simd, c: &'a Coefficients, ins: &'a InteriorUpdate<'a>, outs: [&'a mut [f32]; 5]) -> f64 {
    update_lanes::<false>(c, ins, &[], outs)
}
}

natura_core::simd::multiversion! {
/// Steps 3, 4 and 6 over the interior cells of a row with an erodibility map; returns the water evaporated.
fn update_kernel_erodible<'a>(simd: Simd, c: &'a Coefficients, ins: &'a InteriorUpdate<'a>, erod: &'a [f32], outs: [&'a mut [f32]; 5]) -> f64 {
    update_lanes::<true>(c, ins, erod, outs)
}
}

/// Steps 3, 4 and 6 over the interior cells of a row, in lane groups; returns
/// the water evaporated. `u` and `v` are stored only if their slices are
/// not empty.
#[inline(always)]
fn update_lanes<const ERODIBILITY: bool>(
    c: &Coefficients,
    ins: &InteriorUpdate<'_>,
    erod: &[f32],
    outs: [&mut [f32]; 5],
) -> f64 {
    let [wo, bo, so, uo, vo] = outs;
    let m = wo.len();
    let vel = !uo.is_empty();
    let mut total = 0.0f64;
    let mut lost = [0.0f32; BLOCK];
    let mut a = 0;
    while a < m {
        let b = (a + BLOCK).min(m);
        let n = b - a;
        let d1 = &ins.d1[a..b];
        let [fl, fr, fb, ft] = ins.f.map(|p| p.sub(a, b));
        let s0 = &ins.s0[a..b];
        let bed = ins.bed.sub(a, b);
        let er = if ERODIBILITY { &erod[a..b] } else { &[][..] };
        let (wo, bo, so) = (&mut wo[a..b], &mut bo[a..b], &mut so[a..b]);
        let (uo, vo) = (opt_rows(uo, a..b), opt_rows(vo, a..b));
        let lost = &mut lost[..n];
        // Lanes of LANES cells through local arrays (no aliasing between the
        // row slices for the vectoriser to check); the last one padded.
        let mut k0 = 0;
        while k0 < n {
            let w = (n - k0).min(LANES);
            let g = |s: &[f32]| take::<LANES>(s, k0, w);
            let (dd, s) = (g(d1), g(s0));
            let (flc, frc, fbc, ftc) = (g(fl.c), g(fr.c), g(fb.c), g(ft.c));
            let (frl, flr, ftb, fbt) = (g(fr.l), g(fl.r), g(ft.b), g(fb.t));
            let (bc, bl, br, bb, bt) = (g(bed.c), g(bed.l), g(bed.r), g(bed.b), g(bed.t));
            let e = if ERODIBILITY { g(er) } else { [1.0f32; LANES] };
            let mut o = [[0.0f32; LANES]; 6];
            for k in 0..LANES {
                let r = c.update(&CellIn {
                    d1: dd[k],
                    fo: [flc[k], frc[k], fbc[k], ftc[k]],
                    fin: [frl[k], flr[k], ftb[k], fbt[k]],
                    s: s[k],
                    bed: bc[k],
                    bn: [bl[k], br[k], bb[k], bt[k]],
                    ks: if ERODIBILITY { c.ks_times(e[k]) } else { c.ks },
                });
                o[0][k] = r.w;
                o[1][k] = r.b;
                o[2][k] = r.s;
                o[3][k] = r.lost;
                o[4][k] = r.u;
                o[5][k] = r.v;
            }
            let [ow, ob, os, olost, ou, ov] = &o;
            put(wo, k0, w, ow);
            put(bo, k0, w, ob);
            put(so, k0, w, os);
            put(lost, k0, w, olost);
            if vel {
                put(uo, k0, w, ou);
                put(vo, k0, w, ov);
            }
            k0 += w;
        }
        // Summed in f64 (eight partial sums) like the per-cell path's ledger.
        let mut acc = [0.0f64; 8];
        let mut chunks = lost.chunks_exact(8);
        for ch in &mut chunks {
            for (s, &x) in acc.iter_mut().zip(ch) {
                *s += f64::from(x);
            }
        }
        for (s, &x) in acc.iter_mut().zip(chunks.remainder()) {
            *s += f64::from(x);
        }
        total += acc.iter().sum::<f64>();
        a = b;
    }
    total
}

natura_core::simd::multiversion! {
/// Conservative transport over the interior cells of a row.
fn transport_kernel<'a>(simd: Simd, c: &'a Coefficients, d1: Around<'a>, f: [Around<'a>; 4], s1: Around<'a>, so: &'a mut [f32]) {
    let m = so.len();
    let d1 = d1.sub(0, m);
    let [fl, fr, fb, ft] = f.map(|p| p.sub(0, m));
    let s1 = s1.sub(0, m);
    // Lanes of LANES cells through local arrays (no aliasing between the
    // row slices for the vectoriser to check); the last one padded.
    let mut a = 0;
    while a < m {
        let w = (m - a).min(LANES);
        let g = |s: &[f32]| take::<LANES>(s, a, w);
        let (dc, dl, dr, db, dt) = (g(d1.c), g(d1.l), g(d1.r), g(d1.b), g(d1.t));
        let (sc, sl, sr, sb, st) = (g(s1.c), g(s1.l), g(s1.r), g(s1.b), g(s1.t));
        let (flc, frc, fbc, ftc) = (g(fl.c), g(fr.c), g(fb.c), g(ft.c));
        let (frl, flr, ftb, fbt) = (g(fr.l), g(fl.r), g(ft.b), g(fb.t));
        let mut out = [0.0f32; LANES];
        for k in 0..LANES {
            let from = [
                c.carried(sl[k], dl[k], frl[k]),
                c.carried(sr[k], dr[k], flr[k]),
                c.carried(sb[k], db[k], ftb[k]),
                c.carried(st[k], dt[k], fbt[k]),
            ];
            out[k] = c.transported(sc[k], dc[k], [flc[k], frc[k], fbc[k], ftc[k]], from);
        }
        put(so, a, w, &out);
        a += w;
    }
}
}

/// Cells per lane group of the update and transport kernels (a multiple of
/// the 8 and 16 `f32` lanes of AVX2 and AVX-512).
const LANES: usize = 16;

/// `s[a..a + n]` in a local array, padded with zeros (`n ≤ N`): every lane
/// group has a fixed width, and a padded lane's result is never stored.
#[inline(always)]
fn take<const N: usize>(s: &[f32], a: usize, n: usize) -> [f32; N] {
    let mut x = [0.0f32; N];
    if n == N {
        x.copy_from_slice(&s[a..a + N]);
    } else {
        x[..n].copy_from_slice(&s[a..a + n]);
    }
    x
}

/// Stores the first `n` lanes of `x` at `d[a..a + n]`.
#[inline(always)]
fn put<const N: usize>(d: &mut [f32], a: usize, n: usize, x: &[f32; N]) {
    if n == N {
        d[a..a + N].copy_from_slice(x);
    } else {
        d[a..a + n].copy_from_slice(&x[..n]);
    }
}

natura_core::simd::multiversion! {
/// Semi-Lagrangian transport over the interior cells `1..nx − 1` of row `y`:
/// the back-traced point lies within about one cell (velocities are capped at
/// one cell per step), so one clamp (or wrap) per index suffices.
fn semi_lagrangian_kernel<'a>(simd: Simd, c: &'a Step, u: &'a [f32], v: &'a [f32], s1: &'a [f32], y: usize, so: &'a mut [f32]) {
    let (nx, ny) = (c.nx as i64, c.ny as i64);
    let wrap = c.edges == Edges::Periodic;
    let m = so.len();
    let (u, v) = (&u[..m], &v[..m]);
    let fix = |i: i64, n: i64| {
        if wrap {
            if i < 0 {
                i + n
            } else if i >= n {
                i - n
            } else {
                i
            }
        } else {
            i.clamp(0, n - 1)
        }
    };
    let g = |x: i64, y: i64| s1[(y * nx + x) as usize];
    for k in 0..m {
        let (px, py) = c.k.back_trace((k + 1) as f32, y as f32, u[k], v[k]);
        let (fx, fy) = (px.floor(), py.floor());
        let (ix, iy) = (fx as i64, fy as i64);
        let (x0, x1) = (fix(ix, nx), fix(ix + 1, nx));
        let (y0, y1) = (fix(iy, ny), fix(iy + 1, ny));
        so[k] = bilinear([[g(x0, y0), g(x1, y0)], [g(x0, y1), g(x1, y1)]], px - fx, py - fy);
    }
}
}
