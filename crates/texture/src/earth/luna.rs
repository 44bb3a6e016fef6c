//! Selene: a moon of highlands and maria with one great rayed crater.

use glam::DVec3;
use natura_noise::{Fbm, Perlin};

use crate::error::{Result, colour, finite, in_range, positive};
use crate::footprint::{Footprint, fbm_at, smoothstep};
use crate::fractals::{fbm, perlin, spectral};
use crate::texture::{Sample, SolidTexture, TextureKind, display_to_linear};

/// Parameters of [`Luna`]; `Default` is the `luna` shader's (Musgrave 1998,
/// "Selene"), with a mid-grey base colour for the "featureless gray sphere".
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct LunaParams {
    /// Seed of the noises.
    pub seed: u64,
    /// fBm lacunarity (2).
    pub lacunarity: f64,
    /// fBm octaves (8).
    pub octaves: f64,
    /// fBm `H` (0.7).
    pub h: f64,
    /// The sphere's base colour (grey 0.5).
    pub colour: DVec3,
    /// Added to the highlands in proportion to their chaos (0.7 grey).
    pub highland_color: DVec3,
    /// The maria's base factor (0.7).
    pub maria_basecolor: f64,
    /// The maria's factor per unit of chaos (0.1).
    pub maria_color: f64,
    /// Chaos above which the surface is highland (−0.2).
    pub highland_threshold: f64,
    /// Highland relief per unit chaos (0.01).
    pub highland_altitude: f64,
    /// Maria relief per unit chaos (0.004).
    pub maria_altitude: f64,
    /// Radius of the central peak, in pole distance (0.0075).
    pub peak_rad: f64,
    /// Radius of the flat crater floor (0.01).
    pub inner_rad: f64,
    /// Radius of the crater rim's crest (0.02).
    pub rim_rad: f64,
    /// Radius where the outer rim meets the plain (0.05).
    pub outer_rad: f64,
    /// Height of the central peak (0.005).
    pub peak_ht: f64,
    /// Height of the rim (0.003).
    pub rim_ht: f64,
}

impl Default for LunaParams {
    fn default() -> Self {
        Self {
            seed: 0,
            lacunarity: 2.0,
            octaves: 8.0,
            h: 0.7,
            colour: DVec3::splat(0.5),
            highland_color: DVec3::splat(0.7),
            maria_basecolor: 0.7,
            maria_color: 0.1,
            highland_threshold: -0.2,
            highland_altitude: 0.01,
            maria_altitude: 0.004,
            peak_rad: 0.0075,
            inner_rad: 0.01,
            rim_rad: 0.02,
            outer_rad: 0.05,
            peak_ht: 0.005,
            rim_ht: 0.003,
        }
    }
}

impl LunaParams {
    /// Checks every parameter; the crater radii must increase
    /// (`0 < peak_rad ≤ inner_rad < rim_rad < outer_rad < 0.4`).
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first bad parameter.
    pub fn validate(&self) -> Result<()> {
        spectral(self.h, self.lacunarity, self.octaves).validate()?;
        colour("colour", self.colour)?;
        finite("highland_color", self.highland_color.max_element())?;
        finite("highland_color", self.highland_color.min_element())?;
        finite("maria_basecolor", self.maria_basecolor)?;
        finite("maria_color", self.maria_color)?;
        finite("highland_threshold", self.highland_threshold)?;
        finite("highland_altitude", self.highland_altitude)?;
        finite("maria_altitude", self.maria_altitude)?;
        finite("peak_ht", self.peak_ht)?;
        finite("rim_ht", self.rim_ht)?;
        positive("peak_rad", self.peak_rad)?;
        in_range(
            "inner_rad",
            self.inner_rad,
            self.peak_rad,
            f64::MAX,
            "must be ≥ peak_rad",
        )?;
        let after = |name, v: f64, lo: f64| {
            if v > lo && v.is_finite() {
                Ok(())
            } else {
                Err(crate::error::invalid(name, v, "crater radii must increase"))
            }
        };
        after("rim_rad", self.rim_rad, self.inner_rad)?;
        after("outer_rad", self.outer_rad, self.rim_rad)?;
        in_range(
            "outer_rad",
            self.outer_rad,
            0.0,
            0.4 - 1e-9,
            "must be below 0.4, where the rays end",
        )?;
        Ok(())
    }
}

/// The crater's profile at one pole distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CraterProfile {
    /// Height of the crater's relief.
    pub height: f64,
    /// Brightening of the rim (before the shader's factor 0.2).
    pub lighten: f64,
    /// The rim coordinate `uu` that weights the rough detail (0 on the floor and outside).
    pub uu: f64,
}

/// Musgrave's moon (Musgrave 1998, "Selene", `luna`) — "extreme hackery in
/// pursuit of a specific visual end": on the texture sphere,
///
/// * **maria and highlands**: `chaos = fBm(P)`, pushed down near the north
///   pole so the crater sits in a mare; highland where `chaos` exceeds
///   `highland_threshold` (lighter, `Ct += highland_color·chaos`, raised by
///   `chaos·highland_altitude`), mare elsewhere (darker,
///   `Ct *= maria_basecolor + maria_color·chaos`, sloping by
///   `maria_altitude` per unit of chaos below the shore);
/// * **a rayed crater** at the north pole, in the pole distance
///   `pd = colatitude/π` (the shader's `1 − v`): a central peak, a flat floor,
///   a steep inner rim and a gentle outer rim ([`Luna::crater`]), rough
///   detail on the peak and rims, and bright rays of 62 per turn whose
///   length varies round the crater ([`Luna::rays`]).
///
/// **Errata corrected.** `chaos` is computed twice (the first call passes
/// `ω = λ^(−½−H)` into the fBm's `H` slot, the second uses the older
/// `(point, H, λ, octaves)` order and wins); one fBm with `H = 0.7` is used.
/// The outer rim's `uu = 1 − (pd − outer_rad)/(outer_rad − outer_rad)`
/// divides by zero; it is `1 − (pd − rim_rad)/(outer_rad − rim_rad)`, which
/// makes the profile continuous (0, 0, `rim_ht`, 0 at the four radii).
/// `PQ` (the displaced point) is undeclared; the displacement is the
/// sample's height. The ray-length noise is filtered with width `20·u`
/// where `20·fw` is meant. `uu` is uninitialised on the floor and outside
/// the crater; it is 0 there. The rim's rough detail is added as
/// `0.0025·(½uu + ½fBm)`, which jumps where `uu` reaches 0 at the outer rim;
/// here it fades with `uu`, `0.0025·uu·(½ + ½fBm)`. The seam between the
/// first and last ray (the source: "never been visible") is kept. The
/// rough detail's offset `3·vv` is meant to follow the direction round the
/// crater; the listing's `vv` has the component `z/radial`, which grows
/// without bound towards the pole and rings the crater with aliased
/// moiré: here `vv = (x, y, 0)/max(radial, r_peak)`, the radial direction
/// (linear inside the peak, so it stays smooth at the axis), with the
/// footprint widened by its stretch `3/max(radial, r_peak)`. The listing
/// displaces highland by `chaos·highland_altitude` and mare by
/// `chaos·maria_altitude`, a cliff of `threshold·(highland_altitude −
/// maria_altitude)` at every shore that bump mapping draws as a black
/// line; here the mare continues from the shore's height,
/// `threshold·highland_altitude + (chaos − threshold)·maria_altitude`.
#[derive(Clone, Debug)]
pub struct Luna {
    params: LunaParams,
    chaos: Fbm<Perlin>,
    rough: Fbm<Perlin>,
    rays: Perlin,
}

impl Luna {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`LunaParams::validate`].
    pub fn new(params: LunaParams) -> Result<Self> {
        params.validate()?;
        Ok(Self {
            chaos: fbm(
                params.seed,
                "maria",
                spectral(params.h, params.lacunarity, params.octaves),
            )?,
            rough: fbm(params.seed, "rough", spectral(0.833, 2.0, 4.0))?,
            rays: perlin(params.seed, "rays"),
            params,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &LunaParams {
        &self.params
    }

    /// The crater's profile at pole distance `pd`.
    #[must_use]
    pub fn crater(&self, pd: f64) -> CraterProfile {
        let q = &self.params;
        let (height, lighten, uu) = if pd < q.peak_rad {
            let uu = 1.0 - pd / q.peak_rad;
            (q.peak_ht * smoothstep(0.0, 1.0, uu), 0.0, uu)
        } else if pd < q.inner_rad {
            (0.0, 0.0, 0.0)
        } else if pd < q.rim_rad {
            let uu = (pd - q.inner_rad) / (q.rim_rad - q.inner_rad);
            (q.rim_ht * smoothstep(0.0, 1.0, uu), 0.75 * uu, uu)
        } else if pd < q.outer_rad {
            let uu = 1.0 - (pd - q.rim_rad) / (q.outer_rad - q.rim_rad);
            (q.rim_ht * smoothstep(0.0, 1.0, uu * uu), 0.75 * uu * uu, uu)
        } else {
            (0.0, 0.0, 0.0)
        };
        CraterProfile {
            height,
            lighten,
            uu,
        }
    }

    /// The rays' brightening in `[0, 0.2]` at longitude fraction `u ∈ [0, 1)`
    /// and pole distance `pd`, for a footprint `fw_u` in units of `u`.
    #[must_use]
    pub fn rays(&self, u: f64, pd: f64, fw_u: f64) -> f64 {
        let q = &self.params;
        if !(pd >= q.rim_rad && pd < 0.4) {
            return 0.0;
        }
        let filtered =
            |x: f64, w: f64| self.rays.eval1(x) * Footprint::new(w).map_or(0.0, |fp| fp.fade(1.0));
        let mut lighten = smoothstep(0.15, 0.5, filtered(62.0 * u, 62.0 * fw_u));
        let wrapped = (u + 0.022).rem_euclid(1.0);
        let raydist = 0.2 + 0.2 * filtered(20.0 * wrapped, 20.0 * fw_u);
        lighten *= 1.0 - smoothstep(raydist - 0.2, raydist, pd);
        0.2 * lighten.clamp(0.0, 1.0)
    }

    /// The maria/highland fBm at `p`, pushed down round the north pole.
    #[must_use]
    pub fn chaos(&self, p: DVec3, fp: Footprint) -> f64 {
        let radial = p.x.hypot(p.y);
        let mut chaos = fbm_at(&self.chaos, p, fp);
        if radial < 1.0 {
            chaos -= 0.3 * (1.0 - smoothstep(0.0, 1.0, radial));
        }
        chaos
    }
}

impl SolidTexture for Luna {
    fn name(&self) -> &'static str {
        "luna"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::ColourAndHeight
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        let q = &self.params;
        let chaos = self.chaos(p, fp);
        let (mut ct, mut height) = if chaos > q.highland_threshold {
            (
                q.colour + q.highland_color * chaos,
                chaos * q.highland_altitude,
            )
        } else {
            (
                q.colour * (q.maria_basecolor + q.maria_color * chaos),
                q.highland_threshold * q.highland_altitude
                    + (chaos - q.highland_threshold) * q.maria_altitude,
            )
        };
        let n = p.normalize_or_zero();
        let pd = n.z.clamp(-1.0, 1.0).acos() / std::f64::consts::PI;
        let radial = p.x.hypot(p.y);
        let crater = self.crater(pd);
        height += crater.height;
        ct += DVec3::splat(0.2 * crater.lighten);
        if crater.uu > 0.0 {
            // The radial direction round the crater's axis, linear through
            // the peak so it stays smooth where the direction is undefined;
            // it stretches the rough detail by 1/max(radial, peak radius),
            // and the footprint widens by as much.
            let r0 = (q.peak_rad * std::f64::consts::PI).sin();
            let reach = radial.max(r0);
            let vv = DVec3::new(p.x, p.y, 0.0) / reach;
            let stretch = 3.0 / reach;
            if pd < q.peak_rad {
                let rough = fbm_at(&self.rough, p * 5.0 + vv * 3.0, fp.scaled(5.0 + stretch));
                height += 0.0025 * crater.uu * rough;
            } else {
                let rough = fbm_at(&self.rough, p * 6.0 + vv * 3.0, fp.scaled(6.0 + stretch));
                let uu = if radial > q.rim_rad {
                    crater.uu * crater.uu
                } else {
                    crater.uu
                };
                height += 0.0025 * uu * (0.5 + 0.5 * rough);
            }
        }
        let u = n.y.atan2(n.x).rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU;
        let circumference = std::f64::consts::TAU * radial.max(1e-9);
        let fw_u = (fp.width() / circumference).min(1e6);
        ct += DVec3::splat(self.rays(u.min(1.0 - f64::EPSILON), pd, fw_u));
        Sample {
            colour: display_to_linear(ct),
            opacity: 1.0,
            height,
        }
    }
}
