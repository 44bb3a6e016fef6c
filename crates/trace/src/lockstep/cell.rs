//! The exact cell tests of the lanes: the single-ray walk's cell step
//! ([`crate::step`], [`crate::ray_cell`], [`crate::leaf::near`]) per lane,
//! both triangles' outcomes computed and one selected.

use glam::Vec3;

use super::node::NodeTable;
use super::{CellOut, Exact, FOUND, LANES, Lanes, SCALAR};
use crate::float::coord;
use crate::grid_ray::Shear;
use crate::leaf::near;
use crate::ray_cell::{any_zero, edges32, pair, project_cell};
use crate::step::{Exit, Signs, corner_range, leaves_parent, node_exits, span_meets, step_out};

/// The exact test of every lane's cell at once, as the single-ray walk's
/// cell step: the cell's exit ([`Exit::of`]), the two-sided z cull and the
/// watertight pair of triangle tests ([`crate::ray_cell`]), with the same
/// `f32` operations in the same order per lane and both triangles' outcomes
/// computed and selected, so the loop over lanes vectorises. Lanes whose
/// test needs more than that (a zero edge function, the neighbours of an
/// edge within rounding distance) are flagged [`SCALAR`].
#[inline(always)]
#[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
pub(super) fn cells<const ANY: bool>(
    s: &mut Lanes,
    k: &NodeTable<'_>,
    x: &Exact,
    c: &[[f32; LANES]; 4],
    parked: u32,
    o: &mut CellOut,
) {
    let (mut climbed, mut done) = (0u32, 0u32);
    // (Read once: the step past a cell reads these only on some paths.)
    let (ncx, ncy, top) = (k.ncx, k.ncy, k.top);
    for l in 0..LANES {
        let (ci, cj, t) = (s.ci[l], s.cj[l], s.t[l]);
        let signs = Signs(s.sign[l]);
        let (ox, oy, oz) = (s.ox[l], s.oy[l], x.oz[l]);
        // The cell's exit (cell coordinates are below 2²⁴; dead lanes sit
        // at 0).
        let (tx, ty) = node_exits(signs, ci, cj, 1, ox, oy, s.ix[l], s.iy[l]);
        let (t_exit, exit) = Exit::of(tx, ty, s.t_end[l], t);
        // The cull (`leaf`).
        let h = [c[0][l], c[1][l], c[2][l], c[3][l]];
        let (cmin, cmax) = corner_range(h);
        let (za, zb) = (oz + t * x.dz[l], oz + t_exit * x.dz[l]);
        let pass = span_meets(za, zb, cmin, cmax, x.zm[l]);
        // The watertight pair (`intersect_cell`).
        let row = |q: usize| Vec3::new(x.sh[q][l], x.sh[q + 1][l], x.sh[q + 2][l]);
        let sh = Shear {
            px: row(0),
            py: row(3),
            pz: row(6),
        };
        let p = project_cell(&sh, Vec3::new(ox, oy, oz), ci, cj, h);
        let e = edges32(&p);
        let zero = any_zero(&e);
        let found_pair = pair::<ANY>(&e, &p, x.t_min[l], x.t_max[l]);
        let found = found_pair.found;
        o.t[l] = found_pair.t;
        o.upper[l] = found_pair.upper;
        for q in 0..3 {
            o.bary[q][l] = found_pair.bary[q];
        }
        // The edges and corners within rounding distance (`leaf`'s `near`).
        let (x0, y0, eps) = (coord(ci), coord(cj), x.xyeps[l]);
        let a = near(ox + t * s.dx[l], oy + t * s.dy[l], x0, y0, eps);
        let b = near(ox + t_exit * s.dx[l], oy + t_exit * s.dy[l], x0, y0, eps);
        let first = t == s.t0[l];
        let at_in = first & (a[0] | a[1] | a[2] | a[3]);
        // (Compares rather than a `match`, which LLVM would turn into a
        // table lookup the loop cannot vectorise.)
        let at_out = if exit == Exit::End {
            b[0] | b[1] | b[2] | b[3]
        } else if exit == Exit::X {
            b[2] | b[3]
        } else {
            b[0] | b[1]
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
        let (nci, ncj, out) = step_out(
            exit == Exit::X,
            signs,
            ci,
            cj,
            ci,
            cj,
            1,
            true,
            0.0,
            0.0,
            ncx,
            ncy,
        );
        let left = (exit == Exit::End) | out;
        let climb = (top > 0) & leaves_parent(ci, cj, nci, ncj, 0);
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
