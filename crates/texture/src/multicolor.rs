//! Multicolor: a painterly juxtaposition of random colours that averages to
//! neutral grey.

use glam::DVec3;
use natura_noise::{Fbm, Multifractal, MultifractalParams, Perlin, Spectral, VecNoise, VectorFbm};

use crate::error::{Result, positive};
use crate::footprint::{Footprint, fbm_at, vfbm_at};
use crate::fractals::{fbm, perlin, spectral, spectral_gain, vfbm};
use crate::texture::{Sample, SolidTexture, TextureKind, display_to_linear};

/// Parameters of [`Multicolor`]. The shader has none; its constants are fixed
/// ("small changes in the input parameters can 'break' the result"), so only
/// the seed and a texture frequency are exposed.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct MulticolorParams {
    /// Seed of the noises.
    pub seed: u64,
    /// Texture frequency (1).
    pub txtscale: f64,
}

impl Default for MulticolorParams {
    fn default() -> Self {
        Self {
            seed: 0,
            txtscale: 1.0,
        }
    }
}

impl MulticolorParams {
    /// Checks the texture frequency.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) for a bad `txtscale`.
    pub fn validate(&self) -> Result<()> {
        positive("txtscale", self.txtscale)?;
        Ok(())
    }
}

/// Musgrave's "multicolor" texture (Musgrave 1998, "The 'Multicolor'
/// Texture"): a random GIT-like colour — a vector fBm colour sample, its
/// saturation modulated by a multiplicative cascade in a distorted domain,
/// rotated by a random angle about a random axis — added to 50% grey:
///
/// ```text
/// axis  = 4·vfBm(P; 8 octaves, gain ½)
/// cvec  = 2.5·vfBm(0.3·P; 7 octaves, gain ½);     P' = P + cvec
/// cvec += 4·10⁵·vMultifractal(P'; gain 0.7, λ 2, 8 octaves, zero offset 0.2)
/// cvec  = rotate(cvec, fBm(P'; 6 octaves, H = ½), about axis)
/// Ci    = 0.5 + cvec      (folded into [0, 1])
/// ```
///
/// **Erratum corrected.** The listing's "clamp" sets `c = 1 − |c|` when
/// `|c| > 1`, which is negative for every such `c` (`1 − 1.3 = −0.3`), and
/// leaves `c ∈ (−1, 0)` negative; the evident intent is a reflection back into
/// the cube, so every channel is folded (reflected at 0 and at 1) into
/// `[0, 1]`, which keeps the texture's aim, a colour that averages to 50%
/// grey. The cascade is a
/// product, so its unresolved octaves are not dropped but faded to their
/// mean factor (natura-noise's `Multifractal::eval3_band`).
#[derive(Clone, Debug)]
pub struct Multicolor {
    params: MulticolorParams,
    axis: VectorFbm<VecNoise<Perlin>>,
    axis_spectral: Spectral,
    sample: VectorFbm<VecNoise<Perlin>>,
    sample_spectral: Spectral,
    cascade: Multifractal<Perlin>,
    angle: Fbm<Perlin>,
}

/// Reflects `c` into `[0, 1]` (a triangle wave of period 2).
#[must_use]
pub fn fold(c: f64) -> f64 {
    let t = c.rem_euclid(2.0);
    if t <= 1.0 { t } else { 2.0 - t }
}

impl Multicolor {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`MulticolorParams::validate`].
    pub fn new(params: MulticolorParams) -> Result<Self> {
        params.validate()?;
        let s = params.seed;
        let axis_spectral = spectral_gain(0.5, 2.0, 8.0);
        let sample_spectral = spectral_gain(0.5, 2.0, 7.0);
        Ok(Self {
            axis: vfbm(s, "axis", axis_spectral)?,
            axis_spectral,
            sample: vfbm(s, "colour", sample_spectral)?,
            sample_spectral,
            cascade: Multifractal::new(perlin(s, "saturation"), MultifractalParams::multicolor())?,
            angle: fbm(s, "angle", spectral(0.5, 2.0, 6.0))?,
            params,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &MulticolorParams {
        &self.params
    }

    /// The colour at `p`.
    #[must_use]
    pub fn colour(&self, p: DVec3, fp: Footprint) -> DVec3 {
        let k = self.params.txtscale;
        let tx = p * k;
        let fp = fp.scaled(k);
        let axis = vfbm_at(&self.axis, &self.axis_spectral, tx, fp) * 4.0;
        let mut cvec = vfbm_at(
            &self.sample,
            &self.sample_spectral,
            tx * 0.3,
            fp.scaled(0.3),
        ) * 2.5;
        let tx = tx + cvec;
        // The vector cascade: one scalar cascade per channel at VecNoise's
        // misregistered points, each octave faded to its mean factor once the
        // footprint no longer resolves it.
        let v = fp.visible(&self.cascade.params().spectral);
        let [a, b] = [3.33, 7.77];
        let cascade = DVec3::new(
            self.cascade.eval3_band(tx, v),
            self.cascade.eval3_band(tx + DVec3::splat(a), v),
            self.cascade.eval3_band(tx + DVec3::splat(b), v),
        );
        cvec += cascade * 4.0e5;
        let angle = fbm_at(&self.angle, tx, fp);
        if let Some(a) = axis.try_normalize() {
            let (s, c) = angle.sin_cos();
            cvec = cvec * c + a.cross(cvec) * s + a * a.dot(cvec) * (1.0 - c);
        }
        let ci = DVec3::splat(0.5) + cvec;
        display_to_linear(DVec3::new(fold(ci.x), fold(ci.y), fold(ci.z)))
    }
}

impl SolidTexture for Multicolor {
    fn name(&self) -> &'static str {
        "multicolor"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Colour
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::colour(self.colour(p, fp))
    }
}
