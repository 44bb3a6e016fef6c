//! A cyclonic storm: clouds whose large-scale distribution is twisted into
//! a spiral round a calm eye.

use glam::DVec3;
use natura_noise::{DistNoise, Fbm, Perlin, Twist, TwistLaw};

use crate::error::{Result, finite, in_range, positive};
use crate::footprint::{Footprint, fbm_at};
use crate::fractals::{dist_fbm, spectral};
use crate::texture::{Sample, SolidTexture, TextureKind};

/// Parameters of [`Cyclone`]; `Default` is the RenderMan `cyclone` shader's
/// (Musgrave 1998, "Distortion for Cirrus Clouds and Global Circulation"),
/// which agree with the dissertation's Plate 5.4 arguments.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct CycloneParams {
    /// Seed of the noise.
    pub seed: u64,
    /// Radius `R` of the storm about the z axis, on the unit sphere (1).
    pub max_radius: f64,
    /// Turns of the spiral across the storm (0.5). Only ½ (mod 1) joins the
    /// twisted domain continuously to the untwisted one at `r = R`.
    pub twist: f64,
    /// Scale of the cloud fBm (0.7).
    pub scale: f64,
    /// Offset of the cloud fBm (0.5): the mean density.
    pub offset: f64,
    /// fBm `H` (0.675).
    pub h: f64,
    /// fBm octaves (4).
    pub octaves: f64,
    /// fBm lacunarity (2).
    pub lacunarity: f64,
    /// Distortion of the `DistfBm` basis (1).
    pub distortion: f64,
    /// Exponent of the spiral's radial law `(R − r)^power` (3, the RenderMan
    /// shader; the dissertation's C code uses 2).
    pub radial_power: f64,
    /// Radius of the calm eye as a fraction of `R` (0.1).
    pub eye_radius: f64,
    /// Exponent of the density's rise across the eye (4).
    pub eye_power: f64,
}

impl Default for CycloneParams {
    fn default() -> Self {
        Self {
            seed: 0,
            max_radius: 1.0,
            twist: 0.5,
            scale: 0.7,
            offset: 0.5,
            h: 0.675,
            octaves: 4.0,
            lacunarity: 2.0,
            distortion: 1.0,
            radial_power: 3.0,
            eye_radius: 0.1,
            eye_power: 4.0,
        }
    }
}

impl CycloneParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        positive("max_radius", self.max_radius)?;
        finite("twist", self.twist)?;
        finite("scale", self.scale)?;
        finite("offset", self.offset)?;
        finite("distortion", self.distortion)?;
        in_range(
            "radial_power",
            self.radial_power,
            1.0,
            16.0,
            "must be in [1, 16]",
        )?;
        in_range(
            "eye_radius",
            self.eye_radius,
            1e-6,
            1.0,
            "must be in (0, 1]",
        )?;
        in_range("eye_power", self.eye_power, 0.0, 64.0, "must be in [0, 64]")?;
        spectral(self.h, self.lacunarity, self.octaves).validate()?;
        Ok(())
    }
}

/// Musgrave's cyclone (Musgrave 1993, §5.3; Musgrave 1998, "Distortion for
/// Cirrus Clouds and Global Circulation", `cyclone`): a single storm of radius `R` about the z axis. Inside
/// it the texture point is rotated about z by
/// `θ = π + 2π·twist·(R − (R − r)^power)/R` (a spiral tighter towards the
/// centre), and the cloud density is
///
/// ```text
/// density = |w·(offset + scale·DistfBm(rotated P))|,   w = (r/r_eye)^eye_power in the eye, 1 outside it
/// ```
///
/// and 0 outside the storm. Only the large-scale distribution is twisted;
/// the small clouds are not — "a crude first approximation to viscous damping".
///
/// **Errata corrected.** The dissertation's C code leaves the eye weight
/// uninitialised outside the storm; here it is 0 there (no clouds). The
/// RenderMan shader tests the eye at `0.05·R` but normalises with `0.1·R`,
/// so the density jumps from 1/16 of its value to all of it at `r = 0.05·R`;
/// both sources also normalise by a factor 10 that is right only for
/// `R = 1`. Here the eye has one radius `eye_radius·R` and the weight is
/// `(r/r_eye)^eye_power`, continuous (1) at the eye's rim for every `R`.
/// The dissertation's argument vector for Plate 5.4 has 7 values for 6
/// parameters; the first six are these defaults. The C code passes
/// `omega` as a raw gain and uses the world hit point, the RenderMan shader
/// passes `H` and normalises the point; natura follows the shader: `H` is a
/// spectral exponent and `r` is measured on the unit sphere of directions,
/// so the storm's shape does not depend on the sphere's radius. The density
/// is capped at 1 (an opacity).
#[derive(Clone, Debug)]
pub struct Cyclone {
    params: CycloneParams,
    twist: Twist,
    fbm: Fbm<DistNoise<Perlin>>,
}

impl Cyclone {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`CycloneParams::validate`].
    pub fn new(params: CycloneParams) -> Result<Self> {
        params.validate()?;
        let twist = Twist::new(TwistLaw::Cyclone {
            max_radius: params.max_radius,
            twist: params.twist,
            power: params.radial_power,
        })?;
        let fbm = dist_fbm(
            params.seed,
            "cyclone",
            spectral(params.h, params.lacunarity, params.octaves),
            params.distortion,
        )?;
        Ok(Self { params, twist, fbm })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &CycloneParams {
        &self.params
    }

    /// The distance from the storm's axis of the direction of `p` (on the unit sphere).
    #[must_use]
    pub fn radius(p: DVec3) -> f64 {
        let n = p.normalize_or_zero();
        n.x.hypot(n.y)
    }

    /// The eye weight at axis distance `r`: 0 outside the storm, 1 between
    /// the eye and the rim, `(r/r_eye)^eye_power` in the eye.
    #[must_use]
    pub fn eye_weight(&self, r: f64) -> f64 {
        let q = &self.params;
        let eye = q.eye_radius * q.max_radius;
        if r >= q.max_radius {
            0.0
        } else if r < eye {
            (r / eye).powf(q.eye_power)
        } else {
            1.0
        }
    }

    /// The cloud density in `[0, 1]` at `p`.
    #[must_use]
    pub fn density(&self, p: DVec3, fp: Footprint) -> f64 {
        let q = &self.params;
        let r = Self::radius(p);
        let w = self.eye_weight(r);
        if w <= 0.0 {
            return 0.0;
        }
        let (s, c) = self.twist.angle(r).sin_cos();
        let pp = DVec3::new(c * p.x - s * p.y, s * p.x + c * p.y, p.z);
        let a = fbm_at(&self.fbm, pp, fp);
        (w * (q.offset + q.scale * a)).abs().min(1.0)
    }
}

impl SolidTexture for Cyclone {
    fn name(&self) -> &'static str {
        "cyclone"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Density
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::density(DVec3::ONE, self.density(p, fp))
    }
}
