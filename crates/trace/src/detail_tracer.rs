//! Tracing the height field with procedural detail down to the pixel
//! footprint: the maximum mipmap with every node's `[min, max]` widened by
//! the detail's amplitude bound, then Lipschitz-bounded marching inside the
//! cells it cannot rule out, ending in a bracketed root-finder.
//!
//! The surface is [`DetailSurface`]'s `S = B + m·D(·; w)` with the footprint
//! `w` growing along the ray ([`RayCone`]). Where `w` reaches the first
//! octave's Nyquist limit no detail is left, so from there on the ray is
//! handed to the plain [`MipmapTracer`]: the far field is traced exactly as
//! without detail. Before that, a node of the pyramid (or a cell) is skipped
//! when the ray's altitude span over it misses `[min − A, max + A]`, `A` the
//! detail's amplitude bound at the node's nearest footprint (Tevs et al.
//! 2008 for the pyramid walk); a node's children are visited in the order
//! the ray meets them, found from where it crosses the node's two midlines
//! (Revelles et al. 2000's order, in two dimensions). In a surviving cell the signed gap
//! `g(t) = z(t) − S` is marched with steps `g / (L·|d_xy| + F − d_z)`:
//! `L` bounds the slope of `S` in the cell (the two triangles' and the
//! detail's Lipschitz bounds), `F` the change of `S` with the footprint, so
//! a step never crosses the surface (the Lipschitz step of Hart 1996 applied to a height field).
//! The octaves are evaluated from the coarsest on only until the amplitude
//! left in the finer ones cannot close the gap that remains: the step then
//! uses the gap to that narrower shell and the slope of the octaves
//! evaluated, so far above the surface no noise is evaluated at all (the
//! shell `B ± A`, the triangles' slope alone) and near it the fine octaves'
//! large slopes shorten only the last steps.
//! The mask `m` scales each bound by its greatest value over the node
//! (a max pyramid of the mask beside the heights') or the cell (its
//! corners), so nodes under water cull on their bare heights; a cell bare
//! at every corner is the height field's two planes, whose crossing is
//! solved exactly instead of marched.
//! The bound is loose (the actual slope is mostly a fraction of `L`), so a
//! step reaches 1.3 times what the bound clears (the
//! over-relaxation of Keinert et al. 2014): the bound read backward from
//! where the step lands must cover what the forward bound left, or the march
//! goes back and continues without relaxing. Each step also reaches a
//! quarter of the footprint past the cleared stretch (no less than a
//! quarter footprint in all); where one lands below the surface a bracketed
//! regula falsi finds the crossing. A feature thinner than a quarter of a
//! pixel's footprint along the ray can therefore be stepped over; none
//! thicker is: no stretch a quarter of the footprint long is left unchecked.

use glam::{DVec2, DVec3, UVec2, Vec3};
use natura_core::HeightField;

use crate::detail::{DetailSurface, RayCone, add_gradient};
use crate::error::{Result, TraceError};
use crate::max_mipmap::MipmapTracer;
use crate::ray::{Hit, Ray, TraceStats, Triangle};
use crate::ray_cell::{CellHit, make_hit};
use crate::surface::{cell_at, cell_plane_height, surface_height};
use crate::tracer::Tracer;

/// How far a march step reaches, in multiples of what its Lipschitz bound
/// clears (Keinert et al. 2014). 1.3 took the fewest evaluations on the
/// grazing benchmark view among 1.3, 1.5 and 2.0 (larger factors fail their
/// check more often, and each failure costs an evaluation).
const OMEGA: f64 = 1.3;

/// Smallest march step, as a fraction of the footprint.
const MIN_STEP_FOOTPRINTS: f64 = 0.25;

/// The march stops evaluating octaves once the gap left exceeds this multiple
/// of the finer octaves' amplitude bound.
const STOP_REST: f64 = 2.0;

/// The closing root-finder stops when the bracket is this fraction of the footprint.
const CLOSE_FOOTPRINTS: f64 = 1e-3;

/// A tracer of a height field with procedural detail (see the module docs).
#[derive(Clone, Debug)]
pub struct DetailTracer<'a> {
    base: MipmapTracer<'a>,
    surface: DetailSurface<'a>,
    footprint: RayCone,
}

/// A ray in `f64` with what the walk needs.
struct WalkRay {
    o: DVec3,
    d: DVec3,
    /// `|d|`: footprints grow with distance, not with `t`.
    len: f64,
    /// `|d_xy|`.
    dxy: f64,
    /// `1/d_x`, `1/d_y` (for the slabs).
    inv: DVec2,
    /// `1/d_z` (for the altitude slabs).
    inv_z: f64,
    fp: RayCone,
    /// `+1` if the ray starts above the surface, `−1` below.
    side: f64,
}

/// A cell of the field as the walk read it: its index, its corners'
/// heights and its mask's corner values (in [`FieldView::corners`] order),
/// and the largest of those.
///
/// [`FieldView::corners`]: crate::field::FieldView::corners
struct Cell {
    i: u32,
    j: u32,
    heights: [f32; 4],
    mask: [f32; 4],
    mask_max: f32,
}

impl WalkRay {
    #[inline]
    fn w(&self, t: f64) -> f64 {
        self.fp.at(t * self.len)
    }
}

impl<'a> DetailTracer<'a> {
    /// A tracer of `surface`; `footprint` is the footprint [`Tracer::trace`]
    /// uses (the camera's pixel cone for primary rays).
    ///
    /// # Errors
    ///
    /// Fails like [`MipmapTracer::new`] on a field that cannot be traced, and
    /// with [`TraceError::InvalidParameter`] if a footprint term is NaN,
    /// infinite or negative.
    pub fn new(surface: DetailSurface<'a>, footprint: RayCone) -> Result<Self> {
        check_footprint(footprint)?;
        Ok(Self {
            base: MipmapTracer::new(surface.height_field())?,
            surface,
            footprint,
        })
    }

    /// The surface traced.
    #[must_use]
    pub fn surface(&self) -> &DetailSurface<'a> {
        &self.surface
    }

    /// The plain tracer of the height field (the far field's).
    #[must_use]
    pub fn base(&self) -> &MipmapTracer<'a> {
        &self.base
    }

    /// The footprint [`Tracer::trace`] uses.
    #[must_use]
    pub fn footprint(&self) -> RayCone {
        self.footprint
    }

    /// Bytes of acceleration data (the base tracer's pyramid, the mask's).
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        self.base.memory_bytes() + self.surface.memory_bytes()
    }

    /// The ray parameter from which the footprint leaves no detail (∞ if never).
    fn t_far(&self, ray: &Ray, fp: RayCone) -> f64 {
        let far = self.surface.detail().far_footprint();
        let len = f64::from(ray.dir.length());
        let (w0, k) = (f64::from(fp.at_origin_m), f64::from(fp.per_metre));
        if w0 >= far {
            0.0
        } else if k > 0.0 {
            (far - w0) / (k * len)
        } else {
            f64::INFINITY
        }
    }

    /// The closest hit of `ray` with `t` in `[t_min, t_max]` on the surface
    /// with footprint `fp` along the ray.
    ///
    /// The hit's `point` is on the detailed surface and its normals are the
    /// height field's tilted by the detail's gradient at the hit's footprint;
    /// `cell`, `triangle` and `barycentric` locate it over the height field.
    /// Invalid rays, empty ranges and invalid footprints hit nothing.
    #[must_use]
    pub fn trace_footprint(&self, ray: &Ray, t_min: f32, t_max: f32, fp: RayCone) -> Option<Hit> {
        if !self.surface.detail().is_active() {
            return self.base.trace(ray, t_min, t_max);
        }
        if !ray.is_valid() || t_min.is_nan() || t_max.is_nan() || t_min > t_max {
            return None;
        }
        check_footprint(fp).ok()?;
        let t_far = self.t_far(ray, fp);
        if t_far <= f64::from(t_min) {
            return self.base.trace(ray, t_min, t_max);
        }
        let end = t_far.min(f64::from(t_max));
        if let Some((t, w)) = self.walk(ray, f64::from(t_min), end, fp) {
            return Some(self.make_hit(ray, t, w));
        }
        if t_far < f64::from(t_max) {
            return self.base.trace(ray, t_far as f32, t_max);
        }
        None
    }

    /// Whether anything lies on `ray` with `t` in `[t_min, t_max]` with
    /// footprint `fp` (a shadow ray).
    #[must_use]
    pub fn occluded_footprint(&self, ray: &Ray, t_min: f32, t_max: f32, fp: RayCone) -> bool {
        if !self.surface.detail().is_active() {
            return self.base.occluded(ray, t_min, t_max);
        }
        if !ray.is_valid() || t_min.is_nan() || t_max.is_nan() || t_min > t_max {
            return false;
        }
        if check_footprint(fp).is_err() {
            return false;
        }
        // As `trace_footprint`, without the hit record: the first crossing is enough.
        let t_far = self.t_far(ray, fp);
        if t_far <= f64::from(t_min) {
            return self.base.occluded(ray, t_min, t_max);
        }
        let end = t_far.min(f64::from(t_max));
        if self.walk(ray, f64::from(t_min), end, fp).is_some() {
            return true;
        }
        t_far < f64::from(t_max) && self.base.occluded(ray, t_far as f32, t_max)
    }

    /// `g(t)`: the ray's height above the surface at `t` (the point clamped
    /// into the field).
    #[inline]
    fn gap(&self, r: &WalkRay, t: f64) -> f64 {
        let (p, x, y) = self.at(r, t);
        let s = self.surface.height(x, y, r.w(t)).unwrap_or(f64::NAN);
        p.z - s
    }

    /// The ray's point at `t`, and its `(x, y)` clamped into the field
    /// (where the surface is read).
    #[inline]
    fn at(&self, r: &WalkRay, t: f64) -> (DVec3, f32, f32) {
        let p = r.o + t * r.d;
        let e = self.surface.height_field().extent();
        (
            p,
            (p.x as f32).clamp(0.0, e.x),
            (p.y as f32).clamp(0.0, e.y),
        )
    }

    /// The first crossing of the surface over `[t0, t1]` in the detail
    /// region: `(t, footprint there)`.
    fn walk(&self, ray: &Ray, t0: f64, t1: f64, fp: RayCone) -> Option<(f64, f64)> {
        let hf = self.surface.height_field();
        let d = ray.dir.as_dvec3();
        let mut r = WalkRay {
            o: ray.origin.as_dvec3(),
            d,
            len: d.length(),
            dxy: d.truncate().length(),
            inv: DVec2::ONE / d.truncate(),
            inv_z: 1.0 / d.z,
            fp,
            side: 1.0,
        };
        let e = hf.extent().as_dvec2();
        let (ta, tb) = slab(&r, DVec2::ZERO, e, t0, t1)?;
        let g = self.gap(&r, ta);
        if !g.is_finite() {
            return None;
        }
        r.side = if g >= 0.0 { 1.0 } else { -1.0 };
        let mip = self.base.mipmap();
        self.node(&r, mip.top_level(), 0, 0, ta, tb)
            .map(|t| (t, r.w(t)))
    }

    /// Node `(a, b)` of level `k` (level 0: cells) over `[t0, t1]`.
    fn node(&self, r: &WalkRay, k: u32, a: u32, b: u32, t0: f64, t1: f64) -> Option<f64> {
        let f = &self.base.f;
        // A cell's corners (heights and mask), read once for the test and
        // the march.
        let cell = (k == 0).then(|| {
            let m = self.surface.mask_corners(a, b);
            Cell {
                i: a,
                j: b,
                heights: f.corners(a, b),
                mask: m,
                mask_max: m[0].max(m[1]).max(m[2].max(m[3])),
            }
        });
        let (lo, hi, mask) = if let Some(c) = &cell {
            let h = c.heights;
            (
                h[0].min(h[1]).min(h[2].min(h[3])),
                h[0].max(h[1]).max(h[2].max(h[3])),
                c.mask_max,
            )
        } else {
            let (lo, hi) = self.base.mipmap().node_range(k, a, b)?;
            (lo, hi, self.surface.mask_max_node(k, a, b))
        };
        // The footprint is smallest (the detail largest) where the ray
        // enters; the mask scales it (a node under water has none).
        let amp = if mask == 0.0 {
            0.0
        } else {
            f64::from(mask) * self.surface.amplitude_bound(r.w(t0))
        };
        let (za, zb) = (r.o.z + t0 * r.d.z, r.o.z + t1 * r.d.z);
        let m = 1e-4 * (1.0 + za.abs().max(zb.abs()));
        let (zlo, zhi) = (f64::from(lo) - amp - m, f64::from(hi) + amp + m);
        if za.max(zb) < zlo || za.min(zb) > zhi {
            return None;
        }
        // Only where the ray's altitude is within the node's shell can it
        // meet the surface: the children and the march see that stretch.
        // (The test above rejects what this would empty, more cheaply: the
        // main job took 1–2 % longer with this alone.)
        let (t0, t1) = if r.d.z == 0.0 {
            (t0, t1)
        } else {
            let (ta, tb) = ((zlo - r.o.z) * r.inv_z, (zhi - r.o.z) * r.inv_z);
            (t0.max(ta.min(tb)), t1.min(ta.max(tb)))
        };
        if t0 > t1 {
            return None;
        }
        if let Some(cell) = cell {
            return self.march(r, &cell, t0, t1);
        }
        let (cw, ch) = if k == 1 {
            (f.ncx, f.ncy)
        } else {
            self.base.mipmap().level_dims(k - 1)?
        };
        let size = f64::from(f.cell) * f64::from(1u32 << (k - 1));
        // The children in the order the ray meets them: it starts on one
        // side of each of the node's two midlines and changes side where it
        // crosses one inside `[t0, t1]` (Revelles et al. 2000's order for
        // an octree, here a quadtree).
        let side = |o: f64, d: f64, inv: f64, mid: f64| -> (u32, f64) {
            if d == 0.0 {
                return (u32::from(o >= mid), f64::INFINITY);
            }
            let tm = (mid - o) * inv;
            let start_high = if d > 0.0 { tm <= t0 } else { tm > t0 };
            let cross = if tm > t0 && tm < t1 {
                tm
            } else {
                f64::INFINITY
            };
            (u32::from(start_high), cross)
        };
        let (mut sx, tx) = side(r.o.x, r.d.x, r.inv.x, f64::from(2 * a + 1) * size);
        let (mut sy, ty) = side(r.o.y, r.d.y, r.inv.y, f64::from(2 * b + 1) * size);
        let (first, second, x_first) = if tx <= ty {
            (tx, ty, true)
        } else {
            (ty, tx, false)
        };
        let mut s0 = t0;
        for (n, e) in [first, second, t1].into_iter().enumerate() {
            let e = e.min(t1);
            let (ca, cb) = (2 * a + sx, 2 * b + sy);
            if ca < cw
                && cb < ch
                && let Some(t) = self.node(r, k - 1, ca, cb, s0, e)
            {
                return Some(t);
            }
            if e >= t1 {
                return None;
            }
            s0 = e;
            if (n == 0) == x_first {
                sx ^= 1;
            } else {
                sy ^= 1;
            }
        }
        None
    }

    /// The Lipschitz march over `cell` for `t` in `[t0, t1]`.
    fn march(&self, r: &WalkRay, cell: &Cell, t0: f64, t1: f64) -> Option<f64> {
        let &Cell {
            i,
            j,
            heights: c,
            mask: mc,
            mask_max,
        } = cell;
        let f = &self.base.f;
        let spacing = f64::from(f.cell);
        let slope = |a: f32, b: f32| {
            (f64::from(a) * f64::from(a) + f64::from(b) * f64::from(b)).sqrt() / spacing
        };
        let lb = slope(c[1] - c[0], c[2] - c[0]).max(slope(c[3] - c[2], c[3] - c[1]));
        // The mask over the cell: at most its greatest corner, and its
        // gradient at most √2 × its largest edge difference per cell.
        let m_max = f64::from(mask_max);
        if m_max == 0.0 {
            return self.bare(r, i, j, t0, t1);
        }
        let uniform = (mc[1] == mc[0] && mc[2] == mc[0] && mc[3] == mc[0]).then_some(mc[0]);
        let mask_lip = if uniform.is_some() {
            0.0
        } else {
            let d = (mc[1] - mc[0])
                .abs()
                .max((mc[2] - mc[0]).abs())
                .max((mc[3] - mc[1]).abs().max((mc[3] - mc[2]).abs()));
            std::f64::consts::SQRT_2 * f64::from(d) / spacing
        };
        let detail = self.surface.detail();
        let finest = detail.finest_footprint();
        let fw_per_w = f64::from(r.fp.per_metre) * r.len;
        let s = r.side;
        let hf = self.surface.height_field();
        let (mut t, mut t_prev) = (t0, t0);
        // Over-relaxation: whether the last step reached past its bound
        // (`relaxed`), where the bound ended, and the footprint and its
        // octave counts at the step's start.
        let mut omega = OMEGA;
        let mut relaxed = false;
        let (mut safe_end, mut prev_w, mut prev_whole) = (t0, 0.0f64, (0usize, 0usize));
        // The blended octave's change with the footprint along the ray, at
        // footprint `w` with octave counts `whole`, `k` octaves evaluated
        // (none: the triangles' slope alone).
        let footprint_change = |k: usize, w: f64, whole: (usize, usize)| {
            if k == 0 {
                0.0
            } else {
                m_max * detail.footprint_bound_whole(w, whole) * fw_per_w
            }
        };
        loop {
            let w = r.w(t);
            let (p, x, y) = self.at(r, t);
            let base = f64::from(cell_height(hf, &c, i, j, x, y));
            // The gap above the base surface, then the octaves from the
            // coarsest on until the ones left (bounded by their amplitudes)
            // cannot close what remains: `g` bounds `s·(z − S)` from below.
            // With none evaluated this is the gap to the shell `B ± A(w)`,
            // whose slope is the triangles' alone (`A` only shrinks along
            // the ray); with all of them it is the exact gap.
            // The octave count ⌈n⌉ (and ⌊n⌋), by comparisons where they
            // settle it; `n` itself, a logarithm (4 % of the main job's
            // time when taken at every step), only where they do not or
            // where the blended octave `⌈n⌉ − 1` is summed: every octave
            // below it has weight 1, which `top` gives as well.
            let (whole, mut exact) = detail.octave_count(w);
            let top = whole.0;
            let h = s * (p.z - base);
            let m = f64::from(uniform.unwrap_or_else(|| self.surface.mask_at(x, y)));
            let q = DVec2::new(f64::from(x), f64::from(y));
            let (mut k, mut part) = (0, h);
            let g = loop {
                let rest = m_max * detail.amplitude_between(k, top);
                let g = part - rest;
                if k == top || g >= STOP_REST * rest {
                    break g;
                }
                if m != 0.0 {
                    // A whole `n` (all octaves, or none) is `top` itself.
                    let n = if k + 1 < top || whole.0 == whole.1 {
                        top as f64
                    } else {
                        *exact.get_or_insert_with(|| detail.octaves_at(w))
                    };
                    part -= s * m * detail.octave(k, n, q);
                }
                k += 1;
            };
            if !g.is_finite() {
                return None;
            }
            // The evaluated octaves' slope (and the mask's over all
            // octaves); none evaluated, the triangles' alone.
            let l = if k == 0 {
                lb
            } else {
                lb + m_max * detail.lipschitz_first(k) + detail.amplitude_between(0, top) * mask_lip
            };
            if relaxed {
                // The point was reached by a step longer than the bound at
                // `t_prev` allowed: `[safe_end, t]` is clear only if the
                // bound read backward from here covers it. Backward the
                // footprint shrinks to at most `t_prev`'s, so the octaves
                // not evaluated are bounded as there, and so is the
                // blended octave's change with the footprint.
                let gb = part - m_max * detail.amplitude_between(k, prev_whole.0.max(k));
                let db = l * r.dxy + footprint_change(k, prev_w, prev_whole) + s * r.d.z;
                let back = if gb <= 0.0 {
                    0.0
                } else if db <= 0.0 {
                    f64::INFINITY
                } else {
                    gb / db
                };
                let slack = MIN_STEP_FOOTPRINTS * r.w(safe_end).max(finest) / r.len;
                let clear = t - back - safe_end <= slack;
                if !clear {
                    // Back to where the bound reached, without relaxing again.
                    omega = 1.0;
                    relaxed = false;
                    t = (safe_end + slack).min(t1);
                    continue;
                }
            }
            if k == top && g <= 0.0 {
                return Some(if t == t0 {
                    t0
                } else {
                    self.close_in(r, t_prev, t, g)
                });
            }
            let denom = l * r.dxy + footprint_change(k, w, whole) - s * r.d.z;
            if t >= t1 || denom <= 0.0 {
                // At the cell's end, or `g` cannot shrink over the rest of it.
                return None;
            }
            // The bound clears `[t, t + safe)`; a step reaches a quarter
            // of the footprint past it (what the march may step over), or
            // `omega` times it, checked from where it lands.
            let safe = g.max(0.0) / denom;
            let plain = safe + MIN_STEP_FOOTPRINTS * w.max(finest) / r.len;
            relaxed = omega * safe > plain;
            safe_end = t + safe;
            (prev_w, prev_whole) = (w, whole);
            let step = (omega * safe).max(plain);
            t_prev = t;
            t = (t + step).min(t1);
        }
    }

    /// The first crossing of cell `(i, j)` over `[t0, t1]` where the mask
    /// is 0 at every corner, so the surface there is the bare height
    /// field: the two triangles are planes, the gap is linear along the
    /// ray on each side of the diagonal, and its root is found exactly
    /// (no march). The gap is read as the march reads it, so a ray
    /// already below the surface where it enters is hit there.
    fn bare(&self, r: &WalkRay, i: u32, j: u32, t0: f64, t1: f64) -> Option<f64> {
        let hf = self.surface.height_field();
        let gap = |t: f64| {
            let (p, x, y) = self.at(r, t);
            r.side * (p.z - f64::from(surface_height(hf, x, y).unwrap_or(f32::NAN)))
        };
        // Where the ray crosses the diagonal `u + v = 1`, if inside.
        let cell = f64::from(self.base.f.cell);
        let along = r.d.x + r.d.y;
        let tc = (f64::from(i + j + 1) * cell - r.o.x - r.o.y) / along;
        let ends = if tc > t0 && tc < t1 {
            [t0, tc, t1]
        } else {
            [t0, t1, t1]
        };
        let (mut ta, mut ga) = (t0, gap(t0));
        if !ga.is_finite() {
            return None;
        }
        if ga <= 0.0 {
            return Some(t0);
        }
        for &tb in &ends[1..] {
            if tb <= ta {
                continue;
            }
            let gb = gap(tb);
            if !gb.is_finite() {
                return None;
            }
            if gb <= 0.0 {
                return Some((ta + ga / (ga - gb) * (tb - ta)).clamp(ta, tb));
            }
            (ta, ga) = (tb, gb);
        }
        None
    }

    /// The crossing in `(lo, hi]` where `s·g(lo) > 0 ≥ s·g(hi) = ghi`, to a
    /// thousandth of the footprint: regula falsi with the Illinois
    /// modification (Dowell & Jarratt 1971), which keeps the bracket of
    /// bisection but converges superlinearly on the smooth gap, so the hit
    /// costs a few evaluations of all octaves instead of a dozen.
    fn close_in(&self, r: &WalkRay, mut lo: f64, mut hi: f64, mut ghi: f64) -> f64 {
        let finest = self.surface.detail().finest_footprint();
        let mut glo = r.side * self.gap(r, lo);
        if !(glo > 0.0 && ghi <= 0.0) {
            // Not a proper bracket (the exact gap at `lo` is not positive):
            // `hi` is below the surface, and nothing better is known.
            return hi;
        }
        // Which end moved last: +1 `lo`, −1 `hi`, 0 neither.
        let mut last = 0i8;
        for _ in 0..48 {
            let span = hi - lo;
            if span * r.len <= CLOSE_FOOTPRINTS * r.w(hi).max(finest) {
                break;
            }
            // The secant's root, kept off the ends by a thousandth of the
            // bracket so the bracket always shrinks.
            let f = (glo / (glo - ghi)).clamp(1e-3, 1.0 - 1e-3);
            let mid = lo + f * span;
            let g = r.side * self.gap(r, mid);
            if !g.is_finite() {
                return hi;
            }
            if g > 0.0 {
                lo = mid;
                glo = g;
                if last == 1 {
                    ghi *= 0.5;
                }
                last = 1;
            } else {
                hi = mid;
                ghi = g;
                if last == -1 {
                    glo *= 0.5;
                }
                last = -1;
            }
        }
        hi
    }

    /// The hit record at `t` (footprint `w`).
    fn make_hit(&self, ray: &Ray, t: f64, w: f64) -> Hit {
        let f = &self.base.f;
        let tf = t as f32;
        let p = ray.at(tf);
        let (gx, gy) = (p.x / f.cell, p.y / f.cell);
        let i = (gx.floor().max(0.0) as u32).min(f.ncx - 1);
        let j = (gy.floor().max(0.0) as u32).min(f.ncy - 1);
        let (u, v) = (
            (gx - i as f32).clamp(0.0, 1.0),
            (gy - j as f32).clamp(0.0, 1.0),
        );
        let (triangle, bary) = if u + v <= 1.0 {
            (Triangle::Lower, Vec3::new(1.0 - u - v, u, v))
        } else {
            (Triangle::Upper, Vec3::new(u + v - 1.0, 1.0 - u, 1.0 - v))
        };
        let base = make_hit(
            f,
            ray,
            CellHit {
                t: tf,
                cell: (i, j),
                triangle,
                bary,
            },
        );
        let g = self.surface.detail_gradient(p.x, p.y, w);
        let geometric_normal = add_gradient(base.geometric_normal, g);
        Hit {
            t: tf,
            point: p,
            geometric_normal,
            smooth_normal: add_gradient(base.smooth_normal, g),
            cell: UVec2::new(i, j),
            triangle,
            barycentric: bary,
            from_above: ray.dir.dot(geometric_normal) < 0.0,
        }
    }
}

/// [`surface_height`] at `(x, y)` (inside the field) for a march in cell
/// `(i, j)` whose corners `c` (the field view's `corners`) are already
/// read: the same planes, so the same bits, without reading the heights
/// again. Where rounding puts the point in another cell, that cell's,
/// read by `surface_height`; NaN where it is `None`.
#[inline]
fn cell_height(hf: &HeightField, c: &[f32; 4], i: u32, j: u32, x: f32, y: f32) -> f32 {
    let (gi, gj, u, v) = cell_at(hf, x, y);
    if gi != i as usize || gj != j as usize || x.is_nan() || y.is_nan() {
        return surface_height(hf, x, y).unwrap_or(f32::NAN);
    }
    cell_plane_height(c, u, v)
}

/// The ray's `t` interval over the box `[lo, hi]` in x and y, within `[t0, t1]`.
fn slab(r: &WalkRay, lo: DVec2, hi: DVec2, t0: f64, t1: f64) -> Option<(f64, f64)> {
    let pad = 1e-7 * (1.0 + hi.x.abs().max(hi.y.abs()));
    let (mut a, mut b) = (t0, t1);
    for (o, d, inv, l, h) in [
        (r.o.x, r.d.x, r.inv.x, lo.x, hi.x),
        (r.o.y, r.d.y, r.inv.y, lo.y, hi.y),
    ] {
        let (l, h) = (l - pad, h + pad);
        if d == 0.0 {
            if o < l || o > h {
                return None;
            }
        } else {
            let (p, q) = ((l - o) * inv, (h - o) * inv);
            a = a.max(p.min(q));
            b = b.min(p.max(q));
        }
    }
    (a <= b).then_some((a, b))
}

fn check_footprint(fp: RayCone) -> Result<()> {
    for (name, v) in [
        ("footprint.at_origin_m", fp.at_origin_m),
        ("footprint.per_metre", fp.per_metre),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(TraceError::param(name, v, "finite and ≥ 0"));
        }
    }
    Ok(())
}

impl Tracer for DetailTracer<'_> {
    fn trace(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        self.trace_footprint(ray, t_min, t_max, self.footprint)
    }

    fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.occluded_footprint(ray, t_min, t_max, self.footprint)
    }

    /// The hit with empty counters (the march does not count its steps).
    fn trace_with_stats(&self, ray: &Ray, t_min: f32, t_max: f32) -> (Option<Hit>, TraceStats) {
        (self.trace(ray, t_min, t_max), TraceStats::default())
    }

    fn height_field(&self) -> &HeightField {
        self.surface.height_field()
    }

    fn trace_many(&self, rays: &[Ray], t_min: f32, t_max: f32) -> Vec<Option<Hit>> {
        if !self.surface.detail().is_active() {
            return self.base.trace_many(rays, t_min, t_max);
        }
        rays.iter().map(|r| self.trace(r, t_min, t_max)).collect()
    }

    fn occluded_many(&self, rays: &[Ray], t_min: f32, t_max: f32) -> Vec<bool> {
        if !self.surface.detail().is_active() {
            return self.base.occluded_many(rays, t_min, t_max);
        }
        rays.iter()
            .map(|r| self.occluded(r, t_min, t_max))
            .collect()
    }
}
