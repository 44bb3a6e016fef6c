//! Many rays at once: the max-mipmap walk run for [`LANES`] rays in lock
//! step, without data-dependent branches.
//!
//! A grazing ray spends most of its walk (about 21 of 25 steps on the
//! benchmark's 4096² view) descending from the coarse levels and stepping
//! past nodes above it before it first reaches a cell. Done one ray at a
//! time, each of those steps waits on a node load and then on a branch that
//! goes either way (descend or advance, across x or across y). Here each
//! step computes both outcomes and selects one, for [`LANES`] independent
//! rays at once; the loop over lanes is vectorised (with gathers of the
//! nodes) for AVX-512 or AVX2, chosen at run time.
//!
//! The batch path keeps every per-ray stage in lanes of 16 as well, each a
//! loop over lanes without data-dependent branches that LLVM vectorises
//! (inside `#[target_feature]` functions chosen at run time): the set-up
//! ([`crate::grid_ray::setup_lanes`]: clip, shear, rounding bounds, start
//! cell and level, kept in struct-of-arrays form so no per-ray `GridRay` is
//! built unless the single-ray walk needs one), the walk's sure descents at
//! its start ([`MipmapTracer::descend`] in lanes: where the start altitude
//! lies inside a node's bounds the walk descends, whatever the rest of its
//! span), the exact cell tests, and the hit records
//! ([`crate::ray_cell::hit_lanes`]).
//!
//! A lane whose ray descends to a cell parks in that step and waits while
//! the other lanes step on; once [`PARK_BATCH`] lanes wait (or no lane is
//! stepping), one pass of exact tests takes one cell for every parked lane
//! at once (the single-ray walk's cull and watertight pair, both triangles
//! computed and selected) and steps the lanes that missed on to their next
//! cell; a lane whose walk climbs back to level 1 steps on in the lanes, and
//! a lane whose ray is done is refilled with the next ray. Cells the lane
//! test cannot settle alone (a zero edge function, or an edge or corner
//! within rounding distance, whose neighbours the single-ray [`leaf`] also
//! tests) take `leaf` itself. A hit that a later cell could still beat
//! (rare) hands the ray to the single-ray walk ([`MipmapTracer::walk`])
//! from that cell.
//!
//! Every lane stage computes the same `f32` and integer values in the same
//! order as the single-ray path (set-up, node steps, cell tests, hit
//! records), so every ray visits the same cells at the same `t` and returns
//! the same hit, bit for bit (tested stage by stage against the single-ray
//! code at every instruction set, end to end against `trace`/`occluded`,
//! and against brute force).

use crate::field::FieldView;
use glam::Vec3;

use crate::grid_ray::{GridRay, SETUP_LANES, SetupLanes, setup_lanes};
use crate::leaf::{Exit, fmax, fmin, leaf};
use crate::max_mipmap::{Cursor, MipmapTracer};
use crate::ray::{Hit, Ray, TraceStats, Triangle};
use crate::ray_cell::{CellHit, HIT_LANES, HitLanes, hit_lanes};

/// Rays stepped together.
pub(crate) const LANES: usize = 16;

/// Rays whose walk starts below this level (their clipped span lies within
/// a block of `2^MIN_LANE_LEVEL` cells) take the single-ray walk.
const MIN_LANE_LEVEL: u32 = 4;

/// Per-lane ray constants and walk state, struct-of-arrays.
#[derive(Clone, Copy)]
pub(crate) struct Lanes {
    ox: [f32; LANES],
    oy: [f32; LANES],
    dx: [f32; LANES],
    dy: [f32; LANES],
    ix: [f32; LANES],
    iy: [f32; LANES],
    oq: [f32; LANES],
    dq: [f32; LANES],
    mq: [f32; LANES],
    t_end: [f32; LANES],
    /// The clipped range's start (`GridRay::t0`): a cell entered there is the first.
    t0: [f32; LANES],
    t: [f32; LANES],
    ci: [u32; LANES],
    cj: [u32; LANES],
    level: [u32; LANES],
    /// Bits: 1 `dx > 0`, 2 `dx < 0`, 4 `dy > 0`, 8 `dy < 0`.
    sign: [u32; LANES],
    ray: [usize; LANES],
    live: [bool; LANES],
}

/// All [`LANES`] bits.
const LANE_MASK: u32 = (1 << LANES) - 1;

/// What a lane step leads to.
const GOING: u32 = 0;
const AT_CELL: u32 = 1;
const LEFT: u32 = 2;

impl Lanes {
    fn new() -> Self {
        Self {
            ox: [0.0; LANES],
            oy: [0.0; LANES],
            dx: [0.0; LANES],
            dy: [0.0; LANES],
            ix: [0.0; LANES],
            iy: [0.0; LANES],
            oq: [0.0; LANES],
            dq: [0.0; LANES],
            mq: [0.0; LANES],
            t_end: [0.0; LANES],
            t0: [0.0; LANES],
            t: [0.0; LANES],
            ci: [0; LANES],
            cj: [0; LANES],
            level: [0; LANES],
            sign: [0; LANES],
            ray: [0; LANES],
            live: [false; LANES],
        }
    }

    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn load(
        &mut self,
        l: usize,
        k: usize,
        o: Vec3,
        d: Vec3,
        ix: f32,
        iy: f32,
        zm: f32,
        t0: f32,
        t1: f32,
        c: Cursor,
        lo: f32,
        scale: f32,
    ) {
        self.ox[l] = o.x;
        self.oy[l] = o.y;
        self.dx[l] = d.x;
        self.dy[l] = d.y;
        self.ix[l] = ix;
        self.iy[l] = iy;
        // As in the single-ray walk: altitude and margin in quantised units.
        self.oq[l] = (o.z - lo) / scale;
        self.dq[l] = d.z / scale;
        self.mq[l] = 1.0 + zm / scale;
        self.t_end[l] = t1;
        self.t0[l] = t0;
        self.t[l] = c.t;
        self.ci[l] = c.ci;
        self.cj[l] = c.cj;
        self.level[l] = c.level;
        self.sign[l] = u32::from(d.x > 0.0)
            | u32::from(d.x < 0.0) << 1
            | u32::from(d.y > 0.0) << 2
            | u32::from(d.y < 0.0) << 3;
        self.ray[l] = k;
        self.live[l] = true;
    }

    /// Loads lane `l` with ray `m` of a set-up group whose walk constants
    /// the lane pre-descent computed (the same values as [`Lanes::load`]).
    #[inline(always)]
    fn load_soa(&mut self, l: usize, k: usize, g: &SetupLanes, m: usize, c: Cursor) {
        self.ox[l] = g.o[0][m];
        self.oy[l] = g.o[1][m];
        self.dx[l] = g.d[0][m];
        self.dy[l] = g.d[1][m];
        self.ix[l] = g.inv[0][m];
        self.iy[l] = g.inv[1][m];
        self.oq[l] = g.oq[m];
        self.dq[l] = g.dq[m];
        self.mq[l] = g.mq[m];
        self.t_end[l] = g.t1[m];
        self.t0[l] = g.t0[m];
        self.t[l] = c.t;
        self.ci[l] = c.ci;
        self.cj[l] = c.cj;
        self.level[l] = c.level;
        self.sign[l] = g.sign[m];
        self.ray[l] = k;
        self.live[l] = true;
    }
}

/// The rays a lane walk reads: set up one by one ([`GridRay`]s) or in
/// lanes ([`SoaRays`], the batch path, which never builds a `GridRay` for a
/// ray the lanes finish).
pub(crate) trait Rays {
    /// Ray `k` as a [`GridRay`] (for the single-ray walk's cell test).
    fn ray(&self, k: usize) -> GridRay;
    /// Loads ray `k`, starting at `c`, into lane `l`.
    #[allow(clippy::too_many_arguments)]
    fn load(
        &self,
        k: usize,
        s: &mut Lanes,
        x: &mut Exact,
        l: usize,
        c: Cursor,
        lo: f32,
        scale: f32,
    );
}

impl Rays for [GridRay] {
    #[inline]
    fn ray(&self, k: usize) -> GridRay {
        self[k]
    }

    #[inline]
    fn load(
        &self,
        k: usize,
        s: &mut Lanes,
        x: &mut Exact,
        l: usize,
        c: Cursor,
        lo: f32,
        scale: f32,
    ) {
        let r = &self[k];
        s.load(
            l, k, r.o, r.d, r.inv.x, r.inv.y, r.zm, r.t0, r.t1, c, lo, scale,
        );
        x.load(l, r.o.z, r.d.z, r);
    }
}

/// Rays set up in lanes: ray `k` is lane `k % SETUP_LANES` of group `k / SETUP_LANES`
/// (each group through [`setup_lanes`] and then the lane pre-descent, which
/// stores the walk constants the lanes load).
pub(crate) struct SoaRays<'a> {
    pub groups: &'a [SetupLanes],
    pub t_min: f32,
    pub t_max: f32,
}

impl Rays for SoaRays<'_> {
    #[inline]
    fn ray(&self, k: usize) -> GridRay {
        self.groups[k / SETUP_LANES].ray(k % SETUP_LANES, self.t_min, self.t_max)
    }

    #[inline]
    fn load(
        &self,
        k: usize,
        s: &mut Lanes,
        x: &mut Exact,
        l: usize,
        c: Cursor,
        _lo: f32,
        _scale: f32,
    ) {
        let g = &self.groups[k / SETUP_LANES];
        let m = k % SETUP_LANES;
        // (The walk constants were computed in lanes: `descend_lanes`.)
        s.load_soa(l, k, g, m, c);
        x.oz[l] = g.o[2][m];
        x.dz[l] = g.d[2][m];
        x.zm[l] = g.zm[m];
        x.t_min[l] = self.t_min;
        x.t_max[l] = self.t_max;
        x.xyeps[l] = g.xyeps[m];
        x.ttol[l] = g.ttol[m];
        for q in 0..3 {
            x.sh[q][l] = g.px[q][m];
            x.sh[3 + q][l] = g.py[q][m];
            x.sh[6 + q][l] = g.pz[q][m];
        }
    }
}

/// What every lane step needs besides the lanes.
struct Consts<'a> {
    nodes: &'a [u32],
    offset: &'a [u32; 32],
    ncx: u32,
    ncy: u32,
    top: u32,
}

/// One step of every lane, written without data-dependent branches so that
/// LLVM vectorises the loop over lanes (gathering the nodes) when compiled
/// for AVX2 or AVX-512. Dead lanes compute and are ignored (their state is
/// kept, so their loads stay in bounds).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
fn step(s: &mut Lanes, k: &Consts<'_>, events: &mut [u32; LANES]) {
    assert!(!k.nodes.is_empty());
    // Node indices stay below 2³¹ (the caller checks), so the clamped index
    // converts to the signed 32-bit offsets of a `vpgatherdd`.
    let last = (k.nodes.len() - 1).min(i32::MAX as usize) as u32;
    for l in 0..LANES {
        let (ci, cj, t, lev) = (s.ci[l], s.cj[l], s.t[l], s.level[l]);
        let sign = s.sign[l];
        let (xpos, xneg, ypos, yneg) = (sign & 1 != 0, sign & 2 != 0, sign & 4 != 0, sign & 8 != 0);
        let size = 1u32 << (lev & 31);
        let mask = !(size - 1);
        let (nx0, ny0) = (ci & mask, cj & mask);
        // The node's exits, as in the single-ray walk (coordinates < 2²⁴,
        // so the `i32` conversions are exact).
        let bx = if xpos { nx0 + size } else { nx0 };
        let by = if ypos { ny0 + size } else { ny0 };
        let tx = if xpos | xneg {
            (bx as i32 as f32 - s.ox[l]) * s.ix[l]
        } else {
            f32::INFINITY
        };
        let ty = if ypos | yneg {
            (by as i32 as f32 - s.oy[l]) * s.iy[l]
        } else {
            f32::INFINITY
        };
        let t_end = s.t_end[l];
        let t_exit = fmax(fmin(fmin(tx, ty), t_end), t);
        // The cull against the node's quantised [min, max].
        let lv = (lev & 31) as usize;
        // The level's width `⌈ncx / 2^lev⌉` by a shift rather than a second
        // table gather (the same value for every level ≥ 1).
        let width = ((k.ncx - 1) >> (lev & 31)) + 1;
        let idx = k.offset[lv]
            .wrapping_add((cj >> (lev & 31)).wrapping_mul(width))
            .wrapping_add(ci >> (lev & 31));
        let q = k.nodes[idx.min(last) as usize];
        let (qlo, qhi) = ((q & 0xffff) as i32 as f32, (q >> 16) as i32 as f32);
        let (za, zb) = (s.oq[l] + t * s.dq[l], s.oq[l] + t_exit * s.dq[l]);
        let (zlo, zhi) = (fmin(za, zb), fmax(za, zb));
        let mq = s.mq[l];
        // At a cell (level 0) the lane parks for the exact test, or, once
        // that missed, steps on like a failed cull.
        let at0 = lev == 0;
        let pass = !at0 & (zlo <= qhi + mq) & (zhi >= qlo - mq);
        // The step across x: the next column, and the row where the ray
        // meets it, clamped to the node (clamping before the truncation is
        // the walk's `floor`, `max`, `min`: the bounds are whole numbers).
        let cix = if xpos {
            nx0 + size
        } else {
            nx0.wrapping_sub(1)
        };
        let outx = if xpos { cix >= k.ncx } else { nx0 == 0 };
        let hiy = (ny0 + size).min(k.ncy) - 1;
        let yv = s.oy[l] + t_exit * s.dy[l];
        let yc = trunc(fmin(fmax_nan_lo(yv, ny0 as i32 as f32), hiy as i32 as f32));
        // (Steps between cells keep the other coordinate.)
        let cjx = if at0 {
            cj
        } else if ypos {
            cj.max(yc)
        } else if yneg {
            cj.min(yc)
        } else {
            cj
        };
        // The step across y.
        let cjy = if ypos {
            ny0 + size
        } else {
            ny0.wrapping_sub(1)
        };
        let outy = if ypos { cjy >= k.ncy } else { ny0 == 0 };
        let hix = (nx0 + size).min(k.ncx) - 1;
        let xv = s.ox[l] + t_exit * s.dx[l];
        let xc = trunc(fmin(fmax_nan_lo(xv, nx0 as i32 as f32), hix as i32 as f32));
        let ciy = if at0 {
            ci
        } else if xpos {
            ci.max(xc)
        } else if xneg {
            ci.min(xc)
        } else {
            ci
        };
        let xstep = tx <= ty;
        let nci = if xstep { cix } else { ciy };
        let ncj = if xstep { cjx } else { cjy };
        let out = if xstep { outx } else { outy };
        let done = (t_exit >= t_end) | out;
        // Ascend one level when the step leaves the parent node.
        let up = (lev < k.top) & (((nci ^ ci) | (ncj ^ cj)) >> ((lev + 1) & 31) != 0);
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
fn event_mask(events: &[u32; LANES]) -> u32 {
    let mut mask = 0;
    for (l, &e) in events.iter().enumerate() {
        mask |= u32::from(e == AT_CELL) << l | u32::from(e == LEFT) << (l + LANES);
    }
    mask
}

/// `v as u32` for `v` in `[0, 2²⁴)` (a clamped cell coordinate).
#[inline(always)]
pub(crate) fn trunc(v: f32) -> u32 {
    debug_assert!((0.0..16_777_216.0).contains(&v));
    #[allow(unsafe_code)]
    // SAFETY: `v` is clamped between two cell coordinates, whole numbers in
    // `[0, 2²⁴)` (`MAX_SAMPLES_PER_AXIS`), before this is called, so it is
    // finite and its truncation fits an `i32`.
    let i = unsafe { v.to_int_unchecked::<i32>() };
    i as u32
}

/// `max(v, lo)` for a whole number `lo`, returning `lo` when `v` is NaN (as
/// `f32::max` does), in a form that vectorises to one compare and blend.
#[inline(always)]
fn fmax_nan_lo(v: f32, lo: f32) -> f32 {
    if v > lo { v } else { lo }
}

/// The instruction set the lane steps run with, detected at run time.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Level {
    Scalar,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl Level {
    pub(crate) fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx512f")
                && std::is_x86_feature_detected!("avx512vl")
                && std::is_x86_feature_detected!("avx512dq")
                && std::is_x86_feature_detected!("avx512bw")
                && std::is_x86_feature_detected!("avx2")
                && std::is_x86_feature_detected!("fma")
            {
                return Level::Avx512;
            }
            if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
                return Level::Avx2;
            }
        }
        Level::Scalar
    }

    #[inline(always)]
    fn step(self, s: &mut Lanes, k: &Consts<'_>, events: &mut [u32; LANES]) -> u32 {
        match self {
            Level::Scalar => {
                step(s, k, events);
                event_mask(events)
            }
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            // SAFETY: `Level::Avx2` is only returned by `detect` after the CPU
            // reported AVX2 and FMA, the features `step_avx2` is compiled for.
            Level::Avx2 => unsafe { step_avx2(s, k, events) },
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            // SAFETY: `Level::Avx512` is only returned by `detect` after the
            // CPU reported every feature `step_avx512` is compiled for.
            Level::Avx512 => unsafe { step_avx512(s, k, events) },
        }
    }
}

impl Level {
    #[inline(always)]
    fn cells<const ANY: bool>(
        self,
        s: &mut Lanes,
        k: &Consts<'_>,
        x: &Exact,
        c: &[[f32; LANES]; 4],
        parked: u32,
        o: &mut CellOut,
    ) {
        match self {
            Level::Scalar => cells::<ANY>(s, k, x, c, parked, o),
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            // SAFETY: as for `step_avx2`.
            Level::Avx2 => unsafe { cells_avx2::<ANY>(s, k, x, c, parked, o) },
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            // SAFETY: as for `step_avx512`.
            Level::Avx512 => unsafe { cells_avx512::<ANY>(s, k, x, c, parked, o) },
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn step_avx2(s: &mut Lanes, k: &Consts<'_>, events: &mut [u32; LANES]) -> u32 {
    step(s, k, events);
    event_mask_avx2(events)
}

/// [`event_mask`] in registers: four compares and four move-masks. The
/// scalar loop over the just-stored events stalls on store forwarding.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn event_mask_avx2(events: &[u32; LANES]) -> u32 {
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

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
fn step_avx512(s: &mut Lanes, k: &Consts<'_>, events: &mut [u32; LANES]) -> u32 {
    step(s, k, events);
    event_mask_avx2(events)
}

/// [`setup_lanes`] compiled for `level` (the loop over lanes vectorises
/// for AVX2 and AVX-512).
#[inline]
pub(crate) fn setup_with(
    level: Level,
    f: &FieldView<'_>,
    rays: &[Ray; SETUP_LANES],
    t_min: f32,
    t_max: f32,
    top: u32,
    s: &mut SetupLanes,
) {
    match level {
        Level::Scalar => setup_lanes(f, rays, t_min, t_max, top, s),
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        // SAFETY: `Level::Avx2` is only returned by `detect` after the CPU
        // reported AVX2 and FMA, the features `setup_avx2` is compiled for.
        Level::Avx2 => unsafe { setup_avx2(f, rays, t_min, t_max, top, s) },
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        // SAFETY: as for `step_avx512`.
        Level::Avx512 => unsafe { setup_avx512(f, rays, t_min, t_max, top, s) },
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn setup_avx2(
    f: &FieldView<'_>,
    rays: &[Ray; SETUP_LANES],
    t_min: f32,
    t_max: f32,
    top: u32,
    s: &mut SetupLanes,
) {
    setup_lanes(f, rays, t_min, t_max, top, s);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
fn setup_avx512(
    f: &FieldView<'_>,
    rays: &[Ray; SETUP_LANES],
    t_min: f32,
    t_max: f32,
    top: u32,
    s: &mut SetupLanes,
) {
    setup_lanes(f, rays, t_min, t_max, top, s);
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
fn descend_lanes(
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
        s.sign[l] = u32::from(dx > 0.0)
            | u32::from(dx < 0.0) << 1
            | u32::from(dy > 0.0) << 2
            | u32::from(dy < 0.0) << 3;
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

/// [`descend_lanes`] compiled for `level`.
#[inline]
pub(crate) fn descend_with(
    level: Level,
    tr: &MipmapTracer<'_>,
    offset: &[u32; 32],
    s: &mut SetupLanes,
    out: &mut [u32; SETUP_LANES],
) {
    match level {
        Level::Scalar => descend_lanes(tr, offset, s, out),
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        // SAFETY: as for `setup_avx2`.
        Level::Avx2 => unsafe { descend_avx2(tr, offset, s, out) },
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        // SAFETY: as for `step_avx512`.
        Level::Avx512 => unsafe { descend_avx512(tr, offset, s, out) },
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn descend_avx2(
    tr: &MipmapTracer<'_>,
    offset: &[u32; 32],
    s: &mut SetupLanes,
    out: &mut [u32; SETUP_LANES],
) {
    descend_lanes(tr, offset, s, out);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
fn descend_avx512(
    tr: &MipmapTracer<'_>,
    offset: &[u32; 32],
    s: &mut SetupLanes,
    out: &mut [u32; SETUP_LANES],
) {
    descend_lanes(tr, offset, s, out);
}

/// [`hit_lanes`] compiled for `level`.
#[inline]
pub(crate) fn hits_with(
    level: Level,
    f: &FieldView<'_>,
    s: &HitLanes,
    n: usize,
    out: &mut [Option<Hit>],
    slot: &[usize; HIT_LANES],
) {
    match level {
        Level::Scalar => hit_lanes(f, s, n, |l, h| out[slot[l]] = Some(h)),
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        // SAFETY: as for `setup_avx2`.
        Level::Avx2 => unsafe { hits_avx2(f, s, n, out, slot) },
        #[cfg(target_arch = "x86_64")]
        #[allow(unsafe_code)]
        // SAFETY: as for `step_avx512`.
        Level::Avx512 => unsafe { hits_avx512(f, s, n, out, slot) },
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn hits_avx2(
    f: &FieldView<'_>,
    s: &HitLanes,
    n: usize,
    out: &mut [Option<Hit>],
    slot: &[usize; HIT_LANES],
) {
    hit_lanes(f, s, n, |l, h| out[slot[l]] = Some(h));
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
fn hits_avx512(
    f: &FieldView<'_>,
    s: &HitLanes,
    n: usize,
    out: &mut [Option<Hit>],
    slot: &[usize; HIT_LANES],
) {
    hit_lanes(f, s, n, |l, h| out[slot[l]] = Some(h));
}

/// How a ray's walk in the lanes ended.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Outcome {
    /// It left the field's box: no hit.
    Miss,
    /// Its first hit (with `ANY`, a hit).
    Hit(CellHit),
    /// It found a hit that a later cell could still beat (across an edge
    /// within rounding distance), or the lanes could not take it: the
    /// single-ray walk finishes it from this cursor (re-testing its cell).
    Walk(Cursor),
}

/// Walks every ray of `rays` with a cursor in `cur` (`None`: nothing to
/// trace) to its end, [`LANES`] at a time, running the cell tests of parked
/// lanes one by one: `out[k]` says how ray `k` ended.
pub(crate) fn walk_lanes<const ANY: bool, R: Rays + ?Sized>(
    level: Level,
    tr: &MipmapTracer<'_>,
    rays: &R,
    cur: &[Option<Cursor>],
    descended: Option<&[u32]>,
    out: &mut Vec<Outcome>,
) {
    walk_lanes_with::<ANY, R>(level, MIN_LANE_LEVEL, tr, rays, cur, descended, out);
}

/// [`walk_lanes`] with the lane steps compiled for `level`.
fn walk_lanes_with<const ANY: bool, R: Rays + ?Sized>(
    level: Level,
    min_level: u32,
    tr: &MipmapTracer<'_>,
    rays: &R,
    cur: &[Option<Cursor>],
    descended: Option<&[u32]>,
    out: &mut Vec<Outcome>,
) {
    out.clear();
    out.extend(cur.iter().map(|c| c.map_or(Outcome::Miss, Outcome::Walk)));
    let f = &tr.f;
    let m = &tr.mip;
    let (lo, scale, top) = (m.lo, m.scale, m.top);
    let nodes = m.nodes.as_slice();
    // Node indices in 32 bits (the kernel's gathers); larger pyramids take
    // the single-ray walk.
    if nodes.len() > i32::MAX as usize {
        return;
    }
    let mut offset = [0u32; 32];
    for (o, &m) in offset.iter_mut().zip(&m.offset) {
        *o = m as u32;
    }
    let k = Consts {
        nodes,
        offset: &offset,
        ncx: f.ncx,
        ncy: f.ncy,
        top,
    };

    // The rays the lanes walk, in order. Short walks (a span within a few
    // cells: steep rays) are cheaper one at a time than through a lane.
    let queue: Vec<(u32, Cursor)> = cur
        .iter()
        .enumerate()
        .filter_map(|(k, c)| match *c {
            Some(c) if c.level >= min_level => Some((k as u32, c)),
            _ => None,
        })
        .collect();
    // The next ray to walk: the `*next`-th of the queue.
    let take = |next: &mut usize| -> Option<(usize, Cursor)> {
        let &(k, c) = queue.get(*next)?;
        *next += 1;
        let k = k as usize;
        // The walk's sure descents (see `descend`), taken in lanes at the
        // set-up or here.
        Some((
            k,
            match descended {
                Some(d) => Cursor { level: d[k], ..c },
                None => tr.descend(&rays.ray(k), c, &mut TraceStats::default()),
            },
        ))
    };
    let mut next = 0;
    let mut s = Lanes::new();
    let mut x = Exact::new();
    let mut live = 0u32;
    for l in 0..LANES {
        if let Some((kr, c)) = take(&mut next) {
            rays.load(kr, &mut s, &mut x, l, c, lo, scale);
            live |= 1 << l;
        }
    }
    let mut stats = TraceStats::default();
    // Lanes waiting at a cell for the exact test. They stay put in the lane
    // steps (a lane at level 0 parks) until enough of them wait, and then
    // take one cell each in a lane pass of exact tests.
    let mut parked = 0u32;
    let mut corners = [[0.0f32; LANES]; 4];
    let mut co = CellOut::new();
    // (Every lane step writes every lane's event.)
    let mut events = [GOING; LANES];
    while live != 0 {
        if live & !parked != 0 && parked.count_ones() < PARK_BATCH {
            // Lanes already parked report `AT_CELL` again: nothing new.
            let ev = level.step(&mut s, &k, &mut events);
            parked |= ev & LANE_MASK;
            let mut left = (ev >> LANES) & !parked;
            while left != 0 {
                let l = left.trailing_zeros() as usize;
                left &= left - 1;
                out[s.ray[l]] = Outcome::Miss;
                refill(
                    &mut s, &mut x, &mut live, &mut next, l, &take, rays, lo, scale,
                );
            }
            continue;
        }
        // One cell for every parked lane: the exact tests in lanes, then
        // per lane the walk's bookkeeping (as the single-ray walk's cell steps).
        let mut pm = parked;
        while pm != 0 {
            let l = pm.trailing_zeros() as usize;
            pm &= pm - 1;
            let c = f.corners(s.ci[l], s.cj[l]);
            for (q, &v) in c.iter().enumerate() {
                corners[q][l] = v;
            }
        }
        level.cells::<ANY>(&mut s, &k, &x, &corners, parked, &mut co);
        // Lanes whose miss stepped on to the next cell stay parked; into a
        // new level-1 node, they go back to the lane steps; the others are
        // decided one by one.
        parked &= !co.climb;
        let mut pm = co.done;
        while pm != 0 {
            let l = pm.trailing_zeros() as usize;
            pm &= pm - 1;
            let kr = s.ray[l];
            let (mut ci, mut cj, t) = (s.ci[l], s.cj[l], s.t[l]);
            let t_exit = co.t_exit[l];
            let exit = match co.exit[l] {
                EXIT_X => Exit::X,
                EXIT_Y => Exit::Y,
                _ => Exit::End,
            };
            let flags = co.flags[l];
            let h = if flags & SCALAR != 0 {
                // Within rounding distance of an edge, or a zero edge
                // function: the single-ray walk's cell test, neighbours and all.
                let first = t == s.t0[l];
                leaf::<ANY>(f, &rays.ray(kr), ci, cj, t, t_exit, exit, first, &mut stats)
            } else if flags & FOUND != 0 {
                Some(CellHit {
                    t: co.t[l],
                    cell: (ci, cj),
                    triangle: if co.upper[l] {
                        Triangle::Upper
                    } else {
                        Triangle::Lower
                    },
                    bary: Vec3::new(co.bary[0][l], co.bary[1][l], co.bary[2][l]),
                })
            } else {
                None
            };
            let end = match h {
                Some(h) if ANY || h.t <= t_exit + x.ttol[l] => Some(Outcome::Hit(h)),
                Some(_) => Some(Outcome::Walk(Cursor {
                    ci,
                    cj,
                    t,
                    level: 0,
                })),
                None => {
                    // The walk's step past a cell (as the lane step at level 0).
                    let (oci, ocj) = (ci, cj);
                    let left = match exit {
                        Exit::End => true,
                        Exit::X => {
                            ci = if s.sign[l] & 1 != 0 {
                                ci + 1
                            } else {
                                ci.wrapping_sub(1)
                            };
                            ci >= k.ncx
                        }
                        Exit::Y => {
                            cj = if s.sign[l] & 4 != 0 {
                                cj + 1
                            } else {
                                cj.wrapping_sub(1)
                            };
                            cj >= k.ncy
                        }
                    };
                    if left {
                        Some(Outcome::Miss)
                    } else {
                        s.ci[l] = ci;
                        s.cj[l] = cj;
                        s.t[l] = t_exit;
                        if k.top > 0 && ((ci ^ oci) | (cj ^ ocj)) >> 1 != 0 {
                            // Back to the nodes: the lane steps on at level 1.
                            s.level[l] = 1;
                            parked &= !(1 << l);
                        }
                        None
                    }
                }
            };
            if let Some(e) = end {
                out[kr] = e;
                parked &= !(1 << l);
                refill(
                    &mut s, &mut x, &mut live, &mut next, l, &take, rays, lo, scale,
                );
            }
        }
    }
}

/// Lanes parked at cells before a pass of exact tests runs (unless no lane
/// is stepping).
const PARK_BATCH: u32 = 6;

/// Loads lane `l` with the next ray, or retires it when there is none.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn refill<R: Rays + ?Sized>(
    s: &mut Lanes,
    x: &mut Exact,
    live: &mut u32,
    next: &mut usize,
    l: usize,
    take: &impl Fn(&mut usize) -> Option<(usize, Cursor)>,
    rays: &R,
    lo: f32,
    scale: f32,
) {
    match take(next) {
        Some((kr, c)) => {
            rays.load(kr, s, x, l, c, lo, scale);
        }
        None => {
            // A dead lane keeps stepping (ignored): park its state on
            // cell (0, 0) so its arithmetic stays in range (a ray that
            // left through the low side has a wrapped coordinate).
            s.live[l] = false;
            s.ci[l] = 0;
            s.cj[l] = 0;
            s.level[l] = 0;
            *live &= !(1 << l);
        }
    }
}

/// The per-lane ray constants of the exact cell test (struct-of-arrays
/// copies of [`GridRay`] fields the node steps do not need).
#[derive(Clone, Copy, Default)]
pub(crate) struct Exact {
    oz: [f32; LANES],
    dz: [f32; LANES],
    zm: [f32; LANES],
    t_min: [f32; LANES],
    t_max: [f32; LANES],
    xyeps: [f32; LANES],
    ttol: [f32; LANES],
    /// The shear's rows `px, py, pz`, three components each.
    sh: [[f32; LANES]; 9],
}

impl Exact {
    fn new() -> Self {
        Self::default()
    }

    #[inline]
    fn load(&mut self, l: usize, oz: f32, dz: f32, r: &GridRay) {
        self.oz[l] = oz;
        self.dz[l] = dz;
        self.ttol[l] = r.ttol;
        self.zm[l] = r.zm;
        self.t_min[l] = r.t_min;
        self.t_max[l] = r.t_max;
        self.xyeps[l] = r.xyeps;
        let rows = [r.shear.px, r.shear.py, r.shear.pz];
        for (q, v) in rows.iter().enumerate() {
            self.sh[3 * q][l] = v.x;
            self.sh[3 * q + 1][l] = v.y;
            self.sh[3 * q + 2][l] = v.z;
        }
    }
}

/// How each lane's cell test came out.
#[derive(Clone, Copy, Default)]
struct CellOut {
    /// Bit `l` set: parked lane `l` missed and stepped on into a new
    /// level-1 node (it is at level 1 and steps on in the lanes). A parked
    /// lane that missed and stepped on within its level-1 node stays parked.
    climb: u32,
    /// Bit `l` set: the driver decides parked lane `l` (a hit, a [`SCALAR`]
    /// lane, or the ray left the field); its cursor is unchanged.
    done: u32,
    t_exit: [f32; LANES],
    exit: [u32; LANES],
    flags: [u32; LANES],
    t: [f32; LANES],
    upper: [bool; LANES],
    bary: [[f32; LANES]; 3],
}

impl CellOut {
    fn new() -> Self {
        Self::default()
    }
}

const EXIT_END: u32 = 0;
const EXIT_X: u32 = 1;
const EXIT_Y: u32 = 2;
/// `CellOut::flags`: a triangle was hit (`t`, `upper`, `bary` hold it).
const FOUND: u32 = 1;
/// `CellOut::flags`: the single-ray [`leaf`] must decide (a zero edge
/// function, or an edge or corner within rounding distance whose
/// neighbouring cells the leaf tests too).
const SCALAR: u32 = 2;

/// The exact test of every lane's cell at once, as the single-ray walk's
/// cell step: the cell's exit ([`Exit::of`]), the two-sided z cull and the
/// watertight pair of triangle tests ([`crate::ray_cell`]), with the same
/// `f32` operations in the same order per lane and both triangles' outcomes
/// computed and selected, so the loop over lanes vectorises. Lanes whose
/// test needs more than that (a zero edge function, the neighbours of an
/// edge within rounding distance) are flagged [`SCALAR`].
#[inline(always)]
#[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
fn cells<const ANY: bool>(
    s: &mut Lanes,
    k: &Consts<'_>,
    x: &Exact,
    c: &[[f32; LANES]; 4],
    parked: u32,
    o: &mut CellOut,
) {
    let (mut climbed, mut done) = (0u32, 0u32);
    for l in 0..LANES {
        let (ci, cj, t) = (s.ci[l], s.cj[l], s.t[l]);
        let sign = s.sign[l];
        let (xpos, xneg, ypos, yneg) = (sign & 1 != 0, sign & 2 != 0, sign & 4 != 0, sign & 8 != 0);
        // Cell coordinates are below 2²⁴ (dead lanes sit at 0): the `i32`
        // conversions are exact.
        let (x0, x1) = (ci as i32 as f32, ci.wrapping_add(1) as i32 as f32);
        let (y0, y1) = (cj as i32 as f32, cj.wrapping_add(1) as i32 as f32);
        let (ox, oy, oz) = (s.ox[l], s.oy[l], x.oz[l]);
        let tx = if xpos {
            (x1 - ox) * s.ix[l]
        } else if xneg {
            (x0 - ox) * s.ix[l]
        } else {
            f32::INFINITY
        };
        let ty = if ypos {
            (y1 - oy) * s.iy[l]
        } else if yneg {
            (y0 - oy) * s.iy[l]
        } else {
            f32::INFINITY
        };
        let t_end = s.t_end[l];
        // `Exit::of`.
        let t_exit = fmax(fmin(fmin(tx, ty), t_end), t);
        let exit = if t_exit >= t_end {
            EXIT_END
        } else if tx <= ty {
            EXIT_X
        } else {
            EXIT_Y
        };
        // The cull (`leaf`).
        let h = [c[0][l], c[1][l], c[2][l], c[3][l]];
        let (za, zb) = (oz + t * x.dz[l], oz + t_exit * x.dz[l]);
        let (zlo, zhi) = if za <= zb { (za, zb) } else { (zb, za) };
        let cmax = fmax(fmax(h[0], h[1]), fmax(h[2], h[3]));
        let cmin = fmin(fmin(h[0], h[1]), fmin(h[2], h[3]));
        let zm = x.zm[l];
        let pass = (zlo <= cmax + zm) & (zhi >= cmin - zm);
        // The watertight pair (`intersect_cell`).
        let sh = |q: usize| x.sh[q][l];
        let project = |px: f32, py: f32, ph: f32| {
            let rel = [px - ox, py - oy, ph - oz];
            let dot = |q: usize| sh(q) * rel[0] + sh(q + 1) * rel[1] + sh(q + 2) * rel[2];
            [dot(0), dot(3), dot(6)]
        };
        let p00 = project(x0, y0, h[0]);
        let p10 = project(x1, y0, h[1]);
        let p01 = project(x0, y1, h[2]);
        let p11 = project(x1, y1, h[3]);
        let edge = |a: [f32; 3], b: [f32; 3]| a[0] * b[1] - a[1] * b[0];
        let diag = edge(p01, p10);
        let left = edge(p00, p01);
        let bottom = edge(p10, p00);
        let right = edge(p11, p10);
        let top = edge(p01, p11);
        let zero = (diag == 0.0) | (left == 0.0) | (bottom == 0.0) | (right == 0.0) | (top == 0.0);
        let (t_min, t_max) = (x.t_min[l], x.t_max[l]);
        let tri = |u: f32, v: f32, w: f32, z: [f32; 3]| {
            let det = u + v + w;
            let inside = ((det > 0.0) & (u >= 0.0) & (v >= 0.0) & (w >= 0.0))
                | ((det < 0.0) & (u <= 0.0) & (v <= 0.0) & (w <= 0.0));
            let inv = 1.0 / det;
            let tt = (u * z[0] + v * z[1] + w * z[2]) * inv;
            let ok = inside & (tt >= t_min) & (tt <= t_max);
            (ok, tt, [u * inv, v * inv, w * inv])
        };
        let (lok, lt, lb) = tri(diag, left, bottom, [p00[2], p10[2], p01[2]]);
        let (uok, ut, ub) = tri(-diag, right, top, [p11[2], p01[2], p10[2]]);
        let pick_upper = uok & (!lok | (!ANY & (ut < lt)));
        let found = lok | uok;
        o.t[l] = if pick_upper { ut } else { lt };
        o.upper[l] = pick_upper;
        for q in 0..3 {
            o.bary[q][l] = if pick_upper { ub[q] } else { lb[q] };
        }
        // The edges and corners within rounding distance (`leaf`'s `near`).
        let e = x.xyeps[l];
        let near = |tn: f32| {
            let (px, py) = (ox + tn * s.dx[l], oy + tn * s.dy[l]);
            (
                px < x0 + e,
                px > x0 + 1.0 - e,
                py < y0 + e,
                py > y0 + 1.0 - e,
            )
        };
        let (axm, axp, aym, ayp) = near(t);
        let (bxm, bxp, bym, byp) = near(t_exit);
        let first = t == s.t0[l];
        let at_in = first & (axm | axp | aym | ayp);
        let at_out = if exit == EXIT_END {
            bxm | bxp | bym | byp
        } else if exit == EXIT_X {
            bym | byp
        } else {
            bxm | bxp
        };
        let neighbours = !(ANY & found) & (at_in | at_out);
        let scalar = pass & (zero | neighbours);
        let hit = pass & found;
        o.flags[l] = u32::from(hit) * FOUND + u32::from(scalar) * SCALAR;
        o.t_exit[l] = t_exit;
        o.exit[l] = exit;
        // A parked lane whose cell test settled a miss takes the walk's step
        // past the cell here (as the lane step at level 0).
        let is_parked = (parked >> l) & 1 != 0;
        let xstep = exit == EXIT_X;
        let nci = if !xstep {
            ci
        } else if xpos {
            ci.wrapping_add(1)
        } else {
            ci.wrapping_sub(1)
        };
        let ncj = if xstep {
            cj
        } else if ypos {
            cj.wrapping_add(1)
        } else {
            cj.wrapping_sub(1)
        };
        let left = (exit == EXIT_END) | (nci >= k.ncx) | (ncj >= k.ncy);
        let climb = (k.top > 0) & (((nci ^ ci) | (ncj ^ cj)) >> 1 != 0);
        let mv = is_parked & !hit & !scalar & !left;
        s.ci[l] = if mv { nci } else { ci };
        s.cj[l] = if mv { ncj } else { cj };
        s.t[l] = if mv { t_exit } else { t };
        s.level[l] = if mv & climb { 1 } else { s.level[l] };
        climbed |= u32::from(mv & climb) << l;
        done |= u32::from(is_parked & !mv) << l;
    }
    o.climb = climbed;
    o.done = done;
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn cells_avx2<const ANY: bool>(
    s: &mut Lanes,
    k: &Consts<'_>,
    x: &Exact,
    c: &[[f32; LANES]; 4],
    parked: u32,
    o: &mut CellOut,
) {
    cells::<ANY>(s, k, x, c, parked, o);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
fn cells_avx512<const ANY: bool>(
    s: &mut Lanes,
    k: &Consts<'_>,
    x: &Exact,
    c: &[[f32; LANES]; 4],
    parked: u32,
    o: &mut CellOut,
) {
    cells::<ANY>(s, k, x, c, parked, o);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Ray;
    use glam::Vec3;
    use natura_core::{HeightField, Seed};

    /// The single-ray walk from the scalar pre-descent's cursor ends exactly
    /// as the walk from the start (closest and any hit), on fields with
    /// plateaus and flats (altitudes on node bounds) and rays from inside
    /// the box, from above, along axes and vertical; and the pre-descent
    /// does descend for rays starting among the terrain.
    #[test]
    fn pre_descent_leaves_the_walk_unchanged() {
        let s = Seed(31);
        let mut descended = 0;
        for (case, plateau) in [(0i64, false), (1, true), (2, true), (3, false)] {
            let hf = HeightField::from_fn(150 + case as usize * 40, 97, 1.5, |i, j| {
                let v = 30.0 * s.uniform2(i as i64 / 5 + case * 1000, j as i64 / 4) as f32;
                if plateau {
                    (v / 7.5).floor() * 7.5
                } else {
                    v + s.uniform2(i as i64, j as i64) as f32
                }
            })
            .unwrap();
            let tr = MipmapTracer::new(&hf).unwrap();
            for k in 0..1500i64 {
                let u = |c: i64| s.uniform2(case * 100_000 + k, c) as f32;
                let o = Vec3::new(300.0 * u(0) - 30.0, 170.0 * u(1) - 15.0, 40.0 * u(2) - 5.0);
                let o = if k % 4 == 0 { o.round() } else { o };
                let d = match k % 5 {
                    0 => Vec3::new(u(3) - 0.5, 0.0, 0.1 * (u(5) - 0.5)),
                    1 => Vec3::new(0.0, 0.0, -1.0),
                    _ => Vec3::new(u(3) - 0.5, u(4) - 0.5, 0.3 * (u(5) - 0.6)),
                };
                let Some(r) = tr.setup(&Ray::new(o, d), 0.0, f32::INFINITY) else {
                    continue;
                };
                let c = tr.start(&r);
                let mut st = TraceStats::default();
                let c2 = tr.descend(&r, c, &mut st);
                descended += usize::from(c2.level < c.level);
                let key =
                    |h: Option<CellHit>| h.map(|h| (h.t.to_bits(), h.cell, h.triangle.index()));
                assert_eq!(
                    key(tr.walk::<false>(&r, c2, &mut st)),
                    key(tr.walk::<false>(&r, c, &mut st)),
                    "case {case}, ray {k}"
                );
                assert_eq!(
                    tr.walk::<true>(&r, c2, &mut st).is_some(),
                    tr.walk::<true>(&r, c, &mut st).is_some()
                );
            }
        }
        assert!(descended > 1000, "{descended}");
    }

    /// The step's event masks (parked lanes in the low half, departed lanes
    /// in the high half) are the same from the portable loop and the AVX2
    /// compares, and say exactly which lanes report which event.
    #[test]
    fn event_masks_agree_at_every_instruction_set() {
        let s = Seed(5);
        for k in 0..4000i64 {
            let mut events = [GOING; LANES];
            for (l, e) in events.iter_mut().enumerate() {
                *e = match (s.uniform2(k, l as i64) * 3.0) as u32 {
                    0 => GOING,
                    1 => AT_CELL,
                    _ => LEFT,
                };
            }
            if k % 7 == 0 {
                events = [[GOING, AT_CELL, LEFT][(k / 7 % 3) as usize]; LANES];
            }
            let m = event_mask(&events);
            for (l, &e) in events.iter().enumerate() {
                assert_eq!((m >> l) & 1 == 1, e == AT_CELL);
                assert_eq!((m >> (l + LANES)) & 1 == 1, e == LEFT);
            }
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                #[allow(unsafe_code)]
                // SAFETY: the CPU reported AVX2.
                let v = unsafe { event_mask_avx2(&events) };
                assert_eq!(v, m, "{events:?}");
            }
        }
    }

    /// The instruction sets this CPU supports, portable code first.
    fn levels() -> Vec<Level> {
        #[allow(unused_mut)]
        let mut v = vec![Level::Scalar];
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
                v.push(Level::Avx2);
            }
            if matches!(Level::detect(), Level::Avx512) {
                v.push(Level::Avx512);
            }
        }
        v
    }

    /// The set-up in lanes equals `setup` (`GridRay::new` and the box test),
    /// `start` and `descend` bit for bit, at every instruction set: rays with zero,
    /// tiny, huge, infinite and NaN components, zero directions, axis-parallel
    /// and vertical rays, rays through grid points, inside and outside the
    /// box, over several ranges.
    #[test]
    fn lane_set_up_equals_the_single_ray_set_up() {
        let s = Seed(41);
        let hf = HeightField::from_fn(77, 45, 2.5, |i, j| {
            30.0 * s.uniform2(i as i64, j as i64) as f32 - 4.0
        })
        .unwrap();
        let tr = MipmapTracer::new(&hf).unwrap();
        let f = &tr.f;
        let pick = |k: i64, c: i64, scale: f32, off: f32| {
            let u = s.uniform2(1000 + k, c) as f32;
            match (k + c) % 23 {
                0 => 0.0,
                1 => f32::NAN,
                2 => f32::INFINITY,
                3 => -1e30,
                4 => 1e-30,
                5 => (scale * u + off).round(),
                _ => scale * u + off,
            }
        };
        let mut rays = Vec::new();
        for k in 0..4000i64 {
            let o = Vec3::new(
                pick(k, 0, 260.0, -30.0),
                pick(k, 1, 160.0, -20.0),
                pick(k, 2, 60.0, -10.0),
            );
            let mut d = Vec3::new(
                pick(k, 3, 2.0, -1.0),
                pick(k, 4, 2.0, -1.0),
                pick(k, 5, 2.0, -1.0),
            );
            match k % 6 {
                0 => d.x = 0.0,
                1 => d.y = 0.0,
                2 => d = Vec3::new(0.0, 0.0, d.z),
                3 => d = Vec3::ZERO,
                _ => {}
            }
            rays.push(Ray::new(o, d));
        }
        let bits3 = |v: Vec3| v.to_array().map(f32::to_bits);
        let mut met = 0;
        let mut descents = 0;
        for (t_min, t_max) in [
            (0.0, f32::INFINITY),
            (f32::NEG_INFINITY, f32::INFINITY),
            (-3.0, 70.0),
            (2.0, 2.0),
        ] {
            for &level in &levels() {
                let mut lanes = SetupLanes::new();
                let mut offset = [0u32; 32];
                for (o, &m) in offset.iter_mut().zip(&tr.mip.offset) {
                    *o = m as u32;
                }
                let mut dl = [0u32; SETUP_LANES];
                for group in rays.chunks_exact(SETUP_LANES) {
                    let g: &[Ray; SETUP_LANES] = group.try_into().unwrap();
                    setup_with(level, f, g, t_min, t_max, tr.mip.top, &mut lanes);
                    descend_with(level, &tr, &offset, &mut lanes, &mut dl);
                    for (l, ray) in group.iter().enumerate() {
                        let want = tr.setup(ray, t_min, t_max);
                        assert_eq!(lanes.ok[l], want.is_some(), "{level:?} {ray:?}");
                        let Some(w) = want else { continue };
                        met += 1;
                        let g = lanes.ray(l, t_min, t_max);
                        let key = |r: &GridRay| {
                            (
                                bits3(r.o),
                                bits3(r.d),
                                [r.inv.x, r.inv.y, r.t_min, r.t_max, r.t0, r.t1].map(f32::to_bits),
                                [r.zeps, r.xyeps, r.ttol, r.zm].map(f32::to_bits),
                                [bits3(r.shear.px), bits3(r.shear.py), bits3(r.shear.pz)],
                            )
                        };
                        assert_eq!(key(&g), key(&w), "{level:?} {ray:?}");
                        let c = tr.start(&w);
                        assert_eq!(
                            (lanes.ci[l], lanes.cj[l], lanes.level[l]),
                            (c.ci, c.cj, c.level),
                            "{level:?} {ray:?}"
                        );
                        let dc = tr.descend(&w, c, &mut TraceStats::default());
                        assert_eq!(dl[l], dc.level, "descent: {level:?} {ray:?}");
                        descents += usize::from(dc.level < c.level);
                    }
                }
            }
        }
        assert!(met > 5000, "{met} rays meet the box");
        assert!(descents > 1000, "{descents} rays descend at the start");
    }

    /// The hit records filled in lanes equal `make_hit`'s bit for bit, at
    /// every instruction set: fields too small for interior cells, border and
    /// interior cells, both triangles, barycentrics on corners and edges, flat
    /// (zero-gradient) and steep fields, partial groups.
    #[test]
    fn hit_lanes_equal_make_hit() {
        use crate::ray::Triangle;
        use crate::ray_cell::make_hit;
        let s = Seed(43);
        let mut checked = 0;
        for (case, (nx, ny, cell)) in [
            (2, 2, 1.0),
            (3, 5, 0.5),
            (4, 4, 2.0),
            (37, 23, 3.7),
            (64, 65, 10.0),
        ]
        .into_iter()
        .enumerate()
        {
            for kind in 0..3 {
                let hf = HeightField::from_fn(nx, ny, cell, |i, j| {
                    let v = s.uniform2(case as i64 * 100 + i as i64, j as i64) as f32;
                    match kind {
                        0 => 5.0,
                        1 => 300.0 * v - 50.0,
                        _ => (3.0 * v).floor() * 1e-3 + 1e4,
                    }
                })
                .unwrap();
                let tr = MipmapTracer::new(&hf).unwrap();
                let f = &tr.f;
                let mut lanes = HitLanes::new();
                let mut rays = Vec::new();
                for k in 0..200i64 {
                    let u = |c: i64| s.uniform2(k + 7919 * case as i64, c + 10 * kind) as f32;
                    let (i, j) = ((u(0) * f.ncx as f32) as u32, (u(1) * f.ncy as f32) as u32);
                    let (i, j) = (i.min(f.ncx - 1), j.min(f.ncy - 1));
                    let bary = match k % 5 {
                        0 => Vec3::new(1.0, 0.0, 0.0),
                        1 => Vec3::new(0.5, 0.5, 0.0),
                        _ => {
                            let (a, b) = (u(2), u(3) * (1.0 - u(2)));
                            Vec3::new(a, b, 1.0 - a - b)
                        }
                    };
                    let triangle = if k % 2 == 0 {
                        Triangle::Lower
                    } else {
                        Triangle::Upper
                    };
                    let hit = CellHit {
                        t: u(4) * 100.0,
                        cell: (i, j),
                        triangle,
                        bary,
                    };
                    let ray = Ray::new(Vec3::ZERO, Vec3::new(u(5) - 0.5, u(6) - 0.5, u(7) - 0.7));
                    rays.push((hit, ray));
                }
                for &level in &levels() {
                    for group in rays.chunks(HIT_LANES) {
                        for (l, (h, r)) in group.iter().enumerate() {
                            lanes.hit[l] = *h;
                            lanes.dir[l] = r.dir;
                        }
                        let mut out = vec![None; group.len()];
                        let slot: [usize; HIT_LANES] = std::array::from_fn(|l| l);
                        hits_with(level, f, &lanes, group.len(), &mut out, &slot);
                        for ((h, r), got) in group.iter().zip(&out) {
                            let want = make_hit(f, r, *h);
                            let got = got.expect("every lane is filled in");
                            let key = |h: &Hit| {
                                (
                                    h.t.to_bits(),
                                    [h.point, h.geometric_normal, h.smooth_normal, h.barycentric]
                                        .map(|v| v.to_array().map(f32::to_bits)),
                                    h.cell,
                                    h.triangle,
                                    h.from_above,
                                )
                            };
                            assert_eq!(key(&got), key(&want), "{level:?}, {nx} × {ny}, {h:?}");
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 5000, "{checked}");
    }

    /// The lane step's shift form of a level's width equals the pyramid's.
    #[test]
    fn level_widths_by_shift() {
        for nx in [2usize, 3, 5, 17, 64, 65, 100, 1025] {
            let hf = HeightField::flat(nx, 3, 1.0, 0.0).unwrap();
            let tr = MipmapTracer::new(&hf).unwrap();
            let m = tr.mipmap();
            let ncx = (nx - 1) as u32;
            for k in 1..=m.top_level() {
                assert_eq!(
                    ((ncx - 1) >> k) + 1,
                    m.level_dims(k).unwrap().0,
                    "{nx}, level {k}"
                );
            }
        }
    }

    /// Every instruction set this CPU supports ends every walk the same way
    /// as the portable code, bit for bit.
    #[test]
    fn every_level_gives_the_same_outcomes() {
        let s = Seed(7);
        let hf = HeightField::from_fn(300, 213, 2.0, |i, j| {
            40.0 * s.uniform2(i as i64 / 9, j as i64 / 7) as f32
                + 3.0 * s.uniform2(i as i64, j as i64) as f32
        })
        .unwrap();
        let tr = MipmapTracer::new(&hf).unwrap();
        let mut rays = Vec::new();
        for k in 0..3000i64 {
            let u = |c: i64| s.uniform2(k, c) as f32;
            let o = Vec3::new(600.0 * u(0) - 20.0, 430.0 * u(1) - 20.0, 60.0 * u(2) - 5.0);
            let d = Vec3::new(u(3) - 0.5, u(4) - 0.5, 0.2 * (u(5) - 0.6));
            rays.push(Ray::new(o, d));
        }
        let grid: Vec<GridRay> = rays
            .iter()
            .map(|r| {
                tr.setup(r, 0.0, f32::INFINITY)
                    .unwrap_or_else(GridRay::idle)
            })
            .collect();
        let start: Vec<Option<Cursor>> = rays
            .iter()
            .map(|r| tr.setup(r, 0.0, f32::INFINITY).map(|g| tr.start(&g)))
            .collect();
        let key = |o: &Outcome| match *o {
            Outcome::Miss => (0, 0, 0, 0, 0),
            Outcome::Hit(h) => (1, h.t.to_bits(), h.cell.0, h.cell.1, h.triangle.index()),
            Outcome::Walk(c) => (2, c.t.to_bits(), c.ci, c.cj, c.level),
        };
        let mut levels = vec![];
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
                levels.push(Level::Avx2);
            }
            if matches!(Level::detect(), Level::Avx512) {
                levels.push(Level::Avx512);
            }
        }
        for any in [false, true] {
            let run = |level: Level| {
                let mut out = Vec::new();
                if any {
                    walk_lanes_with::<true, [GridRay]>(
                        level,
                        0,
                        &tr,
                        grid.as_slice(),
                        &start,
                        None,
                        &mut out,
                    );
                } else {
                    walk_lanes_with::<false, [GridRay]>(
                        level,
                        0,
                        &tr,
                        grid.as_slice(),
                        &start,
                        None,
                        &mut out,
                    );
                }
                out
            };
            let want = run(Level::Scalar);
            let hits = want.iter().filter(|o| matches!(o, Outcome::Hit(_))).count();
            assert!(hits > 1000, "{hits}");
            for &level in &levels {
                let got = run(level);
                for (g, w) in got.iter().zip(&want) {
                    assert_eq!(key(g), key(w), "{level:?}");
                }
            }
            // The batch path's rays, set up in lanes (and walked from the
            // lane pre-descent), end the same way at every instruction set.
            for level in levels.iter().copied().chain([Level::Scalar]) {
                let mut groups = vec![SetupLanes::new(); rays.len().div_ceil(SETUP_LANES)];
                let mut dl = vec![0u32; groups.len() * SETUP_LANES];
                let mut offset = [0u32; 32];
                for (o, &m) in offset.iter_mut().zip(&tr.mip.offset) {
                    *o = m as u32;
                }
                for (g, (chunk, d)) in groups
                    .iter_mut()
                    .zip(rays.chunks(SETUP_LANES).zip(dl.chunks_mut(SETUP_LANES)))
                {
                    let mut a = [chunk[0]; SETUP_LANES];
                    a[..chunk.len()].copy_from_slice(chunk);
                    setup_with(level, &tr.f, &a, 0.0, f32::INFINITY, tr.mip.top, g);
                    descend_with(level, &tr, &offset, g, d.try_into().unwrap());
                }
                let soa = SoaRays {
                    groups: &groups,
                    t_min: 0.0,
                    t_max: f32::INFINITY,
                };
                let mut got = Vec::new();
                if any {
                    walk_lanes_with::<true, _>(level, 0, &tr, &soa, &start, Some(&dl), &mut got);
                } else {
                    walk_lanes_with::<false, _>(level, 0, &tr, &soa, &start, Some(&dl), &mut got);
                }
                let mut stats = TraceStats::default();
                for (k, (g, w)) in got.iter().zip(&want).enumerate() {
                    // Hand-overs to the single-ray walk may start from a
                    // different cursor (the lanes walked from the descent):
                    // compare where the walks end.
                    let mut end = |o: &Outcome| match *o {
                        Outcome::Walk(c) => match if any {
                            tr.walk::<true>(&grid[k], c, &mut stats)
                        } else {
                            tr.walk::<false>(&grid[k], c, &mut stats)
                        } {
                            Some(h) => Outcome::Hit(h),
                            None => Outcome::Miss,
                        },
                        o => o,
                    };
                    assert_eq!(
                        key(&end(g)),
                        key(&end(w)),
                        "lane set-up, {level:?}, ray {k}"
                    );
                }
            }
        }
    }

    /// Every ray walked in the lanes from its start (whatever its level)
    /// ends with the single-ray walk's hit, bit for bit: small fields of
    /// every kind (flat, spiky, plateaus, tilted) and rays of every awkward
    /// sort (axis-parallel, vertical, grazing, through corners, from below,
    /// from inside), closest and any hit.
    #[test]
    fn lanes_equal_the_single_ray_walk_on_awkward_rays() {
        let s = Seed(23);
        let mut checked = 0;
        for case in 0..60i64 {
            let u = |a: i64, b: i64| s.uniform2(case * 1000 + a, b) as f32;
            let (nx, ny) = (2 + (u(0, 0) * 40.0) as usize, 2 + (u(0, 1) * 40.0) as usize);
            let cell = [1.0, 0.5, 2.0, 3.7][case as usize % 4];
            let kind = case % 5;
            let hf = HeightField::from_fn(nx, ny, cell, |i, j| {
                let v = s.uniform2(case * 7919 + i as i64, j as i64) as f32;
                match kind {
                    0 => 10.0 * v,
                    1 => 3.0,
                    2 => {
                        if v > 0.85 {
                            20.0 * v
                        } else {
                            0.0
                        }
                    }
                    3 => (4.0 * v).floor() * 2.5,
                    _ => 0.7 * i as f32 - 0.4 * j as f32 + 2.0,
                }
            })
            .unwrap();
            let tr = MipmapTracer::new(&hf).unwrap();
            let (lo, hi) = hf.min_max();
            let mut rays = Vec::new();
            for k in 0..64i64 {
                let r = |c: i64| u(k + 1, c);
                let o = Vec3::new(
                    (1.6 * r(0) - 0.3) * nx as f32 * cell,
                    (1.6 * r(1) - 0.3) * ny as f32 * cell,
                    lo + (1.6 * r(2) - 0.3) * (hi - lo + 1.0),
                );
                let o = if k % 5 == 0 {
                    (o / cell).round() * cell
                } else {
                    o
                };
                let d = match k % 6 {
                    0 => Vec3::new(r(3) - 0.5, r(4) - 0.5, r(5) - 0.5),
                    1 => Vec3::new(if r(3) > 0.5 { 1.0 } else { -1.0 }, 0.0, r(5) - 0.5),
                    2 => Vec3::new(0.0, if r(3) > 0.5 { 1.0 } else { -1.0 }, r(5) - 0.5),
                    3 => Vec3::new(0.0, 0.0, if r(3) > 0.5 { 1.0 } else { -1.0 }),
                    4 => Vec3::new(r(3) - 0.5, r(4) - 0.5, 0.02 * (r(5) - 0.5)),
                    _ => Vec3::new(1.0, if r(3) > 0.5 { 1.0 } else { -1.0 }, 0.3 * (r(5) - 0.5)),
                };
                rays.push(Ray::new(o, d * Vec3::new(cell, cell, 1.0)));
            }
            let grid: Vec<GridRay> = rays
                .iter()
                .map(|r| {
                    tr.setup(r, 0.0, f32::INFINITY)
                        .unwrap_or_else(GridRay::idle)
                })
                .collect();
            let start: Vec<Option<Cursor>> = rays
                .iter()
                .map(|r| tr.setup(r, 0.0, f32::INFINITY).map(|g| tr.start(&g)))
                .collect();
            let key = |h: Option<CellHit>| h.map(|h| (h.t.to_bits(), h.cell, h.triangle.index()));
            let mut stats = TraceStats::default();
            let mut out = Vec::new();
            walk_lanes_with::<false, [GridRay]>(
                Level::detect(),
                0,
                &tr,
                grid.as_slice(),
                &start,
                None,
                &mut out,
            );
            for (k, (r, o)) in grid.iter().zip(&out).enumerate() {
                let got = match *o {
                    Outcome::Miss => None,
                    Outcome::Hit(h) => Some(h),
                    Outcome::Walk(c) => tr.walk::<false>(r, c, &mut stats),
                };
                let want = start[k].and_then(|c| tr.walk::<false>(r, c, &mut stats));
                assert_eq!(key(got), key(want), "case {case}, ray {k}: {:?}", rays[k]);
                checked += usize::from(want.is_some());
            }
            walk_lanes_with::<true, [GridRay]>(
                Level::detect(),
                0,
                &tr,
                grid.as_slice(),
                &start,
                None,
                &mut out,
            );
            for (k, (r, o)) in grid.iter().zip(&out).enumerate() {
                let got = match *o {
                    Outcome::Miss => false,
                    Outcome::Hit(_) => true,
                    Outcome::Walk(c) => tr.walk::<true>(r, c, &mut stats).is_some(),
                };
                let want = start[k].is_some_and(|c| tr.walk::<true>(r, c, &mut stats).is_some());
                assert_eq!(got, want, "any hit: case {case}, ray {k}");
            }
        }
        assert!(checked > 500, "{checked} hits");
    }
}
