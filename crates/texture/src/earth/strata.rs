//! Sedimentary rock strata: a banded colour map indexed by altitude and
//! perturbed by fBm.

use glam::DVec3;
use natura_noise::{Fbm, Perlin};

use crate::error::{Result, finite, positive};
use crate::footprint::{Footprint, fbm_at};
use crate::fractals::{fbm, spectral};
use crate::spline::ColourSpline;
use crate::texture::{Sample, SolidTexture, TextureKind, display_to_linear};

/// The listing's colour map: subdued tans and buffs "with one or two layers
/// that really stand out" (Musgrave 1998, "Sedimentary Rock Strata"), 8-bit.
pub const STRATA_KNOTS: [[u8; 3]; 34] = [
    [166, 131, 70],
    [166, 131, 70],
    [204, 178, 127],
    [184, 153, 97],
    [140, 114, 51],
    [159, 123, 60],
    [204, 178, 127],
    [230, 180, 80],
    [192, 164, 110],
    [172, 139, 80],
    [102, 76, 25],
    [166, 131, 70],
    [201, 175, 124],
    [181, 150, 94],
    [161, 125, 64],
    [177, 145, 87],
    [170, 136, 77],
    [197, 170, 117],
    [180, 100, 50],
    [175, 142, 84],
    [197, 170, 117],
    [177, 145, 87],
    [170, 136, 77],
    [186, 156, 100],
    [166, 131, 70],
    [188, 159, 104],
    [168, 134, 74],
    [159, 123, 60],
    [195, 167, 114],
    [175, 142, 84],
    [161, 125, 64],
    [197, 170, 117],
    [177, 145, 87],
    [177, 145, 87],
];

/// Parameters of [`Strata`]; `Default` is the `strata` shader's.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct StrataParams {
    /// Seed of the noise.
    pub seed: u64,
    /// Texture frequency (1).
    pub txtscale: f64,
    /// Colour-map cycles per unit altitude (2): thinner layers when larger.
    pub zscale: f64,
    /// How much the fBm bends the layers (0.1, "soft-sediment deformation").
    pub turbscale: f64,
    /// Shifts the layers up or down (0).
    pub offset: f64,
    /// fBm octaves (8).
    pub octaves: f64,
}

impl Default for StrataParams {
    fn default() -> Self {
        Self {
            seed: 0,
            txtscale: 1.0,
            zscale: 2.0,
            turbscale: 0.1,
            offset: 0.0,
            octaves: 8.0,
        }
    }
}

impl StrataParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        positive("txtscale", self.txtscale)?;
        finite("zscale", self.zscale)?;
        finite("turbscale", self.turbscale)?;
        finite("offset", self.offset)?;
        spectral(0.5, 2.0, self.octaves).validate()?;
        Ok(())
    }
}

/// Musgrave's sedimentary rock strata (Musgrave 1998, "Sedimentary Rock
/// Strata"), closely related to Perlin's marble:
///
/// ```text
/// PP   = txtscale·P
/// cmap = zscale·PP.z + turbscale·fBm(PP; octaves, λ = 2, H = ½) − offset
/// Ct   = spline(cmap mod 1, 34 tan and buff knots)
/// ```
///
/// With `turbscale = 0` the colour is periodic in `z` with period
/// `1/(zscale·txtscale)` and independent of `x`, `y`. The original C code
/// indexed 256-entry tables; the RenderMan spline is used, as in the listing.
#[derive(Clone, Debug)]
pub struct Strata {
    params: StrataParams,
    fbm: Fbm<Perlin>,
    colours: ColourSpline,
}

impl Strata {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`StrataParams::validate`].
    pub fn new(params: StrataParams) -> Result<Self> {
        params.validate()?;
        Ok(Self {
            fbm: fbm(params.seed, "strata", spectral(0.5, 2.0, params.octaves))?,
            colours: ColourSpline::from_bytes(&STRATA_KNOTS)?,
            params,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &StrataParams {
        &self.params
    }

    /// The colour-map index in `[0, 1)` at `p`.
    #[must_use]
    pub fn index(&self, p: DVec3, fp: Footprint) -> f64 {
        let q = &self.params;
        let pp = p * q.txtscale;
        let turb = fbm_at(&self.fbm, pp, fp.scaled(q.txtscale));
        let cmap = q.zscale * pp.z + q.turbscale * turb - q.offset;
        let m = cmap - cmap.floor();
        // `x − floor(x)` rounds up to 1 for tiny negative x.
        if m < 1.0 { m } else { 0.0 }
    }

    /// The colour at `p`.
    #[must_use]
    pub fn colour(&self, p: DVec3, fp: Footprint) -> DVec3 {
        display_to_linear(self.colours.eval(self.index(p, fp)))
    }
}

impl SolidTexture for Strata {
    fn name(&self) -> &'static str {
        "strata"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Colour
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::colour(self.colour(p, fp))
    }
}
