//! A layer-cloud sky at kilometre scale for landscapes: coverage and cloud
//! type over a region, base and top heights, a height profile per type, and
//! edges eroded by Worley fBm.
//!
//! After Schneider 2015 ("The Real-time Volumetric Cloudscapes of Horizon:
//! Zero Dawn", §"Modeling"): a 2-D weather field gives local coverage; a
//! low-frequency 3-D noise gives the base shape, cut by the coverage with a
//! remap (`remap(v, 1 − c, 1) · c`); a height gradient per cloud type
//! (stratus thin and low in the layer, cumulus rising through it) shapes it
//! vertically; inverted Worley fBm erodes the edges into billows. Ebert's
//! two-level idea again: a smooth macrostructure and a noise microstructure.

use glam::{DVec2, DVec3, Vec3};
use natura_core::{Aabb, smoothstep};
use natura_noise::{Fbm, Field, Perlin, Spectral, Worley, WorleyParams};

use crate::density::{Density, check_bounds};
use crate::detail::{Detail, DetailParams};
use crate::error::{Result, in_range, positive};

/// Parameters of [`LayerClouds`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct LayerParams {
    /// Horizontal region `[min, max]` (m) holding clouds.
    pub region_min: [f32; 2],
    /// See [`LayerParams::region_min`].
    pub region_max: [f32; 2],
    /// Cloud base altitude (m).
    pub base_m: f32,
    /// Cloud top altitude (m).
    pub top_m: f32,
    /// Mean sky coverage in `[0, 1]`.
    pub coverage: f32,
    /// Cloud type in `[0, 1]`: 0 stratus, ½ stratocumulus, 1 cumulus.
    pub cloud_type: f32,
    /// Feature size of the weather (coverage) field (m).
    pub weather_scale_m: f32,
    /// Feature size of the base shape (m).
    pub shape_scale_m: f32,
    /// Feature size of the erosion detail (m).
    pub detail_scale_m: f32,
    /// Strength of the Worley detail erosion in `[0, 1]`.
    pub detail_erosion: f32,
    /// Density at full cloud (multiplies everything; ≥ 0).
    pub density_scale: f32,
    /// Horizontal wind offset of the noise fields (m), to animate drift.
    pub wind_offset: [f32; 2],
    /// Erosion by noise octaves down to the pixel footprint of a camera
    /// ([`crate::detail`]; `None`: the density above, bit for bit). It
    /// belongs to the field as one camera sees it: a layer baked to voxels
    /// takes it around the grid instead ([`crate::detail::Detailed`]).
    pub detail: Option<DetailParams>,
}

impl Default for LayerParams {
    /// Broken cumulus between 1.5 and 3 km over a 40 km square.
    fn default() -> Self {
        Self {
            region_min: [-20_000.0, -20_000.0],
            region_max: [20_000.0, 20_000.0],
            base_m: 1500.0,
            top_m: 3000.0,
            coverage: 0.5,
            cloud_type: 0.8,
            weather_scale_m: 8000.0,
            shape_scale_m: 2500.0,
            detail_scale_m: 450.0,
            detail_erosion: 0.35,
            density_scale: 1.0,
            wind_offset: [0.0, 0.0],
            detail: None,
        }
    }
}

impl LayerParams {
    /// Checks every field.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidBounds`](crate::VolumeError::InvalidBounds) for an empty or
    /// inverted region or base ≥ top; [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter)
    /// naming any other bad field (as [`DetailParams::validate`] for the detail's).
    pub fn validate(&self) -> Result<()> {
        check_bounds("layer", &self.bounds())?;
        in_range("coverage", self.coverage, 0.0, 1.0, "must lie in [0, 1]")?;
        in_range(
            "cloud_type",
            self.cloud_type,
            0.0,
            1.0,
            "must lie in [0, 1]",
        )?;
        positive("weather_scale_m", self.weather_scale_m)?;
        positive("shape_scale_m", self.shape_scale_m)?;
        positive("detail_scale_m", self.detail_scale_m)?;
        in_range(
            "detail_erosion",
            self.detail_erosion,
            0.0,
            1.0,
            "must lie in [0, 1]",
        )?;
        crate::error::non_negative("density_scale", self.density_scale)?;
        crate::error::finite3(
            "wind_offset",
            Vec3::new(self.wind_offset[0], self.wind_offset[1], 0.0),
        )?;
        if let Some(d) = &self.detail {
            d.validate()?;
        }
        Ok(())
    }

    /// The box of the layer.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: Vec3::new(self.region_min[0], self.region_min[1], self.base_m),
            max: Vec3::new(self.region_max[0], self.region_max[1], self.top_m),
        }
    }
}

/// The layer-cloud density (see the module docs).
#[derive(Clone, Debug)]
pub struct LayerClouds {
    params: LayerParams,
    weather: Fbm<Perlin>,
    shape: Fbm<Perlin>,
    detail: Worley,
    fine: Option<Detail>,
    w_norm: f64,
    s_norm: f64,
}

#[inline]
fn remap(v: f32, lo: f32, hi: f32) -> f32 {
    ((v - lo) / (hi - lo).max(1e-6)).clamp(0.0, 1.0)
}

impl LayerClouds {
    /// The layer of `params` with noise `seed`.
    ///
    /// # Errors
    ///
    /// As [`LayerParams::validate`].
    pub fn new(params: LayerParams, seed: u64) -> Result<Self> {
        params.validate()?;
        let weather = Fbm::new(
            Perlin::new(seed),
            Spectral::default()
                .with_octaves(3.0)
                .with_lacunarity(2.0)
                .with_frequency(1.0 / f64::from(params.weather_scale_m)),
        )?;
        let shape = Fbm::new(
            Perlin::new(seed.wrapping_add(1)),
            Spectral::default()
                .with_octaves(3.0)
                .with_lacunarity(2.0)
                .with_frequency(1.0 / f64::from(params.shape_scale_m)),
        )?;
        let detail = Worley::new(seed.wrapping_add(2), WorleyParams::default())?;
        let fine = match &params.detail {
            Some(d) => Some(Detail::new(d, seed.wrapping_add(3))?),
            None => None,
        };
        Ok(Self {
            fine,
            w_norm: 1.0 / weather.bound(),
            s_norm: 1.0 / shape.bound(),
            params,
            weather,
            shape,
            detail,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &LayerParams {
        &self.params
    }

    /// Local coverage in `[0, 1]` at horizontal position `(x, y)`.
    #[must_use]
    pub fn coverage_at(&self, x: f32, y: f32) -> f32 {
        let p = &self.params;
        let q = DVec2::new(
            f64::from(x + p.wind_offset[0]),
            f64::from(y + p.wind_offset[1]),
        );
        // fBm ∈ [−1, 1] (normalised, typically ±0.5) → weather ∈ [0, 1].
        let w = (0.5 + 1.6 * self.weather.eval2(q) * self.w_norm) as f32;
        (p.coverage + (w - 0.5) * 0.8).clamp(0.0, 1.0)
    }

    /// The vertical profile of the cloud type at relative height `h ∈ [0, 1]`.
    #[must_use]
    pub fn profile(&self, h: f32) -> f32 {
        let t = self.params.cloud_type;
        // Stratus: thin, low in the layer; cumulus: rises through it.
        let top = 0.25 + 0.7 * t;
        let rise = 0.05 + 0.1 * t;
        smoothstep(0.0, rise, h) * (1.0 - smoothstep(top * 0.6, top, h))
    }

    /// Inverted Worley fBm (three octaves) at `p` in `[0, 1]`: 1 at cell
    /// feature points, billowy.
    fn detail_noise(&self, p: Vec3) -> f32 {
        let q = p.as_dvec3() / f64::from(self.params.detail_scale_m);
        let mut s = 0.0;
        for (k, w) in [0.625f64, 0.25, 0.125].into_iter().enumerate() {
            let f = self
                .detail
                .eval3(q * f64::from(1u32 << k) + DVec3::splat(k as f64 * 13.1));
            s += w * (1.0 - f.clamp(0.0, 1.0));
        }
        s as f32
    }
}

impl Density for LayerClouds {
    fn density(&self, p: Vec3) -> f32 {
        let lp = &self.params;
        if !lp.bounds().contains(p) {
            return 0.0;
        }
        let h = (p.z - lp.base_m) / (lp.top_m - lp.base_m);
        let prof = self.profile(h);
        if prof <= 0.0 {
            return 0.0;
        }
        let c = self.coverage_at(p.x, p.y);
        if c <= 0.0 {
            return 0.0;
        }
        let q = DVec3::new(
            f64::from(p.x + lp.wind_offset[0]),
            f64::from(p.y + lp.wind_offset[1]),
            f64::from(p.z),
        );
        let s = (0.5 + 1.6 * self.shape.eval3(q) * self.s_norm) as f32;
        let base = remap(s * prof, 1.0 - c, 1.0) * c;
        if base <= 0.0 {
            return 0.0;
        }
        let eroded = remap(
            base,
            lp.detail_erosion * self.detail_noise(p) * (1.0 - base),
            1.0,
        );
        let d = (eroded * lp.density_scale).max(0.0);
        match &self.fine {
            Some(f) => {
                let wind = Vec3::new(lp.wind_offset[0], lp.wind_offset[1], 0.0);
                f.erode_drifting(p, wind, d, lp.density_scale)
            }
            None => d,
        }
    }
    fn bounds(&self) -> Aabb {
        self.params.bounds()
    }
    fn bound_in(&self, region: &Aabb) -> f32 {
        if crate::density::overlaps(region, &self.params.bounds()) {
            self.params.density_scale
        } else {
            0.0
        }
    }
    fn max_density(&self) -> f32 {
        self.params.density_scale
    }
}
