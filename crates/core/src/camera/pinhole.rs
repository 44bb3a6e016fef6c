//! The standard flat virtual screen: a pinhole camera.

use glam::{UVec2, Vec2, Vec3};

use super::{Ray, check_resolution, check_vec, frame, param, pixel_from_screen};
use crate::error::Result;

/// A pinhole camera with a flat virtual screen, set up by look-at, vertical
/// field of view and aspect ratio.
///
/// Rayshade's `RSViewing` / `SampleScreen` (Musgrave 1993, §8.6): the screen
/// is perpendicular to the view direction, spanned by
/// `right = normalize(dir × up)` and `up' = right × dir`, and a sample's ray
/// is `normalize(dir + sx·right + sy·up')` with `sx, sy` linear in the pixel
/// coordinates. The field of view must stay below 180°: at 180° the eye lies
/// in the screen plane (Musgrave 1993, §8.1); use
/// [`PanoramicCamera`](super::PanoramicCamera) for wider views.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PinholeCamera {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    tan_half_v: f32,
    aspect: f32,
    width: u32,
    height: u32,
}

impl PinholeCamera {
    /// Returns a camera at `eye` looking at `target`, with `up` as the up hint,
    /// vertical field of view `vfov` (radians, in `(0, π)`) and a `width ×
    /// height` image with square pixels (aspect = width / height).
    ///
    /// # Errors
    ///
    /// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) if
    /// a vector is not finite, `eye == target`, `up` is zero or parallel to
    /// the view direction, `vfov` is out of range, or the resolution is zero
    /// or over [`MAX_RESOLUTION`](super::MAX_RESOLUTION).
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        vfov: f32,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        check_resolution(width, height)?;
        check_vec("eye", eye)?;
        check_vec("target", target)?;
        if !(vfov > 0.0 && vfov < std::f32::consts::PI) {
            return Err(param("vfov", vfov, "must be in (0, π) radians"));
        }
        let (forward, right, up) = frame(target - eye, up)?;
        Ok(Self {
            eye,
            forward,
            right,
            up,
            tan_half_v: (0.5 * vfov).tan(),
            aspect: width as f32 / height as f32,
            width,
            height,
        })
    }

    /// Returns the camera with screen aspect ratio `aspect` (width / height of
    /// the visible rectangle) instead of the pixel ratio, for non-square pixels.
    ///
    /// # Errors
    ///
    /// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter)
    /// unless `aspect` is finite and positive.
    pub fn with_aspect(mut self, aspect: f32) -> Result<Self> {
        if !(aspect.is_finite() && aspect > 0.0) {
            return Err(param("aspect", aspect, "must be finite and > 0"));
        }
        self.aspect = aspect;
        Ok(self)
    }

    /// Image size in pixels, `(width, height)`.
    #[must_use]
    pub fn resolution(&self) -> UVec2 {
        UVec2::new(self.width, self.height)
    }

    /// The eye position.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        self.eye
    }

    /// The unit view direction (the ray through the image centre).
    #[must_use]
    pub fn direction(&self) -> Vec3 {
        self.forward
    }

    /// The horizontal field of view, radians.
    #[must_use]
    pub fn hfov(&self) -> f32 {
        2.0 * (self.tan_half_v * self.aspect).atan()
    }

    /// Returns the ray through continuous pixel coordinates `(px, py)`: from
    /// the eye along `normalize(dir + sx·right + sy·up')` with
    /// `sx = (2·px/w − 1)·tan(vfov/2)·aspect`, `sy = (1 − 2·py/h)·tan(vfov/2)`.
    #[inline]
    #[must_use]
    pub fn ray_at(&self, px: f32, py: f32) -> Ray {
        let sx = (2.0 * px / self.width as f32 - 1.0) * self.tan_half_v * self.aspect;
        let sy = (1.0 - 2.0 * py / self.height as f32) * self.tan_half_v;
        let d = self.forward + sx * self.right + sy * self.up;
        Ray::new(self.eye, d.normalize())
    }

    /// Returns the continuous pixel coordinates `(px, py)` whose ray passes
    /// through `point` (the inverse of [`PinholeCamera::ray_at`]), or `None`
    /// if `point` is not in front of the eye (on or behind the plane through
    /// the eye perpendicular to the view) or not finite. The coordinates lie
    /// outside `[0, width] × [0, height]` for a point outside the picture.
    #[inline]
    #[must_use]
    pub fn project(&self, point: Vec3) -> Option<Vec2> {
        let q = point - self.eye;
        let (x, y, z) = (q.dot(self.right), q.dot(self.up), q.dot(self.forward));
        if z.is_nan() || z <= 0.0 {
            return None;
        }
        let s = 1.0 / (z * self.tan_half_v);
        let p = pixel_from_screen(x * s / self.aspect, y * s, self.width, self.height);
        p.is_finite().then_some(p)
    }
}
