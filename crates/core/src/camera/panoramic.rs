//! Musgrave's panoramic virtual screen (Musgrave 1993, ch. 8
//! and appendix B; published in *Graphics Gems III*).

use std::f32::consts::{FRAC_PI_2, PI, TAU};

use glam::{UVec2, Vec2, Vec3};

use super::{Ray, check_resolution, check_vec, param};
use crate::error::Result;

/// How rows of a [`PanoramicCamera`] map to elevation. The formulas below
/// are for a screen centred on the horizon;
/// [`PanoramicCamera::with_elevation_centre`] shifts it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Projection {
    /// A cylindrical screen sampled evenly in height (Musgrave 1993,
    /// §8.2): azimuth linear in x, and the vertical offset on the
    /// cylinder linear in y, so `elevation = atan(tan(vfov/2)·(1 − 2y/h))`.
    /// This is the faceted-cylinder panorama of the VPE lab taken to one-pixel
    /// facets (Musgrave 1993, §8.4); its vertical field must stay below 180°.
    Cylindrical,
    /// The cylindrical equirectangular screen of Musgrave 1993, §8.3,
    /// which maps the whole celestial sphere: azimuth linear in x and
    /// **elevation linear in y**, `elevation = vfov·(½ − y/h)`. Vertical
    /// fields beyond 180° give the source's periodic, always right-side-up
    /// images (elevations are wrapped by 180°, as its `tan` table does).
    Spherical,
}

/// Which eye of a stereo pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Eye {
    /// The left eye (offset to the left of each column's view direction).
    Left,
    /// The right eye.
    Right,
}

/// A stereo panorama's eye: the eye points describe a circle of radius
/// `separation / 2` as the view direction scans the screen (Hitchner's scheme,
/// Musgrave 1993, §8.4), which keeps stereo over the whole 360°.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stereo {
    /// Which eye this camera renders.
    pub eye: Eye,
    /// Distance between the two eyes, metres.
    pub separation: f32,
}

/// A panoramic camera: fields of view up to and beyond 360° × 180°.
///
/// Column `x` looks at azimuth `hfov·(½ − x/w)` from the (levelled) view
/// direction, counterclockwise about `up` (so the image's left shows what is on
/// the camera's left); row `y` maps to elevation by the [`Projection`].
///
/// Differences from the source's code (Musgrave 1993, §8.6):
///
/// * Directions are evaluated exactly from the angles instead of by linear
///   interpolation between per-column and per-row tables (Musgrave 1993, §8.2). The
///   printed interpolation also uses `horizdir` where it means `vertdir`
///   (Musgrave 1993, §8.6), an erratum that does not arise here.
/// * The view direction is levelled (projected perpendicular to `up`): the
///   source's "vertical vectors orthogonal to all horizontal directions"
///   (Musgrave 1993, §8.3) holds only for a level view.
/// * Stereo eyes sit at `pos ± (separation/2)·(up × h(x))` for each column's
///   horizontal direction `h(x)`, so the baseline is always perpendicular to
///   the view. The source rotates a fixed offset by `x·hincr` only, which is
///   perpendicular only when `hfov/2` is a multiple of 180°.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PanoramicCamera {
    position: Vec3,
    forward: Vec3,
    left: Vec3,
    up: Vec3,
    hfov: f32,
    vfov: f32,
    tan_half_v: f32,
    /// Elevation of the middle row (spherical screen), radians.
    centre: f32,
    /// Height on the cylinder of the middle row, `tan(centre)` (cylindrical).
    tan_centre: f32,
    projection: Projection,
    stereo: Option<Stereo>,
    width: u32,
    height: u32,
}

impl PanoramicCamera {
    /// Returns a panorama from `position` centred on the horizontal direction
    /// of `look_dir` (levelled), with `up` the zenith, horizontal field `hfov`
    /// and vertical field `vfov` (radians), on a `width × height` image.
    ///
    /// `hfov` may exceed 2π (a periodic "wallpaper", Musgrave 1993, §8.3). For
    /// [`Projection::Spherical`] `vfov` may exceed π; for
    /// [`Projection::Cylindrical`] it must be below π.
    ///
    /// # Errors
    ///
    /// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) on non-finite
    /// vectors, a zero `up`, a `look_dir` parallel to `up`, a non-positive
    /// or non-finite field of view, or a bad resolution.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        position: Vec3,
        look_dir: Vec3,
        up: Vec3,
        hfov: f32,
        vfov: f32,
        projection: Projection,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        check_resolution(width, height)?;
        check_vec("position", position)?;
        check_vec("look_dir", look_dir)?;
        check_vec("up", up)?;
        let up = up
            .try_normalize()
            .ok_or_else(|| param("up", up, "must be non-zero"))?;
        let forward = (look_dir - look_dir.dot(up) * up)
            .try_normalize()
            .ok_or_else(|| {
                param(
                    "look_dir",
                    look_dir,
                    "must be non-zero and not parallel to up",
                )
            })?;
        if !(hfov.is_finite() && hfov > 0.0) {
            return Err(param("hfov", hfov, "must be finite and > 0 radians"));
        }
        let vmax = match projection {
            Projection::Cylindrical => PI,
            Projection::Spherical => f32::INFINITY,
        };
        if !(vfov.is_finite() && vfov > 0.0 && vfov < vmax) {
            return Err(param(
                "vfov",
                vfov,
                "must be finite and > 0 radians (and < π for a cylindrical screen)",
            ));
        }
        Ok(Self {
            position,
            forward,
            left: up.cross(forward),
            up,
            hfov,
            vfov,
            tan_half_v: (0.5 * vfov).tan(),
            centre: 0.0,
            tan_centre: 0.0,
            projection,
            stereo: None,
            width,
            height,
        })
    }

    /// Returns the camera rendering one eye of a stereo pair.
    ///
    /// # Errors
    ///
    /// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) unless
    /// `stereo.separation` is finite and non-negative.
    pub fn with_stereo(mut self, stereo: Stereo) -> Result<Self> {
        if !(stereo.separation.is_finite() && stereo.separation >= 0.0) {
            return Err(param(
                "separation",
                stereo.separation,
                "must be finite and ≥ 0 metres",
            ));
        }
        self.stereo = Some(stereo);
        Ok(self)
    }

    /// Returns the camera with its middle row at elevation `centre` (radians)
    /// instead of the horizon: a rise of the screen, like a view camera's
    /// shift, which keeps verticals vertical.
    ///
    /// On the spherical screen the rows then span the elevations
    /// `centre ± vfov/2`; on the cylindrical screen the screen slides up the
    /// cylinder by `tan(centre)`, keeping its height `2·tan(vfov/2)`.
    ///
    /// # Errors
    ///
    /// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter)
    /// unless `centre` is finite, and for a cylindrical screen inside
    /// `(−π/2, π/2)`.
    pub fn with_elevation_centre(mut self, centre: f32) -> Result<Self> {
        let ok = match self.projection {
            Projection::Cylindrical => centre.abs() < FRAC_PI_2,
            Projection::Spherical => centre.is_finite(),
        };
        if !ok {
            return Err(param(
                "centre",
                centre,
                "must be finite radians (inside (−π/2, π/2) for a cylindrical screen)",
            ));
        }
        self.centre = centre;
        self.tan_centre = if centre == 0.0 { 0.0 } else { centre.tan() };
        Ok(self)
    }

    /// Azimuth of continuous column `px`, radians counterclockwise about `up`
    /// from the levelled view direction: `hfov·(½ − px/w)`.
    #[inline]
    #[must_use]
    pub fn azimuth(&self, px: f32) -> f32 {
        self.hfov * (0.5 - px / self.width as f32)
    }

    /// Elevation of continuous row `py` above the horizon, radians, as the
    /// [`Projection`] states (before the spherical screen's 180° wrap).
    #[inline]
    #[must_use]
    pub fn elevation(&self, py: f32) -> f32 {
        let s = 1.0 - 2.0 * py / self.height as f32;
        match self.projection {
            Projection::Cylindrical => (self.tan_centre + self.tan_half_v * s).atan(),
            Projection::Spherical => self.centre + 0.5 * self.vfov * s,
        }
    }

    /// The unit horizontal direction at azimuth `az`.
    #[inline]
    fn horizontal(&self, az: f32) -> Vec3 {
        let (s, c) = az.sin_cos();
        c * self.forward + s * self.left
    }

    /// Image size in pixels, `(width, height)`.
    #[must_use]
    pub fn resolution(&self) -> UVec2 {
        UVec2::new(self.width, self.height)
    }

    /// Returns the ray through continuous pixel coordinates `(px, py)`: the
    /// direction at [`PanoramicCamera::azimuth`] and
    /// [`PanoramicCamera::elevation`], from the position (mono) or from the
    /// column's eye point (stereo).
    #[inline]
    #[must_use]
    pub fn ray_at(&self, px: f32, py: f32) -> Ray {
        let h = self.horizontal(self.azimuth(px));
        let dir = match self.projection {
            Projection::Cylindrical => {
                let s = 1.0 - 2.0 * py / self.height as f32;
                (h + (self.tan_centre + self.tan_half_v * s) * self.up).normalize()
            }
            Projection::Spherical => {
                // The source's tan table is periodic in 180° and right-side-up:
                // wrap the elevation into [−90°, 90°].
                let mut e = self.elevation(py);
                if e.abs() > FRAC_PI_2 {
                    e -= PI * ((e + FRAC_PI_2) / PI).floor();
                }
                let (s, c) = e.sin_cos();
                (c * h + s * self.up).normalize()
            }
        };
        let origin = match self.stereo {
            None => self.position,
            Some(st) => {
                let side = self.up.cross(h) * (0.5 * st.separation);
                match st.eye {
                    Eye::Left => self.position + side,
                    Eye::Right => self.position - side,
                }
            }
        };
        Ray::new(origin, dir)
    }

    /// Returns the continuous pixel coordinates `(px, py)` whose ray passes
    /// through `point` (the inverse of [`PanoramicCamera::ray_at`]), or
    /// `None` if no ray of the camera's map reaches it: the point is not
    /// finite, sits at the position (or, for a stereo eye, within
    /// `separation / 2` of the vertical through it), or lies on the vertical
    /// through the position for a cylindrical screen.
    ///
    /// A stereo eye's column is the one whose eye point sees `point` straight
    /// ahead horizontally: with `q` the point's horizontal offset from the
    /// position at azimuth `φ` and distance `r`, the column's azimuth is
    /// `φ − asin(±separation / 2r)`.
    ///
    /// Where the screen wraps (a horizontal field over 2π, or a spherical
    /// vertical field over π, Musgrave 1993, §8.3) the first of the columns
    /// or rows showing the point is returned. Otherwise the coordinates lie
    /// outside `[0, width] × [0, height]` for a point outside the picture.
    #[must_use]
    pub fn project(&self, point: Vec3) -> Option<Vec2> {
        let q = point - self.position;
        let (qf, ql, qv) = (q.dot(self.forward), q.dot(self.left), q.dot(self.up));
        let phi = ql.atan2(qf);
        let r = qf.hypot(ql);
        let (az, run) = match self.stereo {
            None => (phi, r),
            Some(st) => {
                let side = match st.eye {
                    Eye::Left => 0.5 * st.separation,
                    Eye::Right => -0.5 * st.separation,
                };
                if r.is_nan() || r <= side.abs() {
                    return None;
                }
                // The eye point sits `side` along `up × h(az)`, i.e. at
                // azimuth `az + π/2`: `r·sin(φ − az) = side`.
                let a = (side / r).asin();
                (phi - a, r * a.cos())
            }
        };
        let (w, h) = (self.width as f32, self.height as f32);
        let mut px = (0.5 - az / self.hfov) * w;
        if self.hfov > TAU {
            px = px.rem_euclid(w * TAU / self.hfov);
        }
        let py = match self.projection {
            Projection::Cylindrical => {
                if run.is_nan() || run <= 0.0 {
                    return None;
                }
                let s = (qv / run - self.tan_centre) / self.tan_half_v;
                (1.0 - s) * 0.5 * h
            }
            Projection::Spherical => {
                if run.is_nan() || (run <= 0.0 && qv == 0.0) {
                    return None;
                }
                let s = 2.0 * (qv.atan2(run) - self.centre) / self.vfov;
                let py = (1.0 - s) * 0.5 * h;
                if self.vfov > PI {
                    py.rem_euclid(h * PI / self.vfov)
                } else {
                    py
                }
            }
        };
        let p = Vec2::new(px, py);
        p.is_finite().then_some(p)
    }
}
