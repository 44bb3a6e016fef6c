//! The equidistant fisheye: the whole sky in one circular picture.

use glam::{UVec2, Vec2, Vec3};

use super::{Ray, check_resolution, check_vec, frame, param};
use crate::error::Result;

/// An equidistant ("f-θ") fisheye camera: the angle from the view direction
/// grows linearly with the distance from the picture's centre, reaching
/// `fov/2` on the circle inscribed in the image.
///
/// A pixel at normalised offset `(u, v)` from the centre (`u` right, `v` up,
/// both in units of half the shorter image side) with `r = √(u² + v²) ≤ 1`
/// looks at angle `θ = r·fov/2` from the view direction, towards
/// `(u·right + v·up)/r`:
/// `dir = cos θ·forward + sin θ·(u·right + v·up)/r`. This is the
/// equidistant projection of all-sky photographs (a hemisphere with the
/// zenith at the centre when `fov` is π). Like every camera of this module, the
/// picture's left shows what is on the camera's left: looking at the zenith
/// with north up, east is on the left, as on a star chart.
///
/// Pixels outside the circle see nothing: their ray has a zero direction,
/// which [`Ray::is_valid`] reports as not traceable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FisheyeCamera {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    half_fov: f32,
    width: u32,
    height: u32,
}

impl FisheyeCamera {
    /// Returns a fisheye at `eye` looking along `look_dir`, with `up` the
    /// direction shown upward, a field `fov` (radians, in `(0, 2π]`: π is a
    /// hemisphere, 2π the whole sphere) across the inscribed circle, on a
    /// `width × height` image.
    ///
    /// # Errors
    ///
    /// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) if
    /// a vector is not finite, `look_dir` is zero, `up` is zero or parallel to
    /// `look_dir`, `fov` is out of range, or the resolution is zero or over
    /// [`MAX_RESOLUTION`](super::MAX_RESOLUTION).
    pub fn new(
        eye: Vec3,
        look_dir: Vec3,
        up: Vec3,
        fov: f32,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        check_resolution(width, height)?;
        check_vec("eye", eye)?;
        if !(fov > 0.0 && fov <= std::f32::consts::TAU) {
            return Err(param("fov", fov, "must be in (0, 2π] radians"));
        }
        let (forward, right, up) = frame(look_dir, up)?;
        Ok(Self {
            eye,
            forward,
            right,
            up,
            half_fov: 0.5 * fov,
            width,
            height,
        })
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

    /// Half the shorter image side, pixels: the image circle's radius.
    #[inline]
    fn radius(&self) -> f32 {
        0.5 * self.width.min(self.height) as f32
    }

    /// Returns the ray through continuous pixel coordinates `(px, py)`; its
    /// direction is zero (an invalid ray) outside the image circle.
    #[inline]
    #[must_use]
    pub fn ray_at(&self, px: f32, py: f32) -> Ray {
        let s = self.radius();
        let u = (px - 0.5 * self.width as f32) / s;
        let v = (0.5 * self.height as f32 - py) / s;
        let r = (u * u + v * v).sqrt();
        if r.is_nan() || r > 1.0 {
            return Ray::new(self.eye, Vec3::ZERO);
        }
        let (st, ct) = (r * self.half_fov).sin_cos();
        let side = if r > 0.0 {
            (u / r) * self.right + (v / r) * self.up
        } else {
            Vec3::ZERO
        };
        Ray::new(self.eye, (ct * self.forward + st * side).normalize())
    }

    /// Returns the continuous pixel coordinates `(px, py)` whose ray passes
    /// through `point` (the inverse of [`FisheyeCamera::ray_at`]), or `None`
    /// if `point` is not finite, sits at the eye, or lies outside the field
    /// (more than `fov/2` from the view direction).
    #[inline]
    #[must_use]
    pub fn project(&self, point: Vec3) -> Option<Vec2> {
        let q = point - self.eye;
        let (x, y, z) = (q.dot(self.right), q.dot(self.up), q.dot(self.forward));
        let side = x.hypot(y);
        let theta = side.atan2(z);
        if !(theta.is_finite() && q != Vec3::ZERO) || theta > self.half_fov {
            return None;
        }
        let r = theta / self.half_fov;
        let (cu, cv) = if side > 0.0 {
            (x / side, y / side)
        } else {
            (0.0, 0.0)
        };
        let s = self.radius();
        let p = Vec2::new(
            0.5 * self.width as f32 + r * cu * s,
            0.5 * self.height as f32 - r * cv * s,
        );
        p.is_finite().then_some(p)
    }
}
