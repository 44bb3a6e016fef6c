//! The walk's arithmetic, written once: where a ray leaves a node or cell,
//! the two-sided altitude cull, and the step into the next node.
//!
//! The single-ray walks ([`crate::MipmapTracer`], [`crate::GridTracer`]) and
//! the lock-step lanes ([`crate::lockstep`]) call these same functions, so every
//! path computes the same `f32` and integer values in the same order and
//! returns the same hits, bit for bit. Each function is `#[inline(always)]`
//! and free of loads and side effects, so inside a loop over lanes LLVM
//! turns its branches into selects and vectorises it.
//!
//! The cull is the erratum to Musgrave 1993, §3.3.2, eq. 3.1: the source
//! rejects a cell when the ray is above its highest corner at both ends of
//! the span, which loses rays travelling below the surface (from a camera
//! under an overhang or inside the terrain's box from below). Here a span is
//! rejected only when it lies wholly above the maximum or wholly below the
//! minimum, each widened by the ray's altitude rounding bound.

use crate::float::{coord, fmax, fmax_nan_lo, fmin, trunc};

/// The signs of a ray's horizontal direction: which way it crosses x and y.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Signs(pub u32);

impl Signs {
    const X_POS: u32 = 1;
    const X_NEG: u32 = 2;
    const Y_POS: u32 = 4;
    const Y_NEG: u32 = 8;

    /// The signs of direction `(dx, dy)` (a zero component has neither).
    #[inline(always)]
    pub(crate) fn of(dx: f32, dy: f32) -> Self {
        Signs(
            (u32::from(dx > 0.0) * Self::X_POS)
                | (u32::from(dx < 0.0) * Self::X_NEG)
                | (u32::from(dy > 0.0) * Self::Y_POS)
                | (u32::from(dy < 0.0) * Self::Y_NEG),
        )
    }

    /// `dx > 0`.
    #[inline(always)]
    pub(crate) fn x_pos(self) -> bool {
        self.0 & Self::X_POS != 0
    }

    /// `dx < 0`.
    #[inline(always)]
    pub(crate) fn x_neg(self) -> bool {
        self.0 & Self::X_NEG != 0
    }

    /// `dy > 0`.
    #[inline(always)]
    pub(crate) fn y_pos(self) -> bool {
        self.0 & Self::Y_POS != 0
    }

    /// `dy < 0`.
    #[inline(always)]
    pub(crate) fn y_neg(self) -> bool {
        self.0 & Self::Y_NEG != 0
    }
}

/// How the ray leaves a cell or node.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[repr(u32)]
pub(crate) enum Exit {
    /// The ray's clipped range ends inside (or on the border of) the cell.
    #[default]
    End = 0,
    /// Through an x boundary (into the next column).
    X = 1,
    /// Through a y boundary (into the next row).
    Y = 2,
}

impl Exit {
    /// How a ray leaves a cell whose x and y boundaries it reaches at `tx`
    /// and `ty`, when its clipped range ends at `t_end`: the traversal's
    /// exit t (never before `t`) and the side.
    #[inline(always)]
    pub(crate) fn of(tx: f32, ty: f32, t_end: f32, t: f32) -> (f32, Exit) {
        let t_exit = fmax(fmin(fmin(tx, ty), t_end), t);
        let exit = if t_exit >= t_end {
            Exit::End
        } else if tx <= ty {
            Exit::X
        } else {
            Exit::Y
        };
        (t_exit, exit)
    }
}

/// The `t` at which a ray with origin coordinate `o`, reciprocal direction
/// `inv` and signs `pos`/`neg` along one axis leaves the span
/// `[lo, lo + size]` of that axis (`+∞` for an axis it does not move along).
/// Coordinates are below 2²⁴, so both bounds convert to `f32` exactly.
#[inline(always)]
pub(crate) fn axis_exit(pos: bool, neg: bool, lo: u32, size: u32, o: f32, inv: f32) -> f32 {
    if pos {
        (coord(lo.wrapping_add(size)) - o) * inv
    } else if neg {
        (coord(lo) - o) * inv
    } else {
        f32::INFINITY
    }
}

/// The exits of node `(x0, y0)` of side `size` cells: `(tx, ty)`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn node_exits(
    s: Signs,
    x0: u32,
    y0: u32,
    size: u32,
    ox: f32,
    oy: f32,
    ix: f32,
    iy: f32,
) -> (f32, f32) {
    (
        axis_exit(s.x_pos(), s.x_neg(), x0, size, ox, ix),
        axis_exit(s.y_pos(), s.y_neg(), y0, size, oy, iy),
    )
}

/// Whether the altitude span of a ray between `za` and `zb` can meet
/// heights in `[lo, hi]`, each side widened by `margin` (the two-sided cull).
#[inline(always)]
pub(crate) fn span_meets(za: f32, zb: f32, lo: f32, hi: f32, margin: f32) -> bool {
    let (zlo, zhi) = (fmin(za, zb), fmax(za, zb));
    (zlo <= hi + margin) & (zhi >= lo - margin)
}

/// The lowest and highest of a cell's four corner heights.
#[inline(always)]
pub(crate) fn corner_range(c: [f32; 4]) -> (f32, f32) {
    (
        fmin(fmin(c[0], c[1]), fmin(c[2], c[3])),
        fmax(fmax(c[0], c[1]), fmax(c[2], c[3])),
    )
}

/// Where the walk goes from node `(x0, y0)` of side `size` holding cell
/// `(ci, cj)`, leaving across x (`across_x`) or y at `t_exit`, where the ray
/// is at `(px, py)`: the next cell `(ci, cj)` and whether that step left the
/// field of `ncx × ncy` cells.
///
/// The step crosses one node boundary; the other coordinate moves to the
/// cell the ray is in at the crossing, clamped to the node (the walk's
/// `floor`, `max`, `min`: clamping before truncation is the same, the bounds
/// being whole numbers; a NaN position keeps the node's low side). From a
/// cell (`size == 1`, `at_cell`) the other coordinate stays.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn step_out(
    across_x: bool,
    s: Signs,
    ci: u32,
    cj: u32,
    x0: u32,
    y0: u32,
    size: u32,
    at_cell: bool,
    px: f32,
    py: f32,
    ncx: u32,
    ncy: u32,
) -> (u32, u32, bool) {
    if across_x {
        let (nci, out) = if s.x_pos() {
            (x0.wrapping_add(size), x0.wrapping_add(size) >= ncx)
        } else {
            (x0.wrapping_sub(1), x0 == 0)
        };
        let ncj = if at_cell {
            cj
        } else {
            let hi = (y0 + size).min(ncy) - 1;
            let yc = trunc(fmin(fmax_nan_lo(py, coord(y0)), coord(hi)));
            if s.y_pos() {
                cj.max(yc)
            } else if s.y_neg() {
                cj.min(yc)
            } else {
                cj
            }
        };
        (nci, ncj, out)
    } else {
        let (ncj, out) = if s.y_pos() {
            (y0.wrapping_add(size), y0.wrapping_add(size) >= ncy)
        } else {
            (y0.wrapping_sub(1), y0 == 0)
        };
        let nci = if at_cell {
            ci
        } else {
            let hi = (x0 + size).min(ncx) - 1;
            let xc = trunc(fmin(fmax_nan_lo(px, coord(x0)), coord(hi)));
            if s.x_pos() {
                ci.max(xc)
            } else if s.x_neg() {
                ci.min(xc)
            } else {
                ci
            }
        };
        (nci, ncj, out)
    }
}

/// Whether a step from cell `(ci, cj)` to `(nci, ncj)` at `level` left its
/// parent node (the walk then ascends one level, as Tevs, Ihrke & Seidel
/// 2008 do; climbing to the highest changed level measured slower).
#[inline(always)]
pub(crate) fn leaves_parent(ci: u32, cj: u32, nci: u32, ncj: u32, level: u32) -> bool {
    ((nci ^ ci) | (ncj ^ cj)) >> ((level + 1) & 31) != 0
}
