//! Where snow lies: cover from altitude, slope, sun exposure and wind
//! shelter, with a soft, noisy edge band-limited at the pixel's footprint.
//!
//! Snow settles where it falls unless the slope sheds it, the sun melts it
//! or the wind carries it away:
//!
//! * **Altitude.** Above the snow line (`snow_line_m`, perturbed by a
//!   large-scale fractal of `snow_line_noise_m`, Musgrave's fractal snow
//!   line, Musgrave 2001, "Driving Function Parameters with Functions") precipitation falls as snow and outlasts the melt.
//! * **Slope.** Snow holds on gentle ground and sloughs off steep ground: the
//!   cover falls from full at `snow_max_slope_deg − snow_slope_band_deg` to
//!   none at `snow_max_slope_deg + snow_slope_band_deg`. Fearing 2000 (its
//!   stability pass) lets snow slide off wherever the slope exceeds the angle
//!   of repose; slab avalanches release between about 30° and 50° and slopes
//!   above about 60° hold almost no snow (McClung & Schaerer 2006, the chapter on avalanche formation),
//!   which the default band (45° ± 15°) spans.
//! * **Sun.** A slope that faces the sun takes more of its light and loses
//!   its snow lower down: the snow line rises by `snow_sun_m` times the
//!   cosine of the angle between the slope's aspect and the sun's azimuth,
//!   times the sine of the slope (the horizontal part of the normal along
//!   the sun), so steep sunny faces melt out first and shady ones keep
//!   their snow.
//! * **Wind.** Wind strips snow from exposed ridges and drops it in their
//!   lee. The measure of shelter is Winstral et al.'s upwind slope parameter
//!   `Sx`: the largest angle up to the
//!   terrain upwind within `snow_shelter_distance_m` (Winstral et al. 2002,
//!   the upwind slope parameter), positive in a lee and
//!   negative on a crest. The snow line falls by `snow_wind_m` where
//!   `Sx ≥ 17°` and rises as much where `Sx ≤ −17°`. The wind is the
//!   scene's prevailing one (`water.wind_azimuth_deg`): the snow lies as
//!   the storms that brought it left it, whatever breeze blows today.
//!
//! The edge between snow and bare ground is a fine fBm (`snow_edge_m` of
//! altitude, `snow_edge_size_m` its largest wavelength): patches and
//! tongues rather than a contour line. Its octaves finer than the pixel's
//! footprint are dropped (natura-noise's band-limited fBm, Musgrave 1993,
//! §5.1.2), and the variance they carried widens the edge instead, so the
//! cover a pixel sees is the average over its footprint of the cover of
//! the finer edge: no hard mask, no aliasing at any distance.

use glam::{DVec2, Vec2, Vec3};
use natura_core::{Boundary, Grid2, HeightField, smoothstep};
use natura_noise::{Fbm, Perlin, Spectral, visible_octaves};

use crate::error::Result;
use crate::scene::MaterialDesc;

/// The angle of `Sx` at which shelter (or exposure) counts in full, radians
/// (17°, a steep lee).
const SHELTER_FULL_RAD: f32 = 0.3;

/// Half the width of the altitude transition of a point-sampled edge, metres.
const ALTITUDE_HALF_WIDTH_M: f32 = 15.0;

/// Winstral et al.'s upwind slope parameter `Sx` over a height field, in
/// radians (see the module docs).
#[derive(Clone, Debug)]
pub struct Shelter {
    sx: Grid2<f32>,
    inv_cell: f32,
}

impl Shelter {
    /// `Sx` at every sample of `terrain` for a wind blowing toward compass
    /// azimuth `wind_azimuth_deg` (clockwise from north, +y), searching the
    /// terrain upwind out to `distance_m` in steps of one cell.
    ///
    /// Winstral et al. 2002, the upwind slope parameter:
    /// `Sx(x) = max over 0 < d ≤ dmax of atan((z(x − d·ŵ) − z(x)) / d)`,
    /// with `ŵ` the unit vector the wind blows toward.
    ///
    /// # Errors
    ///
    /// [`RenderError::Core`](crate::RenderError::Core) if the grid cannot be
    /// allocated.
    pub fn new(terrain: &HeightField, wind_azimuth_deg: f64, distance_m: f32) -> Result<Self> {
        let cell = terrain.cell_size();
        let az = wind_azimuth_deg.to_radians();
        let toward = Vec2::new(az.sin() as f32, az.cos() as f32);
        let steps = ((distance_m / cell).ceil() as usize).clamp(1, 256);
        let h = terrain.heights();
        let fill = |i: usize, j: usize| {
            let z0 = h[(i, j)];
            let p = Vec2::new(i as f32, j as f32);
            let mut best = f32::NEG_INFINITY;
            for k in 1..=steps {
                let d = k as f32;
                let q = p - toward * d;
                let z = h.sample_bilinear(q.x, q.y, Boundary::Clamp);
                best = best.max((z - z0) / (d * cell));
            }
            best.atan()
        };
        #[cfg(feature = "parallel")]
        let sx = Grid2::par_from_fn(h.width(), h.height(), fill)?;
        #[cfg(not(feature = "parallel"))]
        let sx = Grid2::from_fn(h.width(), h.height(), fill)?;
        Ok(Self {
            sx,
            inv_cell: 1.0 / cell,
        })
    }

    /// `Sx` at the world point `p` (bilinear), radians.
    #[must_use]
    pub fn at(&self, p: Vec3) -> f32 {
        self.sx
            .sample_bilinear(p.x * self.inv_cell, p.y * self.inv_cell, Boundary::Clamp)
    }
}

/// The snow cover model of a scene (see the module docs).
#[derive(Debug)]
pub struct SnowCover {
    line_m: f32,
    line_noise_m: f32,
    max_slope: f32,
    band: f32,
    /// Unit horizontal direction toward the sun (zero: no sun exposure).
    sun_xy: Vec2,
    sun_m: f32,
    /// `snow_wind_m` (0 without shelter).
    wind_m: f32,
    shelter: Option<Shelter>,
    /// The terrain whose slope and aspect (at its cell's scale) hold the
    /// snow, if known; otherwise the sample's normal.
    ground: Option<HeightField>,
    edge: Fbm<Perlin>,
    edge_m: f32,
}

impl SnowCover {
    /// The model of `desc` with its edge noise seeded by `seed`, without sun
    /// exposure or wind shelter (see [`Self::with_exposure`]).
    ///
    /// # Errors
    ///
    /// [`RenderError::Noise`](crate::RenderError::Noise) if the edge's fBm
    /// cannot be built.
    pub fn new(desc: &MaterialDesc, seed: u64) -> Result<Self> {
        let edge = Fbm::new(
            Perlin::new(seed),
            Spectral::default()
                .with_h(0.7)
                .with_octaves(6.0)
                .with_frequency(1.0 / f64::from(desc.snow_edge_size_m.max(1e-3))),
        )?;
        Ok(Self {
            line_m: desc.snow_line_m,
            line_noise_m: desc.snow_line_noise_m,
            max_slope: desc.snow_max_slope_deg.to_radians(),
            band: desc.snow_slope_band_deg.to_radians().max(1e-3),
            sun_xy: Vec2::ZERO,
            sun_m: desc.snow_sun_m,
            wind_m: 0.0,
            shelter: None,
            ground: None,
            edge,
            edge_m: desc.snow_edge_m,
        })
    }

    /// The same model with sun exposure toward `sun` (a unit vector toward
    /// the sun), the slope and aspect of `ground` at its cell's scale (snow
    /// settles, slides and melts over metres, not over the pixel's relief)
    /// and, if given, the wind's shelter and `snow_wind_m`.
    #[must_use]
    pub fn with_exposure(
        self,
        sun: Vec3,
        ground: Option<HeightField>,
        shelter: Option<(Shelter, f32)>,
    ) -> Self {
        let sun_xy = Vec2::new(sun.x, sun.y).normalize_or_zero();
        let (shelter, wind_m) = match shelter {
            Some((s, drift)) => (Some(s), drift),
            None => (None, 0.0),
        };
        Self {
            sun_xy,
            wind_m,
            shelter,
            ground,
            ..self
        }
    }

    /// The snow line at `p` with unit normal `n` and large-scale noise
    /// `large` (in about −1…1), metres: the altitude line raised on sunny
    /// and exposed slopes, lowered on shady and sheltered ones.
    #[must_use]
    pub fn line_at(&self, p: Vec3, n: Vec3, large: f32) -> f32 {
        let sunny = Vec2::new(n.x, n.y).dot(self.sun_xy);
        let sheltered = match &self.shelter {
            Some(s) if self.wind_m > 0.0 => (s.at(p) / SHELTER_FULL_RAD).clamp(-1.0, 1.0),
            _ => 0.0,
        };
        self.line_m + self.line_noise_m * large + self.sun_m * sunny - self.wind_m * sheltered
    }

    /// The fraction of the ground covered by snow (0–1) at `p` with unit
    /// normal `n` and large-scale noise `large`, as a pixel whose footprint
    /// there is `footprint_m` metres wide sees it.
    #[must_use]
    pub fn cover(&self, p: Vec3, n: Vec3, large: f32, footprint_m: f32) -> f32 {
        let n = self
            .ground
            .as_ref()
            .and_then(|g| g.normal_at(p.x, p.y))
            .unwrap_or(n);
        let line = self.line_at(p, n, large);
        // Far below the line the edge noise cannot reach: no work.
        let reach = 3.0 * (self.edge_m + ALTITUDE_HALF_WIDTH_M);
        if p.z < line - reach {
            return 0.0;
        }
        let (e, lost) = self.edge_noise(p, footprint_m);
        let slope = n.z.clamp(-1.0, 1.0).acos();
        // The unresolved octaves' spread widens both transitions, and the
        // altitude's by the span of heights the footprint covers on the slope.
        let span = footprint_m.max(0.0) * slope.tan().min(10.0);
        let w = ALTITUDE_HALF_WIDTH_M + self.edge_m * lost + span;
        let alt = smoothstep(-w, w, p.z - line + self.edge_m * e);
        let band = self.band * (1.0 + lost);
        let holds = smoothstep(
            self.max_slope + band,
            self.max_slope - band,
            slope - 0.5 * self.band * e,
        );
        alt * holds
    }

    /// The edge fBm at `p` over the octaves a footprint of `footprint_m`
    /// resolves, normalised to about −1…1, and the fraction (0–1) of its
    /// standard deviation the dropped octaves carried.
    fn edge_noise(&self, p: Vec3, footprint_m: f32) -> (f32, f32) {
        if self.edge_m <= 0.0 {
            return (0.0, 0.0);
        }
        let sp = self.edge.spectral();
        let visible = visible_octaves(f64::from(footprint_m.max(0.0)), sp.frequency, sp.lacunarity);
        let o = self.edge.octaves();
        let (mut all, mut gone, mut bound) = (0.0, 0.0, 0.0);
        for k in 0..o.band_count(f64::INFINITY) {
            let a = o.amplitude(k) * o.partial(k);
            let kept = o.band_factor(k, visible);
            all += a * a;
            gone += (a * (1.0 - kept)).powi(2);
            bound += a;
        }
        let e = self
            .edge
            .eval2_band(DVec2::new(f64::from(p.x), f64::from(p.y)), visible);
        // Perlin noise spans about ±0.5 per unit amplitude in practice.
        let e = (2.0 * e / bound).clamp(-1.0, 1.0) as f32;
        (e, (gone / all).sqrt() as f32)
    }
}
