//! The standard flat virtual screen: a pinhole camera.

use glam::{UVec2, Vec3};

use super::{Camera, RAY_LANES, check_resolution, check_vec, frame, pixel_lanes};
use crate::batch::RenderOptions;
use crate::error::{Result, TraceError};
use crate::ray::Ray;

/// A pinhole camera with a flat virtual screen, set up by look-at, vertical
/// field of view and aspect ratio.
///
/// Rayshade's `RSViewing` / `SampleScreen` (Musgrave 1993, §8.6): the screen is perpendicular to the view direction, spanned by
/// `right = normalize(dir × up)` and `up' = right × dir`, and a sample's ray
/// is `normalize(dir + sx·right + sy·up')` with `sx, sy` linear in the pixel
/// coordinates. The field of view must stay below 180°: at 180° the eye lies
/// in the screen plane (Musgrave 1993, §8.1); use [`crate::PanoramicCamera`] for wider views.
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
    /// Fails if a vector is not finite, `eye == target`, `up` is zero or
    /// parallel to the view direction, `vfov` is out of range, or the
    /// resolution is zero or over [`crate::MAX_RESOLUTION`].
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
            return Err(TraceError::param("vfov", vfov, "must be in (0, π) radians"));
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
    /// Fails unless `aspect` is finite and positive.
    pub fn with_aspect(mut self, aspect: f32) -> Result<Self> {
        if !(aspect.is_finite() && aspect > 0.0) {
            return Err(TraceError::param(
                "aspect",
                aspect,
                "must be finite and > 0",
            ));
        }
        self.aspect = aspect;
        Ok(self)
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
}

impl Camera for PinholeCamera {
    fn resolution(&self) -> UVec2 {
        UVec2::new(self.width, self.height)
    }

    #[inline]
    fn ray_at(&self, px: f32, py: f32) -> Ray {
        let sx = (2.0 * px / self.width as f32 - 1.0) * self.tan_half_v * self.aspect;
        let sy = (1.0 - 2.0 * py / self.height as f32) * self.tan_half_v;
        let d = self.forward + sx * self.right + sy * self.up;
        Ray::new(self.eye, d.normalize())
    }

    /// [`RAY_LANES`] rays at a time: the screen coordinates `sx, sy` and the
    /// direction `forward + sx·right + sy·up` (affine in the pixel
    /// coordinates) and its normalisation as loops over lanes, with the same
    /// `f32` operations in the same order as [`Camera::ray_at`], so the rays
    /// are equal bit for bit.
    #[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
    fn rays_into(
        &self,
        x0: u32,
        y0: u32,
        w: u32,
        h: u32,
        options: &RenderOptions,
        out: &mut Vec<Ray>,
    ) {
        out.reserve(w as usize * h as usize * options.samples_per_pixel as usize);
        let (wf, hf) = (self.width as f32, self.height as f32);
        let (t, a) = (self.tan_half_v, self.aspect);
        let (f, r, u) = (self.forward, self.right, self.up);
        pixel_lanes(x0, y0, w, h, options, |px, py, n| {
            let mut d = [[0.0f32; RAY_LANES]; 3];
            for l in 0..RAY_LANES {
                let sx = (2.0 * px[l] / wf - 1.0) * t * a;
                let sy = (1.0 - 2.0 * py[l] / hf) * t;
                let (x, y, z) = (
                    f.x + sx * r.x + sy * u.x,
                    f.y + sx * r.y + sy * u.y,
                    f.z + sx * r.z + sy * u.z,
                );
                // `Vec3::normalize`: times the reciprocal of the length.
                let k = 1.0 / (x * x + y * y + z * z).sqrt();
                d[0][l] = x * k;
                d[1][l] = y * k;
                d[2][l] = z * k;
            }
            let eye = self.eye;
            out.extend((0..n).map(|l| Ray::new(eye, Vec3::new(d[0][l], d[1][l], d[2][l]))));
        });
    }
}
