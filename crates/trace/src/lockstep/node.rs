//! The node steps of the lanes and their pre-descent: the single-ray walk's
//! node arithmetic ([`crate::step`]) per lane, written without
//! data-dependent branches.

use super::{AT_CELL, LANES, LEFT, Lanes};
use crate::float::{coord, trunc};
use crate::grid_ray::{SETUP_LANES, SetupLanes};
use crate::max_mipmap::MipmapTracer;
use crate::step::{Exit, Signs, leaves_parent, node_exits, span_meets, step_out};

/// What every lane step needs besides the lanes.
pub(crate) struct NodeTable<'a> {
    /// The pyramid's nodes, every level above 0 (quantised `[min, max]`).
    pub nodes: &'a [u32],
    /// Where each level's nodes start in `nodes`.
    pub offset: &'a [u32; 32],
    /// The field's cells along x.
    pub ncx: u32,
    /// The field's cells along y.
    pub ncy: u32,
    /// The pyramid's top level.
    pub top: u32,
}

/// One step of every lane, written without data-dependent branches so that
/// LLVM vectorises the loop over lanes (gathering the nodes) when compiled
/// for AVX2 or AVX-512. Dead lanes compute and are ignored (their state is
/// kept, so their loads stay in bounds).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
pub(super) fn step(s: &mut Lanes, k: &NodeTable<'_>, events: &mut [u32; LANES]) {
    assert!(!k.nodes.is_empty());
    // Node indices stay below 2³¹ (the caller checks), so the clamped index
    // converts to the signed 32-bit offsets of a `vpgatherdd`.
    let last = (k.nodes.len() - 1).min(i32::MAX as usize) as u32;
    // (Read once: the loop stores through `s`, and the step's branches read
    // these only on some paths, which would keep LLVM from vectorising.)
    let (nodes, offset, ncx, ncy, top) = (k.nodes, k.offset, k.ncx, k.ncy, k.top);
    for l in 0..LANES {
        let (ci, cj, t, lev) = (s.ci[l], s.cj[l], s.t[l], s.level[l]);
        let signs = Signs(s.sign[l]);
        let size = 1u32 << (lev & 31);
        let mask = !(size - 1);
        let (nx0, ny0) = (ci & mask, cj & mask);
        let (ox, oy) = (s.ox[l], s.oy[l]);
        let (tx, ty) = node_exits(signs, nx0, ny0, size, ox, oy, s.ix[l], s.iy[l]);
        let (t_exit, exit) = Exit::of(tx, ty, s.t_end[l], t);
        // The cull against the node's quantised [min, max]. The level's
        // width `⌈ncx / 2^lev⌉` by a shift rather than a second table
        // gather (the same value for every level ≥ 1).
        let lv = (lev & 31) as usize;
        let width = ((ncx - 1) >> (lev & 31)) + 1;
        let idx = offset[lv]
            .wrapping_add((cj >> (lev & 31)).wrapping_mul(width))
            .wrapping_add(ci >> (lev & 31));
        let q = nodes[idx.min(last) as usize];
        let (za, zb) = (s.oq[l] + t * s.dq[l], s.oq[l] + t_exit * s.dq[l]);
        // At a cell (level 0) the lane parks for the exact test, or, once
        // that missed, steps on like a failed cull.
        let at0 = lev == 0;
        let pass = !at0 & span_meets(za, zb, coord(q & 0xffff), coord(q >> 16), s.mq[l]);
        let (px, py) = (ox + t_exit * s.dx[l], oy + t_exit * s.dy[l]);
        let (nci, ncj, out) = step_out(
            tx <= ty,
            signs,
            ci,
            cj,
            nx0,
            ny0,
            size,
            at0,
            px,
            py,
            ncx,
            ncy,
        );
        let done = (exit == Exit::End) | out;
        // Ascend one level when the step leaves the parent node.
        let up = (lev < top) & leaves_parent(ci, cj, nci, ncj, lev);
        let live = s.live[l];
        // A lane at a cell parks (only a lane loaded at a cell starts a step
        // there: one that descends to a cell parks in the same step, and the
        // cell walk of a parked lane runs outside the lanes).
        let park = live & at0;
        let go = live & !pass & !park;
        s.ci[l] = if go { nci } else { ci };
        s.cj[l] = if go { ncj } else { cj };
        s.t[l] = if go { t_exit } else { t };
        let down = live & pass;
        s.level[l] = if down {
            lev - 1
        } else if go {
            lev + u32::from(up)
        } else {
            lev
        };
        // `down` and `go` exclude each other, and so do `park` and `go`.
        let arrive = down & (lev == 1);
        events[l] = u32::from(park | arrive) * AT_CELL + u32::from(go & done) * LEFT;
    }
}

/// The step's events as two lane masks: bit `l` of the low half set when
/// lane `l` reports [`AT_CELL`], of the high half when it reports [`LEFT`].
#[inline(always)]
pub(super) fn event_mask(events: &[u32; LANES]) -> u32 {
    let mut mask = 0;
    for (l, &e) in events.iter().enumerate() {
        mask |= u32::from(e == AT_CELL) << l | u32::from(e == LEFT) << (l + LANES);
    }
    mask
}

/// [`event_mask`] with AVX2 compares, for the kernels compiled for AVX2 and
/// above (the same bits).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(super) fn event_mask_avx2(events: &[u32; LANES]) -> u32 {
    use std::arch::x86_64::{
        __m256i, _mm256_castsi256_ps, _mm256_cmpeq_epi32, _mm256_loadu_si256, _mm256_movemask_ps,
        _mm256_set1_epi32,
    };
    let p = events.as_ptr().cast::<__m256i>();
    #[allow(unsafe_code)]
    // SAFETY: `events` holds 16 `u32` (64 bytes): `p` and `p + 1` each
    // address 32 readable bytes; unaligned loads need no alignment.
    let (a, b) = unsafe { (_mm256_loadu_si256(p), _mm256_loadu_si256(p.add(1))) };
    let bits = |e: u32| {
        let v = _mm256_set1_epi32(e as i32);
        let lo = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(a, v))) as u32;
        let hi = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(b, v))) as u32;
        lo | hi << 8
    };
    bits(AT_CELL) | bits(LEFT) << LANES
}

/// [`MipmapTracer::descend`] of the [`SETUP_LANES`] rays set up in `s`
/// (from their walks' starts), in lanes: `out[l]` is the level lane `l`'s
/// walk descends to. Also stores the lane walk's per-ray constants in `s`
/// (`oq`, `dq`, `mq`, `sign`: the same operations as `Lanes::load`). Each round loads every lane's node (a gather) and
/// compares it with the start altitude in integers, as the single-ray
/// descent does level by level; lanes that stop are masked. Only lanes
/// that are `ok` matter (the others stay in range and are ignored).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
pub(super) fn descend_lanes(
    tr: &MipmapTracer<'_>,
    offset: &[u32; 32],
    s: &mut SetupLanes,
    out: &mut [u32; SETUP_LANES],
) {
    let m = &tr.mip;
    let nodes = m.nodes.as_slice();
    // (A pyramid has at least one level of one node.) With this the
    // clamped index below needs no bounds check, and the loop vectorises.
    assert!(!nodes.is_empty());
    let last = (nodes.len() - 1).min(i32::MAX as usize) as u32;
    let ncx = tr.f.ncx;
    let (lo, scale) = (m.lo, m.scale);
    let mut zf = [0u32; SETUP_LANES];
    let mut zc = [0u32; SETUP_LANES];
    let mut on = [false; SETUP_LANES];
    for l in 0..SETUP_LANES {
        // As `Lanes::load`: altitude and margin in quantised units.
        s.oq[l] = (s.o[2][l] - lo) / scale;
        s.dq[l] = s.d[2][l] / scale;
        s.mq[l] = 1.0 + s.zm[l] / scale;
        let (dx, dy) = (s.d[0][l], s.d[1][l]);
        s.sign[l] = Signs::of(dx, dy).0;
        // As `descend`: the start altitude in quantised units; below 0 or
        // above the range no node holds it.
        let za = (s.o[2][l] + s.t0[l] * s.d[2][l] - lo) / scale;
        let inside = (0.0..65536.0).contains(&za);
        // Truncation is the floor here (`za` ≥ 0 where it counts).
        let f = trunc(if inside { za } else { 0.0 });
        zf[l] = f;
        zc[l] = f + u32::from(f as i32 as f32 != za);
        out[l] = s.level[l];
        on[l] = inside & (s.level[l] > 0);
    }
    for _ in 0..m.top {
        let mut more = false;
        for l in 0..SETUP_LANES {
            let lev = out[l];
            let sh = lev & 31;
            let width = ((ncx - 1) >> sh) + 1;
            let idx = offset[sh as usize]
                .wrapping_add((s.cj[l] >> sh).wrapping_mul(width))
                .wrapping_add(s.ci[l] >> sh);
            let q = nodes[idx.min(last) as usize];
            let down = on[l] & ((q & 0xffff) <= zf[l]) & ((q >> 16) >= zc[l]);
            let lev = lev - u32::from(down);
            out[l] = lev;
            on[l] = down & (lev > 0);
            more |= on[l];
        }
        if !more {
            break;
        }
    }
}
