//! The statistical FFT wave model on a periodic patch (Tessendorf 2001,
//! §3.3-3.5 and §3.7; slides "Random surface generation", "Choppy waves").

use std::sync::Arc;

use glam::{DVec2, Vec2};
use natura_core::Seed;
use natura_core::fft::{self, Complex, Fft, FftDirection};

use crate::dispersion::{Dispersion, Quantized};
use crate::error::{OceanError, Result, in_range, invalid, non_negative, positive};
use crate::frame::Frame;
use crate::spectrum::Spectrum;

/// Smallest and largest grid side the FFT model accepts (Tessendorf 2001, §3.4).
pub const MIN_SIZE: usize = 16;
/// Largest grid side; above it "the limits of numerical accuracy for floating
/// point calculations can become noticeable" (Tessendorf 2001, §3.4).
pub const MAX_SIZE: usize = 2048;

/// How the random amplitudes h̃₀(k) are drawn. Both give E|h̃₀|² = ½ P Δk².
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum AmplitudeScheme {
    /// The notes' eq. 25 (§3.4): (ξ_r + i ξ_i)/√2 · √(½ P Δk²) with
    /// ξ_r, ξ_i ~ N(0, 1): a circular complex Gaussian, matching the
    /// "statistically stationary, independent, gaussian fluctuations" the
    /// data show (§3.3).
    #[default]
    ComplexGaussian,
    /// The slides' form ("Simulation of a Random Surface"): ξ e^{iθ} √(½ P Δk²), ξ ~ N(0, 1),
    /// θ ~ U[0, 2π): same variance, but |h̃₀| is half-normal, not Rayleigh.
    GaussianUniformPhase,
}

/// Parameters of an ocean patch. `Default` is the source's Figs. 6-8 grid:
/// 512 × 512 samples over 1000 m × 1000 m (§3.5), deep water, no chop.
///
/// The world is z-up: the notes' horizontal (x, z) become (x, y) here and
/// their height y becomes z. Sample (i, j) sits at rest position
/// (i·Lx/N, j·Ly/M), i.e. Δx = Lx/N and Δy = Ly/M (the resolution paragraph of §3.4
/// swaps N and M; eq. 19 is right).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct OceanParams {
    /// Samples along x (N): a power of two from 16 to 2048.
    pub nx: usize,
    /// Samples along y (M): a power of two from 16 to 2048.
    pub ny: usize,
    /// Patch length along x, metres. The surface repeats with this period.
    pub lx: f64,
    /// Patch length along y, metres.
    pub ly: f64,
    /// Dispersion relation for the time evolution (eq. 26).
    pub dispersion: Dispersion,
    /// If set, frequencies are quantised so the animation repeats exactly
    /// after this many seconds (eqs. 17-18).
    pub loop_period: Option<f64>,
    /// Choppiness λ ≥ 0 of the horizontal displacement: larger sharpens the
    /// crests and flattens the troughs; folds appear where the Jacobian < 0.
    ///
    /// Erratum: with the notes' eq. 29 displacement D and x + λD, λ > 0
    /// folds the *troughs*: the displaced point x + λD moves toward the
    /// crest under a trough. Here the displacement is
    /// d = −λ D, i.e. `choppiness` = −λ_Tessendorf, which sharpens crests as
    /// the text of §3.7 and Gerstner's eq. 9 intend.
    pub choppiness: f64,
    /// How the random amplitudes are drawn.
    pub amplitudes: AmplitudeScheme,
    /// Only waves with `k_min ≤ |k| < k_max` (rad/m) are kept; used by
    /// cascades to split the spectrum between patches.
    pub k_min: f64,
    /// Upper wavenumber bound (may be `f64::INFINITY`).
    pub k_max: f64,
}

impl Default for OceanParams {
    fn default() -> Self {
        Self {
            nx: 512,
            ny: 512,
            lx: 1000.0,
            ly: 1000.0,
            dispersion: Dispersion::default(),
            loop_period: None,
            choppiness: 0.0,
            amplitudes: AmplitudeScheme::default(),
            k_min: 0.0,
            k_max: f64::INFINITY,
        }
    }
}

/// Shortest patch side accepted, metres (1 mm: capillary ripples).
pub const MIN_LENGTH: f64 = 1e-3;
/// Longest patch side accepted, metres (10 000 km: an ocean basin).
pub const MAX_LENGTH: f64 = 1e7;
const PATCH_LENGTH: &str = "must be in [1e-3, 1e7] metres";
/// Largest choppiness accepted; beyond about 1 the surface already folds everywhere.
pub const MAX_CHOPPINESS: f64 = 100.0;
/// Largest bound on any output field (heights, displacements, slopes and the
/// Jacobian's derivatives) that [`Ocean::new`] accepts: far below `f32::MAX`, so
/// every field of every frame is finite.
pub const MAX_FIELD_BOUND: f64 = 1e30;

fn check_size(name: &'static str, n: usize) -> Result<()> {
    if n.is_power_of_two() && (MIN_SIZE..=MAX_SIZE).contains(&n) {
        Ok(())
    } else {
        Err(OceanError::InvalidSize { name, value: n })
    }
}

impl OceanParams {
    /// Checks every parameter and returns a typed error naming the first bad one.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidSize`](crate::OceanError::InvalidSize) for grid sides that are not powers of two in 16..=2048, and
    /// [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter) naming the first other parameter that is NaN, non-positive where it
    /// must be positive, or `k_max ≤ k_min`.
    pub fn validate(&self) -> Result<()> {
        check_size("nx", self.nx)?;
        check_size("ny", self.ny)?;
        in_range("lx", self.lx, MIN_LENGTH, MAX_LENGTH, PATCH_LENGTH)?;
        in_range("ly", self.ly, MIN_LENGTH, MAX_LENGTH, PATCH_LENGTH)?;
        self.dispersion.validate()?;
        if let Some(t) = self.loop_period {
            positive("loop_period", t)?;
        }
        in_range(
            "choppiness",
            self.choppiness,
            0.0,
            MAX_CHOPPINESS,
            "must be in [0, 100] (crests fold over near 1)",
        )?;
        non_negative("k_min", self.k_min)?;
        if self.k_max.is_nan() || self.k_max <= self.k_min {
            return Err(invalid(
                "k_max",
                self.k_max,
                "must be > k_min (may be infinite)",
            ));
        }
        Ok(())
    }

    /// Returns the sample spacing (Δx, Δy), metres.
    #[must_use]
    pub fn cell_size(&self) -> DVec2 {
        DVec2::new(self.lx / self.nx as f64, self.ly / self.ny as f64)
    }
}

/// Returns the signed frequency index of DFT bin `i` of `n`: `i` for `i < n/2`, else `i − n`.
#[inline]
pub(crate) fn signed(i: usize, n: usize) -> i64 {
    if i < n / 2 {
        i as i64
    } else {
        i as i64 - n as i64
    }
}

/// An ocean patch: the random amplitudes h̃₀(k) and frequencies ω(k) of
/// every wave, and the FFT plans to turn them into fields at any time.
///
/// Build it once with [`Ocean::new`]; then [`Ocean::evaluate_into`] fills a
/// reusable [`Frame`] for any time t with no allocation. Evaluation is
/// closed-form in t (eq. 26; "the wave field at any chosen time can be
/// computed without computing the field at any other time", §3.4), so frames
/// may be computed in any order, and `&Ocean` may be shared between threads.
///
/// Time sign: the slides' h̃(k,t) = h̃₀(k) e^{−iωt} + h̃₀*(−k) e^{+iωt}
/// ("FFT solution"), under which energy at k travels along +k̂. The Nyquist
/// row and column (n = −N/2 or m = −M/2) are zeroed: they are their own
/// partner, so their slope and displacement would not be real (a wave
/// with no partner at −k gives a complex field), and k = 0 is zeroed so the mean height is exactly 0.
#[derive(Clone)]
pub struct Ocean {
    pub(crate) params: OceanParams,
    /// h̃₀ over the full grid, row-major (index m·N + n).
    h0: Vec<Complex<f64>>,
    /// ω over the full grid, rad/s (quantised if looping).
    omega: Vec<f64>,
    // The half spectrum 0 ≤ n < N/2 used by the fast path, column-major
    // (index n·M + m), as p = h̃₀(k) + h̃₀*(−k), q = h̃₀(k) − h̃₀*(−k).
    pub(crate) p_re: Vec<f32>,
    pub(crate) p_im: Vec<f32>,
    pub(crate) q_re: Vec<f32>,
    pub(crate) q_im: Vec<f32>,
    /// ω/2π per half-spectrum entry, cycles per second.
    pub(crate) nu: Vec<f64>,
    /// 1/|k| per half-spectrum entry (0 at k = 0).
    pub(crate) inv_k: Vec<f32>,
    /// k_x for n = 0..N/2.
    pub(crate) kx: Vec<f32>,
    /// k_y for m = 0..M (signed).
    pub(crate) ky: Vec<f32>,
    pub(crate) col_fft: Arc<dyn Fft<f32>>,
    pub(crate) row_fft: Arc<dyn Fft<f32>>,
}

impl std::fmt::Debug for Ocean {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ocean")
            .field("params", &self.params)
            .finish_non_exhaustive()
    }
}

impl Ocean {
    /// Builds a patch: draws h̃₀(k) for every wave vector from `spectrum` and
    /// `seed`, computes ω(k), and plans the FFTs.
    ///
    /// Random numbers are indexed by the signed wave indices (n, m), so the
    /// same seed gives bit-identical amplitudes on every run and thread
    /// count, and changing N or M with the same patch size keeps the
    /// coarse waves identical.
    ///
    /// # Errors
    ///
    /// Returns the errors of [`OceanParams::validate`] and the spectrum's own
    /// `validate`, and [`OceanError::BadSpectrum`](crate::OceanError::BadSpectrum) if the spectrum
    /// returns a negative or non-finite density.
    pub fn new(params: &OceanParams, spectrum: &dyn Spectrum, seed: Seed) -> Result<Self> {
        params.validate()?;
        spectrum.validate()?;
        let (nx, ny) = (params.nx, params.ny);
        let dk = DVec2::new(
            std::f64::consts::TAU / params.lx,
            std::f64::consts::TAU / params.ly,
        );
        let cell = dk.x * dk.y;
        let quant = match params.loop_period {
            Some(t) => Some(Quantized::new(params.dispersion, t)?),
            None => None,
        };
        let draw = seed.derive("ocean-h0");
        let mut h0 = vec![Complex::new(0.0, 0.0); nx * ny];
        let mut omega = vec![0.0; nx * ny];
        for m in 0..ny {
            let sm = signed(m, ny);
            for n in 0..nx {
                let sn = signed(n, nx);
                let k = DVec2::new(sn as f64 * dk.x, sm as f64 * dk.y);
                let kk = k.length();
                let idx = m * nx + n;
                omega[idx] = match &quant {
                    Some(q) => crate::dispersion::DispersionRelation::omega(q, kk),
                    None => params.dispersion.omega(kk),
                };
                let nyquist = n == nx / 2 || m == ny / 2;
                if nyquist || kk == 0.0 || kk < params.k_min || kk >= params.k_max {
                    continue;
                }
                let p = spectrum.density(k);
                if !(p.is_finite() && p >= 0.0) {
                    return Err(OceanError::BadSpectrum {
                        kx: k.x,
                        ky: k.y,
                        value: p,
                    });
                }
                let amp = (0.5 * p * cell).sqrt();
                h0[idx] = match params.amplitudes {
                    AmplitudeScheme::ComplexGaussian => {
                        let xr = draw.gaussian(&[sn, sm, 0]);
                        let xi = draw.gaussian(&[sn, sm, 1]);
                        Complex::new(xr, xi) * (amp * std::f64::consts::FRAC_1_SQRT_2)
                    }
                    AmplitudeScheme::GaussianUniformPhase => {
                        let xi = draw.gaussian(&[sn, sm, 0]);
                        let th = std::f64::consts::TAU * draw.uniform(&[sn, sm, 1]);
                        Complex::from_polar(xi * amp, th)
                    }
                };
            }
        }
        // Every output field is a sum over the bins of |h̃₀| times at most
        // (1 + λ)(1 + |k|)²; refuse a spectrum whose bound would overflow f32
        // rather than return frames full of infinities.
        let k_top = DVec2::new(dk.x * (nx / 2) as f64, dk.y * (ny / 2) as f64).length();
        let sum: f64 = h0.iter().map(|c| c.norm()).sum();
        let bound = 2.0 * sum * (1.0 + params.choppiness) * (1.0 + k_top).powi(2);
        if !bound.is_finite() || bound > MAX_FIELD_BOUND {
            return Err(invalid(
                "spectrum",
                bound,
                "its amplitudes make the surface's fields overflow (bound on height, slope and Jacobian > 1e30): reduce the spectrum's amplitude or enlarge the patch",
            ));
        }
        let half = nx / 2;
        let len = half * ny;
        let mut o = Self {
            params: *params,
            h0,
            omega,
            p_re: vec![0.0; len],
            p_im: vec![0.0; len],
            q_re: vec![0.0; len],
            q_im: vec![0.0; len],
            nu: vec![0.0; len],
            inv_k: vec![0.0; len],
            kx: (0..half).map(|n| (n as f64 * dk.x) as f32).collect(),
            ky: (0..ny)
                .map(|m| (signed(m, ny) as f64 * dk.y) as f32)
                .collect(),
            col_fft: fft::plan_f32(ny, FftDirection::Inverse),
            row_fft: fft::plan_f32(nx, FftDirection::Inverse),
        };
        for n in 0..half {
            for m in 0..ny {
                let idx = m * nx + n;
                let neg = ((ny - m) % ny) * nx + (nx - n) % nx;
                let a = o.h0[idx];
                let b = o.h0[neg].conj();
                let i = n * ny + m;
                o.p_re[i] = (a.re + b.re) as f32;
                o.p_im[i] = (a.im + b.im) as f32;
                o.q_re[i] = (a.re - b.re) as f32;
                o.q_im[i] = (a.im - b.im) as f32;
                o.nu[i] = o.omega[idx] / std::f64::consts::TAU;
                let k = DVec2::new(n as f64 * dk.x, signed(m, ny) as f64 * dk.y).length();
                o.inv_k[i] = if k > 0.0 { (1.0 / k) as f32 } else { 0.0 };
            }
        }
        Ok(o)
    }

    /// Returns the parameters the patch was built with.
    #[must_use]
    pub fn params(&self) -> &OceanParams {
        &self.params
    }

    /// Returns the random amplitudes h̃₀(k), row-major over the DFT bins
    /// (index m·N + n; bin n is wave index n for n < N/2, n − N above).
    #[must_use]
    pub fn h0(&self) -> &[Complex<f64>] {
        &self.h0
    }

    /// Returns ω(k) per DFT bin (rad/s, quantised when looping), indexed as [`Ocean::h0`].
    #[must_use]
    pub fn omega(&self) -> &[f64] {
        &self.omega
    }

    /// Returns the wave vector of DFT bin (n, m), rad/m.
    #[must_use]
    pub fn wave_vector(&self, n: usize, m: usize) -> DVec2 {
        DVec2::new(
            signed(n, self.params.nx) as f64 * std::f64::consts::TAU / self.params.lx,
            signed(m, self.params.ny) as f64 * std::f64::consts::TAU / self.params.ly,
        )
    }

    /// Returns h̃(k, t) for every bin (eq. 26 with the slides' sign), in `f64`,
    /// indexed as [`Ocean::h0`]. Satisfies h̃(−k, t) = h̃(k, t)* exactly.
    #[must_use]
    pub fn spectrum_at(&self, t: f64) -> Vec<Complex<f64>> {
        let (nx, ny) = (self.params.nx, self.params.ny);
        let mut out = vec![Complex::new(0.0, 0.0); nx * ny];
        for m in 0..ny {
            for n in 0..nx {
                let idx = m * nx + n;
                let neg = ((ny - m) % ny) * nx + (nx - n) % nx;
                let ph = Complex::from_polar(1.0, -self.omega[idx] * t);
                out[idx] = self.h0[idx] * ph + self.h0[neg].conj() * ph.conj();
            }
        }
        out
    }

    /// Returns the expected height variance Σ_k ½(P(k) + P(−k)) Δk², i.e.
    /// Σ_k E|h̃(k,t)|², estimated from the drawn amplitudes' own spectrum
    /// `spectrum` over the bins this patch keeps.
    #[must_use]
    pub fn expected_variance(&self, spectrum: &dyn Spectrum) -> f64 {
        let p = &self.params;
        let cell = std::f64::consts::TAU.powi(2) / (p.lx * p.ly);
        let mut sum = 0.0;
        for m in 0..p.ny {
            for n in 0..p.nx {
                if n == p.nx / 2 || m == p.ny / 2 {
                    continue;
                }
                let k = self.wave_vector(n, m);
                let kk = k.length();
                if kk == 0.0 || kk < p.k_min || kk >= p.k_max {
                    continue;
                }
                sum += spectrum.density(k) * cell;
            }
        }
        sum
    }

    /// Evaluates every field at time `t` into `frame`, reusing its buffers:
    /// height, slope, displacement and the Jacobian terms (see [`Frame`]).
    ///
    /// Costs four complex FFT passes over half the spectrum plus four
    /// row passes, and allocates nothing.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter) if `t` is not finite and [`OceanError::SizeMismatch`](crate::OceanError::SizeMismatch) if `frame` was made for a
    /// patch of another size.
    pub fn evaluate_into(&self, t: f64, frame: &mut Frame) -> Result<()> {
        crate::error::finite("t", t)?;
        frame.check_matches(self)?;
        crate::fft::evaluate(self, t, frame);
        Ok(())
    }

    /// Returns a new [`Frame`] evaluated at time `t` (allocates; prefer
    /// [`Ocean::evaluate_into`] in a loop).
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter) if `t` is not finite.
    pub fn evaluate(&self, t: f64) -> Result<Frame> {
        let mut f = Frame::new(self)?;
        self.evaluate_into(t, &mut f)?;
        Ok(f)
    }

    /// Evaluates the fields at rest position (`x`, `y`) and time `t` by the
    /// direct sum over all waves (eq. 19, "switching to a discrete fourier
    /// transform", eq. 19) in `f64`: exact between grid points, O(N·M) per call.
    /// The reference the FFT path is tested against.
    #[must_use]
    pub fn sample_direct(&self, x: f64, y: f64, t: f64) -> DirectSample {
        let (nx, ny) = (self.params.nx, self.params.ny);
        let lam = self.params.choppiness;
        let mut s = DirectSample::default();
        for m in 0..ny {
            for n in 0..nx {
                let idx = m * nx + n;
                if self.h0[idx] == Complex::new(0.0, 0.0) {
                    let neg = ((ny - m) % ny) * nx + (nx - n) % nx;
                    if self.h0[neg] == Complex::new(0.0, 0.0) {
                        continue;
                    }
                }
                let neg = ((ny - m) % ny) * nx + (nx - n) % nx;
                let ph = Complex::from_polar(1.0, -self.omega[idx] * t);
                let h = self.h0[idx] * ph + self.h0[neg].conj() * ph.conj();
                let k = self.wave_vector(n, m);
                let e = h * Complex::from_polar(1.0, k.x * x + k.y * y);
                let kk = k.length();
                let i = Complex::new(0.0, 1.0);
                s.height += e.re;
                s.slope += DVec2::new((i * k.x * e).re, (i * k.y * e).re);
                if kk > 0.0 {
                    s.displacement +=
                        DVec2::new((i * k.x / kk * e).re, (i * k.y / kk * e).re) * lam;
                    s.jxx -= lam * k.x * k.x / kk * e.re;
                    s.jyy -= lam * k.y * k.y / kk * e.re;
                    s.jxy -= lam * k.x * k.y / kk * e.re;
                }
            }
        }
        s.jxx += 1.0;
        s.jyy += 1.0;
        s
    }

    /// Returns the patch size (Lx, Ly) in metres as `f32`.
    #[must_use]
    pub fn extent(&self) -> Vec2 {
        Vec2::new(self.params.lx as f32, self.params.ly as f32)
    }
}

/// The fields at one point from [`Ocean::sample_direct`], in `f64`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DirectSample {
    /// Height h, metres.
    pub height: f64,
    /// Slope ∇h (eq. 20).
    pub slope: DVec2,
    /// Horizontal displacement d = choppiness · Σ i k̂ h̃ e^{ik·x}, metres.
    pub displacement: DVec2,
    /// ∂X_x/∂x = 1 + ∂d_x/∂x.
    pub jxx: f64,
    /// ∂X_y/∂y = 1 + ∂d_y/∂y.
    pub jyy: f64,
    /// ∂X_x/∂y = ∂X_y/∂x.
    pub jxy: f64,
}
