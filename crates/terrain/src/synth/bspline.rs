//! Smooth surfaces through stochastic points: a uniform bicubic B-spline
//! surface whose control net is a height field — Fournier et al.'s way to
//! avoid the creases and divergent normals of polygon subdivision, "using
//! the stochastically interpolated points as control points for a B-spline
//! surface" (Fournier et al. 1982, §4.1.2.1, Fig. 15).
//!
//! Span `(i, j)` of the surface is blended from the 4 × 4 control points
//! `i..i+4, j..j+4` with the uniform cubic B-spline basis
//! `B₀ = (1−u)³/6, B₁ = (3u³ − 6u² + 4)/6, B₂ = (−3u³ + 3u² + 3u + 1)/6,
//! B₃ = u³/6`. The basis sums to one and is non-negative, so the surface
//! lies within the range of its control heights; it reproduces linear
//! functions exactly and is C² (curvature-continuous) everywhere. It
//! approximates the control points rather than interpolating them.

use natura_core::{Grid2, HeightField};

use crate::error::{Result, invalid, min_size};

/// The most samples per span accepted by [`bspline_surface`].
pub const MAX_SAMPLES_PER_SPAN: usize = 1024;

/// The uniform cubic B-spline weights of the four control points of a span
/// at `u ∈ [0, 1]`.
#[inline]
#[must_use]
pub fn cubic_bspline_weights(u: f64) -> [f64; 4] {
    let (u2, u3) = (u * u, u * u * u);
    let v = 1.0 - u;
    [
        v * v * v / 6.0,
        (3.0 * u3 - 6.0 * u2 + 4.0) / 6.0,
        (-3.0 * u3 + 3.0 * u2 + 3.0 * u + 1.0) / 6.0,
        u3 / 6.0,
    ]
}

/// Samples the bicubic B-spline surface whose control net is `control`
/// (`n × m` heights, `cell_size` apart) at `samples_per_span` samples per
/// span and axis: `(n − 3)·s + 1 × (m − 3)·s + 1` heights, `cell_size / s`
/// apart (Fournier et al. 1982, §4.1.2.1, Fig. 15).
///
/// Sample `(0, 0)` lies above control point `(1, 1)` and the last sample
/// above control point `(n − 2, m − 2)`: a uniform B-spline's domain ends
/// one control point inside the net.
///
/// ```
/// use natura_terrain::{HeightField, synth::bspline_surface};
/// // A control net on a plane gives the same plane (linear precision).
/// let net = HeightField::from_fn(6, 5, 2.0, |i, j| (i + 2 * j) as f32)?;
/// let s = bspline_surface(&net, 4)?;
/// assert_eq!((s.nx(), s.ny(), s.cell_size()), (13, 9, 0.5));
/// assert!((s.heights()[(4, 4)] - 6.0).abs() < 1e-5); // above control point (2, 2): 2 + 2·2
/// # Ok::<(), natura_terrain::TerrainError>(())
/// ```
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) for a
/// net smaller than 4 × 4, [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
/// for `samples_per_span` outside `1..=`[`MAX_SAMPLES_PER_SPAN`], and
/// [`TerrainError::Core`](crate::TerrainError::Core) for a height that is
/// not finite or a result too large to allocate.
pub fn bspline_surface(control: &HeightField, samples_per_span: usize) -> Result<HeightField> {
    min_size("bspline_surface", control.nx(), control.ny(), 4, 4)?;
    if !(1..=MAX_SAMPLES_PER_SPAN).contains(&samples_per_span) {
        return Err(invalid(
            "samples_per_span",
            samples_per_span,
            format!("must be in 1..={MAX_SAMPLES_PER_SPAN}"),
        ));
    }
    control.check_finite()?;
    let s = samples_per_span;
    let (nx, ny) = ((control.nx() - 3) * s + 1, (control.ny() - 3) * s + 1);
    let c = control.heights();
    // Span index and weights of output column / row k.
    let at = |k: usize, spans: usize| {
        let span = (k / s).min(spans - 1);
        let u = (k - span * s) as f64 / s as f64;
        (span, cubic_bspline_weights(u))
    };
    let (sx, sy) = (control.nx() - 3, control.ny() - 3);
    let heights = Grid2::from_fn(nx, ny, |i, j| {
        let (a, wx) = at(i, sx);
        let (b, wy) = at(j, sy);
        let mut z = 0.0f64;
        for (q, wq) in wy.iter().enumerate() {
            let mut row = 0.0f64;
            for (p, wp) in wx.iter().enumerate() {
                row += wp * f64::from(c[(a + p, b + q)]);
            }
            z += wq * row;
        }
        z as f32
    })?;
    Ok(HeightField::new(heights, control.cell_size() / s as f32)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_are_a_partition_of_unity_and_join_smoothly() {
        for k in 0..=16 {
            let w = cubic_bspline_weights(k as f64 / 16.0);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert!(w.iter().all(|&x| x >= 0.0));
        }
        // The end of one span equals the start of the next, shifted by one point.
        let (a, b) = (cubic_bspline_weights(1.0), cubic_bspline_weights(0.0));
        assert!((a[1] - b[0]).abs() < 1e-15 && (a[2] - b[1]).abs() < 1e-15);
        assert!((a[3] - b[2]).abs() < 1e-15 && a[0].abs() < 1e-15 && b[3].abs() < 1e-15);
    }

    #[test]
    fn stays_within_the_control_heights_and_is_continuous() {
        let net = HeightField::from_fn(9, 7, 1.0, |i, j| {
            (((i * 7919 + j * 104_729) % 97) as f32) / 10.0
        })
        .unwrap();
        let (lo, hi) = net.heights().min_max();
        let s = bspline_surface(&net, 8).unwrap();
        assert_eq!((s.nx(), s.ny()), (49, 33));
        let (a, b) = s.heights().min_max();
        assert!(a >= lo - 1e-5 && b <= hi + 1e-5);
        // Neighbouring samples differ by at most the steepest control step
        // over a sample's length (no jumps at span joints).
        let max_step = 9.7;
        for j in 0..s.ny() {
            for i in 1..s.nx() {
                let d = (s.heights()[(i, j)] - s.heights()[(i - 1, j)]).abs();
                assert!(d <= max_step / 8.0 * 1.5, "jump {d} at ({i}, {j})");
            }
        }
    }

    #[test]
    fn refuses_bad_input() {
        let small = HeightField::flat(3, 8, 1.0, 0.0).unwrap();
        assert!(bspline_surface(&small, 4).is_err());
        let net = HeightField::flat(4, 4, 1.0, 2.0).unwrap();
        assert!(bspline_surface(&net, 0).is_err());
        assert!(bspline_surface(&net, MAX_SAMPLES_PER_SPAN + 1).is_err());
        let one = bspline_surface(&net, 1).unwrap();
        assert_eq!((one.nx(), one.ny()), (2, 2));
        assert!(
            one.heights()
                .as_slice()
                .iter()
                .all(|&z| (z - 2.0).abs() < 1e-6)
        );
    }
}
