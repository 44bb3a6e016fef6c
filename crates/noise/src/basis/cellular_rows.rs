//! Batch row kernels of [`Worley`] noise (f32 lanes, compiled per SIMD
//! level through natura-simd's dispatch).
//!
//! Feature points come from [`feature`], distances from the metric's
//! `axis`/`comb` pair and the sorted nearest distances from [`insert_k`], as
//! in the point search; these kernels only arrange the work:
//!
//! * **Spans** (steps up to [`SPAN_MAX_STEP`]): a row is walked cell by cell.
//!   The 3×3 (3×3×3) candidate feature points of a cell are placed once, with
//!   their y (and z) terms, which are the same for every point of the row;
//!   each point of the span then only adds its x term and keeps the smallest
//!   distances, in whole groups of [`SPAN_GROUP`] lanes. No hashing per point.
//! * **Lanes** (larger steps): every lane finds its own cell and hashes its
//!   block.
//!
//! Either way each lane also checks that its `K`-th distance is below the
//! least possible distance to a feature point two cells away; lanes that do
//! not clear it (rare) are flagged, and the caller redoes them with the
//! exact point search, so batch and point agree.

use core::marker::PhantomData;

use glam::DVec3;

use crate::basis::cellular::{Dist, Worley, insert_k};
use crate::hash::{PX, PY, PZ, corner_spread};
use crate::lattice_math::{Kernel, Simd, min_fast, run, split_fast};

#[cfg(doc)]
use crate::basis::SPAN_MAX_STEP;

/// `√v` for f32 lanes in `core` (no `sqrt` there, and a libm call would stop
/// vectorisation): the bit-trick reciprocal square root refined by three
/// Newton steps (relative error below f32 rounding), times `v`.
#[inline(always)]
pub(crate) fn sqrt32(v: f32) -> f32 {
    let mut y = f32::from_bits(0x5F37_59DF_u32.wrapping_sub(v.to_bits() >> 1));
    for _ in 0..3 {
        y *= 1.5 - 0.5 * v * y * y;
    }
    v * y
}

/// One chunk of a 2-D or 3-D row (origin, step, outputs, flags) for feature
/// rank `K`, metric `D` and pick `F`, as a [`Kernel`] so its body is inlined
/// into (and vectorised for) each SIMD level's trampoline.
pub(crate) struct Chunk<'a, P, const K: usize, D, F> {
    w: &'a Worley,
    origin: P,
    step: f64,
    out: &'a mut [f32],
    flags: &'a mut [u8],
    /// Whether the span kernel applies (step up to [`SPAN_MAX_STEP`]).
    spans: bool,
    pick: F,
    metric: PhantomData<D>,
}

impl<const K: usize, D: Dist<f32>, F: Fn(&[f32; K]) -> f32> Kernel
    for Chunk<'_, glam::DVec2, K, D, F>
{
    type Out = ();
    #[inline(always)]
    fn call(self) {
        let (x0, y) = (self.origin.x, self.origin.y);
        if self.spans {
            worley2_spans::<K, D>(self.w, x0, y, self.step, self.out, self.flags, self.pick);
        } else {
            worley2_row::<K, D>(self.w, x0, y, self.step, self.out, self.flags, self.pick);
        }
    }
}

impl<const K: usize, D: Dist<f32>, F: Fn(&[f32; K]) -> f32> Kernel for Chunk<'_, DVec3, K, D, F> {
    type Out = ();
    #[inline(always)]
    fn call(self) {
        if self.spans {
            worley3_spans::<K, D>(
                self.w,
                self.origin,
                self.step,
                self.out,
                self.flags,
                self.pick,
            );
        } else {
            worley3_row::<K, D>(
                self.w,
                self.origin,
                self.step,
                self.out,
                self.flags,
                self.pick,
            );
        }
    }
}

/// A row chunk's arguments: the field, the chunk's first point, the step,
/// the values, the flags, and whether the span kernel applies.
pub(crate) type ChunkArgs<'a, P> = (&'a Worley, P, f64, &'a mut [f32], &'a mut [u8], bool);

/// Runs a 2-D row chunk at SIMD level `simd` (called through the metric and
/// feature dispatch).
#[inline(always)]
pub(crate) fn chunk2<const K: usize, D: Dist<f32>>(
    simd: Simd,
    (w, origin, step, out, flags, spans): ChunkArgs<'_, glam::DVec2>,
    pick: impl Fn(&[f32; K]) -> f32,
) {
    let metric = PhantomData::<D>;
    run(
        simd,
        Chunk {
            w,
            origin,
            step,
            out,
            flags,
            spans,
            pick,
            metric,
        },
    );
}

/// Runs a 3-D row chunk at SIMD level `simd`.
#[inline(always)]
pub(crate) fn chunk3<const K: usize, D: Dist<f32>>(
    simd: Simd,
    (w, origin, step, out, flags, spans): ChunkArgs<'_, DVec3>,
    pick: impl Fn(&[f32; K]) -> f32,
) {
    let metric = PhantomData::<D>;
    run(
        simd,
        Chunk {
            w,
            origin,
            step,
            out,
            flags,
            spans,
            pick,
            metric,
        },
    );
}

/// Points a span kernel writes per group (one AVX-512 vector, two AVX2 ones).
const SPAN_GROUP: usize = 16;

/// The spread lattice rows `(iy − 1 + r)·PY`, `r < 3`.
#[inline(always)]
fn spread3(i: u32, p: u32) -> [u32; 3] {
    let a = i.wrapping_sub(1).wrapping_mul(p);
    [a, a.wrapping_add(p), a.wrapping_add(p.wrapping_add(p))]
}

/// The per-lane result: the picked value and whether the ring-2 bound
/// `bound` (an axis distance) failed to clear `best[K − 1]`.
#[inline(always)]
fn lane_result<const K: usize, D: Dist<f32>>(
    best: [f32; K],
    bound: f32,
    pick: &impl Fn(&[f32; K]) -> f32,
) -> (f32, u8) {
    // A small tolerance so f32 rounding never hides a needed ring.
    let flag = u8::from(best[K - 1] >= D::kept(bound) * 0.999_9);
    (pick(&best.map(D::value)), flag)
}

/// Per-lane 3×3 search over a 2-D row chunk (any step). Sets `flags[i] = 1`
/// for lanes the block does not settle.
#[inline(always)]
fn worley2_row<const K: usize, D: Dist<f32>>(
    w: &Worley,
    x0: f64,
    y: f64,
    step: f64,
    out: &mut [f32],
    flags: &mut [u8],
    pick: impl Fn(&[f32; K]) -> f32,
) {
    let place = w.place::<f32>();
    let (rows, edge_y) = rows2(w, y);
    for (n, (o, flag)) in out.iter_mut().zip(flags.iter_mut()).enumerate() {
        let (ix, fx) = split_fast(x0 + (n as i32) as f64 * step);
        let fx = fx as f32;
        let cols = columns(ix, fx, place.margin);
        let mut best = [f32::INFINITY; K];
        for (row, gy) in rows {
            for (col, gx) in cols {
                let d = place.disp(corner_spread(col, row));
                insert_k(&mut best, D::comb(D::axis(gx - d[0]), D::axis(gy - d[1])));
            }
        }
        let bound = 1.0 + place.margin + min_fast(min_fast(fx, 1.0 - fx), edge_y);
        (*o, *flag) = lane_result::<K, D>(best, bound, &pick);
    }
}

/// Per-lane 3×3×3 search over a 3-D row chunk (any step).
#[inline(always)]
fn worley3_row<const K: usize, D: Dist<f32>>(
    w: &Worley,
    origin: DVec3,
    step: f64,
    out: &mut [f32],
    flags: &mut [u8],
    pick: impl Fn(&[f32; K]) -> f32,
) {
    let place = w.place::<f32>();
    let (rows, edge_yz) = rows3(w, origin);
    for (n, (o, flag)) in out.iter_mut().zip(flags.iter_mut()).enumerate() {
        let (ix, fx) = split_fast(origin.x + (n as i32) as f64 * step);
        let fx = fx as f32;
        let cols = columns(ix, fx, place.margin);
        let mut best = [f32::INFINITY; K];
        for (row, gy, gz) in rows {
            for (col, gx) in cols {
                let d = place.disp(corner_spread(col, row));
                let yz = D::comb(D::axis(gy - d[1]), D::axis(gz - d[2]));
                insert_k(&mut best, D::comb(D::axis(gx - d[0]), yz));
            }
        }
        let bound = 1.0 + place.margin + min_fast(min_fast(fx, 1.0 - fx), edge_yz);
        (*o, *flag) = lane_result::<K, D>(best, bound, &pick);
    }
}

/// The three lattice columns around a point with x cell `ix` and fraction
/// `fx`: spread indices and the point's offsets from their margin corners
/// (`fx − dx − margin`).
#[inline(always)]
fn columns(ix: u32, fx: f32, margin: f32) -> [(u32, f32); 3] {
    let c = spread3(ix, PX);
    [
        (c[0], fx - (-1.0 + margin)),
        (c[1], fx - margin),
        (c[2], fx - (1.0 + margin)),
    ]
}

/// The three lattice rows around a 2-D row at `y`: row hashes (with the
/// seed) and the row's offsets from their margin corners, and the row's
/// least edge distance.
#[inline(always)]
fn rows2(w: &Worley, y: f64) -> ([(u32, f32); 3], f32) {
    let (iy, fy) = split_fast(y);
    let (hashes, offsets) = (
        spread3(iy, PY),
        columns(0, fy as f32, w.place::<f32>().margin),
    );
    let rows = core::array::from_fn(|r| (hashes[r] ^ w.lattice_seed(), offsets[r].1));
    (rows, min_fast(fy as f32, 1.0 - fy as f32))
}

/// The nine (y, z) lattice rows around a 3-D row: row hashes (with the
/// seed), the row's y and z offsets from their margin corners, and the
/// least y/z edge distance.
#[inline(always)]
fn rows3(w: &Worley, origin: DVec3) -> ([(u32, f32, f32); 9], f32) {
    let margin = w.place::<f32>().margin;
    let (iy, fy) = split_fast(origin.y);
    let (iz, fz) = split_fast(origin.z);
    let (fy, fz) = (fy as f32, fz as f32);
    let (ys, zs) = (spread3(iy, PY), spread3(iz, PZ));
    let (gy, gz) = (columns(0, fy, margin), columns(0, fz, margin));
    let rows = core::array::from_fn(|k| {
        let (r, q) = (k % 3, k / 3);
        (ys[r] ^ zs[q] ^ w.lattice_seed(), gy[r].1, gz[q].1)
    });
    let edge = min_fast(min_fast(fy, 1.0 - fy), min_fast(fz, 1.0 - fz));
    (rows, edge)
}

/// Walks a row chunk cell by cell: `cell(ix, t0, i, count)` fills the
/// `count` points from `i` of one cell's span (at fractions `t0 + k·step`)
/// and may write up to [`SPAN_GROUP`] − 1 points past them (the next cell
/// overwrites them).
#[inline(always)]
fn for_spans(x0: f64, step: f64, n: usize, mut cell: impl FnMut(u32, f32, usize, usize)) {
    let mut i = 0usize;
    while i < n {
        let (ix, fx) = split_fast(x0 + i as f64 * step);
        let count = (libm::ceil((1.0 - fx) / step) as usize).clamp(1, n - i);
        cell(ix, fx as f32, i, count);
        i += count;
    }
}

/// The 2-D span kernel (steps up to [`SPAN_MAX_STEP`]): per cell, the nine
/// candidates' x positions (`dx + margin + disp`) and y terms; per point
/// one x term, one combine and one insertion per candidate.
#[inline(always)]
fn worley2_spans<const K: usize, D: Dist<f32>>(
    w: &Worley,
    x0: f64,
    y: f64,
    step: f64,
    out: &mut [f32],
    flags: &mut [u8],
    pick: impl Fn(&[f32; K]) -> f32,
) {
    let place = w.place::<f32>();
    let (rows, edge_y) = rows2(w, y);
    let s32 = step as f32;
    for_spans(
        x0,
        step,
        out.len(),
        #[inline(always)]
        |ix, t0, i, count| {
            let cols = spread3(ix, PX);
            let mut cx = [0.0f32; 9];
            let mut cy = [0.0f32; 9];
            for (r, (row, gy)) in rows.into_iter().enumerate() {
                for (c, col) in cols.into_iter().enumerate() {
                    let d = place.disp(corner_spread(col, row));
                    cx[3 * r + c] = (c as f32 - 1.0 + place.margin) + d[0];
                    cy[3 * r + c] = D::axis(gy - d[1]);
                }
            }
            let span = Span {
                t0,
                step: s32,
                reach: 1.0 + place.margin,
                edge: edge_y,
            };
            span.nearest::<K, D, 9>(&cx, &cy, &mut out[i..], &mut flags[i..], count, &pick);
        },
    );
}

/// The 3-D span kernel: per cell, the 27 candidates' x positions and
/// combined y/z terms.
#[inline(always)]
fn worley3_spans<const K: usize, D: Dist<f32>>(
    w: &Worley,
    origin: DVec3,
    step: f64,
    out: &mut [f32],
    flags: &mut [u8],
    pick: impl Fn(&[f32; K]) -> f32,
) {
    let place = w.place::<f32>();
    let (rows, edge_yz) = rows3(w, origin);
    let s32 = step as f32;
    for_spans(
        origin.x,
        step,
        out.len(),
        #[inline(always)]
        |ix, t0, i, count| {
            let cols = spread3(ix, PX);
            let mut cx = [0.0f32; 27];
            let mut cyz = [0.0f32; 27];
            for (k, (row, gy, gz)) in rows.into_iter().enumerate() {
                for (c, col) in cols.into_iter().enumerate() {
                    let d = place.disp(corner_spread(col, row));
                    cx[3 * k + c] = (c as f32 - 1.0 + place.margin) + d[0];
                    cyz[3 * k + c] = D::comb(D::axis(gy - d[1]), D::axis(gz - d[2]));
                }
            }
            let span = Span {
                t0,
                step: s32,
                reach: 1.0 + place.margin,
                edge: edge_yz,
            };
            span.nearest::<K, D, 27>(&cx, &cyz, &mut out[i..], &mut flags[i..], count, &pick);
        },
    );
}

/// One cell's span of a row: points at fractions `t0 + k·step` of the cell,
/// candidates reaching `reach` cells, the nearest cell edge across the row
/// at `edge`.
#[derive(Clone, Copy)]
struct Span {
    t0: f32,
    step: f32,
    reach: f32,
    edge: f32,
}

impl Span {
    /// The `K` nearest of the `N` candidates (x positions `cx`, combined
    /// terms of the other axes `rest`) for points `0..count` of the span,
    /// written with their flags by [`write_span`]: one x term, one combine
    /// and one insertion per candidate and point.
    #[inline(always)]
    fn nearest<const K: usize, D: Dist<f32>, const N: usize>(
        self,
        cx: &[f32; N],
        rest: &[f32; N],
        out: &mut [f32],
        flags: &mut [u8],
        count: usize,
        pick: &impl Fn(&[f32; K]) -> f32,
    ) {
        write_span(
            out,
            flags,
            count,
            #[inline(always)]
            |k: usize| {
                let t = self.t0 + (k as i32) as f32 * self.step;
                let mut best = [f32::INFINITY; K];
                for (&x, &r) in cx.iter().zip(rest) {
                    insert_k(&mut best, D::comb(D::axis(t - x), r));
                }
                let bound = self.reach + min_fast(min_fast(t, 1.0 - t), self.edge);
                lane_result::<K, D>(best, bound, pick)
            },
        );
    }
}

/// Writes lanes `0..count` of a span (values and flags) in whole groups of
/// [`SPAN_GROUP`]; the last group may run past `count` (but not past the
/// slice), writing values the next span overwrites.
#[inline(always)]
fn write_span(out: &mut [f32], flags: &mut [u8], count: usize, lane: impl Fn(usize) -> (f32, u8)) {
    let n = out.len();
    let mut g = 0usize;
    while g < count {
        if g + SPAN_GROUP <= n {
            let o: &mut [f32; SPAN_GROUP] = (&mut out[g..g + SPAN_GROUP]).try_into().unwrap();
            let f: &mut [u8; SPAN_GROUP] = (&mut flags[g..g + SPAN_GROUP]).try_into().unwrap();
            for (k, (o, f)) in o.iter_mut().zip(f.iter_mut()).enumerate() {
                (*o, *f) = lane(g + k);
            }
        } else {
            for (k, (o, f)) in out[g..].iter_mut().zip(flags[g..].iter_mut()).enumerate() {
                (*o, *f) = lane(g + k);
            }
        }
        g += SPAN_GROUP;
    }
}
