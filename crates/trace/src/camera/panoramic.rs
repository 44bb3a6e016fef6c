//! Musgrave's panoramic virtual screen (Musgrave 1993, ch. 8
//! and appendix B; published in *Graphics Gems III*).

use glam::{UVec2, Vec3};

use super::{Camera, check_resolution, check_vec};
use crate::error::{Result, TraceError};
use crate::ray::Ray;

/// How rows of a [`PanoramicCamera`] map to elevation.
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
    /// Fails on non-finite
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
            .ok_or_else(|| TraceError::param("up", up, "must be non-zero"))?;
        let forward = (look_dir - look_dir.dot(up) * up)
            .try_normalize()
            .ok_or_else(|| {
                TraceError::param(
                    "look_dir",
                    look_dir,
                    "must be non-zero and not parallel to up",
                )
            })?;
        if !(hfov.is_finite() && hfov > 0.0) {
            return Err(TraceError::param(
                "hfov",
                hfov,
                "must be finite and > 0 radians",
            ));
        }
        let vmax = match projection {
            Projection::Cylindrical => std::f32::consts::PI,
            Projection::Spherical => f32::INFINITY,
        };
        if !(vfov.is_finite() && vfov > 0.0 && vfov < vmax) {
            return Err(TraceError::param(
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
    /// Fails unless
    /// `stereo.separation` is finite and non-negative.
    pub fn with_stereo(mut self, stereo: Stereo) -> Result<Self> {
        if !(stereo.separation.is_finite() && stereo.separation >= 0.0) {
            return Err(TraceError::param(
                "separation",
                stereo.separation,
                "must be finite and ≥ 0 metres",
            ));
        }
        self.stereo = Some(stereo);
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
            Projection::Cylindrical => (self.tan_half_v * s).atan(),
            Projection::Spherical => 0.5 * self.vfov * s,
        }
    }

    /// The unit horizontal direction at azimuth `az`.
    #[inline]
    fn horizontal(&self, az: f32) -> Vec3 {
        let (s, c) = az.sin_cos();
        c * self.forward + s * self.left
    }
}

impl Camera for PanoramicCamera {
    fn resolution(&self) -> UVec2 {
        UVec2::new(self.width, self.height)
    }

    #[inline]
    fn ray_at(&self, px: f32, py: f32) -> Ray {
        let h = self.horizontal(self.azimuth(px));
        let dir = match self.projection {
            Projection::Cylindrical => {
                let s = 1.0 - 2.0 * py / self.height as f32;
                (h + (self.tan_half_v * s) * self.up).normalize()
            }
            Projection::Spherical => {
                // The source's tan table is periodic in 180° and right-side-up:
                // wrap the elevation into [−90°, 90°].
                let half_pi = std::f32::consts::FRAC_PI_2;
                let mut e = self.elevation(py);
                if e.abs() > half_pi {
                    e -= std::f32::consts::PI * ((e + half_pi) / std::f32::consts::PI).floor();
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
}
