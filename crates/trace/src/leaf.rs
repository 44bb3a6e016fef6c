//! The work done at one cell of a traversal: the two-sided z cull, the exact
//! test of the cell's two triangles, and the test of the cells across any
//! edge or corner the ray passes within rounding distance of.

use crate::field::FieldView;
use crate::float::coord;
use crate::grid_ray::GridRay;
use crate::ray::TraceStats;
use crate::ray_cell::{CellHit, intersect_cell};
use crate::step::{Exit, corner_range, span_meets};

/// Whether the ray at `(px, py)` is within `e` of the sides of cell
/// `(x0, y0)`: `[x0 side, x0 + 1 side, y0 side, y0 + 1 side]`.
#[inline(always)]
pub(crate) fn near(px: f32, py: f32, x0: f32, y0: f32, e: f32) -> [bool; 4] {
    [
        px < x0 + e,
        px > x0 + 1.0 - e,
        py < y0 + e,
        py > y0 + 1.0 - e,
    ]
}

/// Keeps the nearer of two hits (the first on a tie).
#[inline(always)]
pub(crate) fn nearer(a: Option<CellHit>, b: CellHit) -> CellHit {
    match a {
        Some(a) if a.t <= b.t => a,
        _ => b,
    }
}

/// Tests cell `(i, j)` over the ray span `[t_in, t_out]`.
///
/// The cull compares the ray's altitude span with the corners' `[min, max]`
/// in both directions (valid for rays from above, below and inside; the
/// erratum to the source's eq. 3.1), widened by [`GridRay::zm`]. A
/// surviving cell gets the exact two-triangle test; then, where the ray
/// passes within [`GridRay::xyeps`] of a side the traversal does not cross
/// (at the exit point, and at the entry point of the `first` cell), the cells
/// across that side or corner are tested too. The traversal and the exact
/// test round independently, so without this a ray grazing a cell edge could
/// slip between a cell the traversal skipped and one whose triangles the
/// exact test says it misses.
///
/// Returns the nearest hit found (with `ANY`, the first). Hits from the
/// neighbouring cells may lie beyond `t_out`; the caller keeps those pending
/// until its traversal has passed them.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn leaf<const ANY: bool>(
    f: &FieldView<'_>,
    r: &GridRay,
    i: u32,
    j: u32,
    t_in: f32,
    t_out: f32,
    exit: Exit,
    first: bool,
    stats: &mut TraceStats,
) -> Option<CellHit> {
    let c = f.corners(i, j);
    let (cmin, cmax) = corner_range(c);
    if !span_meets(r.z_at(t_in), r.z_at(t_out), cmin, cmax, r.zm) {
        return None;
    }
    stats.cells_tested += 1;
    stats.triangle_tests += 2;
    let mut best = intersect_cell::<ANY>(r, i, j, c);
    if ANY && best.is_some() {
        return best;
    }
    let e = r.xyeps;
    let (fi, fj) = (coord(i), coord(j));
    let near = |t: f32| {
        let p = r.o + t * r.d;
        let [xm, xp, ym, yp] = near(p.x, p.y, fi, fj, e);
        (xm, xp, ym, yp)
    };
    let mut extra = |di: i32, dj: i32, best: &mut Option<CellHit>| -> bool {
        let (ni, nj) = (i as i64 + i64::from(di), j as i64 + i64::from(dj));
        if ni < 0 || nj < 0 || ni >= i64::from(f.ncx) || nj >= i64::from(f.ncy) {
            return false;
        }
        let (ni, nj) = (ni as u32, nj as u32);
        stats.triangle_tests += 2;
        match intersect_cell::<ANY>(r, ni, nj, f.corners(ni, nj)) {
            Some(h) => {
                *best = Some(nearer(*best, h));
                ANY
            }
            None => false,
        }
    };
    // All neighbours within rounding distance of point `t` (entry of the first cell, end).
    let mut all_near = |t: f32, best: &mut Option<CellHit>| -> bool {
        let (xm, xp, ym, yp) = near(t);
        let dis = [(xm, -1), (xp, 1), (true, 0)];
        let djs = [(ym, -1), (yp, 1), (true, 0)];
        for &(ok_i, di) in &dis {
            for &(ok_j, dj) in &djs {
                if ok_i && ok_j && (di, dj) != (0, 0) && extra(di, dj, best) {
                    return true;
                }
            }
        }
        false
    };
    if first && all_near(t_in, &mut best) {
        return best;
    }
    match exit {
        Exit::End => {
            all_near(t_out, &mut best);
        }
        Exit::X => {
            // Leaving into column i + s: the rows across y boundaries near the exit,
            // in this column and the next.
            let s = if r.d.x > 0.0 { 1 } else { -1 };
            let (_, _, ym, yp) = near(t_out);
            for (ok, dj) in [(ym, -1), (yp, 1)] {
                if ok && (extra(0, dj, &mut best) || extra(s, dj, &mut best)) {
                    return best;
                }
            }
        }
        Exit::Y => {
            let s = if r.d.y > 0.0 { 1 } else { -1 };
            let (xm, xp, _, _) = near(t_out);
            for (ok, di) in [(xm, -1), (xp, 1)] {
                if ok && (extra(di, 0, &mut best) || extra(di, s, &mut best)) {
                    return best;
                }
            }
        }
    }
    best
}
