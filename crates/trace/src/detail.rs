//! Procedural detail below the cell size, band-limited to the pixel footprint:
//! the one model the detail tracer, its shading normals and its brute-force
//! oracle all evaluate.
//!
//! The surface is `S(x, y; w) = B(x, y) + m(x, y)·D(x, y; w)`: `B` the
//! triangulated height field ([`crate::surface_height`]), `m ∈ [0, 1]` an
//! optional bilinear mask over the samples (0 keeps a region bare, e.g.
//! water), and `D` an fBm of Perlin noise in world metres whose octaves start
//! at the cell size and stop at the footprint `w` (metres) of the ray's pixel
//! there. This is Musgrave's procedural level of detail, "band-limiting the
//! fractal function as a function of distance" (Musgrave 1993, §6.3), with
//! the fractional-octave blend that keeps the octave count continuous
//! (Musgrave 1993, §2.3.2.1): octave `k` (wavelength `λ₀/rᵏ`, amplitude
//! `a·r^(−kH)`) has weight `clamp(n(w) − k, 0, 1)` with
//! `n(w) = log_r(λ₀ / 2w)`, natura-noise's level-of-detail rule
//! (`natura_noise::visible_octaves`, which states why), so it fades in
//! between footprints `λₖ/2r` and `λₖ/2` (the Nyquist limit), and no octave
//! is left once `w ≥ λ₀/2`.
//!
//! The tracer's bounds come from here too (Hart 1996, for the Lipschitz
//! step): `|D| ≤ Σ aₖ` over the octaves present, `|∇D| ≤ L_noise·Σ wₖ aₖ/λₖ`,
//! and `|∂D/∂w|` from the one octave being blended. Each bound is
//! non-increasing in `w`, so one taken where a ray's footprint is smallest
//! holds further along it.

use glam::{DVec2, Vec3};
use natura_core::{Boundary, Grid2, HeightField};
use natura_noise::{Field, Perlin, visible_octaves};

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

/// The detail octaves: values, gradients and bounds at a footprint.
#[derive(Clone, Debug)]
pub struct Detail {
    noise: Perlin,
    /// Octave amplitudes (metres) and frequencies (1/metres).
    amp: Vec<f64>,
    freq: Vec<f64>,
    lambda0: f64,
    /// `1/λ₀`, the first octave's frequency.
    freq0: f64,
    ln_lac: f64,
    lac: f64,
    lip_noise: f64,
    /// `Σ_{j<k} aⱼ` and `Σ_{j<k} aⱼ fⱼ` (index `k` from 0 to the octave
    /// count), and `max_{j<k} aⱼ / w_min,j` for the footprint bound.
    amp_pre: Vec<f64>,
    lip_pre: Vec<f64>,
    fp_max: Vec<f64>,
    /// Octave `k` is present (`n(w) > k`) below the footprint `λ₀/(2rᵏ)`,
    /// widened by a relative 1e-9 so that rounding never drops one.
    nyquist: Vec<f64>,
}

impl Detail {
    /// Checks `p` and builds its octaves.
    ///
    /// # Errors
    ///
    /// Returns [`TraceError::InvalidParameter`] naming the first parameter
    /// that is NaN or out of range: `amplitude_m` (finite, ≥ 0), `h`
    /// (finite, in `[0, 2]`), `lacunarity` (in `(1, 16]`), `octaves` (at
    /// most [`MAX_DETAIL_OCTAVES`]), `wavelength_m` (finite, > 0).
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
        let lac = f64::from(p.lacunarity);
        let n = if p.amplitude_m > 0.0 { p.octaves } else { 0 };
        let lambda0 = f64::from(p.wavelength_m);
        let amp: Vec<f64> = (0..n)
            .map(|k| f64::from(p.amplitude_m) * lac.powf(-f64::from(k) * f64::from(p.h)))
            .collect();
        let freq: Vec<f64> = (0..n).map(|k| lac.powi(k as i32) / lambda0).collect();
        let noise = Perlin::new(p.seed);
        let (mut amp_pre, mut lip_pre, mut fp_max) = (vec![0.0f64], vec![0.0f64], vec![0.0f64]);
        let nyquist = (0..n)
            .map(|k| 0.5 * lambda0 / lac.powi(k as i32) * (1.0 + 1e-9))
            .collect();
        for k in 0..n as usize {
            amp_pre.push(amp_pre[k] + amp[k]);
            lip_pre.push(lip_pre[k] + amp[k] * freq[k]);
            let wmin = 0.5 * lambda0 / lac.powi(k as i32 + 1);
            fp_max.push(fp_max[k].max(amp[k] / wmin));
        }
        Ok(Self {
            nyquist,
            amp_pre,
            lip_pre,
            fp_max,
            lip_noise: noise.lipschitz2(),
            noise,
            amp,
            freq,
            lambda0,
            freq0: 1.0 / lambda0,
            ln_lac: lac.ln(),
            lac,
        })
    }

    /// Whether there is any detail at all (amplitude and octaves > 0).
    #[must_use]
    pub fn is_active(&self) -> bool {
        !self.amp.is_empty()
    }

    /// The footprint (metres) from which on no octave is left: `λ₀/2`.
    #[must_use]
    pub fn far_footprint(&self) -> f64 {
        0.5 * self.lambda0
    }

    /// The smallest footprint that still changes the detail (all octaves
    /// full below it): `λ₀ / (2 r^octaves)`.
    #[must_use]
    pub fn finest_footprint(&self) -> f64 {
        0.5 * self.lambda0 / self.lac.powi(self.amp.len() as i32)
    }

    /// The fractional octave count `n(w)`, clamped to `[0, octaves]`:
    /// natura-noise's level-of-detail rule [`visible_octaves`] for the base
    /// frequency `1/λ₀`.
    #[inline]
    pub(crate) fn octaves_at(&self, w: f64) -> f64 {
        let n = self.amp.len() as f64;
        if w <= 0.0 {
            return n;
        }
        visible_octaves(w, self.freq0, self.lac).min(n)
    }

    /// Octave `k`'s sample point: a fixed irrational shift per octave keeps
    /// the lattices' zeros from lining up.
    #[inline]
    fn point(&self, k: usize, p: DVec2) -> DVec2 {
        let s = (k + 1) as f64;
        p * self.freq[k] + DVec2::new(0.618_034 * s, 0.414_214 * s)
    }

    /// Octave `k`'s weighted term of `D(p; w)` where `n = n(w)`.
    #[inline]
    pub(crate) fn octave(&self, k: usize, n: f64, p: DVec2) -> f64 {
        (n - k as f64).min(1.0) * self.amp[k] * self.noise.eval2(self.point(k, p))
    }

    /// A bound on `|Σ_{k0 ≤ k < k1} wₖ aₖ Nₖ|` (the octaves `k0..k1`).
    #[inline]
    pub(crate) fn amplitude_between(&self, k0: usize, k1: usize) -> f64 {
        (self.amp_pre[k1] - self.amp_pre[k0]) * self.noise.bound()
    }

    /// A bound on the gradient of the first `k` octaves at any footprint
    /// (every weight taken as 1).
    #[inline]
    pub(crate) fn lipschitz_first(&self, k: usize) -> f64 {
        self.lip_pre[k] * self.lip_noise
    }

    /// `D(p; w)`, metres.
    #[must_use]
    pub fn height(&self, p: DVec2, w: f64) -> f64 {
        let n = self.octaves_at(w);
        let mut sum = 0.0;
        for k in 0..n.ceil() as usize {
            let wk = (n - k as f64).min(1.0);
            sum += wk * self.amp[k] * self.noise.eval2(self.point(k, p));
        }
        sum
    }

    /// `D(p; w)` and its gradient `∇D` (per metre), analytically.
    #[must_use]
    pub fn height_grad(&self, p: DVec2, w: f64) -> (f64, DVec2) {
        let n = self.octaves_at(w);
        let (mut v, mut g) = (0.0, DVec2::ZERO);
        for k in 0..n.ceil() as usize {
            let wk = (n - k as f64).min(1.0) * self.amp[k];
            let (nv, ng) = self.noise.eval_grad2(self.point(k, p));
            v += wk * nv;
            g += wk * self.freq[k] * ng;
        }
        (v, g)
    }

    /// A bound on `|D(·; w')|` for every `w' ≥ w`: the sum of the amplitudes
    /// of the octaves present at `w`.
    #[must_use]
    pub fn amplitude_bound(&self, w: f64) -> f64 {
        let present = self.nyquist.iter().take_while(|&&f| w < f).count();
        self.amp_pre[present] * self.noise.bound()
    }

    /// A bound on `|∇D(·; w')|` for every `w' ≥ w`: `L_noise · Σ wₖ aₖ fₖ`.
    #[must_use]
    pub fn lipschitz_bound(&self, w: f64) -> f64 {
        let n = self.octaves_at(w);
        let mut s = 0.0;
        for k in 0..n.ceil() as usize {
            s += (n - k as f64).min(1.0) * self.amp[k] * self.freq[k];
        }
        s * self.lip_noise
    }

    /// A bound on `|∂D/∂w'|` for every `w' ≥ w`. Only the octave being
    /// blended depends on `w'`: `|∂D/∂w'| ≤ a_k / (w' ln r)` while
    /// `n(w') ∈ [k, k + 1)`, where `w' ≥ λ₀/(2 r^(k+1))`.
    #[must_use]
    pub fn footprint_bound(&self, w: f64) -> f64 {
        self.footprint_bound_n(w, self.octaves_at(w))
    }

    /// [`Self::footprint_bound`] with `n = n(w)` already known.
    #[inline]
    pub(crate) fn footprint_bound_n(&self, w: f64, n: f64) -> f64 {
        if n <= 0.0 {
            return 0.0;
        }
        let top = self.amp.len();
        let kstar = (n.floor() as usize).min(top);
        let mut b = 0.0f64;
        if kstar < top && w > 0.0 {
            b = self.amp[kstar] / w;
        }
        b = b.max(self.fp_max[kstar]);
        b * self.noise.bound() / self.ln_lac
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
        Ok(Self {
            hf,
            detail,
            mask,
            mask_lip,
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

    /// The bound on the mask's gradient `|∇m|`, per metre (0 without a mask).
    #[inline]
    pub(crate) fn mask_lipschitz(&self) -> f64 {
        self.mask_lip
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
