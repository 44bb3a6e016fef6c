//! Simplex noise (Perlin 2001), 2-D and 3-D.
//!
//! Gradient noise on the simplex lattice (triangles in 2-D, tetrahedra in 3-D):
//! each point sums the radially attenuated contributions `(½ − r²)⁴·g·d` of the
//! `n + 1` corners of its simplex. Outside the sources (Musgrave 2001, "The
//! Various Basis Functions", lists only lattice "Perlin" variants); offered
//! because it is cheaper in 3-D and has no axis-aligned artefacts. Kernel
//! radius² ½ in both dimensions, so the noise is continuous (C³ kernel) —
//! unlike the common 0.6 in 3-D, which leaves small jumps at simplex faces.
//! Zero at lattice points like Perlin noise.
//!
//! Gradients are the same sets as [`Perlin`](crate::Perlin)'s (8 unit vectors
//! in 2-D, 12 cube edges in 3-D), hashed from the lattice coordinates. Values
//! are scaled by `1/sup|raw|` (numerically maximised over the simplex with
//! every corner picking its worst gradient), so [`Field::bound`] is 1 and
//! attained; the Lipschitz constants are the maximised gradient norms of the
//! scaled noise, rounded up by 1%.
//!
//! Batch rows rebase each 32-point block to its first point's simplex cell:
//! along a row the skewed coordinates advance linearly, so the lanes add
//! precomputed f32 offsets to the block's exact lattice index and fraction
//! and never touch f64.

use glam::{DVec2, DVec3};
use natura_simd::multiversion;

use crate::field::Field;
use crate::hash::{GRAD2_64, PX, PY, PZ, corner_spread, dot3, flat2, flat3, grad2, grad3, seed32};
use crate::lattice_math::{BLOCK, LaneOffsets, Simd, rebase, split, split_fast, split_floor_n};

/// sup |raw 2-D simplex noise| with the ½-radius kernel and unit gradients.
pub const SIMPLEX2_SUP: f64 = 0.010_080_205;
/// sup |raw 3-D simplex noise| with the ½-radius kernel and edge gradients.
pub const SIMPLEX3_SUP: f64 = 0.013_007_158;
const L2: f64 = 7.43;
const L3: f64 = 7.04;

const F2: f64 = 0.366_025_403_784_438_6; // (√3 − 1)/2
const G2: f64 = 0.211_324_865_405_187_1; // (3 − √3)/6
const F3: f64 = 1.0 / 3.0;
const G3: f64 = 1.0 / 6.0;

const SALT: u64 = 0x5349_4D50; // "SIMP"

/// Simplex gradient noise; unit lattice, values in `[-1, 1]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Simplex {
    seed: u64,
    s: u32,
}

impl Default for Simplex {
    fn default() -> Self {
        Simplex::new(0)
    }
}

/// Skews a 2-D point onto the simplex lattice: the base corner's indices and
/// the offset from it (f64, shared by the point and batch paths).
#[inline(always)]
fn skew2(x: f64, y: f64, fast: bool) -> (u32, u32, f64, f64) {
    let s = (x + y) * F2;
    let (xs, ys) = (x + s, y + s);
    let (i, j, fi, fj) = if fast {
        let ((i, fx), (j, fy)) = (split_fast(xs), split_fast(ys));
        (i, j, xs - fx, ys - fy)
    } else {
        let ([i, j], _, [fi, fj]) = split_floor_n([xs, ys]);
        (i, j, fi, fj)
    };
    let t = (fi + fj) * G2;
    (i, j, x - fi + t, y - fj + t)
}

#[inline(always)]
fn skew3(p: [f64; 3], fast: bool) -> ([u32; 3], [f64; 3]) {
    let s = (p[0] + p[1] + p[2]) * F3;
    let mut idx = [0u32; 3];
    let mut fl = [0.0; 3];
    for a in 0..3 {
        let v = p[a] + s;
        let (i, f) = if fast { split_fast(v) } else { split(v) };
        idx[a] = i;
        fl[a] = v - f;
    }
    let t = (fl[0] + fl[1] + fl[2]) * G3;
    (idx, [p[0] - fl[0] + t, p[1] - fl[1] + t, p[2] - fl[2] + t])
}

/// The corner offsets of the 3-D simplex containing offset `d` (Gustavson's ranking).
#[inline(always)]
fn order3(x: f64, y: f64, z: f64) -> ([u32; 3], [u32; 3]) {
    if x >= y {
        if y >= z {
            ([1, 0, 0], [1, 1, 0])
        } else if x >= z {
            ([1, 0, 0], [1, 0, 1])
        } else {
            ([0, 0, 1], [1, 0, 1])
        }
    } else if y < z {
        ([0, 0, 1], [0, 1, 1])
    } else if x < z {
        ([0, 1, 0], [0, 1, 1])
    } else {
        ([0, 1, 0], [1, 1, 0])
    }
}

impl Simplex {
    /// Simplex noise with `seed`.
    #[must_use]
    pub const fn new(seed: u64) -> Self {
        Self {
            seed,
            s: seed32(seed, SALT),
        }
    }

    /// The seed.
    #[must_use]
    pub const fn seed(&self) -> u64 {
        self.seed
    }

    fn grad2_impl(&self, p: DVec2) -> (f64, DVec2) {
        let (i, j, x0, y0) = skew2(p.x, p.y, false);
        let (i1, j1) = if x0 > y0 { (1u32, 0u32) } else { (0, 1) };
        let corners = [
            (0u32, 0u32, x0, y0),
            (i1, j1, x0 - f64::from(i1) + G2, y0 - f64::from(j1) + G2),
            (1, 1, x0 - 1.0 + 2.0 * G2, y0 - 1.0 + 2.0 * G2),
        ];
        let mut v = 0.0;
        let mut g = DVec2::ZERO;
        for (a, b, x, y) in corners {
            let t = 0.5 - x * x - y * y;
            if t > 0.0 {
                let (gx, gy) = grad2(flat2(i.wrapping_add(a), j.wrapping_add(b), self.s));
                let (gx, gy) = (f64::from(gx), f64::from(gy));
                let gd = gx * x + gy * y;
                let t2 = t * t;
                v += t2 * t2 * gd;
                g += DVec2::new(gx, gy) * (t2 * t2) - DVec2::new(x, y) * (8.0 * t2 * t * gd);
            }
        }
        let k = 1.0 / SIMPLEX2_SUP;
        (v * k, g * k)
    }

    fn grad3_impl(&self, p: DVec3) -> (f64, DVec3) {
        let (idx, d0) = skew3(p.to_array(), false);
        let (o1, o2) = order3(d0[0], d0[1], d0[2]);
        let mut v = 0.0;
        let mut g = DVec3::ZERO;
        for (c, off) in [[0u32; 3], o1, o2, [1, 1, 1]].into_iter().enumerate() {
            let d = DVec3::new(
                d0[0] - f64::from(off[0]) + c as f64 * G3,
                d0[1] - f64::from(off[1]) + c as f64 * G3,
                d0[2] - f64::from(off[2]) + c as f64 * G3,
            );
            let t = 0.5 - d.length_squared();
            if t > 0.0 {
                let h = flat3(
                    idx[0].wrapping_add(off[0]),
                    idx[1].wrapping_add(off[1]),
                    idx[2].wrapping_add(off[2]),
                    self.s,
                );
                let (gx, gy, gz) = grad3(h);
                let gv = DVec3::new(f64::from(gx), f64::from(gy), f64::from(gz));
                let gd = gv.dot(d);
                let t2 = t * t;
                v += t2 * t2 * gd;
                g += gv * (t2 * t2) - d * (8.0 * t2 * t * gd);
            }
        }
        let k = 1.0 / SIMPLEX3_SUP;
        (v * k, g * k)
    }
}

/// `(½ − r²)₊`, keeping a NaN (a NaN point gives a NaN value).
#[inline(always)]
fn falloff(t: f64) -> f64 {
    if t < 0.0 { 0.0 } else { t }
}

/// `x` if `on`, else 0 (a mask, not a branch).
#[inline(always)]
fn masked(x: u32, on: bool) -> u32 {
    x & 0u32.wrapping_sub(u32::from(on))
}

impl Simplex {
    /// The 2-D value at `p`: the three corners of its triangle, without
    /// branches, each lattice index spread once. The middle corner, (1, 0)
    /// or (0, 1) by the triangle test, is hashed once, its lattice offsets
    /// selected by integer masks (a branch here would mispredict on half
    /// the points). The test is made twice, as a float mask for the offsets
    /// and as the sign bit of `y0 − x0` for the integer masks (`+ 0` turns
    /// an equal pair's `−0` into `+0`; a difference of unequal finite values
    /// is never zero): one comparison feeding both sides is compiled as a
    /// branch, which mispredicts on points that do not repeat (figures in
    /// `docs/performance.md`).
    #[inline(always)]
    fn value2(&self, p: DVec2) -> f64 {
        let (i, j, x0, y0) = skew2(p.x, p.y, false);
        let i1 = f64::from_bits(1.0f64.to_bits() & 0u64.wrapping_sub(u64::from(x0 > y0)));
        let j1 = 1.0 - i1;
        let upper = ((y0 - x0) + 0.0).is_sign_negative();
        let xp = i.wrapping_mul(PX);
        let yp = j.wrapping_mul(PY) ^ self.s;
        let yq = j.wrapping_mul(PY).wrapping_add(PY) ^ self.s;
        let xq = xp.wrapping_add(PX);
        let corner = |g: [f64; 2], x: f64, y: f64| {
            let t = falloff(0.5 - x * x - y * y);
            let t2 = t * t;
            t2 * t2 * (g[0] * x + g[1] * y)
        };
        let grad = |h: u32| GRAD2_64[(h >> 28) as usize];
        // The middle corner, (1, 0) or (0, 1), selected by masks.
        let xm = xp.wrapping_add(masked(PX, upper));
        let ym = j.wrapping_mul(PY).wrapping_add(masked(PY, !upper)) ^ self.s;
        let g1 = grad(corner_spread(xm, ym));
        let v = corner(grad(corner_spread(xp, yp)), x0, y0)
            + corner(g1, x0 - i1 + G2, y0 - j1 + G2)
            + corner(
                grad(corner_spread(xq, yq)),
                x0 - 1.0 + 2.0 * G2,
                y0 - 1.0 + 2.0 * G2,
            );
        v * (1.0 / SIMPLEX2_SUP)
    }

    /// The 3-D value at `p`: the four corners of its tetrahedron, ranked
    /// without branches (Gustavson's order, ties broken as the batch kernel
    /// breaks them).
    #[inline(always)]
    fn value3(&self, p: DVec3) -> f64 {
        let (idx, [x0, y0, z0]) = skew3(p.to_array(), false);
        let rx = u32::from(x0 >= y0) + u32::from(x0 >= z0);
        let ry = u32::from(y0 > x0) + u32::from(y0 >= z0);
        let rz = u32::from(z0 > x0) + u32::from(z0 > y0);
        let xp = idx[0].wrapping_mul(PX);
        let yp = idx[1].wrapping_mul(PY);
        let zp = idx[2].wrapping_mul(PZ);
        let hash = |o: [bool; 3]| {
            corner_spread(
                xp.wrapping_add(masked(PX, o[0])),
                yp.wrapping_add(masked(PY, o[1])) ^ zp.wrapping_add(masked(PZ, o[2])) ^ self.s,
            )
        };
        let corner = |o: [bool; 3], g: f64| {
            let off = o.map(|b| f64::from(u8::from(b)));
            let (x, y, z) = (x0 - off[0] + g, y0 - off[1] + g, z0 - off[2] + g);
            let t = falloff(0.5 - x * x - y * y - z * z);
            let t2 = t * t;
            t2 * t2 * dot3(hash(o), x, y, z)
        };
        let v = corner([false; 3], 0.0)
            + corner([rx == 2, ry == 2, rz == 2], G3)
            + corner([rx >= 1, ry >= 1, rz >= 1], 2.0 * G3)
            + corner([true; 3], 3.0 * G3);
        v * (1.0 / SIMPLEX3_SUP)
    }
}

impl Field for Simplex {
    #[inline(always)]
    fn eval2(&self, p: DVec2) -> f64 {
        self.value2(p)
    }
    #[inline(always)]
    fn eval3(&self, p: DVec3) -> f64 {
        self.value3(p)
    }
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        self.grad2_impl(p)
    }
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        self.grad3_impl(p)
    }
    fn bound(&self) -> f64 {
        1.0
    }
    fn lipschitz2(&self) -> f64 {
        L2
    }
    fn lipschitz3(&self) -> f64 {
        L3
    }

    fn fill_row2_with(&self, simd: Simd, origin: DVec2, step: f64, out: &mut [f32]) {
        let ok = crate::basis::row_in_fast_range(origin.x + origin.y, step, out.len())
            && origin.y.is_finite()
            && origin.x.abs() < 1e14
            && origin.y.abs() < 1e14;
        if !ok {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval2(DVec2::new(origin.x + i as f64 * step, origin.y)) as f32;
            }
            return;
        }
        simplex2_row_at::<true>(simd, self.s, origin, step, (1.0 / SIMPLEX2_SUP) as f32, out);
    }

    fn fill_row3_with(&self, simd: Simd, origin: DVec3, step: f64, out: &mut [f32]) {
        let ok = crate::basis::row_in_fast_range(origin.x, step, out.len())
            && origin.is_finite()
            && origin.abs().max_element() < 1e14;
        if !ok {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.eval3(DVec3::new(origin.x + i as f64 * step, origin.y, origin.z)) as f32;
            }
            return;
        }
        simplex3_row_at(simd, self.s, origin, step, (1.0 / SIMPLEX3_SUP) as f32, out);
    }
}

multiversion! {
    /// [`simplex2_row`] compiled for `simd`'s instruction set (a named
    /// function, not a closure, so the kernel is inlined into each level's
    /// `#[target_feature]` function whatever the build's inlining budget).
    fn simplex2_row_at<'a, const CELL: bool>(
        simd: Simd,
        s: u32,
        origin: DVec2,
        step: f64,
        k: f32,
        out: &'a mut [f32],
    ) {
        simplex2_row::<CELL>(s, origin, step, k, out);
    }
}

multiversion! {
    /// [`simplex3_row`] compiled for `simd`'s instruction set.
    fn simplex3_row_at<'a>(
        simd: Simd,
        s: u32,
        origin: DVec3,
        step: f64,
        k: f32,
        out: &'a mut [f32],
    ) {
        simplex3_row(s, origin, step, k, out);
    }
}

#[inline(always)]
fn contrib2(h: u32, x: f32, y: f32) -> f32 {
    contrib2g(grad2(h), x, y)
}

/// One corner's contribution `(½ − r²)₊⁴ · g·d` for gradient `g`.
#[inline(always)]
fn contrib2g((gx, gy): (f32, f32), x: f32, y: f32) -> f32 {
    let t = (0.5 - x * x - y * y).max(0.0);
    let t2 = t * t;
    t2 * t2 * (gx * x + gy * y)
}

/// The 2-D row kernel. Along a row both skewed coordinates advance linearly
/// (`xs += step·(1 + F2)`, `ys += step·F2`), so each block of lanes is rebased
/// to its first point's simplex cell ([`LaneOffsets`]) and the rest is f32/u32.
/// The unskewed offset from the cell's base corner is `d = f − (fx + fy)·G2`
/// for skewed fractions `f` (the point path's `x − (i − (i + j)·G2)`,
/// re-associated).
///
/// Each block is two passes: the lanes' cells and fractions first, then the
/// corner sums. When every lane of the block lies in the same skewed cell
/// (about half the blocks at W2's 0.01 cells per sample, where a 32-point
/// block spans 0.44 cells on the skewed x axis), the cell's four lattice
/// gradients are hashed once (and reused by following blocks in the same
/// cell) and each lane only picks its middle corner by the triangle test;
/// otherwise every lane hashes its three corners. Both give the same values
/// bit for bit (the same hashes and the same arithmetic; `CELL = false`
/// forces the per-lane path, which the tests compare against).
#[inline(always)]
fn simplex2_row<const CELL: bool>(s: u32, origin: DVec2, step: f64, k: f32, out: &mut [f32]) {
    let y = origin.y;
    let lx = LaneOffsets::new(step * (1.0 + F2));
    let ly = LaneOffsets::new(step * F2);
    let mut ci = [0u32; BLOCK];
    let mut cj = [0u32; BLOCK];
    let mut fxs = [0.0f32; BLOCK];
    let mut fys = [0.0f32; BLOCK];
    // The last one-cell block's cell and gradients: successive blocks often
    // share a cell at low frequencies.
    let mut cached: Option<(u32, u32)> = None;
    let mut grads = [(0.0f32, 0.0f32); 4];
    for (b, block) in out.chunks_mut(BLOCK).enumerate() {
        let x = origin.x + (b * BLOCK) as f64 * step;
        let sk = (x + y) * F2;
        let (bi, bfx) = LaneOffsets::base(x + sk);
        let (bj, bfy) = LaneOffsets::base(y + sk);
        let n = block.len();
        for m in 0..BLOCK {
            let (i, fx) = rebase(bi, bfx, lx.cell[m], lx.frac[m]);
            let (j, fy) = rebase(bj, bfy, ly.cell[m], ly.frac[m]);
            ci[m] = i;
            cj[m] = j;
            fxs[m] = fx;
            fys[m] = fy;
        }
        // Lanes past the block's end (the row's last block) are ignored.
        let (i0, j0) = (ci[0], cj[0]);
        let diff = ci[..n]
            .iter()
            .zip(&cj[..n])
            .fold(0u32, |a, (&i, &j)| a | (i ^ i0) | (j ^ j0));
        let (fxs, fys) = (&fxs[..n], &fys[..n]);
        if CELL && diff == 0 {
            if cached != Some((i0, j0)) {
                grads = cell_grads2(s, i0, j0);
                cached = Some((i0, j0));
            }
            simplex2_cell_lanes(grads, fxs, fys, k, block);
        } else {
            simplex2_lanes(s, &ci[..n], &cj[..n], fxs, fys, k, block);
        }
    }
}

/// The gradients of skewed cell `(i, j)`'s lattice points `(i, j)`,
/// `(i + 1, j)`, `(i, j + 1)`, `(i + 1, j + 1)`.
#[inline(always)]
fn cell_grads2(s: u32, i: u32, j: u32) -> [(f32, f32); 4] {
    [
        grad2(flat2(i, j, s)),
        grad2(flat2(i.wrapping_add(1), j, s)),
        grad2(flat2(i, j.wrapping_add(1), s)),
        grad2(flat2(i.wrapping_add(1), j.wrapping_add(1), s)),
    ]
}

/// The corners' unskewed offsets for skewed fractions `(fx, fy)`: base
/// corner, middle corner (`upper`: the `(1, 0)` corner, else `(0, 1)`), far corner.
#[inline(always)]
fn offsets2(fx: f32, fy: f32) -> (bool, [(f32, f32); 3]) {
    const G: f32 = G2 as f32;
    let t = (fx + fy) * G;
    let (x0, y0) = (fx - t, fy - t);
    let upper = fx > fy;
    let (i1, j1) = if upper { (1u32, 0u32) } else { (0, 1) };
    let x1 = x0 - i1 as f32 + G;
    let y1 = y0 - j1 as f32 + G;
    let x2 = x0 - 1.0 + 2.0 * G;
    let y2 = y0 - 1.0 + 2.0 * G;
    (upper, [(x0, y0), (x1, y1), (x2, y2)])
}

/// Lanes that all lie in one skewed cell, given its four lattice gradients
/// ([`cell_grads2`]).
#[inline(always)]
fn simplex2_cell_lanes(
    [g00, g10, g01, g11]: [(f32, f32); 4],
    fxs: &[f32],
    fys: &[f32],
    k: f32,
    out: &mut [f32],
) {
    for ((o, &fx), &fy) in out.iter_mut().zip(fxs).zip(fys) {
        let (upper, [(x0, y0), (x1, y1), (x2, y2)]) = offsets2(fx, fy);
        let g1 = if upper { g10 } else { g01 };
        let v = contrib2g(g00, x0, y0) + contrib2g(g1, x1, y1) + contrib2g(g11, x2, y2);
        *o = v * k;
    }
}

/// Lanes in any cells: three hashes per lane.
#[inline(always)]
fn simplex2_lanes(
    s: u32,
    ci: &[u32],
    cj: &[u32],
    fxs: &[f32],
    fys: &[f32],
    k: f32,
    out: &mut [f32],
) {
    let lanes = out
        .iter_mut()
        .zip(ci.iter().zip(cj))
        .zip(fxs.iter().zip(fys));
    for ((o, (&i, &j)), (&fx, &fy)) in lanes {
        let (upper, [(x0, y0), (x1, y1), (x2, y2)]) = offsets2(fx, fy);
        // Each index is spread once; the other corners add `PX` or `PY`
        // to the spread index (the same hashes as `flat2`).
        let xp = i.wrapping_mul(PX);
        let yp = j.wrapping_mul(PY);
        let (xq, yq) = (xp.wrapping_add(PX), yp.wrapping_add(PY) ^ s);
        let yp = yp ^ s;
        let h1 = if upper {
            corner_spread(xq, yp)
        } else {
            corner_spread(xp, yq)
        };
        let v = contrib2(corner_spread(xp, yp), x0, y0)
            + contrib2(h1, x1, y1)
            + contrib2(corner_spread(xq, yq), x2, y2);
        *o = v * k;
    }
}

#[inline(always)]
fn contrib3(h: u32, x: f32, y: f32, z: f32) -> f32 {
    let t = (0.5 - x * x - y * y - z * z).max(0.0);
    let (gx, gy, gz) = grad3(h);
    let t2 = t * t;
    t2 * t2 * (gx * x + gy * y + gz * z)
}

/// The 3-D row kernel, rebased per block like [`simplex2_row`]: along a row
/// the skewed x advances by `step·(1 + F3)` and the skewed y and z by
/// `step·F3`; the simplex ranking and offsets come from the f32 fractions.
#[inline(always)]
fn simplex3_row(s: u32, origin: DVec3, step: f64, k: f32, out: &mut [f32]) {
    const G: f32 = G3 as f32;
    let lx = LaneOffsets::new(step * (1.0 + F3));
    let lyz = LaneOffsets::new(step * F3);
    for (b, block) in out.chunks_mut(BLOCK).enumerate() {
        let x = origin.x + (b * BLOCK) as f64 * step;
        let sk = (x + origin.y + origin.z) * F3;
        let (bi, bfx) = LaneOffsets::base(x + sk);
        let (bj, bfy) = LaneOffsets::base(origin.y + sk);
        let (bk, bfz) = LaneOffsets::base(origin.z + sk);
        let lanes = block
            .iter_mut()
            .zip(lx.cell.iter().zip(&lx.frac))
            .zip(lyz.cell.iter().zip(&lyz.frac));
        for ((o, (&cx, &gx)), (&cyz, &gyz)) in lanes {
            let (i, fx) = rebase(bi, bfx, cx, gx);
            let (j, fy) = rebase(bj, bfy, cyz, gyz);
            let (kk, fz) = rebase(bk, bfz, cyz, gyz);
            let t = (fx + fy + fz) * G;
            let (x0, y0, z0) = (fx - t, fy - t, fz - t);
            // Branch-free ranking of the offsets (Gustavson's order, ties
            // broken the same way): the largest axis steps first.
            let rx = u32::from(x0 >= y0) + u32::from(x0 >= z0);
            let ry = u32::from(y0 > x0) + u32::from(y0 >= z0);
            let rz = u32::from(z0 > x0) + u32::from(z0 > y0);
            let o1 = [u32::from(rx == 2), u32::from(ry == 2), u32::from(rz == 2)];
            let o2 = [u32::from(rx >= 1), u32::from(ry >= 1), u32::from(rz >= 1)];
            let mut v = contrib3(flat3(i, j, kk, s), x0, y0, z0);
            for (c, off) in [o1, o2].into_iter().enumerate() {
                let g = (c + 1) as f32 * G;
                let h = flat3(
                    i.wrapping_add(off[0]),
                    j.wrapping_add(off[1]),
                    kk.wrapping_add(off[2]),
                    s,
                );
                v += contrib3(
                    h,
                    x0 - off[0] as f32 + g,
                    y0 - off[1] as f32 + g,
                    z0 - off[2] as f32 + g,
                );
            }
            let h = flat3(i.wrapping_add(1), j.wrapping_add(1), kk.wrapping_add(1), s);
            v += contrib3(
                h,
                x0 - 1.0 + 3.0 * G,
                y0 - 1.0 + 3.0 * G,
                z0 - 1.0 + 3.0 * G,
            );
            *o = v * k;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-cell block path against the per-lane hashing path: bit for
    /// bit, at every SIMD level, for steps on both sides of the block-span
    /// threshold (≈ 0.023), negative steps and rows crossing the axes.
    #[test]
    fn cell_blocks_equal_per_lane_hashing_bit_for_bit() {
        let s = Simplex::new(9).s;
        let k = (1.0 / SIMPLEX2_SUP) as f32;
        for &step in &[1e-4, 0.003, 0.01, 0.0229, 0.03, 0.2, -0.01, -0.7] {
            for &origin in &[
                DVec2::new(-3.7, 2.2),
                DVec2::new(0.1, -0.05),
                DVec2::new(1e6 + 0.3, -4e5),
            ] {
                for simd in Simd::supported() {
                    let mut fast = [0.0f32; 301];
                    let mut slow = [0.0f32; 301];
                    simplex2_row_at::<true>(simd, s, origin, step, k, &mut fast);
                    simplex2_row_at::<false>(simd, s, origin, step, k, &mut slow);
                    for (m, (f, l)) in fast.iter().zip(&slow).enumerate() {
                        assert_eq!(
                            f.to_bits(),
                            l.to_bits(),
                            "{simd:?} step {step} {origin} lane {m}"
                        );
                    }
                }
            }
        }
    }
}
