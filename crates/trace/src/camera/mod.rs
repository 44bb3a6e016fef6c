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

use crate::batch::RenderOptions;
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

    /// Appends to `out` the rays of the `w × h` pixel block whose top-left
    /// pixel is `(x0, y0)`: row by row, left to right, and for each pixel
    /// `options.samples_per_pixel` rays, sample `s` being
    /// `self.ray(x, y, options.jitter(x, y, s))` — the same rays, bit for
    /// bit, as that per-pixel loop (which is the default implementation).
    ///
    /// [`PinholeCamera`] and [`OrthographicCamera`] generate the rays
    /// [`RAY_LANES`] at a time in struct-of-arrays form (their screen
    /// coordinates are affine in the pixel coordinates), so the arithmetic
    /// runs in vector registers; [`crate::trace_image`] calls this once per
    /// tile. The block must lie within the image for the rays to be the
    /// image's, but nothing is checked: pixels outside it extrapolate the
    /// camera's map.
    fn rays_into(
        &self,
        x0: u32,
        y0: u32,
        w: u32,
        h: u32,
        options: &RenderOptions,
        out: &mut Vec<Ray>,
    ) {
        let n = options.samples_per_pixel;
        out.reserve(w as usize * h as usize * n as usize);
        for y in y0..y0.saturating_add(h) {
            for x in x0..x0.saturating_add(w) {
                for s in 0..n {
                    out.push(self.ray(x, y, options.jitter(x, y, s)));
                }
            }
        }
    }
}

/// Rays a camera generates together in [`Camera::rays_into`].
pub const RAY_LANES: usize = 16;

/// Calls `lanes(px, py, n)` with the continuous pixel coordinates of the
/// rays of [`Camera::rays_into`]'s block, [`RAY_LANES`] at a time (the last
/// call with `n < RAY_LANES` valid lanes; the rest repeat earlier values).
#[inline(always)]
pub(crate) fn pixel_lanes(
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
    options: &RenderOptions,
    mut lanes: impl FnMut(&[f32; RAY_LANES], &[f32; RAY_LANES], usize),
) {
    let n = options.samples_per_pixel;
    let (x1, y1) = (x0.saturating_add(w), y0.saturating_add(h));
    if x0 >= x1 || y0 >= y1 || n == 0 {
        return;
    }
    let mut px = [0.5f32; RAY_LANES];
    let mut py = [0.5f32; RAY_LANES];
    // The next ray: sample `s` of pixel `(x, y)`.
    let (mut x, mut y, mut s) = (x0, y0, 0);
    loop {
        let mut k = 0;
        while k < RAY_LANES {
            // As `Camera::ray`.
            let j = options.jitter(x, y, s);
            px[k] = x as f32 + j.x;
            py[k] = y as f32 + j.y;
            k += 1;
            s += 1;
            if s == n {
                s = 0;
                x += 1;
                if x == x1 {
                    x = x0;
                    y += 1;
                    if y == y1 {
                        break;
                    }
                }
            }
        }
        lanes(&px, &py, k);
        if y == y1 {
            return;
        }
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
    // Musgrave 1993, §8.6: "The view and up directions are identical?"
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
