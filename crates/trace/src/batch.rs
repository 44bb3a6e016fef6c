//! Tile-parallel, deterministic batch tracing of images.
//!
//! The image is cut into square tiles ("postage stamps", which balance the
//! load at the horizon, where the work concentrates: Musgrave 1993, §7.2.1.4), traced in parallel with rayon (feature `parallel`), and
//! reported tile by tile to a [`Progress`]. Every pixel is a pure function of
//! its coordinates, with sub-pixel jitter drawn from [`Seed`] hashes of the
//! pixel and sample index (random numbers indexed by position), so the image
//! is bit-identical for any thread count or tile size.

use glam::{Vec2, Vec3};
use natura_core::camera::check_resolution;
use natura_core::{Grid2, Image, Progress, Seed};

use crate::camera::Camera;
use crate::error::{Result, TraceError};
use crate::ray::{Hit, Ray};
use crate::tracer::Tracer;

/// Default tile side, pixels.
pub const DEFAULT_TILE: u32 = 32;

/// Options of the batch drivers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderOptions {
    /// Tile side in pixels (≥ 1). Changes speed, never results.
    pub tile: u32,
    /// Samples per pixel (≥ 1). One sample goes through the pixel's centre;
    /// more are jittered uniformly over the pixel and averaged.
    pub samples_per_pixel: u32,
    /// Seed of the jitter.
    pub seed: Seed,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            tile: DEFAULT_TILE,
            samples_per_pixel: 1,
            seed: Seed(0),
        }
    }
}

impl RenderOptions {
    ///
    /// # Errors
    ///
    /// Fails if the tile side or the sample count is zero.
    pub fn validate(&self) -> Result<()> {
        if self.tile == 0 {
            return Err(TraceError::param("tile", self.tile, "must be ≥ 1 pixel"));
        }
        if self.samples_per_pixel == 0 {
            return Err(TraceError::param(
                "samples_per_pixel",
                self.samples_per_pixel,
                "must be ≥ 1",
            ));
        }
        Ok(())
    }

    /// The sub-pixel offset of sample `s` of pixel `(x, y)`, in `[0, 1)²`:
    /// the centre for a single sample, else a position-indexed uniform draw.
    #[inline]
    #[must_use]
    pub fn jitter(&self, x: u32, y: u32, s: u32) -> Vec2 {
        if self.samples_per_pixel == 1 {
            return Vec2::splat(0.5);
        }
        let c = [i64::from(x), i64::from(y), i64::from(s)];
        let h = self.seed.hash(&c);
        Vec2::new(
            natura_core::unit_f64(h) as f32,
            natura_core::unit_f64(natura_core::mix64(h ^ 0x9E37_79B9_7F4A_7C15)) as f32,
        )
        .min(Vec2::splat(1.0 - f32::EPSILON))
    }
}

/// Computes `pixel(x, y)` for every pixel of a `width × height` image, in
/// parallel square tiles of `tile` pixels, reporting one unit of `progress`
/// per pixel as tiles complete.
///
/// The result does not depend on the thread count or the tile size.
///
/// # Errors
///
/// Fails on a
/// zero or oversize resolution or a zero tile.
pub fn render<T, F>(
    width: u32,
    height: u32,
    tile: u32,
    progress: &dyn Progress,
    pixel: F,
) -> Result<Grid2<T>>
where
    T: Send + Sync + Clone + Default,
    F: Fn(u32, u32) -> T + Sync,
{
    render_tiles(width, height, tile, progress, |bx, by, w, h, out| {
        for y in by..by + h {
            for x in bx..bx + w {
                out.push(pixel(x, y));
            }
        }
    })
}

/// Computes an image tile by tile: `run(x0, y0, w, h, out)` pushes the
/// `w × h` values of the tile whose top-left pixel is `(x0, y0)`, row-major,
/// into `out`. Tiles of side `tile` run in parallel (feature `parallel`) and
/// are reported to `progress` as they complete, one unit per pixel.
///
/// This is the driver behind [`render`] and [`trace_image`], for renderers
/// that need the whole tile at once — to trace its primary rays together with
/// [`Tracer::trace_many`], for instance. As long as `run` computes each pixel
/// from its coordinates alone, the result does not depend on the thread count
/// or the tile size. Fails on a zero or oversize resolution or a zero tile.
///
/// Each tile's values are copied into the image by the thread that computed
/// them, through the tile's own disjoint row slices, and the image's memory is
/// first filled in parallel: nothing proportional to the pixel count runs on
/// one thread, and a tile's buffer is freed (and its memory reused by the next
/// tile) at once, instead of every tile's buffer (as much fresh memory as the
/// image, page faults and all) living until a serial assembly at the end.
///
/// # Panics
/// If `run` pushes a number of values other than `w × h`.
///
/// # Errors
///
/// Returns [`TraceError::InvalidParameter`] on a zero or oversize resolution
/// or a zero tile, and [`TraceError::Core`] if the image cannot be allocated.
pub fn render_tiles<T, F>(
    width: u32,
    height: u32,
    tile: u32,
    progress: &dyn Progress,
    run: F,
) -> Result<Grid2<T>>
where
    T: Send + Sync + Clone + Default,
    F: Fn(u32, u32, u32, u32, &mut Vec<T>) + Sync,
{
    check_resolution(width, height)?;
    if tile == 0 {
        return Err(TraceError::param("tile", tile, "must be ≥ 1 pixel"));
    }
    let (wu, hu) = (width as usize, height as usize);
    // Checked before anything is allocated (a typed error beyond MAX_GRID_BYTES).
    let len = natura_core::checked_len::<T>(&[wu, hu])?;
    #[cfg(feature = "parallel")]
    let mut data: Vec<T> = {
        use rayon::prelude::*;
        let mut data = Vec::new();
        (0..len)
            .into_par_iter()
            .map(|_| T::default())
            .collect_into_vec(&mut data);
        data
    };
    #[cfg(not(feature = "parallel"))]
    let mut data: Vec<T> = vec![T::default(); len];
    let (tx, ty) = (
        width.div_ceil(tile) as usize,
        height.div_ceil(tile) as usize,
    );
    let t = tile as usize;
    // Every tile's rows as disjoint slices of the image, tiles row-major.
    let mut slots: Vec<Vec<&mut [T]>> = (0..tx * ty)
        .map(|k| Vec::with_capacity(t.min(hu - (k / tx) * t)))
        .collect();
    for (y, row) in data.chunks_exact_mut(wu).enumerate() {
        let mut rest = row;
        for slot in &mut slots[(y / t) * tx..(y / t + 1) * tx] {
            let (mine, next) = rest.split_at_mut(t.min(rest.len()));
            slot.push(mine);
            rest = next;
        }
    }
    progress.start("tracing", u64::from(width) * u64::from(height));
    let fill = |(k, rows): (usize, Vec<&mut [T]>)| {
        let (bx, by) = (((k % tx) * t) as u32, ((k / tx) * t) as u32);
        let (w, h) = (tile.min(width - bx), tile.min(height - by));
        let mut out = Vec::with_capacity((w * h) as usize);
        run(bx, by, w, h, &mut out);
        assert_eq!(
            out.len(),
            (w * h) as usize,
            "a tile yields one value per pixel"
        );
        for (row, values) in rows.into_iter().zip(out.chunks_exact(w as usize)) {
            row.clone_from_slice(values);
        }
        progress.advance(u64::from(w * h));
    };
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        slots.into_par_iter().enumerate().for_each(fill);
    }
    #[cfg(not(feature = "parallel"))]
    slots.into_iter().enumerate().for_each(fill);
    progress.finish();
    Ok(Grid2::from_vec(wu, hu, data)?)
}

/// Renders `camera`'s image with `tracer`: like [`render_camera`], but the
/// rays of each tile (all their samples, generated together by
/// [`Camera::rays_into`]) are traced together with
/// [`Tracer::trace_many`] over `[0, ∞)` — for a [`crate::MipmapTracer`] its
/// lock-step lanes, faster than one [`Tracer::trace`] per pixel (figures in
/// `docs/performance.md`) — and `shade(ray, hit)` turns each into a linear colour;
/// a pixel's samples are averaged.
///
/// The image equals [`render_camera`] with a `shade` that traces each ray
/// itself, bit for bit, for any thread count or tile size.
///
/// # Errors
///
/// Fails on invalid
/// options.
pub fn trace_image<C, Tr, F>(
    tracer: &Tr,
    camera: &C,
    options: &RenderOptions,
    progress: &dyn Progress,
    shade: F,
) -> Result<Image>
where
    C: Camera + ?Sized,
    Tr: Tracer + ?Sized,
    F: Fn(&Ray, Option<&Hit>) -> Vec3 + Sync,
{
    options.validate()?;
    let res = camera.resolution();
    let n = options.samples_per_pixel;
    let inv = 1.0 / n as f32;
    let grid = render_tiles(res.x, res.y, options.tile, progress, |bx, by, w, h, out| {
        let mut rays = Vec::new();
        camera.rays_into(bx, by, w, h, options, &mut rays);
        let hits = tracer.trace_many(&rays, 0.0, f32::INFINITY);
        for (r, h) in rays
            .chunks_exact(n as usize)
            .zip(hits.chunks_exact(n as usize))
        {
            let mut sum = Vec3::ZERO;
            for (ray, hit) in r.iter().zip(h) {
                sum += shade(ray, hit.as_ref());
            }
            out.push(sum * inv);
        }
    })?;
    Ok(Image::from_grid(grid))
}

/// Renders `camera`'s image: for every pixel, `options.samples_per_pixel`
/// rays (jittered by [`RenderOptions::jitter`]) are passed to `shade` and the
/// linear colours averaged.
///
/// `shade` typically traces the ray with a [`crate::Tracer`] and lights the
/// hit. Deterministic for any thread count.
///
/// # Errors
///
/// Fails on invalid options.
pub fn render_camera<C, F>(
    camera: &C,
    options: &RenderOptions,
    progress: &dyn Progress,
    shade: F,
) -> Result<Image>
where
    C: Camera + ?Sized,
    F: Fn(&Ray) -> Vec3 + Sync,
{
    options.validate()?;
    let res = camera.resolution();
    let n = options.samples_per_pixel;
    let inv = 1.0 / n as f32;
    let grid = render(res.x, res.y, options.tile, progress, |x, y| {
        let mut sum = Vec3::ZERO;
        for s in 0..n {
            sum += shade(&camera.ray(x, y, options.jitter(x, y, s)));
        }
        sum * inv
    })?;
    Ok(Image::from_grid(grid))
}
