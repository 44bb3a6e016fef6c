//! Procedural detail below the cell size, band-limited to the pixel footprint:
//! the one model the detail tracer, its shading normals and its brute-force
//! oracle all evaluate.
//!
//! The surface is `S(x, y; w) = B(x, y) + m(x, y)·D(x, y; w)`: `B` the
//! triangulated height field ([`crate::surface_height`]), `m ∈ [0, 1]` an
//! optional bilinear mask over the samples (0 keeps a region bare, e.g.
//! water), and `D` an fBm of Perlin noise in world metres whose octaves start
//! at the cell size and stop at the footprint `w` (metres) of the ray's pixel
//! there: natura-noise's [`FootprintFbm`], which holds the model (Musgrave's
//! procedural level of detail, "band-limiting the fractal function as a
//! function of distance", Musgrave 1993, §6.3, with the fractional-octave
//! blend of Musgrave 1993, §2.3.2.1), its per-octave offsets and its bounds.
//! Octave `k` (wavelength `λ₀/rᵏ`, amplitude `a·r^(−kH)`) has weight
//! `clamp(n(w) − k, 0, 1)` with `n(w) = log_r(λ₀ / 2w)`, natura-noise's
//! level-of-detail rule (`natura_noise::visible_octaves`, which states why),
//! so it fades in between footprints `λₖ/2r` and `λₖ/2` (the Nyquist limit),
//! and no octave is left once `w ≥ λ₀/2`.
//!
//! The tracer's bounds come from there too (Hart 1996, for the Lipschitz
//! step): `|D| ≤ Σ aₖ` over the octaves present, `|∇D| ≤ L_noise·Σ wₖ aₖ/λₖ`,
//! and `|∂D/∂w|` from the one octave being blended. Each bound is
//! non-increasing in `w`, so one taken where a ray's footprint is smallest
//! holds further along it.

use glam::{DVec2, Vec3};
use natura_core::{Boundary, Grid2, HeightField};
use natura_noise::{FootprintFbm, FootprintParams, NoiseError, Perlin};

use crate::error::{Result, TraceError};
use crate::surface::surface_height;

/// Most octaves a [`Detail`] may have.
pub const MAX_DETAIL_OCTAVES: u32 = 24;

/// Parameters of the procedural detail.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DetailParams {
    /// Amplitude of the first (largest) octave, metres (≥ 0; 0 = no detail).
    pub amplitude_m: f32,
    /// Musgrave's H: octave `k` has amplitude `amplitude_m · lacunarity^(−kH)`.
    pub h: f32,
    /// Wavelength ratio between octaves (> 1).
    pub lacunarity: f32,
    /// Most octaves, however small the footprint (0 = no detail).
    pub octaves: u32,
    /// Wavelength of the first octave, metres (the height field's cell size
    /// puts the detail just below the stored data).
    pub wavelength_m: f32,
    /// Seed of the noise.
    pub seed: u64,
}

/// A ray's pixel footprint along it: `w(t) = at_origin_m + per_metre·t·|dir|`
/// metres (a cone: for a primary ray `per_metre` is the pixel's angle; for a
/// shadow ray `at_origin_m` is the footprint where it leaves the surface).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayCone {
    /// RayCone at the ray's origin, metres (≥ 0).
    pub at_origin_m: f32,
    /// Growth per metre travelled (radians of the pixel cone, ≥ 0).
    pub per_metre: f32,
}

impl RayCone {
    /// A cone from a point: `w(t) = angle·t`.
    #[must_use]
    pub const fn cone(angle: f32) -> Self {
        Self {
            at_origin_m: 0.0,
            per_metre: angle,
        }
    }

    /// The footprint at `dist` metres from the origin.
    #[inline]
    #[must_use]
    pub fn at(&self, dist: f64) -> f64 {
        f64::from(self.at_origin_m) + f64::from(self.per_metre) * dist
    }
}

/// The detail octaves: values, gradients and bounds at a footprint. A thin
/// wrapper of natura-noise's [`FootprintFbm`] of [`Perlin`] noise (which
/// holds the model, its octave offsets and its bounds) with the tracer's
/// parameter limits and names.
#[derive(Clone, Debug)]
pub struct Detail {
    fbm: FootprintFbm<Perlin>,
}

impl Detail {
    /// Checks `p` and builds its octaves.
    ///
    /// # Errors
    ///
    /// Returns [`TraceError::InvalidParameter`] naming the first parameter
    /// that is NaN or out of range: `amplitude_m` (finite, ≥ 0, and small
    /// enough that the octave amplitudes sum to at most 1e30), `h` (finite,
    /// in `[0, 2]`), `lacunarity` (in `(1, 16]`), `octaves` (at most
    /// [`MAX_DETAIL_OCTAVES`]), `wavelength_m` (finite, > 0).
    pub fn new(p: &DetailParams) -> Result<Self> {
        let bad = |name, v: f32, why| Err(TraceError::param(name, v, why));
        if !(p.amplitude_m.is_finite() && p.amplitude_m >= 0.0) {
            return bad("amplitude_m", p.amplitude_m, "finite and ≥ 0");
        }
        if !(0.0..=2.0).contains(&p.h) {
            return bad("h", p.h, "in [0, 2]");
        }
        if !(p.lacunarity > 1.0 && p.lacunarity <= 16.0) {
            return bad("lacunarity", p.lacunarity, "in (1, 16]");
        }
        if p.octaves > MAX_DETAIL_OCTAVES {
            return Err(TraceError::param(
                "octaves",
                p.octaves,
                "at most MAX_DETAIL_OCTAVES",
            ));
        }
        if !(p.wavelength_m.is_finite() && p.wavelength_m > 0.0) {
            return bad("wavelength_m", p.wavelength_m, "finite and > 0");
        }
        let params = FootprintParams {
            amplitude: f64::from(p.amplitude_m),
            h: f64::from(p.h),
            lacunarity: f64::from(p.lacunarity),
            octaves: p.octaves,
            wavelength: f64::from(p.wavelength_m),
        };
        let fbm = FootprintFbm::new(Perlin::new(p.seed), &params).map_err(|e| match e {
            // The only limit left after the checks above: the amplitudes' sum.
            NoiseError::Unbounded { .. } => TraceError::param(
                "amplitude_m",
                p.amplitude_m,
                "small enough that the octave amplitudes sum to at most 1e30",
            ),
            other => TraceError::param("detail", other, "parameters natura-noise accepts"),
        })?;
        Ok(Self { fbm })
    }

    /// The octaves: natura-noise's footprint-limited fBm.
    #[must_use]
    pub fn octaves(&self) -> &FootprintFbm<Perlin> {
        &self.fbm
    }

    /// Whether there is any detail at all (amplitude and octaves > 0).
    #[must_use]
    pub fn is_active(&self) -> bool {
        self.fbm.octave_count() > 0
    }

    /// The footprint (metres) from which on no octave is left: `λ₀/2`.
    #[must_use]
    pub fn far_footprint(&self) -> f64 {
        self.fbm.far_footprint()
    }

    /// The smallest footprint that still changes the detail (all octaves
    /// full below it): `λ₀ / (2 r^octaves)`.
    #[must_use]
    pub fn finest_footprint(&self) -> f64 {
        self.fbm.finest_footprint()
    }

    /// The fractional octave count `n(w)`, clamped to `[0, octaves]`
    /// ([`FootprintFbm::visible`]).
    #[inline]
    pub(crate) fn octaves_at(&self, w: f64) -> f64 {
        self.fbm.visible(w)
    }

    /// `(⌈n(w)⌉, ⌊n(w)⌋)`, found without the logarithm where
    /// [`FootprintFbm::visible_whole`] can, and `n(w)` itself where the
    /// logarithm had to decide them (`(0, 0)` for a NaN footprint).
    #[inline]
    pub(crate) fn octave_count(&self, w: f64) -> ((usize, usize), Option<f64>) {
        if let Some(whole) = self.fbm.visible_whole(w) {
            return (whole, None);
        }
        let n = self.octaves_at(w);
        // ⌈n⌉ by truncation, equal to `n.ceil() as usize` for every n (NaN
        // and negatives give 0 both ways): `ceil` is a library call on the
        // baseline instruction set.
        let floor = n as usize;
        let ceil = if (floor as f64) < n { floor + 1 } else { floor };
        ((ceil, floor), Some(n))
    }

    /// Octave `k`'s weighted term of `D(p; w)` where `n = n(w)`.
    #[inline]
    pub(crate) fn octave(&self, k: usize, n: f64, p: DVec2) -> f64 {
        self.fbm.octave_term(k, n, p)
    }

    /// A bound on `|Σ_{k0 ≤ k < k1} wₖ aₖ Nₖ|` (the octaves `k0..k1`).
    #[inline]
    pub(crate) fn amplitude_between(&self, k0: usize, k1: usize) -> f64 {
        self.fbm.amplitude_between(k0, k1)
    }

    /// A bound on the gradient of the first `k` octaves at any footprint
    /// (every weight taken as 1).
    #[inline]
    pub(crate) fn lipschitz_first(&self, k: usize) -> f64 {
        self.fbm.lipschitz_first(k)
    }

    /// `D(p; w)`, metres.
    #[inline]
    #[must_use]
    pub fn height(&self, p: DVec2, w: f64) -> f64 {
        self.fbm.eval2(p, w)
    }

    /// `D(p; w)` and its gradient `∇D` (per metre), analytically.
    #[inline]
    #[must_use]
    pub fn height_grad(&self, p: DVec2, w: f64) -> (f64, DVec2) {
        self.fbm.eval_grad2(p, w)
    }

    /// A bound on `|D(·; w')|` for every `w' ≥ w`: the sum of the amplitudes
    /// of the octaves present at `w`.
    #[must_use]
    pub fn amplitude_bound(&self, w: f64) -> f64 {
        self.fbm.amplitude_bound(w)
    }

    /// A bound on `|∇D(·; w')|` for every `w' ≥ w`: `L_noise · Σ wₖ aₖ fₖ`.
    #[must_use]
    pub fn lipschitz_bound(&self, w: f64) -> f64 {
        self.fbm.lipschitz_bound(w)
    }

    /// A bound on `|∂D/∂w'|` for every `w' ≥ w`
    /// ([`FootprintFbm::footprint_bound`]).
    #[must_use]
    pub fn footprint_bound(&self, w: f64) -> f64 {
        self.fbm.footprint_bound(w)
    }

    /// [`Self::footprint_bound`] with `(⌈n(w)⌉, ⌊n(w)⌋)` already known.
    #[inline]
    pub(crate) fn footprint_bound_whole(&self, w: f64, whole: (usize, usize)) -> f64 {
        self.fbm.footprint_bound_whole(w, whole)
    }
}

/// The traced surface: a height field plus masked detail (see the module docs).
#[derive(Clone, Debug)]
pub struct DetailSurface<'a> {
    hf: &'a HeightField,
    detail: Detail,
    mask: Option<Grid2<f32>>,
    /// `|∇m|` bound, per metre.
    mask_lip: f64,
    /// The mask's maximum over the nodes of the tracer's pyramid: level
    /// `k ≥ 1` (entry `k − 1`) holds its width `⌈ncx/2ᵏ⌉` and its
    /// `⌈ncx/2ᵏ⌉ × ⌈ncy/2ᵏ⌉` nodes of `2ᵏ × 2ᵏ` cells, row-major (empty
    /// without a mask).
    mask_max: Vec<(usize, Vec<f32>)>,
}

impl<'a> DetailSurface<'a> {
    /// The surface over `hf` with `detail`, weighted by `mask` (one value in
    /// `[0, 1]` per sample, bilinear between; `None` = 1 everywhere).
    ///
    /// # Errors
    ///
    /// Returns [`TraceError::InvalidParameter`] if `mask` is not the size of
    /// `hf` or holds a value outside `[0, 1]` (or NaN).
    pub fn new(hf: &'a HeightField, detail: Detail, mask: Option<Grid2<f32>>) -> Result<Self> {
        let mut mask_lip = 0.0f64;
        if let Some(m) = &mask {
            if m.width() != hf.nx() || m.height() != hf.ny() {
                return Err(TraceError::param(
                    "mask",
                    format!("{} × {}", m.width(), m.height()),
                    "the height field's size",
                ));
            }
            if let Some(v) = m.as_slice().iter().find(|v| !(0.0..=1.0).contains(*v)) {
                return Err(TraceError::param("mask", v, "values in [0, 1]"));
            }
            // A bilinear patch's gradient is at most √2 × its largest edge difference per cell.
            let (nx, ny) = (m.width(), m.height());
            let mut d = 0.0f32;
            for j in 0..ny {
                for i in 0..nx {
                    let v = m[(i, j)];
                    if i + 1 < nx {
                        d = d.max((m[(i + 1, j)] - v).abs());
                    }
                    if j + 1 < ny {
                        d = d.max((m[(i, j + 1)] - v).abs());
                    }
                }
            }
            mask_lip = std::f64::consts::SQRT_2 * f64::from(d) / f64::from(hf.cell_size());
        }
        let mask_max = mask.as_ref().map_or_else(Vec::new, mask_pyramid);
        Ok(Self {
            hf,
            detail,
            mask,
            mask_lip,
            mask_max,
        })
    }

    /// The height field.
    #[must_use]
    pub fn height_field(&self) -> &'a HeightField {
        self.hf
    }

    /// The detail octaves.
    #[must_use]
    pub fn detail(&self) -> &Detail {
        &self.detail
    }

    /// The mask's value at world `(x, y)` (1 without a mask).
    #[inline]
    #[must_use]
    pub fn mask_at(&self, x: f32, y: f32) -> f32 {
        match &self.mask {
            None => 1.0,
            Some(m) => {
                let inv = 1.0 / self.hf.cell_size();
                m.sample_bilinear(x * inv, y * inv, Boundary::Clamp)
            }
        }
    }

    /// `S(x, y; w)`, metres, or `None` outside the field or for NaN.
    #[must_use]
    pub fn height(&self, x: f32, y: f32, w: f64) -> Option<f64> {
        let b = f64::from(surface_height(self.hf, x, y)?);
        if !self.detail.is_active() {
            return Some(b);
        }
        let m = self.mask_at(x, y);
        if m == 0.0 {
            return Some(b);
        }
        let d = self
            .detail
            .height(DVec2::new(f64::from(x), f64::from(y)), w);
        Some(b + f64::from(m) * d)
    }

    /// The gradient of the masked detail `∇(m·D)` at `(x, y)` (per metre).
    #[must_use]
    pub fn detail_gradient(&self, x: f32, y: f32, w: f64) -> DVec2 {
        if !self.detail.is_active() {
            return DVec2::ZERO;
        }
        let (d, gd) = self
            .detail
            .height_grad(DVec2::new(f64::from(x), f64::from(y)), w);
        let m = f64::from(self.mask_at(x, y));
        let gm = match &self.mask {
            None => DVec2::ZERO,
            Some(_) => {
                // The bilinear mask's gradient by a central difference of a tenth of a cell.
                let e = 0.05 * self.hf.cell_size();
                let fx = self.mask_at(x + e, y) - self.mask_at(x - e, y);
                let fy = self.mask_at(x, y + e) - self.mask_at(x, y - e);
                DVec2::new(f64::from(fx), f64::from(fy)) / f64::from(2.0 * e)
            }
        };
        m * gd + d * gm
    }

    /// The mask at the corners of cell `(i, j)`, in the order of the
    /// height field's corners: `(i, j)`, `(i + 1, j)`, `(i, j + 1)`,
    /// `(i + 1, j + 1)` (ones without a mask). The bilinear mask over the
    /// cell lies between their least and greatest.
    #[inline]
    pub(crate) fn mask_corners(&self, i: u32, j: u32) -> [f32; 4] {
        match &self.mask {
            None => [1.0; 4],
            Some(m) => {
                let (i, j) = (i as usize, j as usize);
                [m[(i, j)], m[(i + 1, j)], m[(i, j + 1)], m[(i + 1, j + 1)]]
            }
        }
    }

    /// The mask's greatest value over node `(a, b)` of level `k ≥ 1` of the
    /// tracer's pyramid (1 without a mask or outside it).
    #[inline]
    pub(crate) fn mask_max_node(&self, k: u32, a: u32, b: u32) -> f32 {
        let Some((w, level)) = self.mask_max.get(k as usize - 1) else {
            return 1.0;
        };
        level
            .get(b as usize * w + a as usize)
            .copied()
            .unwrap_or(1.0)
    }

    /// Bytes held by the mask and its pyramid.
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        self.mask
            .as_ref()
            .map_or(0, |m| std::mem::size_of_val(m.as_slice()))
            + self
                .mask_max
                .iter()
                .map(|(_, l)| std::mem::size_of_val(l.as_slice()))
                .sum::<usize>()
    }

    /// A bound on `|m·D|` for every footprint `w' ≥ w`.
    #[must_use]
    pub fn amplitude_bound(&self, w: f64) -> f64 {
        self.detail.amplitude_bound(w)
    }

    /// A bound on `|∇(m·D)|` for every footprint `w' ≥ w`:
    /// `L_D + A·L_m` (`m ≤ 1`).
    #[must_use]
    pub fn lipschitz_bound(&self, w: f64) -> f64 {
        self.detail.lipschitz_bound(w) + self.detail.amplitude_bound(w) * self.mask_lip
    }

    /// A bound on `|∂(m·D)/∂w'|` for every `w' ≥ w`.
    #[must_use]
    pub fn footprint_bound(&self, w: f64) -> f64 {
        self.detail.footprint_bound(w)
    }
}

/// Tilts a unit up-facing normal `n` of a surface by adding `g` to its
/// height gradient: the normal of `z = f + δ` where `∇f` is `n`'s.
#[must_use]
pub(crate) fn add_gradient(n: Vec3, g: DVec2) -> Vec3 {
    let nz = n.z.max(1e-6);
    let gx = -n.x / nz + g.x as f32;
    let gy = -n.y / nz + g.y as f32;
    Vec3::new(-gx, -gy, 1.0).normalize()
}

/// The mask's maximum over the nodes of every level `k ≥ 1` of a pyramid
/// over the `(nx − 1) × (ny − 1)` cells of its samples, each level's node
/// covering the 2 × 2 nodes below it (the last row and column clipped), up
/// to a single node: level 1 from the cells' corner samples, each level
/// above from the one below.
fn mask_pyramid(m: &Grid2<f32>) -> Vec<(usize, Vec<f32>)> {
    let (ncx, ncy) = (m.width() - 1, m.height() - 1);
    let mut levels: Vec<(usize, Vec<f32>)> = Vec::new();
    let (mut w, mut h) = (ncx, ncy);
    let mut k = 1;
    while w > 1 || h > 1 || k == 1 {
        let (nw, nh) = (ncx.div_ceil(1 << k), ncy.div_ceil(1 << k));
        let level = (0..nw * nh)
            .map(|n| {
                let (a, b) = (n % nw, n / nw);
                match levels.last() {
                    // Level 1: the samples of cells 2a..2a+2 × 2b..2b+2.
                    None => {
                        let (x1, y1) = ((2 * a + 2).min(ncx), (2 * b + 2).min(ncy));
                        (2 * b..=y1)
                            .flat_map(|y| (2 * a..=x1).map(move |x| (x, y)))
                            .map(|(x, y)| m[(x, y)])
                            .fold(0.0f32, f32::max)
                    }
                    Some((_, below)) => (2 * b..(2 * b + 2).min(h))
                        .flat_map(|y| (2 * a..(2 * a + 2).min(w)).map(move |x| (x, y)))
                        .map(|(x, y)| below[y * w + x])
                        .fold(0.0f32, f32::max),
                }
            })
            .collect();
        levels.push((nw, level));
        (w, h) = (nw, nh);
        k += 1;
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;

    fn detail() -> Detail {
        Detail::new(&DetailParams {
            amplitude_m: 2.0,
            h: 0.8,
            lacunarity: 2.0,
            octaves: 6,
            wavelength_m: 30.0,
            seed: 7,
        })
        .unwrap()
    }

    #[test]
    fn the_mask_pyramid_holds_each_nodes_greatest_sample() {
        // A random mask on a field of 23 × 14 samples (22 × 13 cells, so
        // every level clips its last row or column): each node of every
        // level holds exactly the greatest sample of its cells' corners,
        // found by brute force, up to the one node covering the field.
        let hf = HeightField::from_fn(23, 14, 5.0, |_, _| 0.0).unwrap();
        let mut s = 3u64;
        let mask = Grid2::from_fn(23, 14, |_, _| {
            s = natura_core::mix64(s);
            natura_core::unit_f64(s) as f32
        })
        .unwrap();
        let surface = DetailSurface::new(&hf, detail(), Some(mask.clone())).unwrap();
        let (ncx, ncy) = (22u32, 13u32);
        let mut k = 1;
        loop {
            let size = 1u32 << k;
            let (w, h) = (ncx.div_ceil(size), ncy.div_ceil(size));
            for b in 0..h {
                for a in 0..w {
                    let mut want = 0.0f32;
                    for y in b * size..=((b + 1) * size).min(ncy) {
                        for x in a * size..=((a + 1) * size).min(ncx) {
                            want = want.max(mask[(x as usize, y as usize)]);
                        }
                    }
                    assert_eq!(
                        surface.mask_max_node(k, a, b),
                        want,
                        "level {k}, node ({a}, {b})"
                    );
                }
            }
            if w == 1 && h == 1 {
                break;
            }
            k += 1;
        }
        // Above the top, and without a mask: no bound below 1.
        assert_eq!(surface.mask_max_node(k + 1, 0, 0), 1.0);
        let bare = DetailSurface::new(&hf, detail(), None).unwrap();
        assert_eq!(bare.mask_max_node(1, 0, 0), 1.0);
        assert_eq!(bare.mask_corners(3, 4), [1.0; 4]);
    }

    #[test]
    fn bounds_hold_on_random_points() {
        let d = detail();
        let mut s = 1u64;
        let mut rnd = || {
            s = natura_core::mix64(s);
            natura_core::unit_f64(s)
        };
        for _ in 0..2000 {
            let w = 0.05 + 20.0 * rnd();
            let p = DVec2::new(1000.0 * rnd(), 1000.0 * rnd());
            let q = p + DVec2::new(rnd() - 0.5, rnd() - 0.5) * 0.3;
            let (a, b) = (d.height(p, w), d.height(q, w));
            assert!(a.abs() <= d.amplitude_bound(w) + 1e-12);
            assert!((a - b).abs() <= d.lipschitz_bound(w) * (p - q).length() + 1e-9);
            // Along the footprint: bounded by the bound at the smaller footprint.
            let w2 = w * (1.0 + 0.05 * rnd());
            let c = d.height(p, w2);
            assert!((a - c).abs() <= d.footprint_bound(w) * (w2 - w) + 1e-9);
        }
    }

    #[test]
    fn no_detail_beyond_the_far_footprint_and_continuous_in_footprint() {
        let d = detail();
        let p = DVec2::new(123.4, 56.7);
        assert_eq!(d.height(p, d.far_footprint()), 0.0);
        assert_eq!(d.height(p, 1e6), 0.0);
        let mut prev = d.height(p, 0.01);
        for k in 1..4000 {
            let w = 0.01 * 1.002f64.powi(k);
            let v = d.height(p, w);
            assert!((v - prev).abs() < 0.05, "jump at w = {w}");
            prev = v;
        }
        // All octaves below the finest footprint.
        assert_eq!(d.height(p, d.finest_footprint()), d.height(p, 0.0));
    }

    #[test]
    fn gradient_matches_central_differences() {
        let d = detail();
        let p = DVec2::new(41.3, -7.9);
        let (_, g) = d.height_grad(p, 0.3);
        let e = 1e-5;
        let gx = (d.height(p + DVec2::X * e, 0.3) - d.height(p - DVec2::X * e, 0.3)) / (2.0 * e);
        let gy = (d.height(p + DVec2::Y * e, 0.3) - d.height(p - DVec2::Y * e, 0.3)) / (2.0 * e);
        assert!((g - DVec2::new(gx, gy)).length() < 1e-4 * (1.0 + g.length()));
    }

    #[test]
    fn bad_parameters_name_themselves() {
        let ok = DetailParams {
            amplitude_m: 1.0,
            h: 0.8,
            lacunarity: 2.0,
            octaves: 4,
            wavelength_m: 30.0,
            seed: 1,
        };
        for (p, name) in [
            (
                DetailParams {
                    amplitude_m: f32::NAN,
                    ..ok
                },
                "amplitude_m",
            ),
            (DetailParams { h: -1.0, ..ok }, "h"),
            (
                DetailParams {
                    lacunarity: 1.0,
                    ..ok
                },
                "lacunarity",
            ),
            (DetailParams { octaves: 99, ..ok }, "octaves"),
            (
                DetailParams {
                    wavelength_m: 0.0,
                    ..ok
                },
                "wavelength_m",
            ),
        ] {
            match Detail::new(&p) {
                Err(TraceError::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
                other => panic!("{name}: {other:?}"),
            }
        }
    }
}
