//! The driver of the lock-step walk: loads rays into lanes, runs node steps
//! until enough lanes wait at cells, runs their exact tests, and hands the
//! few rays the lanes cannot settle to the single-ray walk.

use super::kernels::{cells_with, step_with};
use super::node::NodeTable;
use super::{CellOut, Exact, FOUND, GOING, LANE_MASK, LANES, Lanes, MIN_LANE_LEVEL, Rays, SCALAR};
use crate::field::FieldView;
use crate::leaf::leaf;
use crate::max_mipmap::{Cursor, MipmapTracer};
use crate::ray::TraceStats;
use crate::ray_cell::{CellHit, PairHit};
use crate::step::{Exit, Signs, leaves_parent, step_out};
use natura_core::simd::Simd;

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
    simd: Simd,
    tr: &MipmapTracer<'_>,
    rays: &R,
    cur: &[Option<Cursor>],
    descended: Option<&[u32]>,
    out: &mut Vec<Outcome>,
) {
    walk_lanes_with::<ANY, R>(simd, MIN_LANE_LEVEL, tr, rays, cur, descended, out);
}

/// [`walk_lanes`] with the lane steps compiled for `simd`, walking only
/// rays whose walk starts at `min_level` or above.
pub(super) fn walk_lanes_with<const ANY: bool, R: Rays + ?Sized>(
    simd: Simd,
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
    let k = NodeTable {
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
    drive::<ANY, R>(simd, f, &k, rays, &take, lo, scale, out);
}

/// The lanes' loop: fills [`LANES`] lanes from `take`, runs the lane steps
/// until [`PARK_BATCH`] lanes wait at cells (or none is stepping), runs a
/// pass of exact tests for the waiting lanes, settles each, and refills a
/// lane whose ray is done, until no ray is left: `out[k]` says how ray `k`
/// ended.
#[allow(clippy::too_many_arguments)]
fn drive<const ANY: bool, R: Rays + ?Sized>(
    simd: Simd,
    f: &FieldView<'_>,
    k: &NodeTable<'_>,
    rays: &R,
    take: &impl Fn(&mut usize) -> Option<(usize, Cursor)>,
    lo: f32,
    scale: f32,
    out: &mut [Outcome],
) {
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
            let ev = step_with(simd, &mut s, k, &mut events);
            parked |= ev & LANE_MASK;
            let mut left = (ev >> LANES) & !parked;
            while left != 0 {
                let l = left.trailing_zeros() as usize;
                left &= left - 1;
                out[s.ray[l]] = Outcome::Miss;
                refill(
                    &mut s, &mut x, &mut live, &mut next, l, take, rays, lo, scale,
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
        cells_with::<ANY>(simd, &mut s, k, &x, &corners, parked, &mut co);
        // Lanes whose miss stepped on to the next cell stay parked; into a
        // new level-1 node, they go back to the lane steps; the others are
        // decided one by one.
        parked &= !co.climb;
        let mut pm = co.done;
        while pm != 0 {
            let l = pm.trailing_zeros() as usize;
            pm &= pm - 1;
            match settle::<ANY, R>(f, k, rays, &mut s, &x, &co, l, &mut stats) {
                Settled::NextCell => {}
                Settled::Climbed => parked &= !(1 << l),
                Settled::Done(e) => {
                    out[s.ray[l]] = e;
                    parked &= !(1 << l);
                    refill(
                        &mut s, &mut x, &mut live, &mut next, l, take, rays, lo, scale,
                    );
                }
            }
        }
    }
}

/// How a parked lane's cell ended after a pass of exact tests.
enum Settled {
    /// The ray is done (or goes to the single-ray walk): its outcome.
    Done(Outcome),
    /// It missed and stepped on to the next cell of its level-1 node: it
    /// stays parked.
    NextCell,
    /// It missed and stepped on into a new level-1 node: it goes back to
    /// the lane steps at level 1.
    Climbed,
}

/// Decides parked lane `l` after the pass of exact tests `co` (one the
/// pass could not settle alone): its hit (through the single-ray cell test
/// [`leaf`] for a cell within rounding distance of an edge), or the walk's
/// step past its cell (as the lane step at level 0).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn settle<const ANY: bool, R: Rays + ?Sized>(
    f: &FieldView<'_>,
    k: &NodeTable<'_>,
    rays: &R,
    s: &mut Lanes,
    x: &Exact,
    co: &CellOut,
    l: usize,
    stats: &mut TraceStats,
) -> Settled {
    let kr = s.ray[l];
    let (ci, cj, t) = (s.ci[l], s.cj[l], s.t[l]);
    let t_exit = co.t_exit[l];
    let exit = co.exit[l];
    let flags = co.flags[l];
    let h = if flags & SCALAR != 0 {
        // Within rounding distance of an edge, or a zero edge
        // function: the single-ray walk's cell test, neighbours and all.
        let first = t == s.t0[l];
        leaf::<ANY>(f, &rays.ray(kr), ci, cj, t, t_exit, exit, first, stats)
    } else if flags & FOUND != 0 {
        let pair = PairHit {
            found: true,
            upper: co.upper[l],
            t: co.t[l],
            bary: [co.bary[0][l], co.bary[1][l], co.bary[2][l]],
        };
        CellHit::from_pair(pair, (ci, cj))
    } else {
        None
    };
    match h {
        Some(h) if ANY || h.t <= t_exit + x.ttol[l] => Settled::Done(Outcome::Hit(h)),
        Some(_) => Settled::Done(Outcome::Walk(Cursor {
            ci,
            cj,
            t,
            level: 0,
        })),
        None => {
            // The walk's step past a cell (as the lane step at level 0).
            let (nci, ncj, out) = step_out(
                exit == Exit::X,
                Signs(s.sign[l]),
                ci,
                cj,
                ci,
                cj,
                1,
                true,
                0.0,
                0.0,
                k.ncx,
                k.ncy,
            );
            if exit == Exit::End || out {
                return Settled::Done(Outcome::Miss);
            }
            s.ci[l] = nci;
            s.cj[l] = ncj;
            s.t[l] = t_exit;
            if k.top > 0 && leaves_parent(ci, cj, nci, ncj, 0) {
                // Back to the nodes: the lane steps on at level 1.
                s.level[l] = 1;
                Settled::Climbed
            } else {
                Settled::NextCell
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
