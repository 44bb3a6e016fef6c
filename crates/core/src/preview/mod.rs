//! One preview rasterizer for the workspace: the small, fixed, deterministic
//! pictures a crate draws of its own output (a plant mesh, an ocean patch, a
//! texture swatch, an ecosystem from above). Each crate keeps only its scene
//! (the geometry, texture or colour it feeds in); the loops are here:
//!
//! * [`shade_pixels`]: the image loop. Every pixel is resolved from `s × s`
//!   samples a pixel of a closure of continuous pixel coordinates by the
//!   camera's pixel filter ([`PixelFilter::camera`], a Gaussian of σ = 0.5
//!   pixel that shares a point of light with the pixel's neighbours as a
//!   lens does; [`shade_pixels_filtered`] takes another, such as the box),
//!   rows in parallel with the `parallel` feature, the same bits for any
//!   number of threads;
//! * [`trace_pixels`]: the same loop driving a camera, a closure from each
//!   sample's [`Ray`] to a linear colour, for ray-cast previews;
//! * [`Raster`]: triangles filled with edge functions at sample centres,
//!   resolved with a z-buffer and shaded per fragment by a callback
//!   ([`Fragment`]: barycentric weights, depth), then resolved by the same
//!   filter;
//!   [`disc_pixels`] covers discs the same way;
//! * [`PreviewCamera`]: a look-at camera with its framing of a bounding box,
//!   and its [`Projector`] onto a picture (natura-core's
//!   [`PinholeCamera`] or
//!   [`OrthographicCamera`]);
//! * [`lambert`] and [`facing`]: the simple shading previews share.
//!
//! Pixel coordinates follow [`camera`](crate::camera): `(0, 0)` is the
//! top-left corner, pixel `(x, y)` has its centre at `(x + 0.5, y + 0.5)`,
//! and sample `(i, j)` of `s × s` at `(x + (i + 0.5)/s, y + (j + 0.5)/s)`.
//! No randomness is used anywhere, so a scene always gives the same image.
//!
//! ```
//! use natura_core::glam::Vec3;
//! use natura_core::preview;
//! // A disc of radius 4 in a 12 × 12 picture, 4 × 4 samples per pixel: the
//! // camera's filter softens its edge but keeps its light.
//! let img = preview::shade_pixels(12, 12, 4, "disc", &natura_core::NoProgress, |x, y| {
//!     let inside = (x - 6.0).powi(2) + (y - 6.0).powi(2) <= 16.0;
//!     if inside { Vec3::ONE } else { Vec3::ZERO }
//! })?;
//! let covered: f32 = img.pixels().as_slice().iter().map(|c| c.x).sum();
//! assert!((covered - std::f32::consts::PI * 16.0).abs() < 1.0);
//! # Ok::<(), natura_core::CoreError>(())
//! ```

mod camera;
mod raster;
#[cfg(test)]
mod tests;

pub use camera::{PreviewCamera, PreviewProjection, Projector};
pub use raster::{Fragment, Raster, disc_pixels};

use glam::{UVec2, Vec3};

use crate::camera::{MAX_RESOLUTION, OrthographicCamera, PinholeCamera, Ray, check_resolution};
use crate::check::{Checked, ParamError};
use crate::error::Result;
use crate::filter::PixelFilter;
use crate::grid2::Grid2;
use crate::image::Image;
use crate::progress::Progress;

/// Most samples per pixel along each axis a preview takes.
pub const MAX_SUPERSAMPLE: u32 = 16;

/// Checks a preview's size: each side between 1 and
/// [`MAX_RESOLUTION`] pixels ([`check_resolution`]), and
/// `supersample` between 1 and [`MAX_SUPERSAMPLE`] with the sample grid
/// no larger than [`MAX_RESOLUTION`] a side.
///
/// ```
/// use natura_core::preview::check_size;
/// assert!(check_size(64, 48, 2).is_ok());
/// assert_eq!(check_size(64, 48, 0).unwrap_err().name, "supersample");
/// assert_eq!(check_size(0, 48, 1).unwrap_err().name, "width");
/// ```
///
/// # Errors
///
/// A [`ParamError`] naming `width`, `height` or `supersample`.
pub fn check_size(width: u32, height: u32, supersample: u32) -> Checked<()> {
    check_resolution(width, height)?;
    if supersample == 0 || supersample > MAX_SUPERSAMPLE {
        return Err(ParamError::new(
            "supersample",
            supersample,
            "must be between 1 and MAX_SUPERSAMPLE (16)",
        ));
    }
    if u64::from(width.max(height)) * u64::from(supersample) > u64::from(MAX_RESOLUTION) {
        return Err(ParamError::new(
            "supersample",
            supersample,
            "times the longer side must be at most MAX_RESOLUTION (65536) samples",
        ));
    }
    Ok(())
}

/// The mean of the `s × s` samples `sample(i, j)`, summed row by row
/// (`j` outer, `i` inner); a single sample is returned as it is.
#[inline]
fn box_filter(s: usize, mut sample: impl FnMut(usize, usize) -> Vec3) -> Vec3 {
    if s == 1 {
        return sample(0, 0);
    }
    let mut acc = Vec3::ZERO;
    for j in 0..s {
        for i in 0..s {
            acc += sample(i, j);
        }
    }
    acc * (1.0 / (s * s) as f32)
}

/// Fills a `width × height` image row by row with `row(y, pixels)`, rows in
/// parallel with the `parallel` feature, reporting one unit per row to
/// `progress` under `stage`. Each row is handed to exactly one call, so the
/// image does not depend on the number of threads.
///
/// # Errors
///
/// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter)
/// naming `width` or `height` for a zero or oversize side
/// ([`check_resolution`]); [`CoreError::TooLarge`](crate::CoreError::TooLarge)
/// if the image cannot be allocated.
pub fn render_rows(
    width: u32,
    height: u32,
    stage: &str,
    progress: &dyn Progress,
    row: impl Fn(u32, &mut [Vec3]) + Sync,
) -> Result<Image> {
    check_resolution(width, height)?;
    let mut grid = Grid2::new(width as usize, height as usize, Vec3::ZERO)?;
    fill_rows(&mut grid, stage, progress, |y, r| row(y as u32, r));
    Ok(Image::from_grid(grid))
}

/// Fills the rows of `grid` with `row(y, cells)`, rows in parallel with the
/// `parallel` feature (each row computed alone, so the result does not
/// depend on the number of threads), reporting one unit per row to
/// `progress` under `stage`.
pub fn fill_rows<T: Send>(
    grid: &mut Grid2<T>,
    stage: &str,
    progress: &dyn Progress,
    row: impl Fn(usize, &mut [T]) + Sync,
) {
    let (w, h) = grid.dims();
    progress.start(stage, h as u64);
    let run = |(y, r): (usize, &mut [T])| {
        row(y, r);
        progress.advance(1);
    };
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        grid.as_mut_slice()
            .par_chunks_mut(w)
            .enumerate()
            .for_each(run);
    }
    #[cfg(not(feature = "parallel"))]
    grid.as_mut_slice().chunks_mut(w).enumerate().for_each(run);
    progress.finish();
}

/// A `width × height` image whose every pixel is resolved by the camera's
/// pixel filter ([`PixelFilter::camera`]) from `supersample × supersample`
/// samples a pixel, `pixel(px, py)` at the samples' continuous pixel
/// coordinates (one sample: the pixel centre), rows as in [`render_rows`].
///
/// # Errors
///
/// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter)
/// naming `width`, `height` or `supersample` ([`check_size`]);
/// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the image (or,
/// for a filter wider than the box, the frame of its samples) cannot be
/// allocated.
pub fn shade_pixels(
    width: u32,
    height: u32,
    supersample: u32,
    stage: &str,
    progress: &dyn Progress,
    pixel: impl Fn(f64, f64) -> Vec3 + Sync,
) -> Result<Image> {
    shade_pixels_filtered(
        width,
        height,
        supersample,
        PixelFilter::camera(),
        stage,
        progress,
        pixel,
    )
}

/// As [`shade_pixels`], resolved by `filter`. The box makes each pixel the
/// mean of its own samples (summed row by row) without storing them; a
/// wider filter draws the whole frame of samples first, then resolves it
/// ([`PixelFilter::resolve`]).
///
/// ```
/// use natura_core::filter::PixelFilter;
/// use natura_core::glam::Vec3;
/// use natura_core::{NoProgress, preview};
/// // A checkerboard of single pixels: the box keeps it, the camera softens it.
/// let check = |x: f64, y: f64| Vec3::splat(((x as u32 + y as u32) % 2) as f32);
/// let hard = preview::shade_pixels_filtered(6, 6, 2, PixelFilter::BOX, "c", &NoProgress, check)?;
/// let soft = preview::shade_pixels(6, 6, 2, "c", &NoProgress, check)?;
/// assert_eq!(hard.get(3, 2), Some(Vec3::ONE));
/// let v = soft.get(3, 2).unwrap().x;
/// assert!(v < 0.9 && v > 0.5);
/// # Ok::<(), natura_core::CoreError>(())
/// ```
///
/// # Errors
///
/// As [`shade_pixels`].
pub fn shade_pixels_filtered(
    width: u32,
    height: u32,
    supersample: u32,
    filter: PixelFilter,
    stage: &str,
    progress: &dyn Progress,
    pixel: impl Fn(f64, f64) -> Vec3 + Sync,
) -> Result<Image> {
    check_size(width, height, supersample)?;
    let s = supersample as usize;
    let step = 1.0 / f64::from(supersample);
    if filter.is_box() {
        return render_rows(width, height, stage, progress, |y, row| {
            for (x, out) in row.iter_mut().enumerate() {
                *out = box_filter(s, |i, j| {
                    let px = x as f64 + (i as f64 + 0.5) * step;
                    let py = f64::from(y) + (j as f64 + 0.5) * step;
                    pixel(px, py)
                });
            }
        });
    }
    let mut frame = Grid2::new(width as usize * s, height as usize * s, Vec3::ZERO)?;
    fill_rows(&mut frame, stage, progress, |j, row| {
        let py = (j as f64 + 0.5) * step;
        for (i, out) in row.iter_mut().enumerate() {
            *out = pixel((i as f64 + 0.5) * step, py);
        }
    });
    filter.resolve(&frame, s)
}

/// A camera that gives the ray through continuous pixel coordinates of its
/// picture: what [`trace_pixels`] drives.
pub trait PixelRays: Sync {
    /// The picture's size in pixels, `(width, height)`.
    fn resolution(&self) -> UVec2;
    /// The ray through continuous pixel coordinates `(px, py)`.
    fn ray_at(&self, px: f32, py: f32) -> Ray;
}

impl PixelRays for PinholeCamera {
    fn resolution(&self) -> UVec2 {
        PinholeCamera::resolution(self)
    }
    fn ray_at(&self, px: f32, py: f32) -> Ray {
        PinholeCamera::ray_at(self, px, py)
    }
}

impl PixelRays for OrthographicCamera {
    fn resolution(&self) -> UVec2 {
        OrthographicCamera::resolution(self)
    }
    fn ray_at(&self, px: f32, py: f32) -> Ray {
        OrthographicCamera::ray_at(self, px, py)
    }
}

/// The camera's picture, every pixel resolved by the camera's pixel filter
/// from `supersample × supersample` samples `trace(ray)` along the rays
/// through the samples (a ray-cast preview), as [`shade_pixels`].
///
/// ```
/// use natura_core::camera::OrthographicCamera;
/// use natura_core::glam::Vec3;
/// use natura_core::{NoProgress, preview};
/// // Looking down at the ground from 10 m, sky above the horizon never seen.
/// let cam = OrthographicCamera::look_at(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, Vec3::Y, 2.0, 4, 4)?;
/// let img = preview::trace_pixels(&cam, 2, "ground", &NoProgress, |ray| {
///     let t = -ray.origin.z / ray.dir.z;
///     Vec3::splat(t)
/// })?;
/// assert!(img.pixels().as_slice().iter().all(|c| (c.x - 10.0).abs() < 1e-5));
/// # Ok::<(), natura_core::CoreError>(())
/// ```
///
/// # Errors
///
/// As [`shade_pixels`], for the camera's resolution and `supersample`.
pub fn trace_pixels(
    camera: &impl PixelRays,
    supersample: u32,
    stage: &str,
    progress: &dyn Progress,
    trace: impl Fn(Ray) -> Vec3 + Sync,
) -> Result<Image> {
    let r = camera.resolution();
    shade_pixels(r.x, r.y, supersample, stage, progress, |px, py| {
        trace(camera.ray_at(px as f32, py as f32))
    })
}

/// Lambert's law with an ambient floor: `ambient + (1 − ambient)·max(n·l, 0)`
/// for a unit normal `n` and unit direction to the light `l`.
///
/// ```
/// use natura_core::glam::Vec3;
/// use natura_core::preview::lambert;
/// assert_eq!(lambert(Vec3::Z, Vec3::Z, 0.25), 1.0);
/// assert_eq!(lambert(Vec3::Z, Vec3::NEG_Z, 0.25), 0.25);
/// ```
#[inline]
#[must_use]
pub fn lambert(n: Vec3, l: Vec3, ambient: f32) -> f32 {
    ambient + (1.0 - ambient) * n.dot(l).max(0.0)
}

/// The normal `n` turned towards the viewer (`to_viewer` points from the
/// surface to the eye), so a surface is lit on both sides.
///
/// ```
/// use natura_core::glam::Vec3;
/// assert_eq!(natura_core::preview::facing(Vec3::Z, Vec3::NEG_Z), Vec3::NEG_Z);
/// ```
#[inline]
#[must_use]
pub fn facing(n: Vec3, to_viewer: Vec3) -> Vec3 {
    if n.dot(to_viewer) < 0.0 { -n } else { n }
}
