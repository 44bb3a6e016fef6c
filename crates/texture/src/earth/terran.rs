//! Terran: an entire Earth-like planet in one texture — continents and
//! oceans, climate by latitude and altitude, ocean depth and colour mottling.

use glam::DVec3;
use natura_noise::{
    DNoise, Fbm, Perlin, Spectral, VectorField, VectorMultifractal, VectorMultifractalParams,
};

use crate::error::{Result, colour, finite, non_negative, positive};
use crate::footprint::{Footprint, fbm_at, fbm_grad_at};
use crate::fractals::{fbm, perlin, spectral};
use crate::spline::ColourSpline;
use crate::texture::{Sample, SolidTexture, TextureKind, display_to_linear};

/// The land colour spline of the `terran` shader, picked from a photograph
/// of the Earth: brown, greens, buff desert, white (Musgrave 1998, "Gaea").
pub const LAND_KNOTS: [[f64; 3]; 10] = [
    [0.5, 0.39, 0.2],
    [0.5, 0.39, 0.2],
    [0.5, 0.39, 0.2],
    [0.2, 0.3, 0.0],
    [0.085, 0.2, 0.04],
    [0.065, 0.22, 0.04],
    [0.5, 0.42, 0.28],
    [0.6, 0.5, 0.23],
    [1.0, 1.0, 1.0],
    [1.0, 1.0, 1.0],
];

/// The mottle's tint: added in proportion to the mottle fBm.
pub const MOTTLE_TINT: DVec3 = DVec3::new(0.5, 0.175, 0.5);

/// Which fractal raises the continents.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Continents {
    /// Scalar fBm (`spectral`), the shader's `multifractal = 0`: coastlines
    /// equally wiggly everywhere. The default.
    #[default]
    Fbm,
    /// Musgrave's vector multifractal `MVfBm` (`multifractal`) of a domain
    /// distorted by `dist_scale·DNoise`, its component along the surface
    /// normal: Gaea, with smooth coasts in some places and rough in others.
    VectorMultifractal,
}

/// Parameters of [`Terran`]; `Default` is the RenderMan `terran` shader's
/// (Musgrave 1998, "Gaea: Building an Entire Planet").
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct TerranParams {
    /// Seed of the noises.
    pub seed: u64,
    /// Which fractal raises the continents.
    pub continents: Continents,
    /// The fBm continents' `H` (the shader's `spectral_exp`, 0.5), lacunarity
    /// (2) and octaves (7); frequency 1 per unit of the texture sphere.
    pub spectral: Spectral,
    /// The vector multifractal's gain, lacunarity, octaves and offsets
    /// (natura-noise's defaults: the dissertation's Gaea).
    pub multifractal: VectorMultifractalParams,
    /// Strength of the domain distortion before the multifractal (0.2).
    pub dist_scale: f64,
    /// Bump amplitude on land (0.07 units of the texture sphere).
    pub bump_scale: f64,
    /// Added to the bump value ("chaos", 0).
    pub offset: f64,
    /// Chaos level of the coastline (0): raise it for more ocean.
    pub sea_level: f64,
    /// Multiplies the chaos on land (1).
    pub mtn_scale: f64,
    /// Scales the climate index (0.95).
    pub lat_scale: f64,
    /// Extra perturbation of the climate index towards the equator (0).
    pub nonlinear: f64,
    /// How much altitude perturbs the climate index (0.9; the shader's
    /// `purt_scale`, used as `pert_scale`).
    pub pert_scale: f64,
    /// Exponent of the climate index (0: none): larger values "drive back
    /// the glaciers" and widen the deserts.
    pub map_exp: f64,
    /// Climate index above which the ocean is ice (0.9; 0 for no ice caps).
    pub ice_caps: f64,
    /// How fast the ocean darkens with depth (1).
    pub depth_scale: f64,
    /// The largest darkening of deep water (0.5).
    pub depth_max: f64,
    /// Climate index below which land is mottled (0.75: not the snow).
    pub mottle_limit: f64,
    /// Frequency of the mottle (20).
    pub mottle_scale: f64,
    /// The mottle fBm's `H` (0.25).
    pub mottle_dim: f64,
    /// Strength of the mottle (0.02).
    pub mottle_mag: f64,
    /// Shallow-ocean colour (0.12, 0.3, 0.6).
    pub ocean_colour: DVec3,
    /// Polar ice colour (white).
    pub ice_colour: DVec3,
}

impl Default for TerranParams {
    fn default() -> Self {
        Self {
            seed: 0,
            continents: Continents::Fbm,
            spectral: spectral(0.5, 2.0, 7.0),
            multifractal: VectorMultifractalParams::default(),
            dist_scale: 0.2,
            bump_scale: 0.07,
            offset: 0.0,
            sea_level: 0.0,
            mtn_scale: 1.0,
            lat_scale: 0.95,
            nonlinear: 0.0,
            pert_scale: 0.9,
            map_exp: 0.0,
            ice_caps: 0.9,
            depth_scale: 1.0,
            depth_max: 0.5,
            mottle_limit: 0.75,
            mottle_scale: 20.0,
            mottle_dim: 0.25,
            mottle_mag: 0.02,
            ocean_colour: DVec3::new(0.12, 0.3, 0.6),
            ice_colour: DVec3::ONE,
        }
    }
}

impl TerranParams {
    /// Gaea: the dissertation's `PLANET` argument vector (Musgrave 1993,
    /// §5.8) mapped onto these parameters where the two listings correspond
    /// — multifractal continents (`MVfBm`, `ω = 2^−0.02`, 10 octaves,
    /// distortion 0.3), chaos displaced by −0.085, land chaos scale 0.45,
    /// perturbation scales 2.6 (by latitude) and 1.2, climate exponent 4
    /// with the table's scale 300/255, ice from index 220/255, mottle below
    /// 170/255 at frequency 20, deep-water scale 20 and limit 0.75. The C
    /// code's 256-entry colour table is incomplete in the source and its
    /// mottle is multiplicative; the shader's spline and additive mottle
    /// stand in for them.
    #[must_use]
    pub fn gaea() -> Self {
        Self {
            continents: Continents::VectorMultifractal,
            dist_scale: 0.3,
            offset: -0.085,
            mtn_scale: 0.45,
            nonlinear: 2.6,
            pert_scale: 1.2,
            map_exp: 4.0,
            lat_scale: 300.0 / 255.0,
            ice_caps: 220.0 / 255.0,
            mottle_limit: 170.0 / 255.0,
            depth_scale: 20.0,
            depth_max: 0.75,
            ..Self::default()
        }
    }

    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        self.spectral.validate()?;
        self.multifractal.validate()?;
        non_negative("dist_scale", self.dist_scale)?;
        finite("bump_scale", self.bump_scale)?;
        finite("offset", self.offset)?;
        finite("sea_level", self.sea_level)?;
        finite("mtn_scale", self.mtn_scale)?;
        finite("lat_scale", self.lat_scale)?;
        finite("nonlinear", self.nonlinear)?;
        finite("pert_scale", self.pert_scale)?;
        non_negative("map_exp", self.map_exp)?;
        finite("ice_caps", self.ice_caps)?;
        finite("depth_scale", self.depth_scale)?;
        non_negative("depth_max", self.depth_max)?;
        finite("mottle_limit", self.mottle_limit)?;
        positive("mottle_scale", self.mottle_scale)?;
        finite("mottle_dim", self.mottle_dim)?;
        finite("mottle_mag", self.mottle_mag)?;
        colour("ocean_colour", self.ocean_colour)?;
        colour("ice_colour", self.ice_colour)?;
        spectral(self.mottle_dim, 2.0, 6.0).validate()?;
        Ok(())
    }
}

#[derive(Clone, Debug)]
enum Bump {
    Fbm(Fbm<Perlin>),
    Multifractal {
        mf: VectorMultifractal<Perlin>,
        distort: DNoise<Perlin>,
    },
}

/// Musgrave's Earth-like planet texture (Musgrave 1998, "Gaea: Building an
/// Entire Planet", `terran`; Musgrave 1993, §5.6 and the `PLANET` listing of
/// §5.8), evaluated on the sphere of texture space (a unit sphere by default):
///
/// 1. **Continents**: a fractal bump `b` ([`Continents`]); `chaos = b + offset`
///    is land where it exceeds `sea_level` (there `chaos *= mtn_scale` and
///    the surface is bumped by `bump_scale·b`), ocean elsewhere.
/// 2. **Climate by latitude**: the index `ℓ = |z|` of the unit direction,
///    perturbed by altitude, `ℓ += chaos·(nonlinear·(1 − ℓ) + pert_scale)`,
///    optionally raised to `map_exp`, times `lat_scale`; land takes its
///    colour from the land spline at `ℓ`.
/// 3. **Mottle**: land below `mottle_limit` gets
///    `mottle_mag·fBm(mottle_scale·P)·(0.5, 0.175, 0.5)` added.
/// 4. **Oceans**: ice above `ice_caps`, else the ocean colour darkened by
///    depth, `× (1 + max((chaos − sea_level)·depth_scale, −depth_max))`.
///
/// [`Terran::shade`] is that colouring, a function of `(b, ℓ, mottle)` only:
/// the point path, the batch path ([`crate::earth::TerranSphere`]) and the
/// displaced planets ([`crate::planet`]) all call it.
///
/// **Errata corrected.** In the multifractal branch the shader steps the
/// filter width by `fw *= filtwidth` (squaring it) instead of by the
/// lacunarity; here every fractal's octaves come from the footprint through
/// [`Footprint::visible`], one octave per factor λ. The shader declares
/// `filtwidht` and `purt_scale` but uses `filtwidth` and `pert_scale`; the
/// parameter is `pert_scale`. The dissertation's mottle adds the *green*
/// channel's share to blue (`color.blue += color.green·…`, "a feature, not
/// a bug (don't ask me why!)"); the shader's additive tint is used, which
/// adds `0.5·mottle_mag·pert` to blue. The dissertation's 256-entry colour
/// table is declared but only 100 entries are printed; the shader's
/// complete spline is used. A negative climate index raised to a real
/// exponent is undefined, so the index is clamped at 0 before `map_exp`. The
/// multifractal branch uses the dissertation's vector `MVfBm` (its
/// component along the normal, `chaos = −bump·n`), not the shader's scalar
/// stand-in, whose gain and `H` share one parameter.
#[derive(Clone, Debug)]
pub struct Terran {
    params: TerranParams,
    bump: Bump,
    mottle: Fbm<Perlin>,
    land: ColourSpline,
}

/// The colour [`Terran::shade`] gives, and whether it is land.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TerranShade {
    /// The colour, linear RGB, each channel in `[0, 1]`.
    pub colour: DVec3,
    /// The same colour as the listing computes it (display values, clamped
    /// to `[0, 1]`).
    pub display: DVec3,
    /// Whether the point is above sea level.
    pub land: bool,
}

impl Terran {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`TerranParams::validate`].
    pub fn new(params: TerranParams) -> Result<Self> {
        params.validate()?;
        let bump = match params.continents {
            Continents::Fbm => Bump::Fbm(fbm(params.seed, "continents", params.spectral)?),
            Continents::VectorMultifractal => Bump::Multifractal {
                mf: VectorMultifractal::new(
                    perlin(params.seed, "continents"),
                    params.multifractal,
                )?,
                distort: DNoise(perlin(params.seed, "continental drift")),
            },
        };
        let mottle = fbm(params.seed, "mottle", spectral(params.mottle_dim, 2.0, 6.0))?;
        let land = ColourSpline::new(LAND_KNOTS.iter().map(|&k| DVec3::from(k)).collect())?;
        Ok(Self {
            params,
            bump,
            mottle,
            land,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &TerranParams {
        &self.params
    }

    /// The scalar fBm of [`Continents::Fbm`] (for batch evaluation), if used.
    #[must_use]
    pub fn continents_fbm(&self) -> Option<&Fbm<Perlin>> {
        match &self.bump {
            Bump::Fbm(f) => Some(f),
            Bump::Multifractal { .. } => None,
        }
    }

    /// The mottle fBm, evaluated at `mottle_scale·P`.
    #[must_use]
    pub fn mottle_fbm(&self) -> &Fbm<Perlin> {
        &self.mottle
    }

    /// The real-valued number of the continents' octaves footprint `fp` shows.
    #[must_use]
    pub fn visible(&self, fp: Footprint) -> f64 {
        fp.visible(self.continents_spectral())
    }

    /// The continents' bump value `b` at `p` (before `offset`).
    #[must_use]
    pub fn bump(&self, p: DVec3, fp: Footprint) -> f64 {
        self.bump_visible(p, fp, self.visible(fp))
    }

    /// The bump value summed over `visible` octaves (the multifractal's
    /// domain distortion still fades with `fp`).
    #[must_use]
    pub fn bump_visible(&self, p: DVec3, fp: Footprint, visible: f64) -> f64 {
        match &self.bump {
            Bump::Fbm(f) => f.eval3_band(p, visible),
            Bump::Multifractal { mf, distort } => {
                let q = p + distort.eval3(p) * (self.params.dist_scale * fp.fade(1.0));
                -mf.eval3_band(q, visible).dot(p.normalize_or_zero())
            }
        }
    }

    /// The bump value and its gradient at `p` (analytic for fBm continents,
    /// central differences over the footprint for the multifractal).
    #[must_use]
    pub fn bump_grad(&self, p: DVec3, fp: Footprint) -> (f64, DVec3) {
        match &self.bump {
            Bump::Fbm(f) => fbm_grad_at(f, p, fp),
            Bump::Multifractal { .. } => {
                let h = (0.5 * fp.width()).max(1e-6);
                let g = crate::normal::gradient_fd(|q| self.bump(q, fp), p, h);
                (self.bump(p, fp), g)
            }
        }
    }

    /// The spectral parameters whose octaves the footprint limits in the
    /// continents (the fBm's or the multifractal's).
    #[must_use]
    pub fn continents_spectral(&self) -> &Spectral {
        match self.params.continents {
            Continents::Fbm => &self.params.spectral,
            Continents::VectorMultifractal => &self.params.multifractal.spectral,
        }
    }

    /// A bound on `|b|` over all of space and every footprint.
    #[must_use]
    pub fn bump_bound(&self) -> f64 {
        self.bump_bound_visible(f64::INFINITY)
    }

    /// A bound on `|b|` summed over `visible` octaves; the difference of two
    /// such bounds bounds the octaves between them.
    #[must_use]
    pub fn bump_bound_visible(&self, visible: f64) -> f64 {
        match &self.bump {
            Bump::Fbm(f) => f.bound_band(visible),
            Bump::Multifractal { mf, .. } => mf.bound_band(visible),
        }
    }

    /// A Lipschitz constant of the band-limited bump `b(·, fp)` (texture
    /// units) on the sphere of texture radius `radius`.
    #[must_use]
    pub fn bump_lipschitz(&self, fp: Footprint, radius: f64) -> f64 {
        self.bump_lipschitz_visible(fp, self.visible(fp), radius)
    }

    /// A Lipschitz constant of [`bump_visible`](Self::bump_visible).
    #[must_use]
    pub fn bump_lipschitz_visible(&self, fp: Footprint, visible: f64, radius: f64) -> f64 {
        match &self.bump {
            Bump::Fbm(f) => f.lipschitz3_band(visible),
            Bump::Multifractal { mf, distort } => {
                // b = −V(q(p))·p/|p|, q = p + s·D(p): |∇b| ≤ L_V·(1 + s·L_D) + |V|/|p|.
                let s = self.params.dist_scale * fp.fade(1.0);
                mf.lipschitz3_band(visible) * (1.0 + s * distort.lipschitz())
                    + mf.bound_band(visible) / radius
            }
        }
    }

    /// A bound on `|∂b/∂v|`, how fast the bump changes with the number of
    /// visible octaves `v` (only the octave straddling `v` changes).
    #[must_use]
    pub fn bump_band_slope(&self, visible: f64) -> f64 {
        let octave =
            |k: usize| self.bump_bound_visible(k as f64 + 1.0) - self.bump_bound_visible(k as f64);
        let total = self.continents_spectral().octaves;
        if visible >= total || visible < 0.0 || visible.is_nan() {
            0.0
        } else {
            octave(visible as usize)
        }
    }

    /// The mottle fBm at `p` (it is evaluated at `mottle_scale·p`).
    #[must_use]
    pub fn mottle(&self, p: DVec3, fp: Footprint) -> f64 {
        let s = self.params.mottle_scale;
        fbm_at(&self.mottle, p * s, fp.scaled(s))
    }

    /// Whether the bump value `b` is land.
    #[must_use]
    pub fn is_land(&self, b: f64) -> bool {
        b + self.params.offset > self.params.sea_level
    }

    /// The colouring model: the colour for bump value `b` at a point whose
    /// unit direction has `|z| = latitude`, with mottle fBm value `mottle`.
    #[must_use]
    pub fn shade(&self, b: f64, latitude: f64, mottle: f64) -> TerranShade {
        let q = &self.params;
        let mut chaos = b + q.offset;
        let land = chaos > q.sea_level;
        if land {
            chaos *= q.mtn_scale;
        }
        let mut lat = latitude + chaos * (q.nonlinear * (1.0 - latitude) + q.pert_scale);
        lat = if q.map_exp > 0.0 {
            q.lat_scale * lat.max(0.0).powf(q.map_exp)
        } else {
            q.lat_scale * lat
        };
        let colour = if land {
            let mut c = self.land.eval(lat);
            if lat < q.mottle_limit {
                c += MOTTLE_TINT * (q.mottle_mag * mottle);
            }
            c
        } else if q.ice_caps > 0.0 && lat > q.ice_caps {
            q.ice_colour
        } else {
            let depth = ((chaos - q.sea_level) * q.depth_scale).max(-q.depth_max);
            q.ocean_colour * (1.0 + depth)
        };
        let display = colour.clamp(DVec3::ZERO, DVec3::ONE);
        TerranShade {
            colour: display_to_linear(display),
            display,
            land,
        }
    }

    /// The colour at `p`.
    #[must_use]
    pub fn colour(&self, p: DVec3, fp: Footprint) -> DVec3 {
        self.sample(p, fp).colour
    }
}

impl SolidTexture for Terran {
    fn name(&self) -> &'static str {
        "terran"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::ColourAndHeight
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        let b = self.bump(p, fp);
        let latitude = p.normalize_or_zero().z.abs();
        let s = self.shade(b, latitude, self.mottle(p, fp));
        Sample {
            colour: s.colour,
            opacity: 1.0,
            height: if s.land {
                self.params.bump_scale * b
            } else {
                0.0
            },
        }
    }
    fn height_gradient(&self, p: DVec3, fp: Footprint) -> DVec3 {
        let (b, g) = self.bump_grad(p, fp);
        if self.is_land(b) {
            g * self.params.bump_scale
        } else {
            DVec3::ZERO
        }
    }
}
