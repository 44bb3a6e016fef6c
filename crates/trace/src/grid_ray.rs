//! A ray in grid space: clipped to the field's box, with the constants of the
//! watertight ray–triangle test and the rounding margins the culls use.
//!
//! Grid space scales x and y by `1/cell_size` and keeps z, so sample `(i, j)`
//! sits at `(i, j, h)`, cell bounds are exact integers (as the source notes,
//! seed 000 line 1322) and the ray parameter `t` is unchanged.

use glam::{Vec2, Vec3};

use crate::field::FieldView;
use crate::leaf::{fmax, fmin};
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

    /// A placeholder for batch slots whose ray is not traced.
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
