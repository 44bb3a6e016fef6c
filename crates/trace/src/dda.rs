//! Musgrave's grid tracing: a DDA over every cell the ray's projection
//! crosses, front to back, with a z-span cull per cell.
//!
//! Musgrave 1993, ch. 3 and Musgrave et al. 1989, §5. The source walks one octant with a floating-point
//! Bresenham DDA and culls a cell when `min(z_near, z_far) > max(4 corners)`
//! (eq. 3.1, Musgrave 1993, §3.2), which is valid only for rays from above (the source
//! says so in Musgrave 1993, §3.3.1). This implementation:
//!
//! * walks cells Amanatides–Woo style in every octant , visiting
//!   every cell the ray's xy projection crosses, in order of `t`, with exact
//!   per-cell `t` spans. At an exact corner crossing it steps x, then y,
//!   visiting the side cell over an empty span (the source steps
//!   diagonally (Musgrave 1993, §3.7); the extra visit costs nothing and keeps
//!   consecutive cells 4-adjacent);
//! * culls with the two-sided test `max(z_in, z_out) ≥ min(corners) &&
//!   min(z_in, z_out) ≤ max(corners)`, correct for rays from above, from
//!   below, shadow rays and rays starting inside the box (erratum to
//!   eq. 3.1);
//! * tests both triangles of a surviving cell exactly (see [`crate::Triangle`]
//!   and the watertight test in the crate docs) and returns the nearer: the
//!   first hit in traversal order is the closest (Musgrave 1993, §3.2).
//!
//! Per-cell minima and maxima come from the four corners on the fly, so the
//! tracer needs no memory beyond the field (the source's optional `A` grid,
//! eq. 3.2, is subsumed by [`crate::MaxMipmap`]). It is the reference for
//! [`crate::MipmapTracer`] and costs O(√N) per ray.

use glam::UVec2;
use natura_core::HeightField;

use crate::error::Result;
use crate::field::FieldView;
use crate::grid_ray::GridRay;
use crate::leaf::{leaf, nearer};
use crate::ray::{Hit, Ray, TraceStats};
use crate::ray_cell::CellHit;
use crate::step::{Exit, axis_exit};
use crate::tracer::Tracer;

/// One cell visited by the DDA: the cell and the ray's parameter span over it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellVisit {
    /// The cell `(i, j)`.
    pub cell: UVec2,
    /// Parameter where the ray enters the cell (or the clipped start).
    pub t_in: f32,
    /// Parameter where the ray leaves the cell (or the clipped end); `≥ t_in`.
    pub t_out: f32,
}

/// The cells a ray crosses, front to back (see [`GridTracer::cells`]).
#[derive(Clone, Debug)]
pub struct CellWalk {
    i: u32,
    j: u32,
    ncx: u32,
    ncy: u32,
    ox: f32,
    oy: f32,
    dx: f32,
    dy: f32,
    inv_x: f32,
    inv_y: f32,
    t: f32,
    t_end: f32,
    done: bool,
    exit: Exit,
}

impl CellWalk {
    fn new(f: &FieldView<'_>, r: Option<&GridRay>) -> Self {
        let mut w = Self {
            i: 0,
            j: 0,
            ncx: f.ncx,
            ncy: f.ncy,
            ox: 0.0,
            oy: 0.0,
            dx: 0.0,
            dy: 0.0,
            inv_x: 0.0,
            inv_y: 0.0,
            t: 0.0,
            t_end: 0.0,
            done: true,
            exit: Exit::End,
        };
        if let Some(r) = r.filter(|r| !r.misses_box()) {
            let (i, j) = r.entry_cell(f);
            w = Self {
                i,
                j,
                ox: r.o.x,
                oy: r.o.y,
                dx: r.d.x,
                dy: r.d.y,
                inv_x: r.inv.x,
                inv_y: r.inv.y,
                t: r.t0,
                t_end: r.t1,
                done: false,
                ..w
            };
        }
        w
    }

    /// Parameter at which the ray leaves the current cell through an x (resp. y) boundary.
    #[inline(always)]
    fn exits(&self) -> (f32, f32) {
        (
            axis_exit(self.dx > 0.0, self.dx < 0.0, self.i, 1, self.ox, self.inv_x),
            axis_exit(self.dy > 0.0, self.dy < 0.0, self.j, 1, self.oy, self.inv_y),
        )
    }
}

impl Iterator for CellWalk {
    type Item = CellVisit;

    #[inline]
    fn next(&mut self) -> Option<CellVisit> {
        if self.done {
            return None;
        }
        let (tx, ty) = self.exits();
        let t_out = tx.min(ty).min(self.t_end).max(self.t);
        let visit = CellVisit {
            cell: UVec2::new(self.i, self.j),
            t_in: self.t,
            t_out,
        };
        if t_out >= self.t_end {
            self.done = true;
            self.exit = Exit::End;
            return Some(visit);
        }
        self.exit = if tx <= ty { Exit::X } else { Exit::Y };
        // Step one axis; on an exact corner x first, then y next time (empty span).
        if tx <= ty {
            if self.dx > 0.0 {
                self.i += 1;
                self.done = self.i >= self.ncx;
            } else if self.i == 0 {
                self.done = true;
            } else {
                self.i -= 1;
            }
        } else if self.dy > 0.0 {
            self.j += 1;
            self.done = self.j >= self.ncy;
        } else if self.j == 0 {
            self.done = true;
        } else {
            self.j -= 1;
        }
        self.t = t_out;
        Some(visit)
    }
}

/// Musgrave's grid tracer: the plain DDA with a per-cell z-span cull.
///
/// Built once per height field (no precomputation; it borrows the field).
/// Use [`crate::MipmapTracer`] for speed; this one is the reference.
#[derive(Clone, Copy, Debug)]
pub struct GridTracer<'a> {
    f: FieldView<'a>,
}

impl<'a> GridTracer<'a> {
    /// Returns a tracer over `hf`.
    ///
    /// # Errors
    ///
    /// Fails with [`crate::TraceError::Field`] if `hf` has fewer than 2 × 2
    /// samples, more than [`crate::MAX_SAMPLES_PER_AXIS`] along an axis, or a
    /// NaN or infinite height.
    pub fn new(hf: &'a HeightField) -> Result<Self> {
        Ok(Self {
            f: FieldView::new(hf)?,
        })
    }

    /// Returns the cells the ray's xy projection crosses within `[t_min, t_max]`
    /// (clipped to the field's box), front to back, with their `t` spans.
    ///
    /// Consecutive cells share an edge; an invalid ray yields nothing.
    #[must_use]
    pub fn cells(&self, ray: &Ray, t_min: f32, t_max: f32) -> CellWalk {
        CellWalk::new(&self.f, GridRay::new(&self.f, ray, t_min, t_max).as_ref())
    }

    fn run<const ANY: bool>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        stats: &mut TraceStats,
    ) -> Option<CellHit> {
        let r = GridRay::new(&self.f, ray, t_min, t_max)?;
        let mut walk = CellWalk::new(&self.f, Some(&r));
        let mut pending: Option<CellHit> = None;
        let mut first = true;
        while let Some(v) = walk.next() {
            stats.nodes_visited += 1;
            if let Some(p) = pending
                && p.t <= v.t_in
            {
                return pending;
            }
            let (i, j) = (v.cell.x, v.cell.y);
            if let Some(h) =
                leaf::<ANY>(&self.f, &r, i, j, v.t_in, v.t_out, walk.exit, first, stats)
            {
                let h = nearer(pending, h);
                if ANY || h.t <= v.t_out + r.ttol {
                    return Some(h);
                }
                pending = Some(h);
            }
            first = false;
        }
        pending
    }
}

impl Tracer for GridTracer<'_> {
    crate::tracer::walk_queries!();
}
