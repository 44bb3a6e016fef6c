//! A ray in grid space: clipped to the field's box, with the constants of the
//! watertight ray–triangle test and the rounding margins the culls use.
//!
//! Grid space scales x and y by `1/cell_size` and keeps z, so sample `(i, j)`
//! sits at `(i, j, h)`, cell bounds are exact integers (as the source notes,
//! Musgrave 1993, §3.3.2) and the ray parameter `t` is unchanged.

use glam::{Vec2, Vec3};

use crate::field::FieldView;
use crate::float::{cell_of, fmax, fmin};
use crate::ray::Ray;

/// Per-ray constants of Woop, Benthin & Wald's watertight test (JCGT 2013):
/// the shear that maps the ray to the +z axis, as three row vectors so that a
/// vertex transforms by dot products without indexing. Each row has one
/// coefficient 1 (or `1/d[kz]`), one shear and one exact zero, so the results
/// equal the paper's `A[kx] − Sx·A[kz]` bit for bit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shear {
    pub px: Vec3,
    pub py: Vec3,
    pub pz: Vec3,
}

impl Shear {
    fn new(d: Vec3) -> Self {
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        // Plain arrays: indices below 3 need no checks (glam's `Index` does).
        let d = d.to_array();
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let (sx, sy, sz) = (d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
        let mut px = [0.0; 3];
        px[kx] = 1.0;
        px[kz] = -sx;
        let mut py = [0.0; 3];
        py[ky] = 1.0;
        py[kz] = -sy;
        let mut pz = [0.0; 3];
        pz[kz] = sz;
        Self {
            px: Vec3::from_array(px),
            py: Vec3::from_array(py),
            pz: Vec3::from_array(pz),
        }
    }
}

/// A validated ray in grid space, clipped to the field's bounding box.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GridRay {
    /// Origin and direction in grid space.
    pub o: Vec3,
    pub d: Vec3,
    /// `1/d.x`, `1/d.y`; only meaningful where the component is non-zero.
    pub inv: Vec2,
    /// The caller's `t` range.
    pub t_min: f32,
    pub t_max: f32,
    /// The part of `[t_min, t_max]` inside the (slightly padded) box.
    pub t0: f32,
    pub t1: f32,
    /// Bound on the rounding error of any ray altitude `o.z + t·d.z` in the box,
    /// and of the corner heights relative to it: the culls widen by this.
    #[allow(dead_code)]
    pub zeps: f32,
    /// Bound on the rounding error of projected coordinates in the watertight
    /// test and of the traversal's xy positions: where the ray passes within
    /// this of a cell edge or corner, the tracers also test the cells across
    /// it, so a hit the traversal rounded past is still found (no pinholes).
    pub xyeps: f32,
    /// `xyeps` as a parameter span along the ray (infinite for vertical rays).
    pub ttol: f32,
    /// Margin of every z cull: the altitude rounding bound plus how far the
    /// surface can rise within `2·xyeps` of a cell (hits just across a cell
    /// edge or corner are looked for from the near cell, so its cull must
    /// let them through).
    pub zm: f32,
    pub shear: Shear,
}

impl GridRay {
    /// Sets up `ray` over `[t_min, t_max]` against `f`; `None` if the ray is
    /// invalid (NaN, infinite, zero direction) or the range is empty or NaN.
    /// A ray that misses the field's box gets an empty clip: see [`GridRay::misses_box`].
    #[inline]
    pub fn new(f: &FieldView<'_>, ray: &Ray, t_min: f32, t_max: f32) -> Option<Self> {
        if t_min.is_nan() || t_max.is_nan() || t_min > t_max {
            return None;
        }
        let o = Vec3::new(ray.origin.x / f.cell, ray.origin.y / f.cell, ray.origin.z);
        let d = Vec3::new(ray.dir.x / f.cell, ray.dir.y / f.cell, ray.dir.z);
        // `v·0` is ±0 for finite `v` and NaN otherwise, so this is
        // `is_finite` of both in three vector operations; it also covers
        // `Ray::is_valid`: scaling by a finite positive cell keeps NaN and
        // infinity and maps zero to zero.
        if o * 0.0 + d * 0.0 != Vec3::ZERO || d == Vec3::ZERO {
            return None;
        }
        let eps = f32::EPSILON;
        let zabs = f.zabs;
        let zeps = 16.0 * eps * (o.z.abs() + zabs) + 1e-30;
        // Corners and traversal points have |p|₁ ≤ ncx + ncy + |z|; the projected
        // corners (v − o sheared) and the traversal's o + t·d round within a few
        // ulps of |o|₁ + |p|₁.
        let o1 = o.x.abs() + o.y.abs() + o.z.abs();
        let xyeps = 4.0 * eps * (o1 + f.nxy + zabs + 2.0);
        // Clip to the slabs. Nothing here is NaN (finite operands, non-zero
        // divisors), so the plain comparisons give `f32::min`/`max`'s results.
        let mut t0 = t_min;
        let mut t1 = t_max;
        let mut slab = |o: f32, d: f32, lo: f32, hi: f32| {
            if d == 0.0 {
                if o < lo || o > hi {
                    // Parallel to this slab and outside it: an empty range.
                    t0 = f32::INFINITY;
                    t1 = f32::NEG_INFINITY;
                }
            } else {
                let a = (lo - o) / d;
                let b = (hi - o) / d;
                let (near, far) = if a < b { (a, b) } else { (b, a) };
                t0 = fmax(t0, near);
                t1 = fmin(t1, far);
            }
        };
        slab(o.x, d.x, -xyeps, f.ncx as f32 + xyeps);
        slab(o.y, d.y, -xyeps, f.ncy as f32 + xyeps);
        slab(o.z, d.z, f.zmin - zeps, f.zmax + zeps);
        let inv = Vec2::new(1.0 / d.x, 1.0 / d.y);
        let dxy = fmax(d.x.abs(), d.y.abs());
        let ttol = if dxy > 0.0 {
            xyeps / dxy
        } else {
            f32::INFINITY
        };
        Some(Self {
            o,
            d,
            inv,
            t_min,
            t_max,
            t0,
            t1,
            zeps,
            xyeps,
            ttol,
            zm: zeps + 2.0 * f.smax * xyeps,
            shear: Shear::new(d),
        })
    }

    /// A placeholder for batch slots whose ray is not traced (tests).
    #[cfg(test)]
    pub fn idle() -> Self {
        Self {
            o: Vec3::ZERO,
            d: Vec3::Z,
            inv: Vec2::ZERO,
            t_min: 0.0,
            t_max: 0.0,
            t0: f32::INFINITY,
            t1: f32::NEG_INFINITY,
            zeps: 0.0,
            xyeps: 0.0,
            ttol: 0.0,
            zm: 0.0,
            shear: Shear::new(Vec3::Z),
        }
    }

    /// Whether the clipped range is empty (the ray misses the box within `[t_min, t_max]`).
    #[inline]
    pub fn misses_box(&self) -> bool {
        !matches!(
            self.t0.partial_cmp(&self.t1),
            Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
        )
    }

    /// The cell holding the clipped entry point, clamped to the grid.
    #[inline]
    pub fn entry_cell(&self, f: &FieldView<'_>) -> (u32, u32) {
        Self::cell_of(self.o + self.t0 * self.d, f)
    }

    /// The cell holding the clipped exit point, clamped to the grid.
    #[inline]
    pub fn exit_cell(&self, f: &FieldView<'_>) -> (u32, u32) {
        Self::cell_of(self.o + self.t1 * self.d, f)
    }

    /// The cell holding grid point `p`, clamped to the grid. `max(0)` then
    /// truncation is `floor(·).max(0)` (and NaN goes to 0 either way: the
    /// comparison picks 0, the conversion saturates), without a library call
    /// on targets lacking a rounding instruction.
    #[inline(always)]
    fn cell_of(p: Vec3, f: &FieldView<'_>) -> (u32, u32) {
        let i = (fmax(p.x, 0.0) as u32).min(f.ncx - 1);
        let j = (fmax(p.y, 0.0) as u32).min(f.ncy - 1);
        (i, j)
    }

    /// Ray altitude at `t`.
    #[inline(always)]
    pub fn z_at(&self, t: f32) -> f32 {
        self.o.z + t * self.d.z
    }
}

/// Rays set up together by [`setup_lanes`].
pub(crate) const SETUP_LANES: usize = 16;

/// The set-up of [`SETUP_LANES`] rays, struct-of-arrays: each field is the
/// [`GridRay`] field of the same name for every lane, plus the walk's start
/// ([`crate::MipmapTracer`]'s entry cell and level).
#[derive(Clone, Copy, Default)]
pub(crate) struct SetupLanes {
    /// The ray is valid and meets the box within its range (`setup` is `Some`).
    pub ok: [bool; SETUP_LANES],
    pub o: [[f32; SETUP_LANES]; 3],
    pub d: [[f32; SETUP_LANES]; 3],
    pub inv: [[f32; SETUP_LANES]; 2],
    pub t0: [f32; SETUP_LANES],
    pub t1: [f32; SETUP_LANES],
    pub zeps: [f32; SETUP_LANES],
    pub xyeps: [f32; SETUP_LANES],
    pub ttol: [f32; SETUP_LANES],
    pub zm: [f32; SETUP_LANES],
    pub px: [[f32; SETUP_LANES]; 3],
    pub py: [[f32; SETUP_LANES]; 3],
    pub pz: [[f32; SETUP_LANES]; 3],
    /// Entry cell and start level of the hierarchical walk.
    pub ci: [u32; SETUP_LANES],
    pub cj: [u32; SETUP_LANES],
    pub level: [u32; SETUP_LANES],
    /// The lane walk's altitude, climb and margin in the pyramid's
    /// quantised units, and the direction's sign bits (as `Lanes::load`
    /// computes them one ray at a time), set by the lane pre-descent.
    pub oq: [f32; SETUP_LANES],
    pub dq: [f32; SETUP_LANES],
    pub mq: [f32; SETUP_LANES],
    pub sign: [u32; SETUP_LANES],
}

impl SetupLanes {
    /// All zero (every lane not `ok`).
    pub fn new() -> Self {
        Self::default()
    }

    /// Lane `l`'s ray, as [`GridRay::new`] would set it up over `[t_min, t_max]`.
    #[inline(always)]
    pub fn ray(&self, l: usize, t_min: f32, t_max: f32) -> GridRay {
        let v = |a: &[[f32; SETUP_LANES]; 3]| Vec3::new(a[0][l], a[1][l], a[2][l]);
        GridRay {
            o: v(&self.o),
            d: v(&self.d),
            inv: Vec2::new(self.inv[0][l], self.inv[1][l]),
            t_min,
            t_max,
            t0: self.t0[l],
            t1: self.t1[l],
            zeps: self.zeps[l],
            xyeps: self.xyeps[l],
            ttol: self.ttol[l],
            zm: self.zm[l],
            shear: Shear {
                px: v(&self.px),
                py: v(&self.py),
                pz: v(&self.pz),
            },
        }
    }
}

/// [`GridRay::new`], the box test and the walk's start cell and level
/// ([`crate::MipmapTracer`]'s `start`) for [`SETUP_LANES`] rays at once,
/// written without data-dependent branches so that the loop over lanes
/// vectorises (one vector division per quotient for all lanes). Every lane
/// computes the same `f32` operations in the same order as the single-ray
/// set-up, so the results are equal bit for bit (tested). The range must be
/// valid (not NaN, `t_min ≤ t_max`); `top` is the pyramid's top level.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
pub(crate) fn setup_lanes(
    f: &FieldView<'_>,
    rays: &[Ray; SETUP_LANES],
    t_min: f32,
    t_max: f32,
    top: u32,
    s: &mut SetupLanes,
) {
    let mut ro = [[0.0f32; SETUP_LANES]; 3];
    let mut rd = [[0.0f32; SETUP_LANES]; 3];
    for l in 0..SETUP_LANES {
        let (o, d) = (rays[l].origin, rays[l].dir);
        ro[0][l] = o.x;
        ro[1][l] = o.y;
        ro[2][l] = o.z;
        rd[0][l] = d.x;
        rd[1][l] = d.y;
        rd[2][l] = d.z;
    }
    let eps = f32::EPSILON;
    let (cell, zabs, nxy, smax) = (f.cell, f.zabs, f.nxy, f.smax);
    let (ncx, ncy) = (f.ncx as f32, f.ncy as f32);
    let (cx, cy) = ((f.ncx - 1) as f32, (f.ncy - 1) as f32);
    let (zlo, zhi) = (f.zmin, f.zmax);
    for l in 0..SETUP_LANES {
        let o = [ro[0][l] / cell, ro[1][l] / cell, ro[2][l]];
        let d = [rd[0][l] / cell, rd[1][l] / cell, rd[2][l]];
        let finite = (o[0] * 0.0 + d[0] * 0.0 == 0.0)
            & (o[1] * 0.0 + d[1] * 0.0 == 0.0)
            & (o[2] * 0.0 + d[2] * 0.0 == 0.0);
        let zero = (d[0] == 0.0) & (d[1] == 0.0) & (d[2] == 0.0);
        let zeps = 16.0 * eps * (o[2].abs() + zabs) + 1e-30;
        let o1 = o[0].abs() + o[1].abs() + o[2].abs();
        let xyeps = 4.0 * eps * (o1 + nxy + zabs + 2.0);
        // The slabs, as in `GridRay::new`, with both outcomes computed.
        let mut t0 = t_min;
        let mut t1 = t_max;
        let bounds = [
            (-xyeps, ncx + xyeps),
            (-xyeps, ncy + xyeps),
            (zlo - zeps, zhi + zeps),
        ];
        for k in 0..3 {
            let (lo, hi) = bounds[k];
            let (o, d) = (o[k], d[k]);
            let a = (lo - o) / d;
            let b = (hi - o) / d;
            let (near, far) = if a < b { (a, b) } else { (b, a) };
            let outside = (o < lo) | (o > hi);
            let flat = d == 0.0;
            t0 = if flat {
                if outside { f32::INFINITY } else { t0 }
            } else {
                fmax(t0, near)
            };
            t1 = if flat {
                if outside { f32::NEG_INFINITY } else { t1 }
            } else {
                fmin(t1, far)
            };
        }
        let dxy = fmax(d[0].abs(), d[1].abs());
        let ttol = if dxy > 0.0 {
            xyeps / dxy
        } else {
            f32::INFINITY
        };
        // The shear (`Shear::new`): the axis of the largest |d| is z, the
        // other two follow cyclically, swapped when d[kz] < 0.
        let a = [d[0].abs(), d[1].abs(), d[2].abs()];
        let kz: u32 = if a[0] >= a[1] && a[0] >= a[2] {
            0
        } else if a[1] >= a[2] {
            1
        } else {
            2
        };
        let dkz = if kz == 0 {
            d[0]
        } else if kz == 1 {
            d[1]
        } else {
            d[2]
        };
        let (kx0, dx0) = if kz == 0 {
            (1, d[1])
        } else if kz == 1 {
            (2, d[2])
        } else {
            (0, d[0])
        };
        let (ky0, dy0) = if kz == 0 {
            (2, d[2])
        } else if kz == 1 {
            (0, d[0])
        } else {
            (1, d[1])
        };
        let neg = dkz < 0.0;
        let (kx, dkx) = if neg { (ky0, dy0) } else { (kx0, dx0) };
        let (ky, dky) = if neg { (kx0, dx0) } else { (ky0, dy0) };
        let (sx, sy, sz) = (dkx / dkz, dky / dkz, 1.0 / dkz);
        for c in 0..3u32 {
            let cz = c == kz;
            s.px[c as usize][l] = if c == kx {
                1.0
            } else if cz {
                -sx
            } else {
                0.0
            };
            s.py[c as usize][l] = if c == ky {
                1.0
            } else if cz {
                -sy
            } else {
                0.0
            };
            s.pz[c as usize][l] = if cz { sz } else { 0.0 };
        }
        // The walk's start: entry and exit cells (`GridRay::cell_of`: clamping
        // before the truncation is the same, the bounds being whole numbers)
        // and the finest level holding both.
        let (ci, cj, level) = walk_start([o[0], o[1]], [d[0], d[1]], t0, t1, [cx, cy], top);
        s.ok[l] = finite & !zero & (t0 <= t1);
        for k in 0..3 {
            s.o[k][l] = o[k];
            s.d[k][l] = d[k];
        }
        s.inv[0][l] = 1.0 / d[0];
        s.inv[1][l] = 1.0 / d[1];
        s.t0[l] = t0;
        s.t1[l] = t1;
        s.zeps[l] = zeps;
        s.xyeps[l] = xyeps;
        s.ttol[l] = ttol;
        s.zm[l] = zeps + 2.0 * smax * xyeps;
        s.ci[l] = ci;
        s.cj[l] = cj;
        s.level[l] = level;
    }
}

/// The walk's start for a ray `o + t·d` (grid space, `x`, `y`) clipped to
/// `[t0, t1]`: the entry cell, clamped to `[0, hi]` per axis
/// (`GridRay::cell_of`: clamping before the truncation is the same, the
/// bounds being whole numbers), and the finest pyramid level (at most
/// `top`) whose node holds both the entry and the exit cell. Shared by the
/// lane set-up and the packet skip, so a walk started later is set up
/// exactly as the set-up would have set it up.
#[inline(always)]
pub(crate) fn walk_start(
    o: [f32; 2],
    d: [f32; 2],
    t0: f32,
    t1: f32,
    hi: [f32; 2],
    top: u32,
) -> (u32, u32, u32) {
    // `v` is in `[0, 2²⁴)` (NaN goes to 0).
    let cell_of = |t: f32, k: usize| -> u32 { cell_of(o[k] + t * d[k], hi[k]) };
    let (ci, cj) = (cell_of(t0, 0), cell_of(t0, 1));
    let (ei, ej) = (cell_of(t1, 0), cell_of(t1, 1));
    let spread = (ci ^ ei) | (cj ^ ej);
    // Bit length of `spread` (< 2²⁴, exact in f32) from its exponent.
    let bits = if spread == 0 {
        0
    } else {
        ((spread as i32 as f32).to_bits() >> 23) - 126
    };
    (ci, cj, bits.min(top))
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::{HeightField, Seed};

    /// The clip as first written (`f32::min`/`max`, the validity checks in
    /// full), kept as the reference for the streamlined set-up.
    fn reference_clip(f: &FieldView<'_>, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
        if !ray.is_valid() || t_min.is_nan() || t_max.is_nan() || t_min > t_max {
            return None;
        }
        let o = Vec3::new(ray.origin.x / f.cell, ray.origin.y / f.cell, ray.origin.z);
        let d = Vec3::new(ray.dir.x / f.cell, ray.dir.y / f.cell, ray.dir.z);
        if !(o.is_finite() && d.is_finite()) || d == Vec3::ZERO {
            return None;
        }
        let eps = f32::EPSILON;
        let zabs = f.zmin.abs().max(f.zmax.abs());
        let zeps = 16.0 * eps * (o.z.abs() + zabs) + 1e-30;
        let o1 = o.x.abs() + o.y.abs() + o.z.abs();
        let xyeps = 4.0 * eps * (o1 + (f.ncx + f.ncy) as f32 + zabs + 2.0);
        let lo = [-xyeps, -xyeps, f.zmin - zeps];
        let hi = [f.ncx as f32 + xyeps, f.ncy as f32 + xyeps, f.zmax + zeps];
        let (o, d) = (o.to_array(), d.to_array());
        let (mut t0, mut t1) = (t_min, t_max);
        for k in 0..3 {
            if d[k] == 0.0 {
                if o[k] < lo[k] || o[k] > hi[k] {
                    t0 = f32::INFINITY;
                    t1 = f32::NEG_INFINITY;
                }
            } else {
                let a = (lo[k] - o[k]) / d[k];
                let b = (hi[k] - o[k]) / d[k];
                t0 = t0.max(a.min(b));
                t1 = t1.min(a.max(b));
            }
        }
        Some((t0, t1))
    }

    /// The set-up accepts and refuses exactly the rays and ranges the
    /// reference does and clips them to the same `t` range, bit for bit:
    /// random rays, axis-parallel and vertical ones, zero, NaN and infinite
    /// components, huge coordinates, empty and infinite ranges.
    #[test]
    fn set_up_equals_the_reference_clip() {
        let s = Seed(5);
        let hf = HeightField::from_fn(37, 21, 2.5, |i, j| {
            30.0 * s.uniform2(i as i64, j as i64) as f32 - 4.0
        })
        .unwrap();
        let f = FieldView::new(&hf).unwrap();
        let specials = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::NAN,
            f32::INFINITY,
            1e30,
            -3e38,
            1e-30,
        ];
        let mut n = 0;
        for k in 0..20_000i64 {
            let u = |c: i64| s.uniform2(k, c) as f32;
            let pick = |c: i64, scale: f32, off: f32| {
                if u(c + 50) < 0.08 {
                    specials[(u(c + 90) * specials.len() as f32) as usize % specials.len()]
                } else {
                    scale * u(c) + off
                }
            };
            let o = Vec3::new(
                pick(0, 140.0, -25.0),
                pick(1, 90.0, -20.0),
                pick(2, 60.0, -15.0),
            );
            let mut d = Vec3::new(pick(3, 2.0, -1.0), pick(4, 2.0, -1.0), pick(5, 2.0, -1.0));
            match k % 5 {
                0 => d.x = 0.0,
                1 => d.y = 0.0,
                2 => d = Vec3::new(0.0, 0.0, d.z),
                _ => {}
            }
            let (t_min, t_max) = match k % 7 {
                0 => (0.0, f32::INFINITY),
                1 => (f32::NEG_INFINITY, f32::INFINITY),
                2 => (5.0, 1.0),
                3 => (f32::NAN, 1.0),
                _ => (pick(6, 40.0, -10.0), pick(7, 200.0, 0.0)),
            };
            let ray = Ray::new(o, d);
            let want = reference_clip(&f, &ray, t_min, t_max);
            let got = GridRay::new(&f, &ray, t_min, t_max).map(|r| (r.t0, r.t1));
            let bits = |c: Option<(f32, f32)>| c.map(|(a, b)| (a.to_bits(), b.to_bits()));
            assert_eq!(bits(got), bits(want), "{ray:?} over [{t_min}, {t_max}]");
            n += usize::from(want.is_some_and(|(a, b)| a <= b));
        }
        assert!(n > 3000, "{n} rays meet the box");
    }
}
