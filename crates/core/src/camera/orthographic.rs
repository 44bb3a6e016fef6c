//! A parallel projection: every ray has the same direction.

use glam::{UVec2, Vec2, Vec3};

use super::{Ray, check_resolution, check_vec, frame, param, pixel_from_screen};
use crate::error::Result;

/// An orthographic camera: parallel rays from a rectangle perpendicular to
/// the view direction, for maps, top-down views and elevations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrthographicCamera {
    centre: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    half_w: f32,
    half_h: f32,
    aspect: f32,
    width: u32,
    height: u32,
}

impl OrthographicCamera {
    /// Returns a camera whose screen is centred on `eye`, looking toward
    /// `target`, `view_height` metres tall (the width follows from the
    /// `width × height` pixel ratio). Rays start on the screen, so place
    /// `eye` above or in front of everything to be seen.
    ///
    /// # Errors
    ///
    /// Fails like [`PinholeCamera::look_at`](super::PinholeCamera::look_at),
    /// or if `view_height` is not finite and positive.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        view_height: f32,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        check_resolution(width, height)?;
        check_vec("eye", eye)?;
        check_vec("target", target)?;
        if !(view_height.is_finite() && view_height > 0.0) {
            return Err(param(
                "view_height",
                view_height,
                "must be finite and > 0 metres",
            ));
        }
        let (forward, right, up) = frame(target - eye, up)?;
        let half_h = 0.5 * view_height;
        Ok(Self {
            centre: eye,
            forward,
            right,
            up,
            half_w: half_h * width as f32 / height as f32,
            half_h,
            aspect: width as f32 / height as f32,
            width,
            height,
        })
    }

    /// Image size in pixels, `(width, height)`.
    #[must_use]
    pub fn resolution(&self) -> UVec2 {
        UVec2::new(self.width, self.height)
    }

    /// The centre of the screen (the `eye` it was set up with).
    #[must_use]
    pub fn centre(&self) -> Vec3 {
        self.centre
    }

    /// The unit view direction shared by all rays.
    #[must_use]
    pub fn direction(&self) -> Vec3 {
        self.forward
    }

    /// Returns the ray through continuous pixel coordinates `(px, py)`: from
    /// `centre + sx·right + sy·up'` along the view direction, with
    /// `sx = (2·px/w − 1)·half_width`, `sy = (1 − 2·py/h)·half_height`.
    #[inline]
    #[must_use]
    pub fn ray_at(&self, px: f32, py: f32) -> Ray {
        let sx = (2.0 * px / self.width as f32 - 1.0) * self.half_w;
        let sy = (1.0 - 2.0 * py / self.height as f32) * self.half_h;
        Ray::new(self.centre + sx * self.right + sy * self.up, self.forward)
    }

    /// Returns the continuous pixel coordinates `(px, py)` whose ray passes
    /// through `point` (the inverse of [`OrthographicCamera::ray_at`]), or
    /// `None` if `point` lies behind the screen (rays start on it) or is not
    /// finite. The coordinates lie outside `[0, width] × [0, height]` for a
    /// point outside the picture.
    #[inline]
    #[must_use]
    pub fn project(&self, point: Vec3) -> Option<Vec2> {
        let q = point - self.centre;
        let (x, y, z) = (q.dot(self.right), q.dot(self.up), q.dot(self.forward));
        if z.is_nan() || z < 0.0 {
            return None;
        }
        let (nx, ny) = (x / self.half_h, y / self.half_h);
        let p = pixel_from_screen(nx / self.aspect, ny, self.width, self.height);
        p.is_finite().then_some(p)
    }
}
