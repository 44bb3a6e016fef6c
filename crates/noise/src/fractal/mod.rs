//! Fractals: sums and cascades of scaled basis octaves.
//!
//! All fractals share one parameterisation ([`Spectral`]): the spectral
//! exponent `H`, the lacunarity `λ`, a real-valued octave count and a base
//! frequency, with the per-octave weights precomputed once ([`Octaves`]).
//!
//! **Amplitude convention.** The sources use three. The canonical one here is
//! the sources' C code: octave `k` (counting from 0) has amplitude `λ^(−kH)`
//! (Musgrave 1993, §2.3.2.1 and §2.3.2.5.1), which gives a power spectrum `∝
//! f^−(2H+1)`, i.e. `β = 2H + 1`. The two others are available through
//! [`GainConvention`] to reproduce their pictures: `HalfBeta` (`ϖ = λ^−(H+½)`,
//! the equations of Musgrave 1993, §2.3.2.1, and Musgrave et al. 1989, §3.3,
//! and `PLANET`) and `Raw` (a gain `ω` passed directly, `VLfBm`/`VfBm`/`MVfBm`,
//! RenderMan `vfBm`). The dissertation's pseudo-code computes the amplitude as
//! `pow(r, −H·octave)` starting from octave 2, an off-by-one against its own C
//! code; that is not reproduced: the first octave has amplitude 1.
//!
//! **Fractional octaves** (Musgrave 1993, §2.3.2.1 and §2.3.2.5.1): with
//! `octaves = n + t`, the partial octave `n` enters with its amplitude scaled
//! by `t`, so every fractal is continuous (piecewise linear for fBm) in
//! `octaves`.
//!
//! **Lacunarity**: the default is MojoWorld's `e − ½ ≈ 2.218` (Musgrave 2001,
//! "Lacunarity: The Gap Between Successive Frequencies"). With an integer
//! lacunarity and gradient noise every octave vanishes on the integer lattice,
//! so fBm is identically 0 there (our observation; the sources' misregistration
//! offsets have the same cause); the non-integer default avoids that
//! coincidence.

pub mod altitude;
mod band;
pub(crate) mod batch_rows;
pub mod cascade;
pub mod crossover;
#[cfg(feature = "alloc")]
pub mod driven;
pub mod fbm;
pub mod filtered;
pub mod footprint;
pub mod hetero;
pub mod hybrid;
pub mod lod;
pub mod ridged;
pub mod vector_multifractal;

use crate::error::{NoiseError, Result, finite, in_range};

/// The largest octave count any fractal accepts.
pub const MAX_OCTAVES: usize = 64;

/// The largest bound on `|f|` a fractal may have: every value then fits an
/// `f32` with a wide margin, and no intermediate overflows `f64`. Parameters
/// that would exceed it are refused ([`NoiseError::Unbounded`]).
pub const MAX_BOUND: f64 = 1e30;

/// The highest octave's frequency may be at most this multiple of the base
/// frequency: beyond it, `f64` coordinates of order 1 no longer resolve the
/// lattice cell finely (≈ 2⁻²⁰ of a cell at 2³²).
pub const MAX_FREQUENCY_RATIO: f64 = 4_294_967_296.0;

/// How the per-octave amplitude follows from the `h` parameter (see the
/// module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
// Variants keep their names in files: `H` is the sources' symbol.
pub enum GainConvention {
    /// Octave `k` has amplitude `λ^(−k·H)`: the sources' C code, `β = 2H + 1`. The default.
    #[default]
    H,
    /// Octave `k` has amplitude `ϖ^k` with `ϖ = λ^−(H+½)`: the sources' equations,
    /// `PLANET` and `luna`.
    HalfBeta,
    /// Octave `k` has amplitude `ω^k` with `ω = h` given directly ("omega").
    Raw,
}

/// The spectral parameters every fractal shares.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct Spectral {
    /// Spectral exponent `H` (Hölder exponent; `D_f = D_E + 1 − H`, Musgrave
    /// 1993, §2.2.1.4), or the raw gain `ω` under [`GainConvention::Raw`].
    /// Larger `H` gives smoother results (less high-frequency amplitude). Any
    /// finite value; `ω` must be positive.
    pub h: f64,
    /// Frequency ratio between successive octaves, `λ > 1`. Above ≈ 2 the
    /// individual octaves start to show (Musgrave 2001, "Lacunarity: The Gap
    /// Between Successive Frequencies").
    pub lacunarity: f64,
    /// Number of octaves, real-valued, in `(0, 64]`; the last partial octave is
    /// weighted by the fractional part. Fewer than 3 is not meaningfully
    /// fractal Musgrave 1993, §2.2.1.2.
    pub octaves: f64,
    /// Frequency of the first octave (cycles of the basis lattice per unit), `> 0`.
    pub frequency: f64,
    /// How `h` becomes amplitudes.
    pub convention: GainConvention,
}

impl Default for Spectral {
    /// `H = 0.5`, `λ = e − ½`, 8 octaves, frequency 1 (the RenderMan defaults
    /// of Musgrave 1998, "Puffy Clouds", MojoWorld λ).
    fn default() -> Self {
        Self {
            h: 0.5,
            lacunarity: DEFAULT_LACUNARITY,
            octaves: 8.0,
            frequency: 1.0,
            convention: GainConvention::H,
        }
    }
}

/// MojoWorld's default lacunarity `e − ½` (Musgrave 2001, "Lacunarity: The Gap
/// Between Successive Frequencies"): not an integer, so octave lattices never
/// coincide.
pub const DEFAULT_LACUNARITY: f64 = core::f64::consts::E - 0.5;

impl Spectral {
    /// These parameters with `H = h`.
    #[must_use]
    pub fn with_h(mut self, h: f64) -> Self {
        self.h = h;
        self
    }

    /// These parameters with lacunarity `l`.
    #[must_use]
    pub fn with_lacunarity(mut self, l: f64) -> Self {
        self.lacunarity = l;
        self
    }

    /// These parameters with `n` octaves.
    #[must_use]
    pub fn with_octaves(mut self, n: f64) -> Self {
        self.octaves = n;
        self
    }

    /// These parameters with base frequency `f`.
    #[must_use]
    pub fn with_frequency(mut self, f: f64) -> Self {
        self.frequency = f;
        self
    }

    /// These parameters with gain convention `c`.
    #[must_use]
    pub fn with_convention(mut self, c: GainConvention) -> Self {
        self.convention = c;
        self
    }

    /// Checks every parameter: finite `h` (positive under `Raw`), `λ > 1`,
    /// `0 < octaves ≤ 64` within the precision limit, `frequency > 0`.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] naming the first parameter that is NaN, infinite or outside its domain, or [`NoiseError::OctavesBeyondPrecision`] if the octave count passes the precision limit for the lacunarity.
    pub fn validate(&self) -> Result<()> {
        // The table the checks compute is the one `octaves_table` returns:
        // remembered, so a constructor that validates and then asks for
        // the table computes it once.
        self.octaves_table().map(|_| ())
    }

    /// [`validate`](Self::validate)'s checks, returning the octave table
    /// they compute (one table, not one for the check and another for the
    /// caller: its amplitudes are a `pow` each).
    fn checked_table(&self) -> Result<Octaves> {
        finite("h", self.h)?;
        if self.convention == GainConvention::Raw && self.h <= 0.0 {
            return Err(NoiseError::InvalidParam {
                name: "h",
                value: self.h,
                expected: "the raw gain ω must be > 0",
            });
        }
        if !(self.lacunarity.is_finite() && self.lacunarity > 1.0) {
            return Err(NoiseError::InvalidParam {
                name: "lacunarity",
                value: self.lacunarity,
                expected: "must be finite and > 1",
            });
        }
        in_range(
            "octaves",
            self.octaves,
            f64::MIN_POSITIVE,
            MAX_OCTAVES as f64,
            "must be in (0, 64]",
        )?;
        if !(self.frequency.is_finite() && self.frequency > 0.0) {
            return Err(NoiseError::InvalidParam {
                name: "frequency",
                value: self.frequency,
                expected: "must be finite and > 0",
            });
        }
        let table = Octaves::new(self);
        let amplitudes = table.weight_sum();
        if !(amplitudes.is_finite() && amplitudes <= MAX_BOUND) {
            return Err(NoiseError::InvalidParam {
                name: "h",
                value: self.h,
                expected: "the octave amplitudes it gives must sum to at most 1e30",
            });
        }
        let top = libm::pow(self.lacunarity, libm::ceil(self.octaves) - 1.0);
        if top > MAX_FREQUENCY_RATIO {
            let max =
                libm::floor(libm::log(MAX_FREQUENCY_RATIO) / libm::log(self.lacunarity)) + 1.0;
            return Err(NoiseError::OctavesBeyondPrecision {
                octaves: self.octaves,
                lacunarity: self.lacunarity,
                top_frequency: top,
                max_octaves: max,
            });
        }
        Ok(table)
    }

    /// The per-octave gain ratio this convention gives (`λ^−H`, `λ^−(H+½)` or `ω`).
    #[must_use]
    pub fn gain(&self) -> f64 {
        match self.convention {
            GainConvention::H => libm::pow(self.lacunarity, -self.h),
            GainConvention::HalfBeta => libm::pow(self.lacunarity, -self.h - 0.5),
            GainConvention::Raw => self.h,
        }
    }

    /// Precomputes the octave table (call after [`validate`](Self::validate)).
    ///
    /// # Errors
    /// As [`Spectral::validate`].
    pub fn octaves_table(&self) -> Result<Octaves> {
        #[cfg(feature = "std")]
        return self.remembered_table();
        #[cfg(not(feature = "std"))]
        self.checked_table()
    }

    /// [`checked_table`](Self::checked_table), remembering per thread the
    /// table of the last parameters asked for: a fractal built again and
    /// again with the same parameters (a binding's call per point, a loop)
    /// skips the checks' and the amplitudes' `pow` calls. Only valid
    /// parameters are kept, compared bit for bit, so a hit returns the very
    /// table they compute.
    #[cfg(feature = "std")]
    fn remembered_table(&self) -> Result<Octaves> {
        std::thread_local! {
            static LAST: core::cell::RefCell<Option<(Spectral, Octaves)>> =
                const { core::cell::RefCell::new(None) };
        }
        let same = |a: &Spectral| {
            a.h.to_bits() == self.h.to_bits()
                && a.lacunarity.to_bits() == self.lacunarity.to_bits()
                && a.octaves.to_bits() == self.octaves.to_bits()
                && a.frequency.to_bits() == self.frequency.to_bits()
                && a.convention == self.convention
        };
        let hit = LAST.with_borrow(|last| {
            last.as_ref()
                .filter(|(s, _)| same(s))
                .map(|(_, t)| t.clone())
        });
        if let Some(table) = hit {
            return Ok(table);
        }
        let table = self.checked_table()?;
        LAST.with_borrow_mut(|last| *last = Some((*self, table.clone())));
        Ok(table)
    }
}

/// Precomputed octave table: frequency and amplitude of every octave.
#[derive(Clone, Debug, PartialEq)]
pub struct Octaves {
    freq: [f64; MAX_OCTAVES],
    amp: [f64; MAX_OCTAVES],
    /// `amp[k]` times the partial factor of octave `k`.
    weight: [f64; MAX_OCTAVES],
    count: usize,
    fraction: f64,
}

impl Octaves {
    fn new(s: &Spectral) -> Self {
        let mut freq = [0.0; MAX_OCTAVES];
        let mut amp = [0.0; MAX_OCTAVES];
        let full = libm::floor(s.octaves);
        let fraction = s.octaves - full;
        let count = (full as usize + usize::from(fraction > 0.0)).min(MAX_OCTAVES);
        let mut f = s.frequency;
        for k in 0..count {
            freq[k] = f;
            // pow per octave rather than repeated multiplication, so the
            // weights are exact to the last ulp for every k.
            amp[k] = match s.convention {
                GainConvention::H => libm::pow(s.lacunarity, -(k as f64) * s.h),
                GainConvention::HalfBeta => libm::pow(s.lacunarity, -(k as f64) * (s.h + 0.5)),
                GainConvention::Raw => libm::pow(s.h, k as f64),
            };
            f *= s.lacunarity;
        }
        let mut o = Self {
            freq,
            amp,
            weight: [0.0; MAX_OCTAVES],
            count,
            fraction,
        };
        for k in 0..count {
            o.weight[k] = o.amp[k] * o.partial(k);
        }
        o
    }

    /// Number of octaves evaluated (the partial one included).
    #[must_use]
    pub fn count(&self) -> usize {
        self.count
    }

    /// Frequency of octave `k` (base frequency × `λ^k`).
    #[must_use]
    pub fn frequency(&self, k: usize) -> f64 {
        self.freq[k]
    }

    /// Full amplitude of octave `k` (before the fractional-octave factor).
    #[must_use]
    pub fn amplitude(&self, k: usize) -> f64 {
        self.amp[k]
    }

    /// The factor of octave `k` in the sum: 1, or the fractional part of
    /// `octaves` for the last, partial octave.
    #[must_use]
    pub fn partial(&self, k: usize) -> f64 {
        if k + 1 == self.count && self.fraction > 0.0 {
            self.fraction
        } else {
            1.0
        }
    }

    /// Amplitude × partial factor of octave `k`: the fBm weight.
    #[must_use]
    #[inline]
    pub fn weight(&self, k: usize) -> f64 {
        self.weight[k]
    }

    /// The frequencies of the octaves evaluated, lowest first.
    #[must_use]
    #[inline]
    pub fn frequencies(&self) -> &[f64] {
        &self.freq[..self.count]
    }

    /// The weights (amplitude × partial factor) of the octaves evaluated.
    #[must_use]
    #[inline]
    pub fn weights(&self) -> &[f64] {
        &self.weight[..self.count]
    }

    /// `Σ_k weight(k)`.
    #[must_use]
    pub fn weight_sum(&self) -> f64 {
        (0..self.count).map(|k| self.weight(k)).sum()
    }

    /// `Σ_k weight(k)·frequency(k)`: the factor turning a basis Lipschitz
    /// constant into the fBm's.
    #[must_use]
    pub fn weighted_frequency_sum(&self) -> f64 {
        (0..self.count).map(|k| self.weight(k) * self.freq[k]).sum()
    }
}

/// Rows are processed in chunks of this many points with stack scratch buffers
/// (no heap allocation in any batch path).
pub(crate) const CHUNK: usize = 256;
