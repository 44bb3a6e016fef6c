//! A parallel projection: every ray has the same direction.

use glam::{UVec2, Vec3};

use super::{Camera, RAY_LANES, check_resolution, check_vec, frame, pixel_lanes};
use crate::batch::RenderOptions;
use crate::error::{Result, TraceError};
use crate::ray::Ray;

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
    /// Fails like [`crate::PinholeCamera::look_at`], or if `view_height` is
    /// not finite and positive.
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
            return Err(TraceError::param(
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
            width,
            height,
        })
    }

    /// The unit view direction shared by all rays.
    #[must_use]
    pub fn direction(&self) -> Vec3 {
        self.forward
    }
}

impl Camera for OrthographicCamera {
    fn resolution(&self) -> UVec2 {
        UVec2::new(self.width, self.height)
    }

    #[inline]
    fn ray_at(&self, px: f32, py: f32) -> Ray {
        let sx = (2.0 * px / self.width as f32 - 1.0) * self.half_w;
        let sy = (1.0 - 2.0 * py / self.height as f32) * self.half_h;
        Ray::new(self.centre + sx * self.right + sy * self.up, self.forward)
    }

    /// [`RAY_LANES`] rays at a time: the origins `centre + sx·right +
    /// sy·up` (affine in the pixel coordinates) as loops over lanes, with the
    /// same `f32` operations in the same order as [`Camera::ray_at`], so the
    /// rays are equal bit for bit.
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
        let (c, r, u) = (self.centre, self.right, self.up);
        let (hw, hh) = (self.half_w, self.half_h);
        pixel_lanes(x0, y0, w, h, options, |px, py, n| {
            let mut o = [[0.0f32; RAY_LANES]; 3];
            for l in 0..RAY_LANES {
                let sx = (2.0 * px[l] / wf - 1.0) * hw;
                let sy = (1.0 - 2.0 * py[l] / hf) * hh;
                o[0][l] = c.x + sx * r.x + sy * u.x;
                o[1][l] = c.y + sx * r.y + sy * u.y;
                o[2][l] = c.z + sx * r.z + sy * u.z;
            }
            let f = self.forward;
            out.extend((0..n).map(|l| Ray::new(Vec3::new(o[0][l], o[1][l], o[2][l]), f)));
        });
    }
}
