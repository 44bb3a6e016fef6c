//! Wind-blown waters: ripples modulated by a large-scale turbulent wind.

use glam::DVec3;
use natura_noise::{Fbm, Perlin, Turbulence};

use crate::error::{Result, finite, non_negative, positive};
use crate::footprint::{Footprint, fbm_grad_at, turbulence_at};
use crate::fractals::{fbm, spectral, turbulence};
use crate::texture::{Sample, SolidTexture, TextureKind};

/// Parameters of [`WindyWave`]; `Default` is the `windywave` shader's plus
/// the ripple-to-wind frequency ratio its listing hard-codes (8).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct WindyWaveParams {
    /// Seed of the noises.
    pub seed: u64,
    /// Displacement amplitude `Km` (0.1).
    pub km: f64,
    /// Texture frequency (1).
    pub txtscale: f64,
    /// Frequency of the wind field (0.5): the scale of the gusts.
    pub windfreq: f64,
    /// How much the wind varies (1).
    pub windamp: f64,
    /// The calmest wind (0.3): ripples never vanish entirely.
    pub minwind: f64,
    /// How much finer the ripples are than the wind gusts (8).
    pub ripple_ratio: f64,
}

impl Default for WindyWaveParams {
    fn default() -> Self {
        Self {
            seed: 0,
            km: 0.1,
            txtscale: 1.0,
            windfreq: 0.5,
            windamp: 1.0,
            minwind: 0.3,
            ripple_ratio: 8.0,
        }
    }
}

impl WindyWaveParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        finite("km", self.km)?;
        positive("txtscale", self.txtscale)?;
        positive("windfreq", self.windfreq)?;
        non_negative("windamp", self.windamp)?;
        non_negative("minwind", self.minwind)?;
        positive("ripple_ratio", self.ripple_ratio)?;
        Ok(())
    }
}

/// Musgrave's wind-blown waters (Musgrave 1998, "Wind-Blown Waters",
/// `windywave`): ripples `Km·fBm` (2 octaves, `λ = 2`, `H = ½`) scaled by a
/// wind field `minwind + windamp·turbulence` (4 octaves), so gusts roughen
/// the water in patches:
///
/// ```text
/// PP   = txtscale·windfreq·P
/// wind = minwind + windamp·turbulence(PP)
/// h    = wind · Km·fBm(ripple_ratio·PP)
/// ```
///
/// **Erratum.** The text applies "a large-scale, as compared to the
/// ripples, fractal weighting function", but the listing evaluates the
/// ripples at `PP` and then the wind at `8·PP`, eight times *finer* than the
/// ripples. natura follows the text: the wind is the large scale (at
/// `windfreq`, as its name says) and the ripples are `ripple_ratio = 8`
/// times finer. `turbulence()` is not defined in the source; it is Perlin's
/// sum of `|noise|` (Perlin 1985; natura-noise's `Turbulence`).
#[derive(Clone, Debug)]
pub struct WindyWave {
    params: WindyWaveParams,
    ripples: Fbm<Perlin>,
    wind: Turbulence<Perlin>,
}

impl WindyWave {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`WindyWaveParams::validate`].
    pub fn new(params: WindyWaveParams) -> Result<Self> {
        params.validate()?;
        let ripples = fbm(params.seed, "ripples", spectral(0.5, 2.0, 2.0))?;
        let wind = turbulence(params.seed, "wind", spectral(0.5, 2.0, 4.0))?;
        Ok(Self {
            params,
            ripples,
            wind,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &WindyWaveParams {
        &self.params
    }

    /// The wind strength at `p` (at least `minwind`).
    #[must_use]
    pub fn wind(&self, p: DVec3, fp: Footprint) -> f64 {
        let q = &self.params;
        let f = q.txtscale * q.windfreq;
        q.minwind + q.windamp * turbulence_at(&self.wind, p * f, fp.scaled(f))
    }

    /// The displacement and its gradient at `p`.
    #[must_use]
    pub fn height_grad(&self, p: DVec3, fp: Footprint) -> (f64, DVec3) {
        let q = &self.params;
        let f = q.txtscale * q.windfreq;
        let (t, dt) = self
            .wind
            .eval_grad3_band(p * f, fp.scaled(f).visible(self.wind.spectral()));
        let wind = q.minwind + q.windamp * t;
        let fr = f * q.ripple_ratio;
        let (r, dr) = fbm_grad_at(&self.ripples, p * fr, fp.scaled(fr));
        let ripples = q.km * r;
        let grad = dr * (q.km * fr * wind) + dt * (q.windamp * f * ripples);
        (wind * ripples, grad)
    }

    /// The displacement at `p`.
    #[must_use]
    pub fn height(&self, p: DVec3, fp: Footprint) -> f64 {
        self.height_grad(p, fp).0
    }
}

impl SolidTexture for WindyWave {
    fn name(&self) -> &'static str {
        "windywave"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Height
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::height(self.height(p, fp))
    }
    fn height_gradient(&self, p: DVec3, fp: Footprint) -> DVec3 {
        self.height_grad(p, fp).1
    }
}
