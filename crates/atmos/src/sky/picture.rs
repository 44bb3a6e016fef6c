//! Whole-image sky renders from a [`SkyView`]: fisheye, panorama and pinhole
//! projections, with an optional Lambertian ground seen through the aerial
//! perspective. Used by the examples and benchmarks, and as a backdrop.

use std::f32::consts::{PI, TAU};

use glam::{DVec3, Vec3};
use natura_core::camera::{FisheyeCamera, PanoramicCamera, PinholeCamera, Projection};
use natura_core::{Grid2, Image};

use super::SkyView;
use crate::Dir3;
use crate::error::{Result, in_range, invalid};

/// How image pixels map to view directions (world frame, z up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SkyProjection {
    /// The upper hemisphere, equidistant fisheye: zenith at the centre, the
    /// horizon on the inscribed circle, north (+y) up, east (+x) left (the
    /// sky as seen lying on the ground, head to the south).
    Fisheye,
    /// Equirectangular: azimuth 0–360° across (+x at both edges, −x in the
    /// middle, turning clockwise seen from above), elevation linear from
    /// `max_elevation` (top) to `min_elevation` (bottom), radians.
    Panorama {
        /// Lowest elevation shown, radians.
        min_elevation: f64,
        /// Highest elevation shown, radians.
        max_elevation: f64,
    },
    /// A pinhole camera with vertical field of view `fov_y` (radians), looking
    /// towards azimuth `yaw` (from +x towards +y) and elevation `pitch`.
    Pinhole {
        /// Vertical field of view, radians.
        fov_y: f64,
        /// Azimuth of the view axis, radians.
        yaw: f64,
        /// Elevation of the view axis, radians.
        pitch: f64,
    },
}

impl SkyProjection {
    fn validate(&self) -> Result<()> {
        match *self {
            SkyProjection::Fisheye => Ok(()),
            SkyProjection::Panorama {
                min_elevation,
                max_elevation,
            } => {
                in_range(
                    "min_elevation",
                    min_elevation,
                    -std::f64::consts::FRAC_PI_2,
                    std::f64::consts::FRAC_PI_2,
                    "must lie in [−π/2, π/2]",
                )?;
                in_range(
                    "max_elevation",
                    max_elevation,
                    -std::f64::consts::FRAC_PI_2,
                    std::f64::consts::FRAC_PI_2,
                    "must lie in [−π/2, π/2]",
                )?;
                if max_elevation <= min_elevation {
                    return Err(invalid(
                        "max_elevation",
                        max_elevation,
                        "must exceed min_elevation",
                    ));
                }
                Ok(())
            }
            SkyProjection::Pinhole { fov_y, yaw, pitch } => {
                in_range("fov_y", fov_y, 1e-4, 3.1, "must lie in (0, 3.1] rad")?;
                crate::error::finite("yaw", yaw)?;
                in_range("pitch", pitch, -1.5, 1.5, "must lie in [−1.5, 1.5] rad")?;
                Ok(())
            }
        }
    }

    /// Returns the camera of this framing on a `w × h` image: natura-core's
    /// [`FisheyeCamera`] looking at the zenith with north up, its
    /// [`PanoramicCamera`] on the spherical screen (the whole horizon, the
    /// middle column looking towards −x, the rows raised to span
    /// `[min_elevation, max_elevation]`), or its [`PinholeCamera`].
    ///
    /// As with every natura-core camera the picture's left shows what is on
    /// the camera's left: the dome has east on the left, the panorama turns
    /// clockwise (seen from above) from left to right.
    ///
    /// # Errors
    ///
    /// [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter)
    /// for an invalid projection, or a zero or oversized image.
    pub fn camera(&self, w: usize, h: usize) -> Result<SkyCamera> {
        self.validate()?;
        let side = |name, v: usize| {
            u32::try_from(v).map_err(|_| invalid(name, v, "must fit the camera's u32 sizes"))
        };
        let (w, h) = (side("width", w)?, side("height", h)?);
        let eye = Vec3::ZERO;
        Ok(match *self {
            SkyProjection::Fisheye => FisheyeCamera::new(eye, Vec3::Z, Vec3::Y, PI, w, h)?.into(),
            SkyProjection::Panorama {
                min_elevation,
                max_elevation,
            } => {
                let vfov = (max_elevation - min_elevation) as f32;
                let centre = (0.5 * (min_elevation + max_elevation)) as f32;
                PanoramicCamera::new(
                    eye,
                    Vec3::NEG_X,
                    Vec3::Z,
                    TAU,
                    vfov,
                    Projection::Spherical,
                    w,
                    h,
                )?
                .with_elevation_centre(centre)?
                .into()
            }
            SkyProjection::Pinhole { fov_y, yaw, pitch } => {
                let (sp, cp) = (pitch as f32).sin_cos();
                let (sy, cy) = (yaw as f32).sin_cos();
                let fwd = Vec3::new(cp * cy, cp * sy, sp);
                PinholeCamera::look_at(eye, fwd, Vec3::Z, fov_y as f32, w, h)?.into()
            }
        })
    }
}

/// The camera of a sky picture: any of natura-core's cameras that can look
/// at the sky. Only the directions of its rays matter; the eye is the
/// [`SkyView`]'s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SkyCamera {
    /// A flat virtual screen.
    Pinhole(PinholeCamera),
    /// A cylindrical or spherical panorama.
    Panoramic(PanoramicCamera),
    /// An equidistant fisheye (pixels outside its circle are black).
    Fisheye(FisheyeCamera),
}

impl From<PinholeCamera> for SkyCamera {
    fn from(c: PinholeCamera) -> Self {
        SkyCamera::Pinhole(c)
    }
}

impl From<PanoramicCamera> for SkyCamera {
    fn from(c: PanoramicCamera) -> Self {
        SkyCamera::Panoramic(c)
    }
}

impl From<FisheyeCamera> for SkyCamera {
    fn from(c: FisheyeCamera) -> Self {
        SkyCamera::Fisheye(c)
    }
}

impl SkyCamera {
    /// Image size in pixels, `(width, height)`.
    #[must_use]
    pub fn resolution(&self) -> (usize, usize) {
        let r = match self {
            SkyCamera::Pinhole(c) => c.resolution(),
            SkyCamera::Panoramic(c) => c.resolution(),
            SkyCamera::Fisheye(c) => c.resolution(),
        };
        (r.x as usize, r.y as usize)
    }

    /// The unit view direction through the centre of pixel `(x, y)` (world
    /// frame, z up), or `None` where the camera sees nothing (outside a
    /// fisheye's circle).
    #[inline]
    #[must_use]
    pub fn direction(&self, x: usize, y: usize) -> Option<Vec3> {
        let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
        let ray = match self {
            SkyCamera::Pinhole(c) => c.ray_at(px, py),
            SkyCamera::Panoramic(c) => c.ray_at(px, py),
            SkyCamera::Fisheye(c) => c.ray_at(px, py),
        };
        ray.is_valid().then_some(ray.dir)
    }
}

/// A Lambertian ground (the planet's surface) under the sun and the sky.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    /// Diffuse albedo (linear RGB, each in `[0, 1]`).
    pub albedo: Vec3,
}

impl SkyView {
    /// Distance from the camera along `view` to the planet's surface, if the ray meets it.
    #[must_use]
    pub fn ground_distance(&self, view: Vec3) -> Option<f32> {
        let q = self.camera_planet();
        let d = view.as_dvec3();
        let r = self.bottom_radius();
        let b = q.dot(d);
        let c = q.length_squared() - r * r;
        let disc = b * b - c;
        (b < 0.0 && disc >= 0.0).then(|| (c.max(0.0) / (-b + disc.sqrt())) as f32)
    }

    /// Radiance of the Lambertian `ground` seen along `view` at distance `d`
    /// (sunlight with the camera's transmittance and the sky's irradiance),
    /// through the aerial perspective.
    #[must_use]
    pub fn ground_radiance(&self, view: Vec3, d: f32, ground: &Ground) -> Vec3 {
        // The surface normal at the hit: (q + d·v)/R, with q the planet-centred camera.
        let q = self.camera_planet();
        let r = self.bottom_radius();
        let n = (q / r).as_vec3() + view * (d / r as f32);
        let cos = n.dot(self.sun().as_vec3()).max(0.0) / n.length();
        let e = self.sun_irradiance_cached() * cos + self.sky_irradiance();
        let l = ground.albedo * e * std::f32::consts::FRAC_1_PI;
        let ap = if f64::from(d) <= self.aerial_range() {
            self.aerial_perspective_f32(view, d)
        } else {
            self.aerial_perspective(Dir3::from_f32(view).unwrap_or(Dir3::DOWN), f64::from(d))
                .unwrap_or(super::ApSample {
                    transmittance: Vec3::ZERO,
                    in_scatter: Vec3::ZERO,
                })
        };
        ap.apply(l)
    }

    /// Renders linear radiance for every pixel of the framing `projection`
    /// on a `w × h` image (through [`SkyProjection::camera`]); see
    /// [`SkyView::render_camera`].
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for an invalid projection, a negative or non-finite
    /// ground albedo, and a zero or oversized image (through natura-core's size checks).
    pub fn render(
        &self,
        projection: SkyProjection,
        w: usize,
        h: usize,
        ground: Option<Ground>,
        sun_disc: bool,
    ) -> Result<Image> {
        self.render_camera(&projection.camera(w, h)?, ground, sun_disc)
    }

    /// Renders linear radiance for every pixel of `camera`: sky (with the sun
    /// disc if `sun_disc`), and the ground if given (otherwise the sky LUT's
    /// value below the horizon). Pixels where the camera sees nothing are
    /// black. Only the directions of the camera's rays are used; the eye is
    /// this view's. Rows run in
    /// parallel, each in SIMD chunks of 16 pixels at the widest instruction set
    /// the CPU has (see [`crate::simd`]); the result equals per-pixel
    /// [`SkyView::radiance_f32`] / [`SkyView::ground_radiance`] shading to
    /// 1e-4 relative, and is bit-identical for any thread count.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for a negative or non-finite
    /// ground albedo.
    pub fn render_camera(
        &self,
        camera: &SkyCamera,
        ground: Option<Ground>,
        sun_disc: bool,
    ) -> Result<Image> {
        if let Some(g) = ground {
            crate::error::non_negative3("albedo", g.albedo.as_dvec3())?;
        }
        let (w, h) = camera.resolution();
        let mut grid = Grid2::new(w, h, Vec3::ZERO)?;
        self.render_rows(
            crate::simd::Simd::best(),
            camera,
            &mut grid,
            ground,
            sun_disc,
        );
        Ok(Image::from_grid(grid))
    }
}

/// Returns the exposure (in stops) that maps the mean luminance of the
/// non-black pixels of `img` to `key` (0.18 for mid-grey), like a camera's
/// automatic exposure; 0 for a black image.
#[must_use]
pub fn auto_exposure(img: &Image, key: f32) -> f32 {
    let mut sum = 0.0f64;
    let mut n = 0usize;
    for c in img.pixels().as_slice() {
        let y = natura_core::colour::luminance(*c);
        if y > 0.0 && y.is_finite() {
            sum += f64::from(y).ln();
            n += 1;
        }
    }
    if n == 0 {
        return 0.0;
    }
    let mean = (sum / n as f64).exp() as f32;
    (key / mean).log2()
}

#[allow(dead_code)]
fn _assert_send_sync() {
    fn is<T: Send + Sync>() {}
    is::<SkyView>();
    is::<super::Atmosphere>();
    let _ = DVec3::ZERO;
}
