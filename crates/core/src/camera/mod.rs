//! Cameras: maps from image pixels to primary rays and back.
//!
//! One convention for the whole workspace. Pixel `(x, y)` covers
//! `[x, x + 1) × [y, y + 1)` with `x` to the right and `y` **down** (row 0 at
//! the top, as in [`crate::Image`]); its centre is `(x + 0.5, y + 0.5)`.
//! Angles are radians, image sizes `u32` pixels (at most [`MAX_RESOLUTION`]
//! a side), positions metres in the world frame (z up). Directions are unit
//! length.
//!
//! Each camera has `ray_at(px, py)`, the [`Ray`] through continuous pixel
//! coordinates (`(0, 0)` is the top-left corner of the image, `(width,
//! height)` the bottom-right corner), and its inverse `project(point)`, the
//! continuous pixel coordinates whose ray passes through a point:
//!
//! * [`PinholeCamera`]: the flat virtual screen (Musgrave 1993, §8.1, §8.6);
//! * [`OrthographicCamera`]: parallel rays from a rectangle;
//! * [`PanoramicCamera`]: Musgrave's cylindrical and spherical virtual
//!   screens (Musgrave 1993, ch. 8 and appendix B), optionally one eye of a
//!   [`Stereo`] pair;
//! * [`FisheyeCamera`]: the equidistant fisheye of sky photographs.
//!
//! Generating many rays at once (lanes, jittered samples) is the renderer's
//! business: natura-trace's `Camera::rays_into` calls these maps.
//!
//! ```
//! use natura_core::camera::PinholeCamera;
//! use natura_core::glam::Vec3;
//! let cam = PinholeCamera::look_at(Vec3::ZERO, Vec3::X, Vec3::Z, 0.8, 64, 48)?;
//! let ray = cam.ray_at(10.5, 20.5);
//! let p = cam.project(ray.at(25.0)).expect("a point along a ray is in front");
//! assert!((p.x - 10.5).abs() < 1e-3 && (p.y - 20.5).abs() < 1e-3);
//! # Ok::<(), natura_core::CoreError>(())
//! ```

mod fisheye;
mod orthographic;
mod panoramic;
mod pinhole;

pub use fisheye::FisheyeCamera;
pub use orthographic::OrthographicCamera;
pub use panoramic::{Eye, PanoramicCamera, Projection, Stereo};
pub use pinhole::PinholeCamera;

use glam::Vec3;

use crate::check::ParamError;
use crate::error::{CoreError, Result};

/// Largest image side a camera accepts (pixels): big enough for any print,
/// small enough that a typo fails with an error instead of an allocation.
pub const MAX_RESOLUTION: u32 = 1 << 16;

/// A ray `origin + t·dir`, world space (z up, metres).
///
/// `dir` need not be unit length: distances `t` are in units of `|dir|`, so
/// with a unit `dir` they are metres. A ray whose origin or direction is not
/// finite, or whose direction is zero, is not valid ([`Ray::is_valid`]) and
/// a tracer finds no hit along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Which way it goes.
    pub dir: Vec3,
}

impl Ray {
    /// Returns the ray from `origin` along `dir`.
    #[inline]
    #[must_use]
    pub const fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
    }

    /// Returns the point at parameter `t`, `origin + t·dir`.
    #[inline]
    #[must_use]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }

    /// Whether the ray can be traced: finite origin, finite non-zero direction.
    #[inline]
    #[must_use]
    pub fn is_valid(&self) -> bool {
        self.origin.is_finite() && self.dir.is_finite() && self.dir != Vec3::ZERO
    }
}

/// The error for parameter `name` with value `value`, which should have been `reason`.
fn param(name: &'static str, value: impl std::fmt::Display, reason: &'static str) -> CoreError {
    ParamError::new(name, value, reason).into()
}

/// Checks an image size: each side between 1 and [`MAX_RESOLUTION`] pixels.
///
/// # Errors
///
/// A [`ParamError`] naming `width` or `height` if a side is zero or over
/// [`MAX_RESOLUTION`].
pub fn check_resolution(width: u32, height: u32) -> Result<(), ParamError> {
    for (name, v) in [("width", width), ("height", height)] {
        if v == 0 || v > MAX_RESOLUTION {
            return Err(ParamError::new(
                name,
                v,
                "must be between 1 and MAX_RESOLUTION (65536) pixels",
            ));
        }
    }
    Ok(())
}

/// Checks that `v` is finite.
fn check_vec(name: &'static str, v: Vec3) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(param(name, v, "must be finite"))
    }
}

/// An orthonormal view frame `(forward, right, up)` from a view direction and
/// an up hint; fails if either is zero or they are parallel.
fn frame(dir: Vec3, up: Vec3) -> Result<(Vec3, Vec3, Vec3)> {
    check_vec("direction", dir)?;
    check_vec("up", up)?;
    let f = dir
        .try_normalize()
        .ok_or_else(|| param("direction", dir, "must be non-zero (eye ≠ target)"))?;
    // Musgrave 1993, §8.6: "The view and up directions are identical?"
    let r = f.cross(up).try_normalize().ok_or_else(|| {
        param(
            "up",
            up,
            "must be non-zero and not parallel to the view direction",
        )
    })?;
    let u = r.cross(f);
    Ok((f, r, u))
}

/// Continuous pixel coordinates from screen coordinates `(nx, ny)` in
/// `[−1, 1]²` (x right, y up) on a `w × h` image: the inverse of
/// `nx = 2·px/w − 1`, `ny = 1 − 2·py/h`.
#[inline]
fn pixel_from_screen(nx: f32, ny: f32, w: u32, h: u32) -> glam::Vec2 {
    glam::Vec2::new((nx + 1.0) * 0.5 * w as f32, (1.0 - ny) * 0.5 * h as f32)
}
