//! Primary rays in batches from the cameras of [`natura_core::camera`].
//!
//! The projections themselves (pinhole, orthographic, panoramic) and their
//! pixel convention live in natura-core. Pixel `(x, y)` covers
//! `[x, x + 1) × [y, y + 1)` with `x` to the right and `y` **down** (row 0 at
//! the top, as in [`natura_core::Image`]); its centre is `(x + 0.5, y + 0.5)`,
//! which is what [`Camera::ray`] gives for a jitter of `(0.5, 0.5)`.
//! Directions are unit length. Here is only what tracing adds: jittered
//! samples and the generation of a tile's rays [`RAY_LANES`] at a time.

use glam::{UVec2, Vec2, Vec3};
use natura_core::camera::{OrthographicCamera, PanoramicCamera, PinholeCamera};

use crate::batch::RenderOptions;
use crate::ray::Ray;

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
    /// coordinates are affine in the pixel coordinates, and their `ray_at`
    /// is inlined into a loop over lanes), so the arithmetic runs in vector
    /// registers; [`crate::trace_image`] calls this once per
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

/// Appends the rays of [`Camera::rays_into`]'s block, computing them
/// [`RAY_LANES`] at a time with `ray_at` (the camera's own map, inlined into
/// the loop over lanes) into struct-of-arrays lanes: the same rays, bit for
/// bit, as one call per pixel.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // `l` indexes every lane array alike
fn lane_rays(
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
    options: &RenderOptions,
    out: &mut Vec<Ray>,
    ray_at: impl Fn(f32, f32) -> Ray,
) {
    out.reserve(w as usize * h as usize * options.samples_per_pixel as usize);
    pixel_lanes(x0, y0, w, h, options, |px, py, n| {
        let mut o = [[0.0f32; RAY_LANES]; 3];
        let mut d = [[0.0f32; RAY_LANES]; 3];
        for l in 0..RAY_LANES {
            let r = ray_at(px[l], py[l]);
            o[0][l] = r.origin.x;
            o[1][l] = r.origin.y;
            o[2][l] = r.origin.z;
            d[0][l] = r.dir.x;
            d[1][l] = r.dir.y;
            d[2][l] = r.dir.z;
        }
        out.extend((0..n).map(|l| {
            Ray::new(
                Vec3::new(o[0][l], o[1][l], o[2][l]),
                Vec3::new(d[0][l], d[1][l], d[2][l]),
            )
        }));
    });
}

/// The [`Camera`] of a core camera whose screen is affine in the pixel
/// coordinates: its own map, and [`RAY_LANES`] rays at a time in
/// [`Camera::rays_into`].
macro_rules! affine_camera {
    ($t:ty) => {
        impl Camera for $t {
            fn resolution(&self) -> UVec2 {
                <$t>::resolution(self)
            }

            #[inline]
            fn ray_at(&self, px: f32, py: f32) -> Ray {
                <$t>::ray_at(self, px, py)
            }

            /// [`RAY_LANES`] rays at a time (see [`Camera::rays_into`]).
            fn rays_into(
                &self,
                x0: u32,
                y0: u32,
                w: u32,
                h: u32,
                options: &RenderOptions,
                out: &mut Vec<Ray>,
            ) {
                lane_rays(x0, y0, w, h, options, out, |px, py| {
                    <$t>::ray_at(self, px, py)
                });
            }
        }
    };
}

affine_camera!(PinholeCamera);
affine_camera!(OrthographicCamera);

/// One ray per pixel sample (the trait's default): the panorama's
/// trigonometry does not vectorise the way an affine screen does.
impl Camera for PanoramicCamera {
    fn resolution(&self) -> UVec2 {
        PanoramicCamera::resolution(self)
    }

    #[inline]
    fn ray_at(&self, px: f32, py: f32) -> Ray {
        PanoramicCamera::ray_at(self, px, py)
    }
}
