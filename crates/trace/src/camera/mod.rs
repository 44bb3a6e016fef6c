//! Cameras: maps from pixels to primary rays.
//!
//! Every camera implements [`Camera`]: a resolution and a map from continuous
//! pixel coordinates to a [`Ray`]. Pixel `(x, y)` covers `[x, x + 1) × [y, y + 1)`
//! with `x` to the right and `y` **down** (row 0 at the top, as in
//! [`natura_core::Image`]); its centre is `(x + 0.5, y + 0.5)`, which is what
//! [`Camera::ray`] gives for a jitter of `(0.5, 0.5)`. Directions are unit length.

mod orthographic;
mod panoramic;
mod pinhole;

pub use orthographic::OrthographicCamera;
pub use panoramic::{Eye, PanoramicCamera, Projection, Stereo};
pub use pinhole::PinholeCamera;

use glam::{UVec2, Vec2, Vec3};

use crate::error::{Result, TraceError};
use crate::ray::Ray;

/// Largest image side a camera accepts (pixels): big enough for any print,
/// small enough that a typo fails with an error instead of an allocation.
pub const MAX_RESOLUTION: u32 = 1 << 16;

/// A map from image pixels to primary rays.
pub trait Camera: Sync {
    /// Image size in pixels, `(width, height)`.
    fn resolution(&self) -> UVec2;

    /// Returns the ray through continuous pixel coordinates `(px, py)`:
    /// `(0, 0)` is the top-left corner of the image, `(width, height)` the
    /// bottom-right corner.
    fn ray_at(&self, px: f32, py: f32) -> Ray;

    /// Returns the ray through pixel `(x, y)` at sub-pixel offset `jitter`
    /// (each component in `[0, 1)`; `(0.5, 0.5)` is the pixel's centre).
    #[inline]
    fn ray(&self, x: u32, y: u32, jitter: Vec2) -> Ray {
        self.ray_at(x as f32 + jitter.x, y as f32 + jitter.y)
    }
}

/// Checks a resolution.
pub(crate) fn check_resolution(width: u32, height: u32) -> Result<()> {
    for (name, v) in [("width", width), ("height", height)] {
        if v == 0 || v > MAX_RESOLUTION {
            return Err(TraceError::param(
                name,
                v,
                "must be between 1 and MAX_RESOLUTION (65536) pixels",
            ));
        }
    }
    Ok(())
}

/// Checks that `v` is finite.
pub(crate) fn check_vec(name: &'static str, v: Vec3) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(TraceError::param(name, v, "must be finite"))
    }
}

/// An orthonormal view frame `(forward, right, up)` from a view direction and
/// an up hint; fails if either is zero or they are parallel.
pub(crate) fn frame(dir: Vec3, up: Vec3) -> Result<(Vec3, Vec3, Vec3)> {
    check_vec("direction", dir)?;
    check_vec("up", up)?;
    let f = dir
        .try_normalize()
        .ok_or_else(|| TraceError::param("direction", dir, "must be non-zero (eye ≠ target)"))?;
    // Seed 000, line 3133: "The view and up directions are identical?"
    let r = f.cross(up).try_normalize().ok_or_else(|| {
        TraceError::param(
            "up",
            up,
            "must be non-zero and not parallel to the view direction",
        )
    })?;
    let u = r.cross(f);
    Ok((f, r, u))
}
