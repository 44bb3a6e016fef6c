//! The colour ellipsoid of a GIT texture and the principal-components
//! analysis (the Hotelling transform) that finds it in a set of colours.

use glam::{DMat3, DMat4, DVec3};

use crate::error::{Result, colour, invalid};

/// A swarm of colours as an ellipsoid in the RGB cube (display values,
/// each channel in `[0, 1]`): its centre is the average colour the
/// juxtaposition should show, its principal axes the directions of colour
/// variation and `sigma` the standard deviation along each (Musgrave 1998,
/// "The GIT Texturing System"). The axes are orthonormal, the major axis
/// first.
///
/// ```
/// use natura_texture::git::ColourEllipsoid;
/// use natura_texture::glam::DVec3;
/// // Sandstone varying mostly from blue-grey to yellow.
/// let e = ColourEllipsoid::along(
///     DVec3::new(0.7, 0.47, 0.33),
///     DVec3::new(1.0, 1.0, -1.0),
///     [0.12, 0.05, 0.03],
/// )?;
/// assert!((e.axes[0].length() - 1.0).abs() < 1e-12);
/// assert!(e.axes[0].dot(e.axes[1]).abs() < 1e-12);
/// // The 4 × 4 matrix takes the centre of the unit swarm to the mean.
/// let m = e.matrix().transform_point3(DVec3::ZERO);
/// assert!((m - e.mean).length() < 1e-12);
/// # Ok::<(), natura_texture::TextureError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct ColourEllipsoid {
    /// The average colour (display RGB, each channel in `[0, 1]`).
    pub mean: DVec3,
    /// The principal axes: unit, mutually perpendicular, the major first.
    pub axes: [DVec3; 3],
    /// The standard deviation of the colours along each axis (finite, ≥ 0).
    pub sigma: [f64; 3],
}

/// How far from unit length and from perpendicular the axes may be.
const AXIS_TOLERANCE: f64 = 1e-6;

impl ColourEllipsoid {
    /// The ellipsoid with the given centre, axes and spreads.
    ///
    /// # Errors
    /// [`TextureError::InvalidParameter`](crate::TextureError::InvalidParameter)
    /// naming `mean` (a channel outside `[0, 1]` or NaN), `axes` (not unit
    /// or not perpendicular within 10⁻⁶) or `sigma` (negative or not
    /// finite).
    pub fn new(mean: DVec3, axes: [DVec3; 3], sigma: [f64; 3]) -> Result<Self> {
        let e = Self { mean, axes, sigma };
        e.validate()?;
        Ok(e)
    }

    /// The ellipsoid around `mean` whose major axis points along `major`
    /// (any length; for instance `yellow − blue`), the other two completing
    /// a right-handed frame, with standard deviations `sigma` (major
    /// first).
    ///
    /// # Errors
    /// As [`ColourEllipsoid::new`], and `major` zero or not finite.
    pub fn along(mean: DVec3, major: DVec3, sigma: [f64; 3]) -> Result<Self> {
        let a = crate::error::direction("major", major)?.normalize();
        let (b, c) = a.any_orthonormal_pair();
        Self::new(mean, [a, b, c], sigma)
    }

    /// The ellipsoid of a set of colours by principal-components analysis
    /// (the Hotelling transform, as Musgrave 1998's image filter finds it):
    /// the mean, and the eigenvectors and square roots of the eigenvalues
    /// of their covariance, the largest first. The covariance is the
    /// population one (divided by the number of colours).
    ///
    /// # Errors
    /// [`TextureError::InvalidSize`](crate::TextureError::InvalidSize) for
    /// fewer than two colours; `colours` as an invalid parameter for a
    /// channel that is NaN or outside `[0, 1]`.
    pub fn from_colours(colours: &[DVec3]) -> Result<Self> {
        if colours.len() < 2 {
            return Err(crate::TextureError::InvalidSize {
                name: "colours",
                value: colours.len(),
                reason: "a colour ellipsoid needs at least two colours".into(),
            });
        }
        for &c in colours {
            colour("colours", c)?;
        }
        let n = colours.len() as f64;
        let mean = colours.iter().copied().sum::<DVec3>() / n;
        let mut cov = DMat3::ZERO;
        for &c in colours {
            let d = c - mean;
            cov += outer(d, d);
        }
        Ok(Self::of_covariance(mean, cov * (1.0 / n)))
    }

    /// The ellipsoid of a mean and a covariance matrix (symmetric, positive
    /// semi-definite; negative eigenvalues from rounding count as 0).
    pub(crate) fn of_covariance(mean: DVec3, cov: DMat3) -> Self {
        let (values, vectors) = symmetric_eigen(cov);
        Self {
            mean,
            axes: vectors,
            sigma: values.map(|v| v.max(0.0).sqrt()),
        }
    }

    /// Checks the centre, the axes and the spreads (see [`ColourEllipsoid::new`]).
    ///
    /// # Errors
    /// As [`ColourEllipsoid::new`].
    pub fn validate(&self) -> Result<()> {
        colour("mean", self.mean)?;
        for (i, a) in self.axes.iter().enumerate() {
            if !a.is_finite() || (a.length() - 1.0).abs() > AXIS_TOLERANCE {
                return Err(invalid("axes", a, "each axis must be a unit vector"));
            }
            for b in &self.axes[i + 1..] {
                if a.dot(*b).abs() > AXIS_TOLERANCE {
                    return Err(invalid("axes", a, "the axes must be perpendicular"));
                }
            }
        }
        for s in self.sigma {
            crate::error::non_negative("sigma", s)?;
        }
        Ok(())
    }

    /// The 3 × 3 part of [`ColourEllipsoid::matrix`]: the axes as columns,
    /// each scaled by its standard deviation. It takes a sample of unit
    /// variance in each component to an offset from the mean with this
    /// ellipsoid's covariance.
    #[must_use]
    pub fn spread(&self) -> DMat3 {
        DMat3::from_cols(
            self.axes[0] * self.sigma[0],
            self.axes[1] * self.sigma[1],
            self.axes[2] * self.sigma[2],
        )
    }

    /// The GIT matrix: the 4 × 4 transformation (scaling by the standard
    /// deviations, rotation onto the principal axes, translation to the
    /// mean) that maps a vector-fBm sample of unit variance to a colour.
    #[must_use]
    pub fn matrix(&self) -> DMat4 {
        DMat4::from_translation(self.mean) * DMat4::from_mat3(self.spread())
    }

    /// The covariance matrix the ellipsoid stands for, `Σ = A·diag(σ²)·Aᵀ`.
    #[must_use]
    pub fn covariance(&self) -> DMat3 {
        let s = self.spread();
        s * s.transpose()
    }
}

/// `a·bᵀ`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// The eigenvalues of the symmetric matrix `m` in decreasing order and
/// their unit eigenvectors (a right-handed orthonormal frame), by cyclic
/// Jacobi rotations: each rotation zeroes one off-diagonal element, and
/// the sweeps stop once the off-diagonal part is below 10⁻³⁰ of the
/// matrix's squared norm (or after 32 sweeps; 3 × 3 matrices converge
/// quadratically in four to six).
#[must_use]
pub fn symmetric_eigen(m: DMat3) -> ([f64; 3], [DVec3; 3]) {
    let mut a = m.to_cols_array_2d();
    // Symmetrise: the upper and lower triangles may differ by rounding.
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let s = 0.5 * (a[i][j] + a[j][i]);
        a[i][j] = s;
        a[j][i] = s;
    }
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let norm2: f64 = a.iter().flatten().map(|x| x * x).sum();
    for _ in 0..32 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if off <= 1e-30 * norm2 || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // The rotation that zeroes a[p][q] (Golub and Van Loan, 8.5.2).
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in &mut a {
                let (x, y) = (row[p], row[q]);
                row[p] = c * x - s * y;
                row[q] = s * x + c * y;
            }
            let (x, y) = (a[p], a[q]);
            a[p] = rotate(x, y, c, -s);
            a[q] = rotate(y, x, c, s);
            // Columns of `v` (stored as v[column][row]) are the vectors.
            let (x, y) = (v[p], v[q]);
            v[p] = rotate(x, y, c, -s);
            v[q] = rotate(y, x, c, s);
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let values = order.map(|i| a[i][i]);
    let mut vectors = order.map(|i| DVec3::from_array(v[i]));
    // Each vector's sign: its largest component positive, then a
    // right-handed frame, so equal matrices give equal frames.
    for e in &mut vectors[..2] {
        let big = if e.x.abs() >= e.y.abs() && e.x.abs() >= e.z.abs() {
            e.x
        } else if e.y.abs() >= e.z.abs() {
            e.y
        } else {
            e.z
        };
        if big < 0.0 {
            *e = -*e;
        }
    }
    if vectors[0].cross(vectors[1]).dot(vectors[2]) < 0.0 {
        vectors[2] = -vectors[2];
    }
    (values, vectors)
}

/// `c·x + s·y`, element by element.
fn rotate(x: [f64; 3], y: [f64; 3], c: f64, s: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| c * x[k] + s * y[k])
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn reconstruct(values: [f64; 3], vectors: [DVec3; 3]) -> DMat3 {
        (0..3).fold(DMat3::ZERO, |acc, i| {
            acc + outer(vectors[i], vectors[i]) * values[i]
        })
    }

    proptest! {
        #[test]
        fn eigen_decomposition_reconstructs_the_matrix(
            d in proptest::array::uniform3(-2.0f64..2.0),
            o in proptest::array::uniform3(-2.0f64..2.0),
        ) {
            let m = DMat3::from_cols_array_2d(&[
                [d[0], o[0], o[1]],
                [o[0], d[1], o[2]],
                [o[1], o[2], d[2]],
            ]);
            let (values, vectors) = symmetric_eigen(m);
            prop_assert!(values[0] >= values[1] && values[1] >= values[2]);
            for i in 0..3 {
                prop_assert!((vectors[i].length() - 1.0).abs() < 1e-12);
                // m·v = λ·v.
                prop_assert!((m * vectors[i] - vectors[i] * values[i]).length() < 1e-10);
                for j in i + 1..3 {
                    prop_assert!(vectors[i].dot(vectors[j]).abs() < 1e-12);
                }
            }
            let r = reconstruct(values, vectors);
            prop_assert!((r - m).to_cols_array().iter().all(|e| e.abs() < 1e-10));
            // Right-handed.
            prop_assert!(vectors[0].cross(vectors[1]).dot(vectors[2]) > 0.0);
        }
    }

    #[test]
    fn a_diagonal_matrix_is_its_own_decomposition() {
        let (values, vectors) = symmetric_eigen(DMat3::from_diagonal(DVec3::new(0.2, 3.0, 1.0)));
        assert_eq!(values, [3.0, 1.0, 0.2]);
        assert_eq!(vectors[0], DVec3::Y);
        assert_eq!(vectors[1], DVec3::Z);
        assert_eq!(vectors[2], DVec3::X);
    }

    #[test]
    fn pca_recovers_a_known_swarm() {
        // Colours on a known ellipsoid, at the ± points of each axis (their
        // covariance is exactly diag(σ²) in the axes' frame).
        let e = ColourEllipsoid::along(
            DVec3::new(0.5, 0.45, 0.4),
            DVec3::new(1.0, 1.0, -1.0),
            [0.2, 0.08, 0.03],
        )
        .unwrap();
        let colours: Vec<DVec3> = (0..3)
            .flat_map(|i| {
                let d = e.axes[i] * e.sigma[i] * 3f64.sqrt();
                [e.mean + d, e.mean - d]
            })
            .collect();
        let f = ColourEllipsoid::from_colours(&colours).unwrap();
        assert!((f.mean - e.mean).length() < 1e-12);
        for i in 0..3 {
            assert!((f.sigma[i] - e.sigma[i]).abs() < 1e-12, "{:?}", f.sigma);
            assert!(f.axes[i].dot(e.axes[i]).abs() > 1.0 - 1e-12);
        }
        let c = f.covariance() - e.covariance();
        assert!(c.to_cols_array().iter().all(|x| x.abs() < 1e-12));
    }

    #[test]
    fn bad_ellipsoids_are_refused_by_name() {
        let axes = [DVec3::X, DVec3::Y, DVec3::Z];
        let name = |r: Result<ColourEllipsoid>| match r {
            Err(crate::TextureError::InvalidParameter { name, .. }) => name,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            name(ColourEllipsoid::new(DVec3::splat(1.2), axes, [0.1; 3])),
            "mean"
        );
        assert_eq!(
            name(ColourEllipsoid::new(DVec3::NAN, axes, [0.1; 3])),
            "mean"
        );
        let skew = [DVec3::X, DVec3::new(0.1, 1.0, 0.0).normalize(), DVec3::Z];
        assert_eq!(
            name(ColourEllipsoid::new(DVec3::splat(0.5), skew, [0.1; 3])),
            "axes"
        );
        let long = [DVec3::X * 2.0, DVec3::Y, DVec3::Z];
        assert_eq!(
            name(ColourEllipsoid::new(DVec3::splat(0.5), long, [0.1; 3])),
            "axes"
        );
        assert_eq!(
            name(ColourEllipsoid::new(
                DVec3::splat(0.5),
                axes,
                [0.1, -0.1, 0.0]
            )),
            "sigma"
        );
        assert_eq!(
            name(ColourEllipsoid::new(
                DVec3::splat(0.5),
                axes,
                [f64::NAN, 0.1, 0.0]
            )),
            "sigma"
        );
        assert_eq!(
            name(ColourEllipsoid::along(
                DVec3::splat(0.5),
                DVec3::ZERO,
                [0.1; 3]
            )),
            "major"
        );
        assert!(matches!(
            ColourEllipsoid::from_colours(&[DVec3::splat(0.5)]),
            Err(crate::TextureError::InvalidSize {
                name: "colours",
                ..
            })
        ));
        assert_eq!(
            name(ColourEllipsoid::from_colours(&[
                DVec3::splat(0.5),
                DVec3::new(0.1, f64::NAN, 0.0)
            ])),
            "colours"
        );
    }
}
