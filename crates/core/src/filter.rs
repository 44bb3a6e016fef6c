//! The pixel filter: how much each sample counts toward each pixel, shared
//! by natura-render's path tracer and the preview pictures every crate
//! draws ([`preview`](crate::preview)).
//!
//! A pixel of a camera does not see a hard-edged square of the scene. The
//! lens's blur, the sensor's optical low-pass filter and the demosaicing
//! spread a point of light over a small patch of pixels, so a lit needle,
//! a star or a sun-fleck narrower than a pixel shows in a photograph as a
//! soft dot shared with its neighbours, never as one lone bright pixel.
//! natura's pictures do the same with a Gaussian reconstruction filter of
//! standard deviation σ pixels, truncated at 3σ and lowered by its value
//! there so it meets zero without a step (the Gaussian filter of Pharr,
//! Jakob & Humphreys, *Physically Based Rendering*, 4th ed., 2023, §8.8.4,
//! whose default is σ = 0.5 with radius 1.5): [`PixelFilter::camera`].
//!
//! A pixel's value is the filter-weighted mean of the samples of every
//! pixel whose square the filter reaches (Pharr et al., §8.8.1's weighted
//! reconstruction, `Σ f(x − xᵢ) L(xᵢ) / Σ f(x − xᵢ)`), each pixel's samples
//! counted by their mean ([`PixelFilter::mean`]). σ = 0 is the box: each
//! pixel is the plain mean of its own samples.
//!
//! ```
//! use natura_core::filter::PixelFilter;
//! use natura_core::glam::{Vec2, Vec3};
//! use natura_core::Grid2;
//! // One bright sample in a 3 × 3 picture of one sample a pixel.
//! let mut frame = Grid2::new(3, 3, Vec3::ZERO)?;
//! frame[(1, 1)] = Vec3::ONE;
//! let boxed = PixelFilter::BOX.resolve(&frame, 1)?;
//! assert_eq!(boxed.get(0, 1), Some(Vec3::ZERO));
//! // The camera's Gaussian shares the point with its neighbours.
//! let soft = PixelFilter::camera().resolve(&frame, 1)?;
//! let (centre, side) = (soft.get(1, 1).unwrap().x, soft.get(0, 1).unwrap().x);
//! assert!(centre < 1.0 && side > 0.05 && centre > 3.0 * side);
//! # Ok::<(), natura_core::CoreError>(())
//! ```

use glam::{Vec2, Vec3};

use crate::error::Result;
use crate::grid2::Grid2;
use crate::image::Image;

/// The filter's truncation radius in standard deviations.
const RADIUS_SIGMAS: f32 = 3.0;

/// The standard deviation of [`PixelFilter::camera`], pixels.
pub const CAMERA_SIGMA_PX: f32 = 0.5;

/// A separable pixel filter: the box over the pixel, or a truncated
/// Gaussian (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelFilter {
    /// Standard deviation, pixels; 0 for the box.
    sigma: f32,
    /// The Gaussian's value at the truncation radius, subtracted.
    floor: f32,
}

impl PixelFilter {
    /// The box: each pixel the plain mean of its own samples.
    pub const BOX: Self = Self {
        sigma: 0.0,
        floor: 0.0,
    };

    /// The Gaussian filter of standard deviation `sigma` pixels, truncated
    /// at `3σ`; the box filter when `sigma` is 0 (or not a positive finite
    /// number: callers validate σ where a user gives it).
    #[must_use]
    pub fn gaussian(sigma: f32) -> Self {
        if !(sigma.is_finite() && sigma > 0.0) {
            return Self::BOX;
        }
        Self {
            sigma,
            floor: (-0.5 * RADIUS_SIGMAS * RADIUS_SIGMAS).exp(),
        }
    }

    /// The camera's blur every natura picture takes by default: the
    /// Gaussian of σ = [`CAMERA_SIGMA_PX`] (0.5 pixel).
    #[must_use]
    pub fn camera() -> Self {
        Self::gaussian(CAMERA_SIGMA_PX)
    }

    /// The standard deviation in pixels, 0 for the box.
    #[must_use]
    pub fn sigma(&self) -> f32 {
        self.sigma
    }

    /// Whether this is the box filter.
    #[must_use]
    pub fn is_box(&self) -> bool {
        self.sigma == 0.0
    }

    /// How many pixels beyond its own a sample can count toward, along
    /// each axis: 0 for the box; for the Gaussian, the pixels whose centre
    /// lies within the radius of some point of the sample's pixel.
    #[must_use]
    pub fn reach(&self) -> u32 {
        if self.is_box() {
            0
        } else {
            (RADIUS_SIGMAS * self.sigma - 0.5).ceil().max(0.0) as u32
        }
    }

    /// The weight along one axis of a sample `x` pixels from a pixel's
    /// centre (the Gaussian's; the box's is 1 within half a pixel).
    #[must_use]
    pub fn weight_1d(&self, x: f32) -> f32 {
        if self.is_box() {
            return f32::from(u8::from(x.abs() <= 0.5));
        }
        let s = x / self.sigma;
        ((-0.5 * s * s).exp() - self.floor).max(0.0)
    }

    /// The weight of a sample at `offset` pixels from a pixel's centre
    /// (the box: 1 inside the pixel's square, else 0).
    #[must_use]
    pub fn weight(&self, offset: Vec2) -> f32 {
        self.weight_1d(offset.x) * self.weight_1d(offset.y)
    }

    /// The value of pixel `(x, y)` of a `size = (width, height)` image
    /// under this filter, from the samples `visit(nx, ny, f)` hands to `f`
    /// (as `f(position in the pixel, radiance)`) for each pixel `(nx, ny)`
    /// the filter reaches.
    ///
    /// Each pixel's samples estimate the filter's integral over that
    /// pixel's square, `∫ f·L` and `∫ f`, by their mean (the pixel's area
    /// is 1); the value is the sum of the first over the sum of the
    /// second. So a pixel that took more samples than its neighbours
    /// (adaptive refinement) counts as much as they do, not in proportion
    /// to its samples, as it would in the weighted mean over all samples
    /// at once (`Σ f(x − xᵢ) L(xᵢ) / Σ f(x − xᵢ)`, Pharr et al. 2023,
    /// §8.8.1, which assumes the samples evenly spread). A pixel none of
    /// whose reached samples weighs anything is NaN.
    pub fn mean(
        &self,
        x: u32,
        y: u32,
        size: (u32, u32),
        visit: impl Fn(u32, u32, &mut dyn FnMut(Vec2, Vec3)),
    ) -> Vec3 {
        let r = self.reach();
        let (mut acc, mut weight) = (Vec3::ZERO, 0.0f32);
        for ny in y.saturating_sub(r)..=(y + r).min(size.1 - 1) {
            for nx in x.saturating_sub(r)..=(x + r).min(size.0 - 1) {
                let d = Vec2::new(nx as f32 - x as f32 - 0.5, ny as f32 - y as f32 - 0.5);
                let (mut a, mut w, mut n) = (Vec3::ZERO, 0.0f32, 0u32);
                visit(nx, ny, &mut |p, l| {
                    let f = self.weight(d + p);
                    a += l * f;
                    w += f;
                    n += 1;
                });
                if n > 0 {
                    acc += a / n as f32;
                    weight += w / n as f32;
                }
            }
        }
        acc / weight
    }

    /// The picture of a supersampled `frame` whose every pixel holds `s ×
    /// s` samples on a regular grid (sample `(i, j)` of pixel `(x, y)` at
    /// `(x + (i + 0.5)/s, y + (j + 0.5)/s)`, stored at `(x·s + i, y·s +
    /// j)`): each pixel the filter-weighted mean of the samples it reaches,
    /// as [`mean`](Self::mean) gives for such a frame (every pixel has as
    /// many samples, so the pixels' means weigh alike), weighed about the
    /// pixel's first sample so that a flat region keeps its value bit for
    /// bit. The box sums a
    /// pixel's samples row by row and scales by `1/s²`. Rows are resolved in
    /// parallel with the `parallel` feature, the same bits for any number
    /// of threads.
    ///
    /// # Errors
    ///
    /// [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter)
    /// naming `supersample` if `s` is 0 or does not divide both of the
    /// frame's sides; [`CoreError::TooLarge`](crate::CoreError::TooLarge) if
    /// the picture cannot be allocated.
    pub fn resolve(&self, frame: &Grid2<Vec3>, s: usize) -> Result<Image> {
        let (fw, fh) = frame.dims();
        if s == 0 || fw % s != 0 || fh % s != 0 || fw == 0 || fh == 0 {
            return Err(crate::check::ParamError::new(
                "supersample",
                s,
                "must be positive and divide the frame's width and height",
            )
            .into());
        }
        let (w, h) = (fw / s, fh / s);
        let samples = frame.as_slice();
        let mut grid = Grid2::new(w, h, Vec3::ZERO)?;
        if self.is_box() {
            let scale = 1.0 / (s * s) as f32;
            crate::preview::fill_rows(&mut grid, "resolve", &crate::NoProgress, |y, row| {
                for (x, out) in row.iter_mut().enumerate() {
                    let mut acc = Vec3::ZERO;
                    for j in 0..s {
                        let line = &samples[(y * s + j) * fw + x * s..][..s];
                        for &c in line {
                            acc += c;
                        }
                    }
                    *out = if s == 1 { acc } else { acc * scale };
                }
            });
            return Ok(Image::from_grid(grid));
        }
        let r = self.reach() as usize;
        // Weights of the samples of the pixels r before to r after, along
        // one axis, relative to a pixel's centre: the same for every pixel.
        let span = (2 * r + 1) * s;
        let taps: Vec<f32> = (0..span)
            .map(|k| self.weight_1d((k as f32 + 0.5) / s as f32 - r as f32 - 0.5))
            .collect();
        crate::preview::fill_rows(&mut grid, "resolve", &crate::NoProgress, |y, row| {
            let j0 = (y as isize - r as isize) * s as isize;
            for (x, out) in row.iter_mut().enumerate() {
                let i0 = (x as isize - r as isize) * s as isize;
                // Weighted about the pixel's first sample, so a flat region
                // resolves to its own value bit for bit.
                let base = samples[y * s * fw + x * s];
                let (mut acc, mut weight) = (Vec3::ZERO, 0.0f32);
                for (kj, &wy) in taps.iter().enumerate() {
                    let sj = j0 + kj as isize;
                    if sj < 0 || sj >= fh as isize || wy == 0.0 {
                        continue;
                    }
                    let line = &samples[sj as usize * fw..][..fw];
                    let (mut a, mut wsum) = (Vec3::ZERO, 0.0f32);
                    for (ki, &wx) in taps.iter().enumerate() {
                        let si = i0 + ki as isize;
                        if si < 0 || si >= fw as isize {
                            continue;
                        }
                        a += (line[si as usize] - base) * wx;
                        wsum += wx;
                    }
                    acc += a * wy;
                    weight += wsum * wy;
                }
                *out = base + acc / weight;
            }
        });
        Ok(Image::from_grid(grid))
    }
}

#[cfg(test)]
mod tests;
