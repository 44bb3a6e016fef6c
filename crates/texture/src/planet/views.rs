//! Views of a planet — from orbit and from a mountain top — and rendering.

use glam::DVec3;
use natura_core::{Image, Progress, preview};

use super::Planet;
use crate::error::{Result, TextureError, finite, in_range, non_negative};
use crate::planet::trace::TraceSettings;
use crate::view::View;

/// Where to stand for a view from the ground.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct GroundViewParams {
    /// Latitude of the search's centre, radians.
    pub latitude: f64,
    /// Longitude of the search's centre, radians.
    pub longitude: f64,
    /// The view stands on the highest point found within this distance
    /// of the centre, metres (2 500 km: the highest peak of a continent).
    pub search_radius_m: f64,
    /// Height of the eye above the ground, metres (40: above the rounded
    /// summit, so the view clears it).
    pub eye_height_m: f64,
    /// Compass direction of the view, radians from north towards east.
    pub heading: f64,
    /// Elevation of the view, radians (negative looks down).
    pub pitch: f64,
    /// Vertical field of view, radians.
    pub vfov: f64,
}

impl Default for GroundViewParams {
    fn default() -> Self {
        Self {
            latitude: 0.5,
            longitude: 0.3,
            search_radius_m: 2_500_000.0,
            eye_height_m: 40.0,
            heading: 1.2,
            pitch: -0.12,
            vfov: 0.9,
        }
    }
}

impl GroundViewParams {
    /// Checks every field.
    ///
    /// # Errors
    /// [`TextureError`] naming the bad field.
    pub fn validate(&self) -> Result<()> {
        finite("latitude", self.latitude)?;
        finite("longitude", self.longitude)?;
        non_negative("search_radius_m", self.search_radius_m)?;
        in_range(
            "eye_height_m",
            self.eye_height_m,
            f64::MIN_POSITIVE,
            MAX_ALTITUDE_M,
            "must be in (0, 10¹²] m",
        )?;
        finite("heading", self.heading)?;
        in_range(
            "pitch",
            self.pitch,
            -1.5,
            1.5,
            "must be in [−1.5, 1.5] radians",
        )?;
        Ok(())
    }
}

/// Highest eye above the surface a view accepts, metres (10¹²: the largest
/// planet radius).
pub const MAX_ALTITUDE_M: f64 = 1e12;

/// The unit direction of latitude `lat` and longitude `lon` (radians).
#[must_use]
pub fn direction(lat: f64, lon: f64) -> DVec3 {
    DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin())
}

/// East and north unit vectors of the tangent plane at unit direction `up`.
fn tangent_frame(up: DVec3) -> (DVec3, DVec3) {
    let east = DVec3::Z.cross(up).try_normalize().unwrap_or(DVec3::Y);
    (east, up.cross(east))
}

impl Planet {
    /// A view from `altitude_m` above sea level over latitude `latitude`
    /// and longitude `longitude` (radians), looking at the planet's centre.
    ///
    /// # Errors
    /// [`TextureError`] naming `altitude_m` outside
    /// `(0, 10¹²]` metres, a non-finite `latitude` or `longitude`, or a bad
    /// field of view or resolution.
    pub fn orbit_view(
        &self,
        altitude_m: f64,
        latitude: f64,
        longitude: f64,
        vfov: f64,
        width: u32,
        height: u32,
    ) -> Result<View> {
        in_range(
            "altitude_m",
            altitude_m,
            f64::MIN_POSITIVE,
            MAX_ALTITUDE_M,
            "must be in (0, 10¹²] m",
        )?;
        finite("latitude", latitude)?;
        finite("longitude", longitude)?;
        let up = direction(latitude, longitude);
        let eye = up * (self.radius() + altitude_m);
        let hint = if up.z.abs() > 0.999 {
            DVec3::X
        } else {
            DVec3::Z
        };
        View::look_at(eye, DVec3::ZERO, hint, vfov, width, height)
    }

    /// The unit direction of the highest point of the surface within
    /// `radius_m` of the unit direction `dir` (a coarse-to-fine grid search
    /// over the tangent plane).
    #[must_use]
    pub fn summit_near(&self, dir: DVec3, radius_m: f64) -> DVec3 {
        let mut best = dir.normalize();
        let mut span = radius_m;
        for _ in 0..6 {
            if span <= 0.0 {
                break;
            }
            let (east, north) = tangent_frame(best);
            let centre = best;
            let fp = span / 16.0;
            let mut top = self.height(best, fp);
            for j in -16..=16 {
                for i in -16..=16 {
                    let off = (east * f64::from(i) + north * f64::from(j)) * (span / 16.0);
                    let c = (centre * self.radius() + off).normalize();
                    let h = self.height(c, fp);
                    if h > top {
                        top = h;
                        best = c;
                    }
                }
            }
            span /= 8.0;
        }
        best
    }

    /// A view from a mountain top: the eye stands `eye_height_m` above the
    /// highest point found near the given position, looking along `heading`
    /// and `pitch`.
    ///
    /// # Errors
    /// [`TextureError`] for bad view parameters or
    /// resolution, naming `search_radius_m` if it exceeds half the
    /// planet's circumference (`π R`).
    pub fn ground_view(&self, g: &GroundViewParams, width: u32, height: u32) -> Result<View> {
        g.validate()?;
        if g.search_radius_m > std::f64::consts::PI * self.radius() {
            return Err(TextureError::InvalidParameter {
                name: "search_radius_m",
                value: format!("{} (planet radius {} m)", g.search_radius_m, self.radius()),
                reason: "must be in [0, π × radius_m]: half the planet's circumference",
            });
        }
        let up = self.summit_near(direction(g.latitude, g.longitude), g.search_radius_m);
        let ground = self.height(up, 0.01);
        let eye = up * (self.radius() + ground + g.eye_height_m);
        let (east, north) = tangent_frame(up);
        let level = north * g.heading.cos() + east * g.heading.sin();
        let forward = level * g.pitch.cos() + up * g.pitch.sin();
        View::look_at(eye, eye + forward * 1000.0, up, g.vfov, width, height)
    }

    /// Renders `view`: `settings.supersample²` rays a pixel on a regular
    /// grid, each with the pixel's footprint, resolved by the camera's
    /// pixel filter (natura-core's `PixelFilter::camera`); rows in parallel
    /// (with the `parallel` feature), the same bits on any number of
    /// threads; linear RGB with the sun's light = 1.
    ///
    /// # Errors
    /// [`TextureError`] for bad trace settings
    /// ([`TraceSettings::validate_for`]: a tolerance finer than the scene
    /// resolves), an image too large for memory, or naming `eye` for a view
    /// whose eye is not above the surface (at the centre, below sea level
    /// or inside a mountain), from where no pixel could be rendered.
    pub fn render(
        &self,
        view: &View,
        settings: &TraceSettings,
        progress: &dyn Progress,
    ) -> Result<Image> {
        let eye = view.eye();
        settings.validate_for(self, eye)?;
        let alpha = view.pixel_angle();
        let clearance = self.gap(eye, DVec3::Z, 0.0, alpha);
        if clearance.is_nan() || clearance <= 0.0 {
            return Err(TextureError::InvalidParameter {
                name: "eye",
                value: format!("{eye} ({clearance} m above the surface)"),
                reason: "the view's eye must lie above the planet's surface",
            });
        }
        Ok(preview::shade_pixels(
            view.width(),
            view.height(),
            settings.supersample,
            "planet",
            progress,
            |px, py| {
                let d = view.direction(px, py);
                self.radiance(eye, d, alpha, settings).as_vec3()
            },
        )?)
    }
}
