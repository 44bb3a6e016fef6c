//! Colour splines with RenderMan's `spline()` semantics, the colour maps of
//! Musgrave's shaders.

use glam::DVec3;

use crate::error::{Result, invalid};

/// A Catmull–Rom colour spline through `n ≥ 4` knots, as the RenderMan
/// shading language's `spline(t, k0, …, kₙ₋₁)`: the curve runs from `k1`
/// (`t = 0`) to `kₙ₋₂` (`t = 1`) over `n − 3` equal segments, and the first
/// and last knots only shape the end tangents (Musgrave 1998 repeats them to
/// make the ends flat).
///
/// `t` is clamped to `[0, 1]` and the result to `[0, 1]` per channel:
/// Catmull–Rom can overshoot its knots slightly, and a texture's colour must
/// stay in gamut.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ColourSpline {
    knots: Vec<DVec3>,
}

impl ColourSpline {
    /// A spline through `knots` (linear RGB, each channel in `[0, 1]`).
    ///
    /// # Errors
    /// [`TextureError::InvalidParameter`](crate::TextureError::InvalidParameter)
    /// for fewer than 4 knots or a channel outside `[0, 1]`.
    pub fn new(knots: Vec<DVec3>) -> Result<Self> {
        if knots.len() < 4 {
            return Err(invalid(
                "knots",
                knots.len(),
                "a colour spline needs at least 4 knots",
            ));
        }
        for &k in &knots {
            crate::error::colour("knots", k)?;
        }
        Ok(Self { knots })
    }

    /// A spline through 8-bit knots (each divided by 255, as the listings do).
    ///
    /// # Errors
    /// [`TextureError::InvalidParameter`](crate::TextureError::InvalidParameter)
    /// for fewer than 4 knots.
    pub fn from_bytes(knots: &[[u8; 3]]) -> Result<Self> {
        Self::new(
            knots
                .iter()
                .map(|k| DVec3::new(f64::from(k[0]), f64::from(k[1]), f64::from(k[2])) / 255.0)
                .collect(),
        )
    }

    /// The knots.
    #[must_use]
    pub fn knots(&self) -> &[DVec3] {
        &self.knots
    }

    /// Checks the knot count and gamut (for deserialised splines).
    ///
    /// # Errors
    /// As [`ColourSpline::new`].
    pub fn validate(&self) -> Result<()> {
        Self::new(self.knots.clone()).map(|_| ())
    }

    /// The colour at `t ∈ [0, 1]` (clamped), each channel clamped to `[0, 1]`.
    #[must_use]
    pub fn eval(&self, t: f64) -> DVec3 {
        let segments = self.knots.len() - 3;
        let x = t.clamp(0.0, 1.0) * segments as f64;
        let i = (x as usize).min(segments - 1);
        let u = x - i as f64;
        let [k0, k1, k2, k3] = [
            self.knots[i],
            self.knots[i + 1],
            self.knots[i + 2],
            self.knots[i + 3],
        ];
        let (u2, u3) = (u * u, u * u * u);
        let c = (k0 * (-u3 + 2.0 * u2 - u)
            + k1 * (3.0 * u3 - 5.0 * u2 + 2.0)
            + k2 * (-3.0 * u3 + 4.0 * u2 + u)
            + k3 * (u3 - u2))
            * 0.5;
        c.clamp(DVec3::ZERO, DVec3::ONE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_through_inner_knots_and_clamps() {
        let s = ColourSpline::new(vec![
            DVec3::ZERO,
            DVec3::splat(0.2),
            DVec3::splat(0.6),
            DVec3::splat(0.4),
            DVec3::ONE,
        ])
        .unwrap();
        assert!((s.eval(0.0) - DVec3::splat(0.2)).length() < 1e-15);
        assert!((s.eval(0.5) - DVec3::splat(0.6)).length() < 1e-15);
        assert!((s.eval(1.0) - DVec3::splat(0.4)).length() < 1e-15);
        assert_eq!(s.eval(-3.0), s.eval(0.0));
        assert_eq!(s.eval(7.0), s.eval(1.0));
        for i in 0..=100 {
            let c = s.eval(f64::from(i) / 100.0);
            assert!(c.cmpge(DVec3::ZERO).all() && c.cmple(DVec3::ONE).all());
        }
        assert!(ColourSpline::new(vec![DVec3::ZERO; 3]).is_err());
        assert!(ColourSpline::new(vec![DVec3::splat(2.0); 4]).is_err());
    }

    #[test]
    fn continuous_across_segments() {
        let s = ColourSpline::from_bytes(&[
            [0, 0, 0],
            [10, 200, 30],
            [250, 5, 90],
            [30, 30, 30],
            [255; 3],
            [7, 7, 7],
        ])
        .unwrap();
        for j in 1..3 {
            let t = f64::from(j) / 3.0;
            assert!((s.eval(t - 1e-12) - s.eval(t + 1e-12)).length() < 1e-9);
        }
    }
}
