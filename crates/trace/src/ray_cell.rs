//! The exact, watertight intersection of a ray with one cell's two triangles.
//!
//! Musgrave's steps 6–7 (Musgrave 1993, §3.3.2): build the cell's two
//! triangles from its four corner heights and intersect the ray with both.
//! Instead of the source's plane-then-clip test (whose printed clip bound is
//! wrong, see [`Triangle`]), each triangle is tested with Woop, Benthin &
//! Wald's watertight algorithm (JCGT 2(1), 2013): the ray is sheared onto the
//! +z axis and the three edge functions are 2-D cross products of the
//! projected corners. A corner transforms the same way in every cell that
//! shares it and every shared edge's function is computed as the exact
//! negation on its two sides, so no ray can slip between the triangles of a
//! cell, or between cells. Both triangles can be hit (the surface folds along
//! the diagonal); the nearer hit is kept.

use glam::{UVec2, Vec3};
use natura_core::HeightField;

use crate::field::FieldView;
use crate::float::coord;
use crate::grid_ray::{GridRay, Shear};
use crate::ray::{Hit, Ray, Triangle};

/// A cell's corner `(x, y, h)` in the ray's sheared frame (origin `o`):
/// `[x, y, z]`, each a dot product of the corner relative to the origin with
/// one row of the shear.
#[inline(always)]
pub(crate) fn project(sh: &Shear, o: Vec3, x: f32, y: f32, h: f32) -> [f32; 3] {
    let rel = Vec3::new(x - o.x, y - o.y, h - o.z);
    [sh.px.dot(rel), sh.py.dot(rel), sh.pz.dot(rel)]
}

/// The corners `[p00, p10, p01, p11]` of cell `(x0, y0)`, heights `c`, in
/// the ray's sheared frame.
#[inline(always)]
pub(crate) fn project_cell(sh: &Shear, o: Vec3, x0: u32, y0: u32, c: [f32; 4]) -> [[f32; 3]; 4] {
    let (x0, x1) = (coord(x0), coord(x0.wrapping_add(1)));
    let (y0, y1) = (coord(y0), coord(y0.wrapping_add(1)));
    [
        project(sh, o, x0, y0, c[0]),
        project(sh, o, x1, y0, c[1]),
        project(sh, o, x0, y1, c[2]),
        project(sh, o, x1, y1, c[3]),
    ]
}

/// The edge function of the directed edge `a → b` (twice the signed area of
/// the triangle it spans with the ray): `a.x·b.y − a.y·b.x`.
#[inline(always)]
fn edge(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[1] - a[1] * b[0]
}

/// The same edge function evaluated exactly in `f64` (products of two `f32`
/// are exact in `f64`), rounded back: Woop's fallback for zero results.
#[inline(never)]
fn edge64(a: [f32; 3], b: [f32; 3]) -> f32 {
    (f64::from(a[0]) * f64::from(b[1]) - f64::from(a[1]) * f64::from(b[0])) as f32
}

/// A cell's five edge functions from its projected corners `[p00, p10,
/// p01, p11]`: `[diagonal, left, bottom, right, top]`. The diagonal's is
/// shared (negated) by the two triangles.
#[inline(always)]
pub(crate) fn edges(p: &[[f32; 3]; 4], edge: impl Fn([f32; 3], [f32; 3]) -> f32) -> [f32; 5] {
    let [p00, p10, p01, p11] = *p;
    [
        edge(p01, p10),
        edge(p00, p01),
        edge(p10, p00),
        edge(p11, p10),
        edge(p01, p11),
    ]
}

/// [`edges`] in `f32`.
#[inline(always)]
pub(crate) fn edges32(p: &[[f32; 3]; 4]) -> [f32; 5] {
    edges(p, edge)
}

/// Whether an edge function is exactly zero (the `f32` result cannot say
/// on which side the ray passes).
#[inline(always)]
pub(crate) fn any_zero(e: &[f32; 5]) -> bool {
    (e[0] == 0.0) | (e[1] == 0.0) | (e[2] == 0.0) | (e[3] == 0.0) | (e[4] == 0.0)
}

/// One triangle from its edge functions `(u, v, w)` (the weights of
/// corners `a, b, c`) and the corners' sheared depths: inclusive, no
/// culling of back faces, `t` in `[t_min, t_max]`. Returns whether it is
/// hit, the `t` and the barycentric weights (meaningful only when hit).
#[inline(always)]
fn triangle(u: f32, v: f32, w: f32, z: [f32; 3], t_min: f32, t_max: f32) -> (bool, f32, [f32; 3]) {
    let det = u + v + w;
    let inside = ((det > 0.0) & (u >= 0.0) & (v >= 0.0) & (w >= 0.0))
        | ((det < 0.0) & (u <= 0.0) & (v <= 0.0) & (w <= 0.0));
    let inv = 1.0 / det;
    let t = (u * z[0] + v * z[1] + w * z[2]) * inv;
    (
        inside & (t >= t_min) & (t <= t_max),
        t,
        [u * inv, v * inv, w * inv],
    )
}

/// The outcome of a cell's two triangles.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PairHit {
    /// Either triangle was hit.
    pub found: bool,
    /// The upper triangle is the one kept.
    pub upper: bool,
    /// The kept hit's `t`.
    pub t: f32,
    /// The kept hit's barycentric weights.
    pub bary: [f32; 3],
}

/// Both triangles of a cell from its edge functions `e` and projected
/// corners `p`, both computed and one selected (no branches): the nearer
/// hit, or with `ANY` the lower triangle's when both are hit.
#[inline(always)]
pub(crate) fn pair<const ANY: bool>(
    e: &[f32; 5],
    p: &[[f32; 3]; 4],
    t_min: f32,
    t_max: f32,
) -> PairHit {
    let [diag, left, bottom, right, top] = *e;
    let [p00, p10, p01, p11] = *p;
    // Lower: corners (p00, p10, p01); weights (diag, left, bottom).
    let (lok, lt, lb) = triangle(diag, left, bottom, [p00[2], p10[2], p01[2]], t_min, t_max);
    // Upper: corners (p11, p01, p10); weights (−diag, right, top).
    let (uok, ut, ub) = triangle(-diag, right, top, [p11[2], p01[2], p10[2]], t_min, t_max);
    let upper = uok & (!lok | (!ANY & (ut < lt)));
    PairHit {
        found: lok | uok,
        upper,
        t: if upper { ut } else { lt },
        bary: [
            if upper { ub[0] } else { lb[0] },
            if upper { ub[1] } else { lb[1] },
            if upper { ub[2] } else { lb[2] },
        ],
    }
}

/// A triangle hit found in a cell, before the world-space details are filled in.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CellHit {
    pub t: f32,
    pub cell: (u32, u32),
    pub triangle: Triangle,
    pub bary: Vec3,
}

impl CellHit {
    /// The hit a [`PairHit`] of cell `cell` found, if any.
    #[inline(always)]
    pub(crate) fn from_pair(h: PairHit, cell: (u32, u32)) -> Option<CellHit> {
        h.found.then(|| CellHit {
            t: h.t,
            cell,
            triangle: if h.upper {
                Triangle::Upper
            } else {
                Triangle::Lower
            },
            bary: Vec3::from_array(h.bary),
        })
    }
}

/// Intersects the ray with cell `(i, j)` whose corners are `c = [h00, h10, h01, h11]`.
///
/// Returns the nearer of the two triangles' hits in `[r.t_min, r.t_max]`, or
/// with `ANY` the lower triangle's when both are hit. Where an `f32` edge
/// function is exactly zero, all five are recomputed exactly (Woop et al.'s
/// double-precision fallback), so a ray through a shared edge or corner is
/// decided consistently on both sides.
#[inline(always)]
pub(crate) fn intersect_cell<const ANY: bool>(
    r: &GridRay,
    i: u32,
    j: u32,
    c: [f32; 4],
) -> Option<CellHit> {
    let p = project_cell(&r.shear, r.o, i, j, c);
    let mut e = edges32(&p);
    if any_zero(&e) {
        e = edges(&p, edge64);
    }
    CellHit::from_pair(pair::<ANY>(&e, &p, r.t_min, r.t_max), (i, j))
}

/// [`HeightField::normal_at_sample`](natura_core::HeightField::normal_at_sample)
/// at sample `(x, y)`, bit for bit: for samples off the border the central
/// differences are read straight from the row-major heights (no clamping,
/// no checked indexing); border samples go through the height field.
#[inline(always)]
fn sample_normal(f: &FieldView<'_>, x: usize, y: usize) -> Vec3 {
    let nx = f.nx;
    let ny = f.ncy as usize + 1;
    if x == 0 || y == 0 || x + 1 >= nx || y + 1 >= ny {
        return f.hf.normal_at_sample(x, y);
    }
    let k = y * nx + x;
    let h = f.h;
    // The same expressions as `gradient_at_sample`, with its span `2·cell`.
    let span = 2.0 * f.cell;
    let gx = HeightField::central_difference(h[k - 1], h[k + 1], span);
    let gy = HeightField::central_difference(h[k - nx], h[k + nx], span);
    HeightField::normal_from_gradient(gx, gy)
}

/// Fills in the world-space details of a cell hit.
pub(crate) fn make_hit(f: &FieldView<'_>, ray: &Ray, h: CellHit) -> Hit {
    make_hit_dir(f, ray.dir, h)
}

/// [`make_hit`] for a ray of direction `dir`.
#[inline]
fn make_hit_dir(f: &FieldView<'_>, dir: Vec3, h: CellHit) -> Hit {
    let (i, j) = h.cell;
    let c = f.corners(i, j);
    let s = f.cell;
    let corners = h.triangle.corners();
    let height = |(di, dj): (u32, u32)| c[(di + 2 * dj) as usize];
    let world = |(di, dj): (u32, u32)| {
        Vec3::new((i + di) as f32 * s, (j + dj) as f32 * s, height((di, dj)))
    };
    let w = h.bary;
    let point = world(corners[0]) * w.x + world(corners[1]) * w.y + world(corners[2]) * w.z;
    // Plane slopes per cell (grid units): z = a + b·u + c·v.
    let (b, cc) = match h.triangle {
        Triangle::Lower => (c[1] - c[0], c[2] - c[0]),
        Triangle::Upper => (c[3] - c[2], c[3] - c[1]),
    };
    let geometric_normal = Vec3::new(-b / s, -cc / s, 1.0).normalize();
    let vn = |(di, dj): (u32, u32)| sample_normal(f, (i + di) as usize, (j + dj) as usize);
    let smooth_normal = (vn(corners[0]) * w.x + vn(corners[1]) * w.y + vn(corners[2]) * w.z)
        .try_normalize()
        .unwrap_or(geometric_normal);
    Hit {
        t: h.t,
        point,
        geometric_normal,
        smooth_normal,
        cell: UVec2::new(i, j),
        triangle: h.triangle,
        barycentric: w,
        from_above: dir.dot(geometric_normal) < 0.0,
    }
}

/// Hits whose records [`hit_lanes`] fills in together.
pub(crate) const HIT_LANES: usize = 16;

/// The inputs of [`hit_lanes`], struct-of-arrays: for each lane a cell hit
/// and its ray's direction.
#[derive(Clone, Copy)]
pub(crate) struct HitLanes {
    pub hit: [CellHit; HIT_LANES],
    pub dir: [Vec3; HIT_LANES],
}

impl HitLanes {
    pub fn new() -> Self {
        Self {
            hit: [CellHit {
                t: 0.0,
                cell: (0, 0),
                triangle: Triangle::Lower,
                bary: Vec3::ZERO,
            }; HIT_LANES],
            dir: [Vec3::Z; HIT_LANES],
        }
    }
}

/// [`make_hit`] for the first `n` lanes of `s` at once: `emit(l, hit)` with
/// exactly `make_hit`'s record for lane `l` (bit for bit, tested). The
/// heights around each cell (its corners and the central differences'
/// neighbours) are gathered into struct-of-arrays form, then the points and
/// both normals are computed for all lanes with the same `f32` operations in
/// the same order as `make_hit`, in a loop without data-dependent branches
/// that vectorises (divisions and square roots included). Cells on the
/// field's border, whose corner normals clamp their differences, take
/// `make_hit` itself.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
pub(crate) fn hit_lanes(
    f: &FieldView<'_>,
    s: &HitLanes,
    n: usize,
    mut emit: impl FnMut(usize, Hit),
) {
    const N: usize = HIT_LANES;
    let nx = f.nx;
    let ny = f.ncy as usize + 1;
    // The 4 × 4 block of samples around cell (i, j), rows j − 1 ..= j + 2,
    // without its 4 outer corners: 12 heights, named by (column, row)
    // offsets from (i − 1, j − 1).
    const TAPS: [(usize, usize); 12] = [
        (1, 0),
        (2, 0),
        (0, 1),
        (1, 1),
        (2, 1),
        (3, 1),
        (0, 2),
        (1, 2),
        (2, 2),
        (3, 2),
        (1, 3),
        (2, 3),
    ];
    let mut g = [[0.0f32; N]; 12];
    let mut border = [true; N];
    let mut ci = [0u32; N];
    let mut cj = [0u32; N];
    let mut upper = [false; N];
    let mut w = [[0.0f32; N]; 3];
    let mut dir = [[0.0f32; N]; 3];
    let interior = nx >= 4 && ny >= 4;
    for l in 0..n {
        let h = &s.hit[l];
        let (i, j) = (h.cell.0 as usize, h.cell.1 as usize);
        let b = i == 0 || j == 0 || i + 2 >= nx || j + 2 >= ny;
        border[l] = b;
        ci[l] = h.cell.0;
        cj[l] = h.cell.1;
        upper[l] = h.triangle == Triangle::Upper;
        w[0][l] = h.bary.x;
        w[1][l] = h.bary.y;
        w[2][l] = h.bary.z;
        dir[0][l] = s.dir[l].x;
        dir[1][l] = s.dir[l].y;
        dir[2][l] = s.dir[l].z;
        if interior {
            // Border lanes read a stand-in block (their records come from `make_hit`).
            let (i0, j0) = if b { (0, 0) } else { (i - 1, j - 1) };
            let base = j0 * nx + i0;
            let rows = &f.h[base..base + 3 * nx + 4];
            for (tap, &(a, r)) in TAPS.iter().enumerate() {
                g[tap][l] = rows[r * nx + a];
            }
        }
    }
    let cell = f.cell;
    let span = 2.0 * cell;
    let mut point = [[0.0f32; N]; 3];
    let mut gn = [[0.0f32; N]; 3];
    let mut sn = [[0.0f32; N]; 3];
    let mut above = [false; N];
    for l in 0..N {
        let tap = |k: usize| g[k][l];
        // Corner heights [h00, h10, h01, h11].
        let c = [tap(3), tap(4), tap(7), tap(8)];
        // Corner normals by central differences (`sample_normal`).
        let normal = |west: usize, east: usize, south: usize, north: usize| {
            let gx = HeightField::central_difference(tap(west), tap(east), span);
            let gy = HeightField::central_difference(tap(south), tap(north), span);
            HeightField::normal_from_gradient(gx, gy).to_array()
        };
        let n00 = normal(2, 4, 0, 7);
        let n10 = normal(3, 5, 1, 8);
        let n01 = normal(6, 8, 3, 10);
        let n11 = normal(7, 9, 4, 11);
        let up = upper[l];
        // The triangle's corners in barycentric order (`Triangle::corners`):
        // lower (0,0), (1,0), (0,1); upper (1,1), (0,1), (1,0).
        let (ai, aj, ah, an) = if up {
            (1, 1, c[3], n11)
        } else {
            (0, 0, c[0], n00)
        };
        let (bi, bj, bh, bn) = if up {
            (0, 1, c[2], n01)
        } else {
            (1, 0, c[1], n10)
        };
        let (ki, kj, kh, kn) = if up {
            (1, 0, c[1], n10)
        } else {
            (0, 1, c[2], n01)
        };
        let (i, j) = (ci[l], cj[l]);
        let world = |di: u32, dj: u32, h: f32| {
            [
                // Cell coordinates are below 2²⁴: the `i32` conversion is exact.
                i.wrapping_add(di) as i32 as f32 * cell,
                j.wrapping_add(dj) as i32 as f32 * cell,
                h,
            ]
        };
        let (pa, pb, pc) = (world(ai, aj, ah), world(bi, bj, bh), world(ki, kj, kh));
        let (wx, wy, wz) = (w[0][l], w[1][l], w[2][l]);
        for k in 0..3 {
            point[k][l] = pa[k] * wx + pb[k] * wy + pc[k] * wz;
        }
        let (b, cc) = if up {
            (c[3] - c[2], c[3] - c[1])
        } else {
            (c[1] - c[0], c[2] - c[0])
        };
        let v = [-b / cell, -cc / cell, 1.0f32];
        let r = 1.0 / (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let gv = [v[0] * r, v[1] * r, v[2] * r];
        let m = [
            an[0] * wx + bn[0] * wy + kn[0] * wz,
            an[1] * wx + bn[1] * wy + kn[1] * wz,
            an[2] * wx + bn[2] * wy + kn[2] * wz,
        ];
        let rm = 1.0 / (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
        let ok = rm.is_finite() & (rm > 0.0);
        for k in 0..3 {
            gn[k][l] = gv[k];
            sn[k][l] = if ok { m[k] * rm } else { gv[k] };
        }
        above[l] = dir[0][l] * gv[0] + dir[1][l] * gv[1] + dir[2][l] * gv[2] < 0.0;
    }
    for l in 0..n {
        let h = s.hit[l];
        if border[l] || !interior {
            emit(l, make_hit_dir(f, s.dir[l], h));
            continue;
        }
        let v = |a: &[[f32; N]; 3]| Vec3::new(a[0][l], a[1][l], a[2][l]);
        emit(
            l,
            Hit {
                t: h.t,
                point: v(&point),
                geometric_normal: v(&gn),
                smooth_normal: v(&sn),
                cell: UVec2::new(h.cell.0, h.cell.1),
                triangle: h.triangle,
                barycentric: h.bary,
                from_above: above[l],
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::{HeightField, Seed};

    /// The direct central differences equal `HeightField::normal_at_sample`
    /// bit for bit at every sample (border samples included), for several
    /// cell sizes and field shapes.
    #[test]
    fn sample_normals_equal_the_height_fields() {
        let s = Seed(3);
        for (nx, ny, cell) in [(2, 2, 1.0), (3, 7, 0.5), (17, 9, 3.7), (40, 33, 10.0)] {
            let hf = HeightField::from_fn(nx, ny, cell, |i, j| {
                500.0 * s.uniform2(i as i64, j as i64) as f32 - 100.0
            })
            .unwrap();
            let f = FieldView::new(&hf).unwrap();
            for y in 0..ny {
                for x in 0..nx {
                    let want = hf.normal_at_sample(x, y).to_array().map(f32::to_bits);
                    let got = sample_normal(&f, x, y).to_array().map(f32::to_bits);
                    assert_eq!(got, want, "sample ({x}, {y}) of {nx} × {ny}");
                }
            }
        }
    }
}
