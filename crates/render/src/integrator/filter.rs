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

use glam::Vec2;

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

#[cfg(test)]
mod tests {
    use super::*;

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
