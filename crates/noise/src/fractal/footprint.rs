//! fBm band-limited to a footprint in world units, with the bounds a
//! Lipschitz ray marcher needs.
//!
//! [`FootprintFbm`] is the sum `D(p; w) = Σ_k c_k(w)·a_k·N(f_k·p + o_k)` of
//! a basis `N` (gradient noise in practice) in world units: octave `k` has
//! wavelength `λ₀/rᵏ` (frequency `f_k = rᵏ/λ₀`), amplitude `a_k = a·r^(−kH)`
//! (the canonical convention of the crate, Musgrave 1993, §2.3.2.1) and a
//! fixed offset `o_k` in its lattice units. The octave count follows the
//! footprint `w` of the sample: `c_k(w) = clamp(v(w) − k, 0, 1)` with
//! `v(w) = `[`visible_octaves`](crate::fractal::lod::visible_octaves)`(w, 1/λ₀, r)`, Musgrave's procedural level of
//! detail, "band-limiting the fractal function as a function of distance"
//! (Musgrave 1993, §6.3), with the fractional-octave blend that keeps the sum
//! continuous in the octave count (Musgrave 1993, §2.3.2.1). So octave `k`
//! fades in between the footprints `λ_k/2r` and `λ_k/2` (the Nyquist limit),
//! and nothing is left once `w ≥ λ₀/2`.
//!
//! **Offsets.** With lacunarity 2 and the first wavelength equal to a height
//! field's cell, every octave's lattice would contain the field's samples, and
//! gradient noise vanishes on its lattice: the detail would be 0 at every
//! sample. Octave `k` is therefore shifted by `(k + 1)·(0.618034, 0.414214)`
//! lattice units (multiples of the golden ratio's and √2's fractional parts),
//! so no two octaves' lattices line up with each other or with the samples
//! (our choice; [`Fbm`](crate::Fbm) keeps the sources' unshifted loop).
//! The 3-D evaluation ([`FootprintFbm::eval3`]) adds a third component
//! `(k + 1)·0.732051` (√3's fractional part), [`octave_offset3`]; its first
//! two components are the 2-D offsets, and the 2-D evaluation is unchanged.
//!
//! **Frequency range.** Unlike [`Spectral`](crate::Spectral), the top octave
//! may lie beyond [`MAX_FREQUENCY_RATIO`](crate::fractal::MAX_FREQUENCY_RATIO)
//! times the first (24 octaves with lacunarity 4 reach `2⁴⁶`): an octave
//! enters only below the footprint `λ₀/(2rᵏ)`, so such octaves are summed only
//! for samples far finer than any `f32` position resolves. There the lattice
//! coordinates have lost their fractional part and the octave adds little or
//! nothing, but every value stays finite and within the bounds below.
//!
//! **Bounds** (for sphere tracing with a Lipschitz bound, Hart 1996):
//! `|D(·; w)| ≤ B_N·Σ a_k` over the octaves present at `w`,
//! `|∇D(·; w)| ≤ L_N·Σ c_k(w)·a_k·f_k`, and `|∂D/∂w|` from the one octave
//! being blended. Each is non-increasing in `w`, so one taken where a ray's
//! footprint is smallest holds further along it.

use glam::{DVec2, DVec3};

use crate::error::{NoiseError, Result, bounded};
use crate::field::Field;
use crate::fractal::MAX_OCTAVES;
use crate::fractal::lod::visible_octaves_ln;

/// The relative margin about each `rᵏ` within which
/// [`FootprintFbm::visible_whole`] leaves `⌈v⌉` to the logarithm.
const WHOLE_MARGIN: f64 = 1e-9;

/// Parameters of a [`FootprintFbm`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FootprintParams {
    /// Amplitude `a` of the first (largest) octave, world units (finite,
    /// ≥ 0; 0 = no octaves).
    pub amplitude: f64,
    /// Musgrave's `H`: octave `k` has amplitude `a·r^(−kH)` (finite).
    pub h: f64,
    /// Wavelength ratio `r` between octaves (finite, > 1).
    pub lacunarity: f64,
    /// Most octaves, however small the footprint (at most [`MAX_OCTAVES`];
    /// 0 = no octaves).
    pub octaves: u32,
    /// Wavelength `λ₀` of the first octave, world units (finite, > 0).
    pub wavelength: f64,
}

/// `x^n` by binary powering, the order of the multiplications of
/// `f64::powi` (and its run-time library routine), so a table built with it
/// has the same bits as one built with `powi`.
fn powi(mut x: f64, mut n: u32) -> f64 {
    let mut r = 1.0;
    loop {
        if n & 1 != 0 {
            r *= x;
        }
        n >>= 1;
        if n == 0 {
            return r;
        }
        x *= x;
    }
}

/// The fixed offset of octave `k`, in its lattice units:
/// `(k + 1)·(0.618034, 0.414214)` (see the [module documentation](self)).
#[must_use]
pub fn octave_offset(k: usize) -> DVec2 {
    let s = (k + 1) as f64;
    DVec2::new(0.618_034 * s, 0.414_214 * s)
}

/// The fixed offset of octave `k` of the 3-D evaluation, in its lattice
/// units: `(k + 1)·(0.618034, 0.414214, 0.732051)`, the 2-D
/// [`octave_offset`] with a third component of √3's fractional part (see the
/// [module documentation](self)).
#[must_use]
pub fn octave_offset3(k: usize) -> DVec3 {
    octave_offset(k).extend(0.732_051 * (k + 1) as f64)
}

/// fBm of `basis` band-limited to a footprint, with per-octave offsets, its
/// analytic 2-D gradient and bounds over ranges of octaves and footprints
/// (see the [module documentation](self) for the model and its sources).
///
/// ```
/// use natura_noise::{FootprintFbm, FootprintParams, Perlin, glam::DVec2};
/// let d = FootprintFbm::new(Perlin::new(7), &FootprintParams {
///     amplitude: 2.0, h: 0.8, lacunarity: 2.0, octaves: 9, wavelength: 10.0,
/// })?;
/// let p = DVec2::new(123.0, 45.0);
/// let (v, g) = d.eval_grad2(p, 0.05);
/// assert!((v - d.eval2(p, 0.05)).abs() < 1e-12);
/// assert!(v.abs() <= d.amplitude_bound(0.05));
/// assert!(g.length() <= d.lipschitz_bound(0.05));
/// assert_eq!(d.eval2(p, d.far_footprint()), 0.0);
/// # Ok::<(), natura_noise::NoiseError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct FootprintFbm<B> {
    basis: B,
    /// Octaves summed at a zero footprint.
    count: usize,
    /// Octave amplitudes `a_k` and frequencies `f_k = rᵏ/λ₀`.
    amp: [f64; MAX_OCTAVES],
    freq: [f64; MAX_OCTAVES],
    /// [`octave_offset`] of each octave.
    offset: [DVec2; MAX_OCTAVES],
    /// [`octave_offset3`] of each octave.
    offset3: [DVec3; MAX_OCTAVES],
    /// Octave `k` is present (`v(w) > k`) below the footprint `λ₀/(2rᵏ)`,
    /// widened by a relative 1e-9 so that rounding never drops one.
    nyquist: [f64; MAX_OCTAVES],
    /// `rᵏ·(1 − 1e-9)` and `rᵏ·(1 + 1e-9)` for `k` from 0 to the octave
    /// count: where `NYQUIST/(w·f₀)`, the logarithm's argument in `v(w)`,
    /// lies between two of them, `⌈v⌉` and `⌊v⌋` are known without the
    /// logarithm ([`FootprintFbm::visible_whole`]).
    whole_lo: [f64; MAX_OCTAVES + 1],
    whole_hi: [f64; MAX_OCTAVES + 1],
    /// `Σ_{j<k} a_j` and `Σ_{j<k} a_j f_j` (index `k` from 0 to the octave
    /// count), and `max_{j<k} a_j / w_min,j` for the footprint bound.
    amp_pre: [f64; MAX_OCTAVES + 1],
    lip_pre: [f64; MAX_OCTAVES + 1],
    fp_max: [f64; MAX_OCTAVES + 1],
    wavelength: f64,
    /// `1/λ₀`, the first octave's frequency.
    frequency: f64,
    lacunarity: f64,
    ln_lacunarity: f64,
    /// The basis's bound and 2-D and 3-D Lipschitz constants.
    basis_bound: f64,
    basis_lipschitz: f64,
    basis_lipschitz3: f64,
}

impl<B: Field> FootprintFbm<B> {
    /// The octaves of `basis` with parameters `p`.
    ///
    /// # Errors
    ///
    /// [`NoiseError::InvalidParam`] naming the first parameter that is NaN or
    /// out of range: `amplitude` (finite, ≥ 0), `h` (finite), `lacunarity`
    /// (finite, > 1), `octaves` (at most [`MAX_OCTAVES`]), `wavelength`
    /// (finite, > 0); [`NoiseError::Unbounded`] if the octave amplitudes
    /// would sum beyond [`MAX_BOUND`](crate::MAX_BOUND).
    pub fn new(basis: B, p: &FootprintParams) -> Result<Self> {
        let bad = |name, value, expected| {
            Err(NoiseError::InvalidParam {
                name,
                value,
                expected,
            })
        };
        if !(p.amplitude.is_finite() && p.amplitude >= 0.0) {
            return bad("amplitude", p.amplitude, "must be finite and ≥ 0");
        }
        if !p.h.is_finite() {
            return bad("h", p.h, "must be finite");
        }
        if !(p.lacunarity.is_finite() && p.lacunarity > 1.0) {
            return bad("lacunarity", p.lacunarity, "must be finite and > 1");
        }
        if p.octaves as usize > MAX_OCTAVES {
            return bad("octaves", f64::from(p.octaves), "must be at most 64");
        }
        if !(p.wavelength.is_finite() && p.wavelength > 0.0) {
            return bad("wavelength", p.wavelength, "must be finite and > 0");
        }
        let (lac, lambda0) = (p.lacunarity, p.wavelength);
        let count = if p.amplitude > 0.0 {
            p.octaves as usize
        } else {
            0
        };
        let mut f = Self {
            count,
            amp: [0.0; MAX_OCTAVES],
            freq: [0.0; MAX_OCTAVES],
            offset: [DVec2::ZERO; MAX_OCTAVES],
            offset3: [DVec3::ZERO; MAX_OCTAVES],
            nyquist: [0.0; MAX_OCTAVES],
            whole_lo: [0.0; MAX_OCTAVES + 1],
            whole_hi: [0.0; MAX_OCTAVES + 1],
            amp_pre: [0.0; MAX_OCTAVES + 1],
            lip_pre: [0.0; MAX_OCTAVES + 1],
            fp_max: [0.0; MAX_OCTAVES + 1],
            wavelength: lambda0,
            frequency: 1.0 / lambda0,
            lacunarity: lac,
            ln_lacunarity: libm::log(lac),
            basis_bound: basis.bound(),
            basis_lipschitz: basis.lipschitz2(),
            basis_lipschitz3: basis.lipschitz3(),
            basis,
        };
        for k in 0..count {
            // The crate's amplitude convention, as `Octaves` computes it.
            f.amp[k] = p.amplitude * libm::pow(lac, -(k as f64) * p.h);
            f.freq[k] = powi(lac, k as u32) / lambda0;
            f.offset[k] = octave_offset(k);
            f.offset3[k] = octave_offset3(k);
            f.nyquist[k] = 0.5 * lambda0 / powi(lac, k as u32) * (1.0 + 1e-9);
            f.amp_pre[k + 1] = f.amp_pre[k] + f.amp[k];
            f.lip_pre[k + 1] = f.lip_pre[k] + f.amp[k] * f.freq[k];
            let wmin = 0.5 * lambda0 / powi(lac, k as u32 + 1);
            f.fp_max[k + 1] = f.fp_max[k].max(f.amp[k] / wmin);
        }
        for k in 0..=count {
            let p = powi(lac, k as u32);
            f.whole_lo[k] = p * (1.0 - WHOLE_MARGIN);
            f.whole_hi[k] = p * (1.0 + WHOLE_MARGIN);
        }
        bounded("FootprintFbm", f.amplitude_between(0, count))?;
        Ok(f)
    }

    /// The basis.
    #[must_use]
    pub fn basis(&self) -> &B {
        &self.basis
    }

    /// The number of octaves summed at a zero footprint (0 when the amplitude
    /// is 0).
    #[must_use]
    pub fn octave_count(&self) -> usize {
        self.count
    }

    /// Amplitude `a_k` of octave `k < `[`octave_count`](Self::octave_count).
    #[must_use]
    pub fn amplitude(&self, k: usize) -> f64 {
        self.amp[k]
    }

    /// Frequency `f_k = rᵏ/λ₀` of octave `k < `[`octave_count`](Self::octave_count).
    #[must_use]
    pub fn frequency(&self, k: usize) -> f64 {
        self.freq[k]
    }

    /// The footprint from which on no octave is left: `λ₀/2`.
    #[must_use]
    pub fn far_footprint(&self) -> f64 {
        0.5 * self.wavelength
    }

    /// The smallest footprint that still changes the sum (every octave whole
    /// below it): `λ₀ / (2 r^octaves)`.
    #[must_use]
    pub fn finest_footprint(&self) -> f64 {
        0.5 * self.wavelength / powi(self.lacunarity, self.count as u32)
    }

    /// The real-valued number of octaves `v(w)` at footprint `w`: the
    /// crate's level-of-detail rule [`visible_octaves`](crate::fractal::lod::visible_octaves) for the base
    /// frequency `1/λ₀`, at most the octave count (all of them for `w ≤ 0`).
    #[inline]
    #[must_use]
    pub fn visible(&self, w: f64) -> f64 {
        let n = self.count as f64;
        if w <= 0.0 {
            return n;
        }
        visible_octaves_ln(w, self.frequency, self.ln_lacunarity).min(n)
    }

    /// `⌈v(w)⌉` and `⌊v(w)⌋` of [`visible`](Self::visible) without its
    /// logarithm, or `None` where they need it.
    ///
    /// `v(w) > k` exactly when the logarithm's argument `x = ½/(w·f₀)`
    /// exceeds `rᵏ`, so comparing `x` with the powers of `r` gives both
    /// whole numbers. Where `x` lies within a relative `1e-9` of a power
    /// the rounding of `v` could decide, and `None` is returned, as for a
    /// NaN footprint or an `x` that is not a normal number. Elsewhere the
    /// margin exceeds every rounding error of `v` (at most a few units in
    /// the last place of `x`, of the logarithm and of `rᵏ`, all under
    /// `1e-13` against the margin's `1e-9/ln r`), so the pair equals
    /// `(v.ceil(), v.floor())` of `visible(w)` in every case: a marcher that
    /// needs only the octave count, or the weights of the octaves below
    /// the blended one (1), skips the logarithm.
    #[inline]
    #[must_use]
    pub fn visible_whole(&self, w: f64) -> Option<(usize, usize)> {
        if w <= 0.0 {
            return Some((self.count, self.count));
        }
        let x = crate::fractal::lod::NYQUIST / (w * self.frequency);
        if !x.is_normal() {
            return None;
        }
        // The powers `rᵏ` that `x` exceeds, `v > k` for each.
        let mut above = 0;
        while above <= self.count {
            if x > self.whole_hi[above] {
                above += 1;
            } else if x >= self.whole_lo[above] {
                return None;
            } else {
                break;
            }
        }
        Some(match above {
            0 => (0, 0),
            a if a > self.count => (self.count, self.count),
            a => (a, a - 1),
        })
    }

    /// Octave `k`'s lattice point for the world point `p`: `f_k·p + o_k`.
    #[inline]
    fn point(&self, k: usize, p: DVec2) -> DVec2 {
        p * self.freq[k] + self.offset[k]
    }

    /// Octave `k`'s weighted term `c_k·a_k·N(f_k·p + o_k)` where
    /// `visible = v(w)` ([`visible`](Self::visible)). Summing the terms
    /// `k = 0, 1, …` in order from 0 gives [`eval2`](Self::eval2) bit for bit,
    /// so a marcher can sum the octaves incrementally and stop early.
    #[inline]
    #[must_use]
    pub fn octave_term(&self, k: usize, visible: f64, p: DVec2) -> f64 {
        (visible - k as f64).min(1.0) * self.amp[k] * self.basis.eval2(self.point(k, p))
    }

    /// `D(p; w)`.
    #[inline]
    #[must_use]
    pub fn eval2(&self, p: DVec2, w: f64) -> f64 {
        let n = self.visible(w);
        let mut sum = 0.0;
        for k in 0..libm::ceil(n) as usize {
            sum += self.octave_term(k, n, p);
        }
        sum
    }

    /// `D(p; w)` and its analytic gradient `∇D = Σ_k c_k a_k f_k ∇N`.
    #[inline]
    #[must_use]
    pub fn eval_grad2(&self, p: DVec2, w: f64) -> (f64, DVec2) {
        let n = self.visible(w);
        let (mut v, mut g) = (0.0, DVec2::ZERO);
        for k in 0..libm::ceil(n) as usize {
            let wk = (n - k as f64).min(1.0) * self.amp[k];
            let (nv, ng) = self.basis.eval_grad2(self.point(k, p));
            v += wk * nv;
            g += wk * self.freq[k] * ng;
        }
        (v, g)
    }

    /// Octave `k`'s lattice point for the 3-D world point `p`: `f_k·p + o_k`
    /// with the 3-D offset [`octave_offset3`].
    #[inline]
    fn point3(&self, k: usize, p: DVec3) -> DVec3 {
        p * self.freq[k] + self.offset3[k]
    }

    /// The 3-D octave term `c_k·a_k·N(f_k·p + o_k)` (as
    /// [`octave_term`](Self::octave_term), with the 3-D basis and offsets):
    /// summed in order from `k = 0` it gives [`eval3`](Self::eval3) bit for bit.
    #[inline]
    #[must_use]
    pub fn octave_term3(&self, k: usize, visible: f64, p: DVec3) -> f64 {
        (visible - k as f64).min(1.0) * self.amp[k] * self.basis.eval3(self.point3(k, p))
    }

    /// `D(p; w)` of a 3-D point: the same octaves, amplitudes, footprint
    /// rule and bounds as [`eval2`](Self::eval2), with the basis's 3-D
    /// evaluation and the offsets of [`octave_offset3`]. For volumes whose
    /// detail must stop at a pixel's footprint (Musgrave 1993, §6.3).
    #[inline]
    #[must_use]
    pub fn eval3(&self, p: DVec3, w: f64) -> f64 {
        let n = self.visible(w);
        let mut sum = 0.0;
        for k in 0..libm::ceil(n) as usize {
            sum += self.octave_term3(k, n, p);
        }
        sum
    }

    /// [`eval3`](Self::eval3) and its analytic gradient
    /// `∇D = Σ_k c_k a_k f_k ∇N` (its norm is bounded by
    /// [`lipschitz_bound3`](Self::lipschitz_bound3)).
    #[inline]
    #[must_use]
    pub fn eval_grad3(&self, p: DVec3, w: f64) -> (f64, DVec3) {
        let n = self.visible(w);
        let (mut v, mut g) = (0.0, DVec3::ZERO);
        for k in 0..libm::ceil(n) as usize {
            let wk = (n - k as f64).min(1.0) * self.amp[k];
            let (nv, ng) = self.basis.eval_grad3(self.point3(k, p));
            v += wk * nv;
            g += wk * self.freq[k] * ng;
        }
        (v, g)
    }

    /// A bound on `|∇D(·; w')|` of the 3-D evaluation for every `w' ≥ w`:
    /// `L_N·Σ c_k(w) a_k f_k` with the basis's 3-D Lipschitz constant.
    #[must_use]
    pub fn lipschitz_bound3(&self, w: f64) -> f64 {
        self.lipschitz_bound(w) / self.basis_lipschitz * self.basis_lipschitz3
    }

    /// A bound on `|Σ_{k0 ≤ k < k1} c_k a_k N_k|` at any footprint (the
    /// octaves `k0..k1`, `k0 ≤ k1 ≤ `[`octave_count`](Self::octave_count)).
    #[inline]
    #[must_use]
    pub fn amplitude_between(&self, k0: usize, k1: usize) -> f64 {
        (self.amp_pre[k1] - self.amp_pre[k0]) * self.basis_bound
    }

    /// A bound on the gradient of the first `k` octaves at any footprint
    /// (every weight taken as 1): `L_N·Σ_{j<k} a_j f_j`.
    #[inline]
    #[must_use]
    pub fn lipschitz_first(&self, k: usize) -> f64 {
        self.lip_pre[k] * self.basis_lipschitz
    }

    /// A bound on `|D(·; w')|` for every `w' ≥ w`: the sum of the amplitudes
    /// of the octaves present at `w`.
    #[must_use]
    pub fn amplitude_bound(&self, w: f64) -> f64 {
        let present = self.nyquist[..self.count]
            .iter()
            .take_while(|&&f| w < f)
            .count();
        self.amp_pre[present] * self.basis_bound
    }

    /// A bound on `|∇D(·; w')|` for every `w' ≥ w`: `L_N·Σ c_k(w) a_k f_k`.
    #[must_use]
    pub fn lipschitz_bound(&self, w: f64) -> f64 {
        let n = self.visible(w);
        let mut s = 0.0;
        for k in 0..libm::ceil(n) as usize {
            s += (n - k as f64).min(1.0) * self.amp[k] * self.freq[k];
        }
        s * self.basis_lipschitz
    }

    /// A bound on `|∂D/∂w'|` for every `w' ≥ w`. Only the octave being
    /// blended depends on `w'`: `|∂D/∂w'| ≤ B_N·a_k / (w' ln r)` while
    /// `v(w') ∈ [k, k + 1)`, where `w' ≥ λ₀/(2 r^(k+1))`.
    #[must_use]
    pub fn footprint_bound(&self, w: f64) -> f64 {
        self.footprint_bound_visible(w, self.visible(w))
    }

    /// [`footprint_bound`](Self::footprint_bound) with `visible = v(w)`
    /// already known.
    #[inline]
    #[must_use]
    pub fn footprint_bound_visible(&self, w: f64, visible: f64) -> f64 {
        if visible <= 0.0 {
            return 0.0;
        }
        self.footprint_bound_floor(w, libm::floor(visible) as usize)
    }

    /// [`footprint_bound`](Self::footprint_bound) with `(⌈v(w)⌉, ⌊v(w)⌋)`
    /// already known ([`visible_whole`](Self::visible_whole)); the same
    /// value as [`footprint_bound_visible`](Self::footprint_bound_visible).
    #[inline]
    #[must_use]
    pub fn footprint_bound_whole(&self, w: f64, (ceil, floor): (usize, usize)) -> f64 {
        // `v ≤ 0` exactly when its ceiling is 0 (`v` is never negative).
        if ceil == 0 {
            return 0.0;
        }
        self.footprint_bound_floor(w, floor)
    }

    /// The footprint bound for `v(w) > 0` with `⌊v(w)⌋ = floor`.
    #[inline]
    fn footprint_bound_floor(&self, w: f64, floor: usize) -> f64 {
        let top = self.count;
        let kstar = floor.min(top);
        let mut b = 0.0f64;
        if kstar < top && w > 0.0 {
            b = self.amp[kstar] / w;
        }
        b = b.max(self.fp_max[kstar]);
        b * self.basis_bound / self.ln_lacunarity
    }
}

impl FootprintFbm<crate::Perlin> {
    /// [`eval3`](Self::eval3) at many points in `f32` lanes: `out[i]` is
    /// `Σ_k c_k(w[i])·a_k·N(f_k·p_i + o_k)` over the point's own octaves,
    /// each octave's noise from the lane kernel of
    /// [`Perlin::fill_points3`](crate::Perlin::fill_points3) (within 1e-5
    /// of the point path's noise) and the sum in `f32`, in octave order.
    /// The octaves of all the points go through the kernel together, and a
    /// point's value depends on that point alone, not on the others in the
    /// batch or their number: a batch of one gives the same bits, so a
    /// field can evaluate its points one by one or together and see one
    /// field.
    ///
    /// # Errors
    ///
    /// [`NoiseError::BufferLength`] if a slice is not as long as `out`.
    pub fn fill_points3(
        &self,
        x: &[f64],
        y: &[f64],
        z: &[f64],
        w: &[f64],
        out: &mut [f32],
    ) -> Result<()> {
        for len in [x.len(), y.len(), z.len(), w.len()] {
            if len != out.len() {
                return Err(NoiseError::BufferLength {
                    expected: out.len(),
                    got: len,
                });
            }
        }
        // Small scratch for one point, so single points stay cheap; for
        // more, four octaves of 16 points per pass of the kernel (the
        // scratch is zeroed on every call, so it is kept small).
        if out.len() <= 1 {
            self.points_lanes::<1, 32>(x, y, z, w, out)
        } else {
            self.points_lanes::<16, 64>(x, y, z, w, out)
        }
    }

    /// [`fill_points3`](Self::fill_points3) in chunks of `P` points with
    /// `L ≥ P` lanes of scratch.
    fn points_lanes<const P: usize, const L: usize>(
        &self,
        x: &[f64],
        y: &[f64],
        z: &[f64],
        w: &[f64],
        out: &mut [f32],
    ) -> Result<()> {
        let mut lanes = Lanes::<L> {
            x: [0.0; L],
            y: [0.0; L],
            z: [0.0; L],
            noise: [0.0; L],
            weight: [0.0; L],
            who: [0; L],
            len: 0,
        };
        let (mut vis, mut top) = ([0.0f64; P], [0usize; P]);
        for (c, acc) in out.chunks_mut(P).enumerate() {
            let r = c * P..c * P + acc.len();
            let mut most = 0;
            for (i, j) in r.clone().enumerate() {
                vis[i] = self.visible(w[j]);
                top[i] = (libm::ceil(vis[i]) as usize).min(self.count);
                most = most.max(top[i]);
            }
            acc.fill(0.0);
            for k in 0..most {
                if lanes.len + acc.len() > L {
                    lanes.flush(&self.basis, acc)?;
                }
                let (f, o) = (self.freq[k], self.offset3[k]);
                for (i, j) in r.clone().enumerate() {
                    if k < top[i] {
                        let n = lanes.len;
                        lanes.x[n] = x[j] * f + o.x;
                        lanes.y[n] = y[j] * f + o.y;
                        lanes.z[n] = z[j] * f + o.z;
                        lanes.weight[n] = ((vis[i] - k as f64).min(1.0) * self.amp[k]) as f32;
                        lanes.who[n] = i;
                        lanes.len += 1;
                    }
                }
            }
            lanes.flush(&self.basis, acc)?;
        }
        Ok(())
    }
}

/// The octave lanes of [`FootprintFbm::fill_points3`] waiting for the kernel:
/// lattice points, weights, and the point each belongs to.
struct Lanes<const L: usize> {
    x: [f64; L],
    y: [f64; L],
    z: [f64; L],
    noise: [f32; L],
    weight: [f32; L],
    who: [usize; L],
    len: usize,
}

impl<const L: usize> Lanes<L> {
    /// Runs the kernel over the waiting lanes and adds each weighted value
    /// to its point's sum, in the order the lanes were added.
    fn flush(&mut self, basis: &crate::Perlin, acc: &mut [f32]) -> Result<()> {
        let n = self.len;
        basis.fill_points3(
            &self.x[..n],
            &self.y[..n],
            &self.z[..n],
            &mut self.noise[..n],
        )?;
        for l in 0..n {
            acc[self.who[l]] += self.weight[l] * self.noise[l];
        }
        self.len = 0;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powi_has_the_bits_of_the_standard_powi() {
        for x in [
            2.0,
            2.1,
            1.5,
            3.7,
            16.0,
            1.000_1,
            core::f64::consts::E - 0.5,
        ] {
            for n in 0..70u32 {
                assert_eq!(powi(x, n).to_bits(), x.powi(n as i32).to_bits(), "{x}^{n}");
            }
        }
    }
}
