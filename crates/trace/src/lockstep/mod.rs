//! Many rays at once: the max-mipmap walk run for [`LANES`] rays in lock
//! step, without data-dependent branches.
//!
//! A grazing ray spends most of its walk descending from the coarse levels
//! and stepping past nodes above it before it first reaches a cell (step
//! counts in `docs/performance.md`). Done one ray at a time, each of those
//! steps waits on a node load and then on a branch that goes either way
//! (descend or advance, across x or across y). Here each
//! step computes both outcomes and selects one, for [`LANES`] independent
//! rays at once; the loop over lanes is vectorised (with gathers of the
//! nodes) for the widest instruction set the CPU has, chosen at run time
//! through `natura_core::simd`.
//!
//! The batch path keeps every per-ray stage in lanes of 16 as well, each a
//! loop over lanes without data-dependent branches that LLVM vectorises
//! (through `natura_core::simd`'s dispatch, see [`kernels`]): the set-up
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
//!
//! The arithmetic of every stage is the single-ray path's own:
//! [`crate::step`] (node and cell exits, the altitude cull, the step into
//! the next node), [`crate::ray_cell`] (the watertight pair of triangle
//! tests) and [`crate::leaf::near`] (the rounding-distance test), called per
//! lane. The files here hold only the lanes' state, their bookkeeping and
//! the dispatch: [`node`] (the node steps and the lane pre-descent),
//! [`cell`] (the exact cell tests), [`walk`] (the driver) and [`kernels`]
//! (the instruction-set dispatch).

mod cell;
pub(crate) mod kernels;
mod node;
mod walk;

#[cfg(test)]
mod tests;

use glam::Vec3;

use crate::grid_ray::{GridRay, SETUP_LANES, SetupLanes};
use crate::max_mipmap::Cursor;
use crate::step::{Exit, Signs};

pub(crate) use walk::{Outcome, walk_lanes};

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
    /// The direction's [`Signs`].
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
        self.sign[l] = Signs::of(d.x, d.y).0;
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
    exit: [Exit; LANES],
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

/// `CellOut::flags`: a triangle was hit (`t`, `upper`, `bary` hold it).
const FOUND: u32 = 1;
/// `CellOut::flags`: the single-ray [`leaf`] must decide (a zero edge
/// function, or an edge or corner within rounding distance whose
/// neighbouring cells the leaf tests too).
const SCALAR: u32 = 2;
