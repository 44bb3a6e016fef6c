//! The ridge by position: fractal statistics by altitude multiplied by a
//! tent across the terrain, a mountain ridge (Plate 2.6 of Musgrave 1993).

use glam::DVec3;
use natura_noise::{Fbm, Field, Perlin, StatsByAltitude, StatsByAltitudeParams};

use crate::error::{Result, direction, finite, positive};
use crate::footprint::{Footprint, fbm_at};
use crate::fractals::{fbm, perlin, spectral};
use crate::texture::{Sample, SolidTexture, TextureKind};

/// The tent `F(x) = min(2x, 2 − 2x)`: 0 at `x = 0` and `x = 1`, 1 at `x = ½`.
///
/// **Erratum corrected.** The dissertation prints it as `F(x) = [2x, 2 − 2x]`
/// (Musgrave 1993, §2.3.2.3.3), a pair rather than a function; the 1989 paper
/// gives the minimum (Musgrave et al. 1989, §3.3), which is what this is.
#[must_use]
pub fn tent(x: f64) -> f64 {
    (2.0 * x).min(2.0 - 2.0 * x)
}

/// Parameters of [`Ridge`]. The sources give no values for the plate; these
/// make one ridge per unit along `axis`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct RidgeParams {
    /// Seed of the noises.
    pub seed: u64,
    /// The statistics-by-altitude fractal (`c_t`, `c_s`, `c_0`, spectrum);
    /// natura-noise's defaults.
    pub altitude: StatsByAltitudeParams,
    /// The direction across the ridge (x).
    pub axis: DVec3,
    /// Distance between ridge crests along `axis` (1).
    pub period: f64,
    /// Amplitude of the `1/f³` noise added to the position before the tent
    /// (0.1): bends the ridge line.
    pub perturbation: f64,
}

impl Default for RidgeParams {
    fn default() -> Self {
        Self {
            seed: 0,
            altitude: StatsByAltitudeParams::default(),
            axis: DVec3::X,
            period: 1.0,
            perturbation: 0.1,
        }
    }
}

impl RidgeParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        self.altitude.validate()?;
        direction("axis", self.axis)?;
        positive("period", self.period)?;
        finite("perturbation", self.perturbation)?;
        Ok(())
    }
}

/// Musgrave's ridge (Musgrave 1993, §2.3.2.3.3 and Plate 2.6; Musgrave et al.
/// 1989, §3.3): the first octave of the statistics-by-altitude fractal is
/// multiplied by the tent [`tent`] of the position across the ridge,
///
/// ```text
/// A_0 = F(x)·(N(p) + c_t)·c_s + c_0,     x = frac(p·axis/period + perturbation·fBm_{H=1}(p))
/// ```
///
/// and the cascade `A_k = A_{k−1}·(1 + (N_k + c_t)·c_s·w_k)` carries the
/// ridge to every scale: high ground along the crest is rough, the flanks
/// smooth. "Noise (1/f³)" is added to `x` before `F` (amplitude ∝ `1/f` per
/// octave, i.e. fBm with `H = 1`). The cascade is linear in `A_0`, so
/// `A_n = F·S(p) + c_0·Π(p)` with `S` the fractal for `c_0 = 0` and `Π` the
/// product of the octave factors, and the tent is periodic (`frac`).
#[derive(Clone, Debug)]
pub struct Ridge {
    params: RidgeParams,
    axis: DVec3,
    zero_base: StatsByAltitude<Perlin>,
    unit_base: StatsByAltitude<Perlin>,
    wobble: Fbm<Perlin>,
}

impl Ridge {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`RidgeParams::validate`].
    pub fn new(params: RidgeParams) -> Result<Self> {
        params.validate()?;
        let basis = perlin(params.seed, "ridge");
        let zero = StatsByAltitudeParams {
            sea_level: 0.0,
            ..params.altitude
        };
        let unit = StatsByAltitudeParams {
            sea_level: 1.0,
            ..params.altitude
        };
        Ok(Self {
            axis: params.axis.normalize(),
            zero_base: StatsByAltitude::new(basis, zero)?,
            unit_base: StatsByAltitude::new(basis, unit)?,
            wobble: fbm(params.seed, "ridge line", spectral(1.0, 2.0, 6.0))?,
            params,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &RidgeParams {
        &self.params
    }

    /// The perturbed position across the ridge, in `[0, 1)`.
    #[must_use]
    pub fn position(&self, p: DVec3, fp: Footprint) -> f64 {
        let q = &self.params;
        let x = p.dot(self.axis) / q.period + q.perturbation * fbm_at(&self.wobble, p, fp);
        let f = x - x.floor();
        if f < 1.0 { f } else { 0.0 }
    }

    /// The altitude at `p`.
    #[must_use]
    pub fn height(&self, p: DVec3, fp: Footprint) -> f64 {
        let s = self.zero_base.eval3(p);
        let product = self.unit_base.eval3(p) - s;
        tent(self.position(p, fp)) * s + self.params.altitude.sea_level * product
    }
}

impl SolidTexture for Ridge {
    fn name(&self) -> &'static str {
        "ridge"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Height
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::height(self.height(p, fp))
    }
}
