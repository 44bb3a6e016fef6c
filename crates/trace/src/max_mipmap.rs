//! Maximum mipmaps: a min/max quadtree over the cells, and the hierarchical
//! tracer that skips empty space with it.
//!
//! Tevs, Ihrke & Seidel, "Maximum Mipmaps for Fast, Accurate, and Scalable
//! Dynamic Height Field Rendering", I3D 2008 — the `m = 2` case of the
//! "n² tree" hierarchy that Musgrave proposes and Kolb implemented at
//! `m = 16` (Musgrave 1993, §3.5; Musgrave et al. 1989, §5). Each node of
//! level `k ≥ 1` bounds the heights of a `2ᵏ × 2ᵏ` block of cells. A ray
//! walks the nodes of the coarsest level it may, descends only where its
//! z-span over a node meets the node's `[min, max]`, and ascends again when
//! it crosses into a new parent. At the leaves it runs the grid tracer's
//! exact cell test (two-sided cull against the 4 corners, two watertight
//! triangle tests), so its hits are the grid tracer's hits.
//!
//! **Memory.** Level 0 (one node per cell) is not stored: a cell's bounds
//! are its four corners, which the leaf test reads anyway. Levels `k ≥ 1`
//! store `min` and `max` as 16-bit values quantised conservatively (min
//! rounded down, max rounded up) over the field's height range, 4 bytes per
//! node, about `N/3` bytes in all for `N` samples: one third of the `f32`
//! field. Min and max make the cull valid for
//! rays from any direction, which the source's max-only `A` grid is not
//! (Musgrave 1993, §3.3.1).

use natura_core::HeightField;

use crate::error::Result;
use crate::field::FieldView;
use crate::grid_ray::{GridRay, SETUP_LANES, SetupLanes};
use crate::leaf::{leaf, nearer};
use crate::lockstep::kernels::{descend_with, hits_with, setup_with};
use crate::lockstep::{Outcome, Rays, SoaRays, walk_lanes};
use crate::ray::{Hit, Ray, TraceStats};
use crate::ray_cell::{CellHit, HIT_LANES, HitLanes};
use crate::step::{Exit, Signs, leaves_parent, node_exits, span_meets, step_out};
use crate::tracer::Tracer;

/// Set-up groups of [`SETUP_LANES`] rays per packet of the packet skip
/// ([`MipmapTracer::packet_skip`]).
const PACKET_GROUPS: usize = 8;

/// Headroom below `u16::MAX` so rounding a maximum up never overflows.
const Q_RANGE: f32 = 65000.0;

/// A node's quantised `(min, max)` in one word.
#[inline(always)]
fn pack(mn: u16, mx: u16) -> u32 {
    u32::from(mn) | u32::from(mx) << 16
}

/// The inverse of [`pack`].
#[inline(always)]
fn unpack(q: u32) -> (u16, u16) {
    (q as u16, (q >> 16) as u16)
}

/// The min/max pyramid of a height field, levels `1..=top`.
///
/// Node `(a, b)` of level `k` bounds the cells `[a·2ᵏ, (a+1)·2ᵏ) × [b·2ᵏ, (b+1)·2ᵏ)`
/// (clipped to the grid): every height of those cells' corners lies in
/// [`MaxMipmap::node_range`]. Build it once with [`MaxMipmap::new`]; it does
/// not hold the field.
#[derive(Clone, Debug)]
pub struct MaxMipmap {
    /// Nodes of all levels, level 1 first, each level row-major; quantised
    /// `min | max << 16` (one 32-bit word, so lane kernels gather a node at once).
    pub(crate) nodes: Vec<u32>,
    /// Per level `k` (index `k`): offset into `nodes` and size in nodes. Index 0 unused.
    pub(crate) offset: [usize; 32],
    pub(crate) width: [u32; 32],
    height: [u32; 32],
    /// Dequantisation: `h = lo + q·scale`.
    pub(crate) lo: f32,
    pub(crate) scale: f32,
    pub(crate) top: u32,
}

impl MaxMipmap {
    /// Builds the pyramid of `hf` (in parallel rows with the `parallel` feature).
    ///
    /// # Errors
    ///
    /// Fails like [`MipmapTracer::new`].
    pub fn new(hf: &HeightField) -> Result<Self> {
        Ok(Self::build(&FieldView::new(hf)?))
    }

    pub(crate) fn build(f: &FieldView<'_>) -> Self {
        let (lo, hi) = (f.zmin, f.zmax);
        let scale = if hi > lo { (hi - lo) / Q_RANGE } else { 1.0 };
        let deq = |q: u16| lo + f32::from(q) * scale;
        // Conservative quantisation: deq(qmin(m)) ≤ m and deq(qmax(m)) ≥ m, exactly in f32.
        let qmin = |m: f32| {
            let mut q = ((m - lo) / scale).floor().clamp(0.0, 65535.0) as u16;
            while q > 0 && deq(q) > m {
                q -= 1;
            }
            q
        };
        let qmax = |m: f32| {
            let mut q = ((m - lo) / scale).ceil().clamp(0.0, 65535.0) as u16;
            while q < u16::MAX && deq(q) < m {
                q += 1;
            }
            q
        };

        let (ncx, ncy) = (f.ncx, f.ncy);
        let mut top = 0;
        while (1u32 << top) < ncx.max(ncy) {
            top += 1;
        }
        let top = top.max(1);
        let mut offset = [0usize; 32];
        let mut width = [0u32; 32];
        let mut height = [0u32; 32];
        let mut total = 0usize;
        for k in 1..=top {
            width[k as usize] = ncx.div_ceil(1 << k);
            height[k as usize] = ncy.div_ceil(1 << k);
            offset[k as usize] = total;
            total += width[k as usize] as usize * height[k as usize] as usize;
        }
        let mut nodes = vec![0u32; total];

        // Level 1 from the samples: node (a, b) spans samples 2a..=2a+2, 2b..=2b+2.
        let (w1, h1) = (width[1] as usize, height[1] as usize);
        let nx = f.nx;
        let ny = f.ncy as usize + 1;
        let level1 = |b: usize, out: &mut [u32]| {
            let y0 = 2 * b;
            let y1 = (2 * b + 2).min(ny - 1);
            for (a, node) in out.iter_mut().enumerate() {
                let x0 = 2 * a;
                let x1 = (2 * a + 2).min(nx - 1);
                let (mut mn, mut mx) = (f32::INFINITY, f32::NEG_INFINITY);
                for y in y0..=y1 {
                    for &v in &f.h[y * nx + x0..=y * nx + x1] {
                        mn = mn.min(v);
                        mx = mx.max(v);
                    }
                }
                *node = pack(qmin(mn), qmax(mx));
            }
        };
        {
            let l1 = &mut nodes[..w1 * h1];
            #[cfg(feature = "parallel")]
            {
                use rayon::prelude::*;
                l1.par_chunks_mut(w1)
                    .enumerate()
                    .for_each(|(b, row)| level1(b, row));
            }
            #[cfg(not(feature = "parallel"))]
            for (b, row) in l1.chunks_mut(w1).enumerate() {
                level1(b, row);
            }
        }
        // Coarser levels from their four children (quantised bounds combine exactly).
        for k in 2..=top as usize {
            let (cw, ch) = (width[k - 1] as usize, height[k - 1] as usize);
            let (w, h) = (width[k] as usize, height[k] as usize);
            let (done, rest) = nodes.split_at_mut(offset[k]);
            let child = &done[offset[k - 1]..offset[k - 1] + cw * ch];
            for b in 0..h {
                for a in 0..w {
                    let (mut mn, mut mx) = (u16::MAX, 0);
                    for cb in 2 * b..(2 * b + 2).min(ch) {
                        for ca in 2 * a..(2 * a + 2).min(cw) {
                            let (cmn, cmx) = unpack(child[cb * cw + ca]);
                            mn = mn.min(cmn);
                            mx = mx.max(cmx);
                        }
                    }
                    rest[b * w + a] = pack(mn, mx);
                }
            }
        }
        Self {
            nodes,
            offset,
            width,
            height,
            lo,
            scale,
            top,
        }
    }

    /// The coarsest level; its single row of nodes covers the whole grid.
    #[must_use]
    pub fn top_level(&self) -> u32 {
        self.top
    }

    /// `(width, height)` in nodes of level `k` (`1 ≤ k ≤ top`), or `None`.
    #[must_use]
    pub fn level_dims(&self, k: u32) -> Option<(u32, u32)> {
        (1..=self.top)
            .contains(&k)
            .then(|| (self.width[k as usize], self.height[k as usize]))
    }

    /// The conservative `(min, max)` height of node `(a, b)` of level `k`, or
    /// `None` outside the pyramid.
    #[must_use]
    pub fn node_range(&self, k: u32, a: u32, b: u32) -> Option<(f32, f32)> {
        let (w, h) = self.level_dims(k)?;
        if a >= w || b >= h {
            return None;
        }
        let (mn, mx) = unpack(self.nodes[self.offset[k as usize] + (b * w + a) as usize]);
        Some((
            self.lo + f32::from(mn) * self.scale,
            self.lo + f32::from(mx) * self.scale,
        ))
    }

    /// Bytes held by the pyramid (its nodes and level tables).
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of_val(self.nodes.as_slice()) + std::mem::size_of::<Self>()
    }
}

/// The fast path: hierarchical tracing over a [`MaxMipmap`].
///
/// Runs the same leaf test as [`crate::GridTracer`] on the same cells in the
/// same order, minus the cells whose whole block the pyramid proves the ray
/// cannot touch, so it returns the same hits (both are tested against
/// [`crate::brute_force`]) in far fewer steps on large fields.
#[derive(Clone, Debug)]
pub struct MipmapTracer<'a> {
    pub(crate) f: FieldView<'a>,
    pub(crate) mip: MaxMipmap,
}

/// A point of a hierarchical walk: cell `(ci, cj)`, ray parameter `t`, level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cursor {
    pub ci: u32,
    pub cj: u32,
    pub t: f32,
    pub level: u32,
}

impl<'a> MipmapTracer<'a> {
    /// Builds the pyramid of `hf` and returns a tracer over it.
    ///
    /// # Errors
    ///
    /// Fails with [`crate::TraceError::Field`] if `hf` has fewer than 2 × 2
    /// samples, more than [`crate::MAX_SAMPLES_PER_AXIS`] along an axis, or a
    /// NaN or infinite height (checked again here because
    /// [`HeightField::heights_mut`] can store one after construction).
    pub fn new(hf: &'a HeightField) -> Result<Self> {
        let f = FieldView::new(hf)?;
        Ok(Self {
            mip: MaxMipmap::build(&f),
            f,
        })
    }

    /// The pyramid.
    #[must_use]
    pub fn mipmap(&self) -> &MaxMipmap {
        &self.mip
    }

    /// Bytes of acceleration data (the pyramid); the field is borrowed, not copied.
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        self.mip.memory_bytes()
    }

    /// Closest hits of many rays over the same `[t_min, t_max]`: element `k`
    /// is exactly [`Tracer::trace`] of `rays[k]` (the same hit, bit for bit).
    ///
    /// Faster than one call per ray on long (grazing) rays: the walks run 16
    /// rays in lock step without data-dependent branches (see the crate docs,
    /// *Performance*). Rays need not be coherent, but rays that are near in
    /// the array and in space share cache lines.
    #[must_use]
    pub fn trace_many(&self, rays: &[Ray], t_min: f32, t_max: f32) -> Vec<Option<Hit>> {
        let mut out = Vec::with_capacity(rays.len());
        // Hit records in a second pass, `HIT_LANES` hits at a time.
        let simd = natura_core::simd::Simd::best();
        let mut lanes = HitLanes::new();
        let mut slot = [0usize; HIT_LANES];
        let mut n = 0;
        self.many::<false>(rays, t_min, t_max, |k, h| {
            out.push(None);
            if let Some(h) = h {
                lanes.hit[n] = h;
                lanes.dir[n] = rays[k].dir;
                slot[n] = k;
                n += 1;
                if n == HIT_LANES {
                    hits_with(simd, &self.f, &lanes, n, &mut out, &slot);
                    n = 0;
                }
            }
        });
        hits_with(simd, &self.f, &lanes, n, &mut out, &slot);
        out
    }

    /// Any-hit queries of many rays over the same `[t_min, t_max]`: element
    /// `k` is exactly [`Tracer::occluded`] of `rays[k]`. Faster than one call
    /// per ray, like [`MipmapTracer::trace_many`].
    #[must_use]
    pub fn occluded_many(&self, rays: &[Ray], t_min: f32, t_max: f32) -> Vec<bool> {
        let mut out = Vec::with_capacity(rays.len());
        self.many::<true>(rays, t_min, t_max, |_, h| out.push(h.is_some()));
        out
    }

    /// Runs `rays` in chunks: set-up, the lock-step walks, and the single-ray
    /// walk for the few rays the lanes hand back; `emit(k, hit)` in order.
    fn many<const ANY: bool>(
        &self,
        rays: &[Ray],
        t_min: f32,
        t_max: f32,
        mut emit: impl FnMut(usize, Option<CellHit>),
    ) {
        const CHUNK: usize = 1024;
        let mut groups = Vec::with_capacity(CHUNK.div_ceil(SETUP_LANES));
        let mut cur = Vec::with_capacity(CHUNK.min(rays.len()));
        let mut ends = Vec::with_capacity(CHUNK.min(rays.len()));
        let mut descended = Vec::with_capacity(CHUNK.min(rays.len()));
        // The set-up of `GridRay::new` needs a valid range; with an invalid
        // one no ray is traced.
        let range_ok = !(t_min.is_nan() || t_max.is_nan() || t_min > t_max);
        let simd = natura_core::simd::Simd::best();
        let mut dl = [0u32; SETUP_LANES];
        let mut offset = [0u32; 32];
        for (o, &m) in offset.iter_mut().zip(&self.mip.offset) {
            // Offsets beyond 32 bits only occur in pyramids the lanes leave
            // to the single-ray walk (see `walk_lanes`).
            *o = m as u32;
        }
        for (n, chunk) in rays.chunks(CHUNK).enumerate() {
            cur.clear();
            descended.clear();
            // The set-up of `SETUP_LANES` rays at once (the tail padded with
            // copies of its first ray), kept in lanes: the lane walk loads
            // rays from there, and a `GridRay` is only built for the few
            // rays that need the single-ray walk.
            groups.resize(chunk.len().div_ceil(SETUP_LANES), SetupLanes::new());
            // Packet by packet (8 groups, so the set-up stays in L1 between
            // its stages): set-up, the packet skip, pre-descent, cursors.
            let rays_per_packet = PACKET_GROUPS * SETUP_LANES;
            for (packet_rays, packet) in chunk
                .chunks(rays_per_packet)
                .zip(groups.chunks_mut(PACKET_GROUPS))
            {
                let mut lens = [0usize; PACKET_GROUPS];
                if range_ok {
                    for ((group, lanes), len) in packet_rays
                        .chunks(SETUP_LANES)
                        .zip(packet.iter_mut())
                        .zip(lens.iter_mut())
                    {
                        let mut g = [group[0]; SETUP_LANES];
                        g[..group.len()].copy_from_slice(group);
                        setup_with(simd, &self.f, &g, t_min, t_max, self.mip.top, lanes);
                        *len = group.len();
                    }
                    // Rays from one origin (a camera tile's primary rays)
                    // skip the empty space they provably cross together.
                    let lens = &lens[..packet.len()];
                    if let Some(s) = self.packet_bound(packet, lens, 0.0) {
                        self.packet_skip(packet, lens, s);
                    }
                }
                for (group, lanes) in packet_rays.chunks(SETUP_LANES).zip(packet.iter_mut()) {
                    if range_ok {
                        descend_with(simd, self, &offset, lanes, &mut dl);
                    }
                    #[allow(clippy::needless_range_loop)] // `l` indexes the lane arrays alike
                    for l in 0..group.len() {
                        if range_ok && lanes.ok[l] {
                            cur.push(Some(Cursor {
                                ci: lanes.ci[l],
                                cj: lanes.cj[l],
                                t: lanes.t0[l],
                                level: lanes.level[l],
                            }));
                            descended.push(dl[l]);
                        } else {
                            // Never walked.
                            cur.push(None);
                            descended.push(0);
                        }
                    }
                }
            }
            let soa = SoaRays {
                groups: &groups,
                t_min,
                t_max,
            };
            walk_lanes::<ANY, _>(simd, self, &soa, &cur, Some(&descended), &mut ends);
            let mut stats = TraceStats::default();
            for (k, end) in ends.iter().enumerate() {
                let h = match *end {
                    Outcome::Miss => None,
                    Outcome::Hit(h) => Some(h),
                    Outcome::Walk(c) => self.walk::<ANY>(&soa.ray(k), c, &mut stats),
                };
                emit(n * CHUNK + k, h);
            }
        }
    }

    /// Sets up `ray` over `[t_min, t_max]`; `None` if it is invalid or misses the box.
    #[inline]
    pub(crate) fn setup(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<GridRay> {
        let r = GridRay::new(&self.f, ray, t_min, t_max)?;
        (!r.misses_box()).then_some(r)
    }

    /// Where the walk of `r` starts: its entry cell, at the finest level whose
    /// node holds the whole clipped span (every coarser node holds it too, so
    /// it could only pass the cull).
    #[inline]
    pub(crate) fn start(&self, r: &GridRay) -> Cursor {
        let (ci, cj) = r.entry_cell(&self.f);
        let (ei, ej) = r.exit_cell(&self.f);
        let spread = (ci ^ ei) | (cj ^ ej);
        Cursor {
            ci,
            cj,
            t: r.t0,
            level: (32 - spread.leading_zeros()).min(self.mip.top),
        }
    }

    /// The walk's first descents from its start `c`, without its node steps:
    /// where the ray's altitude at the start lies within the quantised
    /// `[min, max]` of the node holding the start cell, the walk's cull
    /// passes there whatever the rest of the ray's span over the node (the
    /// span includes the start, and the cull's margin is at least a quantum,
    /// far more than the rounding of the altitude here), so the walk would
    /// descend; this does so with one node load and two integer comparisons
    /// per level. Walking from the result is walking from `c` minus those
    /// descents, bit for bit. A ray from a camera near the ground starts most
    /// of the way down the pyramid.
    #[inline]
    pub(crate) fn descend(&self, r: &GridRay, c: Cursor, stats: &mut TraceStats) -> Cursor {
        let m = &self.mip;
        // The start altitude in quantised units; below 0 or above the range
        // no node holds it.
        let za = (r.z_at(c.t) - m.lo) / m.scale;
        if !(0.0..65536.0).contains(&za) {
            return c;
        }
        // `za` lies in `[zf, zc]` (whole numbers): truncation is the floor here.
        let zf = za as u32;
        let zc = zf + u32::from(zf as f32 != za);
        let mut level = c.level;
        while level > 0 {
            let k = level as usize;
            let q = m.nodes[m.offset[k]
                + (c.cj >> level) as usize * m.width[k] as usize
                + (c.ci >> level) as usize];
            if !((q & 0xffff) <= zf && q >> 16 >= zc) {
                break;
            }
            stats.nodes_visited += 1;
            level -= 1;
        }
        Cursor { level, ..c }
    }

    fn run<const ANY: bool>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        stats: &mut TraceStats,
    ) -> Option<CellHit> {
        let r = self.setup(ray, t_min, t_max)?;
        let c = self.descend(&r, self.start(&r), stats);
        self.walk::<ANY>(&r, c, stats)
    }

    /// The hierarchical walk of `r` from cursor `c` (with nothing found yet).
    pub(crate) fn walk<const ANY: bool>(
        &self,
        r: &GridRay,
        c: Cursor,
        stats: &mut TraceStats,
    ) -> Option<CellHit> {
        let f = &self.f;
        let m = &self.mip;
        let (o, d, inv) = (r.o, r.d, r.inv);
        // Ray altitude in quantised units, and the cull margin there: a full
        // quantum plus the altitude rounding bound.
        let oq = (o.z - m.lo) / m.scale;
        let dq = d.z / m.scale;
        let mq = 1.0 + r.zm / m.scale;
        let (ncx, ncy) = (f.ncx, f.ncy);
        let t_end = r.t1;
        let signs = Signs::of(d.x, d.y);
        let (mut ci, mut cj, mut t, mut level) = (c.ci, c.cj, c.t, c.level);
        let mut pending: Option<CellHit> = None;
        loop {
            stats.nodes_visited += 1;
            if let Some(p) = pending
                && p.t <= t
            {
                return pending;
            }
            let size = 1u32 << level;
            let mask = !(size - 1);
            let (nx0, ny0) = (ci & mask, cj & mask);
            let (tx, ty) = node_exits(signs, nx0, ny0, size, o.x, o.y, inv.x, inv.y);
            let (t_exit, exit) = Exit::of(tx, ty, t_end, t);
            if level == 0 {
                let first = t == r.t0;
                if let Some(h) = leaf::<ANY>(f, r, ci, cj, t, t_exit, exit, first, stats) {
                    let h = nearer(pending, h);
                    if ANY || h.t <= t_exit + r.ttol {
                        return Some(h);
                    }
                    pending = Some(h);
                }
            } else {
                let k = level as usize;
                let q = unpack(
                    m.nodes[m.offset[k]
                        + (cj >> level) as usize * m.width[k] as usize
                        + (ci >> level) as usize],
                );
                let (za, zb) = (oq + t * dq, oq + t_exit * dq);
                if span_meets(za, zb, f32::from(q.0), f32::from(q.1), mq) {
                    level -= 1;
                    continue;
                }
            }
            if exit == Exit::End {
                return pending;
            }
            let (px, py) = (o.x + t_exit * d.x, o.y + t_exit * d.y);
            let (nci, ncj, out) = step_out(
                tx <= ty,
                signs,
                ci,
                cj,
                nx0,
                ny0,
                size,
                level == 0,
                px,
                py,
                ncx,
                ncy,
            );
            if out {
                return pending;
            }
            let up = level < m.top && leaves_parent(ci, cj, nci, ncj, level);
            (ci, cj, t) = (nci, ncj, t_exit);
            if up {
                level += 1;
            }
        }
    }
}

impl Tracer for MipmapTracer<'_> {
    crate::tracer::walk_queries!();

    fn trace_many(&self, rays: &[Ray], t_min: f32, t_max: f32) -> Vec<Option<Hit>> {
        MipmapTracer::trace_many(self, rays, t_min, t_max)
    }

    fn occluded_many(&self, rays: &[Ray], t_min: f32, t_max: f32) -> Vec<bool> {
        MipmapTracer::occluded_many(self, rays, t_min, t_max)
    }
}
