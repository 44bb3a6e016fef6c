//! Level of detail: the one rule that turns the width of what a sample
//! covers into the real-valued number of octaves a fractal may show there.
//!
//! Musgrave's scheme (Musgrave 1993, §5.1.2) makes the number of iterations
//! of the fractal loop a parameter given by the screen resolution, and the
//! fractional remainder octave (§2.3.2.1) keeps the sum continuous in it; the
//! band-limited evaluations ([`Fbm::eval3_band`](crate::Fbm::eval3_band) and
//! its siblings) take that number. This module places the octaves against
//! the footprint by the sampling theorem.
//!
//! Samples `w` apart represent frequencies up to the Nyquist limit `1/(2w)`
//! (Shannon 1949, §II, Theorem 1); power above it folds back as aliasing.
//! Gradient noise of lattice frequency `f` has its power at and below `f`:
//! the periodogram of [`Perlin`](crate::Perlin) along a line keeps about 1 %
//! of its power above `f` and 0.01 % above `2f`, but about 30 % between
//! `f/2` and `f` (measured by the crate's tests). So octave `k`, of lattice
//! frequency `f_k = f₀·rᵏ`, is resolved while `f_k ≤ 1/(2w)`. Fading an
//! octave scales it but does not lower its frequencies, so an octave that
//! still has weight above the limit aliases in proportion to that weight:
//! the fade must be over by the time `f_k` reaches `1/(2w)`. With the
//! fractional-octave weight `clamp(v − k, 0, 1)` of the band-limited sums
//! that gives
//!
//! `v(w) = log_r(1 / (2·w·f₀))`,
//!
//! so octave `k` is whole while `f_k ≤ 1/(2rw)`, fades linearly in `log f`
//! over the octave below the limit, and has weight exactly 0 from
//! `f_k = 1/(2w)` on. Sampled `w` apart, an fBm with `H = ½` summed this far
//! keeps under 1.5·10⁻⁴ of its power above the limit; one octave more gives
//! 2.5·10⁻⁴ to 2·10⁻³ (the crate's tests).
//!
//! The rule is alias-free, not the sum closest to an ideal low-pass at the
//! limit: an octave with `f_k` just below `1/(2w)` has 99 % of its power
//! below the limit yet is already faded, so the sum misses 5 % to 20 % of
//! the fBm's power below the limit at `H = ½` (1.5 % to 6 % with one octave
//! more, which aliases 30 times as much or more), and a box filter over the
//! footprint keeps more of the fading octave than the rule does. It trades
//! that blur for the absence of shimmer. natura-texture's footprint rule
//! was `1 + log_r(½/(w·f₀))`, one octave more: it kept each octave whole up
//! to the limit and faded it over the octave *above* it, so every footprint
//! showed a partly aliased octave. It now calls this function, as
//! natura-trace's detail does (whose rule was already this one).

/// `width × lattice frequency` at which an octave is gone: the Nyquist limit
/// of samples `width` apart, half a cycle per sample.
pub const NYQUIST: f64 = 0.5;

/// The real-valued number of octaves of a fractal with base (lattice)
/// frequency `frequency` and lacunarity `lacunarity` that samples `width`
/// apart may show: `v = log_r(1 / (2·width·f₀))`, at least 0 (see the
/// [module documentation](self) for why). Octave `k` then has the band
/// factor `clamp(v − k, 0, 1)` ([`Octaves::band_factor`](crate::Octaves::band_factor)):
/// 1 while `width·f_k ≤ ½/r`, 0 from `width·f_k ≥ ½` on.
///
/// A `width ≤ 0` is a point sample (`+∞`, every octave); a NaN argument
/// gives NaN. `lacunarity` must be `> 1` (as [`Spectral`](crate::Spectral)
/// requires) and `frequency > 0`; otherwise the count is meaningless (NaN or
/// 0), never a panic.
#[must_use]
pub fn visible_octaves(width: f64, frequency: f64, lacunarity: f64) -> f64 {
    if lacunarity.is_nan() {
        return f64::NAN;
    }
    visible_octaves_ln(width, frequency, libm::log(lacunarity))
}

/// [`visible_octaves`] with the lacunarity's natural logarithm given
/// (a caller that asks for every sample keeps it and saves one logarithm a
/// call); the same bits as [`visible_octaves`] for `ln_lacunarity =
/// libm::log(lacunarity)`.
#[inline]
#[must_use]
pub(crate) fn visible_octaves_ln(width: f64, frequency: f64, ln_lacunarity: f64) -> f64 {
    if width.is_nan() || frequency.is_nan() || ln_lacunarity.is_nan() {
        return f64::NAN;
    }
    if width <= 0.0 {
        return f64::INFINITY;
    }
    let v = libm::log(NYQUIST / (width * frequency)) / ln_lacunarity;
    if v > 0.0 { v } else { 0.0 }
}

impl crate::Spectral {
    /// [`visible_octaves`] for these parameters' base frequency and
    /// lacunarity: the octaves samples `width` apart may show.
    #[must_use]
    pub fn visible_octaves(&self, width: f64) -> f64 {
        visible_octaves(width, self.frequency, self.lacunarity)
    }
}
