//! The pixel filter: how much each sample counts toward each pixel.
//!
//! A pixel of a camera does not see a hard-edged square of the scene. The
//! lens's blur, the sensor's optical low-pass filter and the demosaicing
//! spread a point of light over a small patch of pixels, so a lit needle
//! or a sun-fleck narrower than a pixel shows in a photograph as a soft
//! dot shared with its neighbours, never as one lone bright pixel. The
//! renderer does the same with a Gaussian reconstruction filter of
//! standard deviation σ pixels, truncated at 3σ and lowered by its value
//! there so it meets zero without a step (the Gaussian filter of Pharr,
//! Jakob & Humphreys, *Physically Based Rendering*, 4th ed., 2023, §8.8.4,
//! whose default is σ = 0.5 with radius 1.5).
//!
//! Every pixel's samples are stratified over its own square as before; a
//! pixel's value is the filter-weighted mean of the samples of every pixel
//! whose square the filter reaches (Pharr et al., §8.8.1's weighted
//! reconstruction, `Σ f(x − xᵢ) L(xᵢ) / Σ f(x − xᵢ)`). A pixel's samples are
//! functions of its position, index and the seed only, so a tile traces its
//! own pixels' samples and those of the ring of pixels around it the filter
//! reaches, and the picture stays bit-identical on any thread count and
//! for any region.
//!
//! σ = 0 is the box: each pixel is the plain mean of its own samples.

use glam::{Vec2, Vec3};

/// The filter's truncation radius in standard deviations.
const RADIUS_SIGMAS: f32 = 3.0;

/// A separable pixel filter: the box over the pixel, or a truncated
/// Gaussian.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PixelFilter {
    /// Standard deviation, pixels; 0 for the box.
    sigma: f32,
    /// The Gaussian's value at the truncation radius, subtracted.
    floor: f32,
}

impl PixelFilter {
    /// The Gaussian filter of standard deviation `sigma` pixels, truncated
    /// at `3σ`; the box filter when `sigma` is 0 (or not a positive finite
    /// number, which the scene's validation has already refused).
    pub(crate) fn gaussian(sigma: f32) -> Self {
        if !(sigma.is_finite() && sigma > 0.0) {
            return Self {
                sigma: 0.0,
                floor: 0.0,
            };
        }
        Self {
            sigma,
            floor: (-0.5 * RADIUS_SIGMAS * RADIUS_SIGMAS).exp(),
        }
    }

    /// Whether this is the box filter.
    pub(crate) fn is_box(&self) -> bool {
        self.sigma == 0.0
    }

    /// How many pixels beyond its own a sample can count toward, along
    /// each axis: 0 for the box; for the Gaussian, the pixels whose centre
    /// lies within the radius of some point of the sample's pixel.
    pub(crate) fn reach(&self) -> u32 {
        if self.is_box() {
            0
        } else {
            (RADIUS_SIGMAS * self.sigma - 0.5).ceil().max(0.0) as u32
        }
    }

    /// The weight along one axis of a sample `x` pixels from a pixel's
    /// centre.
    fn weight_1d(&self, x: f32) -> f32 {
        let s = x / self.sigma;
        ((-0.5 * s * s).exp() - self.floor).max(0.0)
    }

    /// The weight of a sample at `offset` pixels from a pixel's centre
    /// (the box: 1 inside the pixel's square, else 0).
    pub(crate) fn weight(&self, offset: Vec2) -> f32 {
        if self.is_box() {
            return f32::from(u8::from(offset.x.abs() <= 0.5 && offset.y.abs() <= 0.5));
        }
        self.weight_1d(offset.x) * self.weight_1d(offset.y)
    }
}

impl PixelFilter {
    /// The value of pixel `(x, y)` of a `size = (width, height)` image
    /// under this (Gaussian) filter, from the samples `visit(nx, ny, f)`
    /// hands to `f` (as `f(position in the pixel, radiance)`) for each
    /// pixel `(nx, ny)` the filter reaches.
    ///
    /// Each pixel's samples estimate the filter's integral over that
    /// pixel's square, `∫ f·L` and `∫ f`, by their mean (the pixel's area
    /// is 1); the value is the sum of the first over the sum of the
    /// second. So a pixel that took more samples than its neighbours
    /// (adaptive refinement) counts as much as they do, not in proportion
    /// to its samples, as it would in the weighted mean over all samples
    /// at once (`Σ f(x − xᵢ) L(xᵢ) / Σ f(x − xᵢ)`, Pharr et al. 2023,
    /// §8.8.1, which assumes the samples evenly spread).
    pub(crate) fn mean(
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
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pixel that took four times its neighbours' samples, all at the
    /// same places in their pixels, counts as much as when it took as few:
    /// the value is that of the even sampling.
    #[test]
    fn a_pixel_with_more_samples_does_not_weigh_more() {
        let f = PixelFilter::gaussian(0.5);
        let spots = [
            Vec2::new(0.25, 0.25),
            Vec2::new(0.75, 0.25),
            Vec2::new(0.25, 0.75),
            Vec2::new(0.75, 0.75),
        ];
        // The pixel right of (1, 1) is bright; it took 16 or 4 samples.
        let value = |copies: usize| {
            f.mean(1, 1, (3, 3), |nx, ny, g| {
                let l = if (nx, ny) == (2, 1) {
                    Vec3::ONE
                } else {
                    Vec3::ZERO
                };
                let k = if (nx, ny) == (2, 1) { copies } else { 1 };
                for _ in 0..k {
                    for &p in &spots {
                        g(p, l);
                    }
                }
            })
        };
        let (even, refined) = (value(1), value(4));
        assert!(even.x > 0.01 && even.x < 0.3, "{even}");
        approx::assert_relative_eq!(even.x, refined.x, max_relative = 1e-6);
        // The plain weighted mean over all samples would weigh it 4 times.
        let all = |copies: f32| {
            let w = |p: Vec2, dx: f32| f.weight(Vec2::new(dx - 0.5, -0.5) + p);
            let bright: f32 = spots.iter().map(|&p| w(p, 1.0)).sum::<f32>() * copies;
            let dark: f32 = (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
                .filter(|&d| d != (1, 0))
                .map(|(dx, dy)| {
                    spots
                        .iter()
                        .map(|&p| f.weight(Vec2::new(dx as f32 - 0.5, dy as f32 - 0.5) + p))
                        .sum::<f32>()
                })
                .sum();
            bright / (bright + dark)
        };
        approx::assert_relative_eq!(all(1.0), even.x, max_relative = 1e-5);
        assert!(all(4.0) > 2.0 * even.x);
    }

    #[test]
    fn the_box_counts_its_own_square() {
        let f = PixelFilter::gaussian(0.0);
        assert!(f.is_box());
        assert_eq!(f.reach(), 0);
        assert_eq!(f.weight(Vec2::new(0.4, -0.3)), 1.0);
        assert_eq!(f.weight(Vec2::new(0.6, 0.0)), 0.0);
        assert!(PixelFilter::gaussian(f32::NAN).is_box());
    }

    #[test]
    fn the_gaussian_is_smooth_symmetric_and_truncated() {
        let f = PixelFilter::gaussian(0.5);
        assert_eq!(f.reach(), 1);
        assert_eq!(PixelFilter::gaussian(0.2).reach(), 1);
        assert_eq!(PixelFilter::gaussian(1.0).reach(), 3);
        // Zero at and beyond 3σ, continuous there, and decreasing before.
        assert_eq!(f.weight(Vec2::new(1.5, 0.0)), 0.0);
        assert_eq!(f.weight(Vec2::new(0.0, 2.0)), 0.0);
        assert!(f.weight(Vec2::new(1.49, 0.0)) < 1e-3);
        let mut last = f32::INFINITY;
        for i in 0..150 {
            let x = i as f32 * 0.01;
            let w = f.weight(Vec2::new(x, 0.0));
            assert!(w < last || (w == 0.0 && last == 0.0), "at {x}");
            assert_eq!(w, f.weight(Vec2::new(-x, 0.0)));
            // Separable: w(x, y)·w(0, 0) = w(x, 0)·w(0, y).
            approx::assert_relative_eq!(
                w * f.weight(Vec2::new(0.0, 0.3)),
                f.weight(Vec2::new(x, 0.3)) * f.weight(Vec2::ZERO),
                max_relative = 1e-6
            );
            last = w;
        }
        // The shifted Gaussian's values: 1 − e^{−4.5} at the centre,
        // e^{−2} − e^{−4.5} one pixel away.
        let floor = (-4.5f32).exp();
        approx::assert_relative_eq!(f.weight(Vec2::ZERO), (1.0 - floor) * (1.0 - floor));
        approx::assert_relative_eq!(
            f.weight(Vec2::new(1.0, 0.0)),
            ((-2.0f32).exp() - floor) * (1.0 - floor)
        );
    }

    #[test]
    fn a_sample_counts_only_within_the_reach() {
        // A sample anywhere in its pixel weighs nothing on the pixels
        // beyond `reach`, for every σ the scene allows.
        for sigma in [0.1f32, 0.3, 0.5, 0.7, 1.0] {
            let f = PixelFilter::gaussian(sigma);
            let r = f.reach() as f32;
            for i in 0..=20 {
                let u = i as f32 / 20.0;
                // Distance from a point u of the pixel [0, 1) to the centre
                // of the pixel r + 1 away.
                let beyond = (r + 1.0 + 0.5) - u;
                assert_eq!(f.weight(Vec2::new(beyond, 0.0)), 0.0, "σ {sigma}, u {u}");
            }
        }
    }
}
