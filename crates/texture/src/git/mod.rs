//! GIT, the "generalized Impressionistic texture" (Musgrave 1998, "The GIT
//! Texturing System" and "An Impressionistic Image Processing Filter"):
//! fractal juxtaposition of colours that averages to a chosen colour, as a
//! solid texture ([`Git`]) and as a painterly filter over a picture
//! ([`git_filter`]).
//!
//! Both rest on one model, a [`ColourEllipsoid`] in the RGB cube: a centre
//! (the average colour) and principal axes scaled by the spread of colour
//! along each. Vector fBm of unit variance, taken through the ellipsoid's
//! 4 × 4 matrix, gives colours whose mean is the centre and whose
//! covariance is the ellipsoid's. The source designs the matrix
//! interactively, watching a swarm of about a hundred samples;
//! [`ColourEllipsoid::from_colours`] finds it instead from a palette of
//! colours by principal-components analysis, the Hotelling transform the
//! source's filter applies to each neighbourhood of a picture.
//!
//! Colours outside the cube are reflected back into it, as the source does
//! (its footnote 8: reflecting or clipping both skew the average, and
//! "there's no easy fix"); keep the spread within the cube around the mean
//! to hold the average.

mod ellipsoid;
mod filter;

pub use ellipsoid::{ColourEllipsoid, symmetric_eigen};
pub use filter::{GitFilterParams, git_filter};

use glam::{DMat3, DVec3};
use natura_noise::{Perlin, Spectral, VecNoise, VectorFbm, VectorField};

use crate::error::{Result, positive};
use crate::footprint::{Footprint, vfbm_at};
use crate::fractals::{spectral_gain, vfbm};
use crate::multicolor::fold;
use crate::texture::{Sample, SolidTexture, TextureKind, display_to_linear};

/// Parameters of [`Git`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct GitParams {
    /// Seed of the vector fBm.
    pub seed: u64,
    /// The colours' ellipsoid. Default: a sandstone, RGB (0.70, 0.47, 0.33),
    /// varying most from blue-grey to yellow (σ 0.12 along `(1, 1, −1)`,
    /// the source's example of a major axis), little across (0.05, 0.03).
    pub ellipsoid: ColourEllipsoid,
    /// Texture frequency: the vector fBm's first octave has wavelength
    /// `1 / txtscale` (1).
    pub txtscale: f64,
    /// Scale of the domain along x, y and z before the fBm (all 1). A
    /// large `z` "squashes down" the variation into strata, as the source
    /// does for its sandstone (Fig. 15.13).
    pub stretch: DVec3,
    /// Octaves of the vector fBm (8).
    pub octaves: f64,
    /// Lacunarity (2).
    pub lacunarity: f64,
    /// Gain per octave, the listings' raw ω (0.5).
    pub gain: f64,
}

impl Default for GitParams {
    fn default() -> Self {
        Self {
            seed: 0,
            ellipsoid: ColourEllipsoid {
                mean: DVec3::new(0.70, 0.47, 0.33),
                axes: sandstone_axes(),
                sigma: [0.12, 0.05, 0.03],
            },
            txtscale: 1.0,
            stretch: DVec3::ONE,
            octaves: 8.0,
            lacunarity: 2.0,
            gain: 0.5,
        }
    }
}

/// Blue-to-yellow `(1, 1, −1)/√3` and a right-handed frame around it.
fn sandstone_axes() -> [DVec3; 3] {
    let a = DVec3::new(1.0, 1.0, -1.0).normalize();
    let (b, c) = a.any_orthonormal_pair();
    [a, b, c]
}

impl GitParams {
    /// Checks every parameter.
    ///
    /// # Errors
    /// [`TextureError::InvalidParameter`](crate::TextureError::InvalidParameter)
    /// naming `txtscale`, `stretch` (a component NaN, zero or negative),
    /// `octaves`, `lacunarity`, `gain` or a part of the ellipsoid (see
    /// [`ColourEllipsoid::new`]).
    pub fn validate(&self) -> Result<()> {
        self.ellipsoid.validate()?;
        positive("txtscale", self.txtscale)?;
        for s in self.stretch.to_array() {
            positive("stretch", s)?;
        }
        self.spectral().validate()?;
        Ok(())
    }

    fn spectral(&self) -> Spectral {
        spectral_gain(self.gain, self.lacunarity, self.octaves)
    }
}

/// Musgrave's GIT solid texture (Musgrave 1998, "The GIT Texturing
/// System"): a vector fBm sample `v` at the point, divided by the fBm's
/// standard deviation, taken through the ellipsoid's matrix,
///
/// ```text
/// colour = mean + Σᵢ axisᵢ · σᵢ · vᵢ / σ_fBm      (reflected into [0, 1]³)
/// ```
///
/// so the colours juxtapose around the mean with the ellipsoid's
/// covariance. `σ_fBm` is measured when the texture is built, over 4096
/// points of the full fBm. Seen through a wide footprint the unresolved
/// octaves fade out and the colour tends to the mean, the texture's
/// average, so it does not shimmer.
///
/// ```
/// use natura_texture::git::{Git, GitParams};
/// use natura_texture::glam::DVec3;
/// use natura_texture::{Footprint, SolidTexture};
/// let git = Git::new(GitParams::default())?;
/// let c = git.colour(DVec3::new(0.3, 1.7, -2.1), Footprint::POINT);
/// assert!(c.cmpge(DVec3::ZERO).all() && c.cmple(DVec3::ONE).all());
/// // From far away the texture shows its average, the mean.
/// let far = git.display_colour(DVec3::new(0.3, 1.7, -2.1), Footprint::new(100.0)?);
/// assert!((far - git.params().ellipsoid.mean).length() < 1e-12);
/// # Ok::<(), natura_texture::TextureError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Git {
    params: GitParams,
    fbm: VectorFbm<VecNoise<Perlin>>,
    spectral: Spectral,
    /// The standard deviation of one component of the full fBm.
    sigma_fbm: f64,
    /// The ellipsoid's spread matrix ([`ColourEllipsoid::spread`]).
    spread: DMat3,
}

impl Git {
    /// The texture for `params`.
    ///
    /// # Errors
    /// As [`GitParams::validate`].
    pub fn new(params: GitParams) -> Result<Self> {
        params.validate()?;
        let spectral = params.spectral();
        let fbm = vfbm(params.seed, "git", spectral)?;
        let sigma_fbm = vector_fbm_sigma(&fbm);
        Ok(Self {
            params,
            fbm,
            spectral,
            sigma_fbm,
            spread: params.ellipsoid.spread(),
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &GitParams {
        &self.params
    }

    /// The vector fBm's standard deviation per component (its samples are
    /// divided by it).
    #[must_use]
    pub fn fbm_sigma(&self) -> f64 {
        self.sigma_fbm
    }

    /// The colour at `p` as the source computes it, in display RGB (the
    /// cube the ellipsoid lives in).
    #[must_use]
    pub fn display_colour(&self, p: DVec3, fp: Footprint) -> DVec3 {
        let k = self.params.txtscale;
        let s = self.params.stretch;
        let tx = p * s * k;
        let fp = fp.scaled(k * s.max_element());
        let v = vfbm_at(&self.fbm, &self.spectral, tx, fp) / self.sigma_fbm;
        let c = self.params.ellipsoid.mean + self.spread * v;
        DVec3::new(fold(c.x), fold(c.y), fold(c.z))
    }

    /// The colour at `p`, linear RGB.
    #[must_use]
    pub fn colour(&self, p: DVec3, fp: Footprint) -> DVec3 {
        display_to_linear(self.display_colour(p, fp))
    }
}

/// The standard deviation of one component of `fbm`, over 4096 points of a
/// 16³ lattice spaced 3.71 apart (farther than the first octave's
/// wavelength, so the samples are nearly independent), offset off the
/// noise's lattice.
fn vector_fbm_sigma(fbm: &VectorFbm<VecNoise<Perlin>>) -> f64 {
    let mut sum2 = 0.0;
    let n = 16usize;
    for k in 0..n * n * n {
        let p = DVec3::new((k % n) as f64, ((k / n) % n) as f64, (k / (n * n)) as f64) * 3.71
            + DVec3::new(0.377, 0.619, 0.143);
        sum2 += fbm.eval3(p).length_squared();
    }
    (sum2 / (3 * n * n * n) as f64).sqrt()
}

impl SolidTexture for Git {
    fn name(&self) -> &'static str {
        "git"
    }
    fn kind(&self) -> TextureKind {
        TextureKind::Colour
    }
    fn sample(&self, p: DVec3, fp: Footprint) -> Sample {
        Sample::colour(self.colour(p, fp))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Display colours at `n` points spread over many wavelengths.
    fn swarm(git: &Git, n: usize) -> Vec<DVec3> {
        (0..n)
            .map(|k| {
                let t = k as f64;
                let p = DVec3::new(t * 0.7548776662, t * 0.5698402910, t * 0.3141592653) % 200.0;
                git.display_colour(p, Footprint::POINT)
            })
            .collect()
    }

    #[test]
    fn the_colours_average_to_the_mean_with_the_ellipsoids_spread() {
        let git = Git::new(GitParams::default()).unwrap();
        let e = git.params().ellipsoid;
        let found = ColourEllipsoid::from_colours(&swarm(&git, 20_000)).unwrap();
        // The defaults' spread stays inside the cube, so nothing is
        // reflected and the average is the mean.
        assert!((found.mean - e.mean).length() < 0.003, "{:?}", found.mean);
        for i in 0..3 {
            let rel = found.sigma[i] / e.sigma[i];
            assert!(
                (0.95..1.05).contains(&rel),
                "axis {i}: {:?} against {:?}",
                found.sigma,
                e.sigma
            );
        }
        // The major axis of the colours found is the one asked for.
        assert!(
            found.axes[0].dot(e.axes[0]).abs() > 0.995,
            "{:?}",
            found.axes[0]
        );
    }

    #[test]
    fn a_flat_ellipsoid_gives_colours_on_its_axis() {
        let e = ColourEllipsoid::along(
            DVec3::new(0.5, 0.5, 0.5),
            DVec3::new(1.0, 1.0, -1.0),
            [0.1, 0.0, 0.0],
        )
        .unwrap();
        let git = Git::new(GitParams {
            ellipsoid: e,
            ..GitParams::default()
        })
        .unwrap();
        for c in swarm(&git, 500) {
            // Blue-to-yellow only: the offset is parallel to (1, 1, −1).
            let d = c - e.mean;
            assert!(d.cross(e.axes[0]).length() < 1e-12, "{c:?}");
        }
    }

    #[test]
    fn out_of_cube_colours_are_reflected_in() {
        let e =
            ColourEllipsoid::along(DVec3::new(0.95, 0.5, 0.05), DVec3::X, [0.5, 0.5, 0.5]).unwrap();
        let git = Git::new(GitParams {
            ellipsoid: e,
            ..GitParams::default()
        })
        .unwrap();
        let s = swarm(&git, 2000);
        assert!(
            s.iter()
                .all(|c| c.cmpge(DVec3::ZERO).all() && c.cmple(DVec3::ONE).all())
        );
    }

    #[test]
    fn stretch_squashes_the_variation_into_strata() {
        // With z stretched 16 times, the colour changes 16 times faster
        // up than across.
        let git = Git::new(GitParams {
            stretch: DVec3::new(1.0, 1.0, 16.0),
            ..GitParams::default()
        })
        .unwrap();
        let (mut across, mut up) = (0.0, 0.0);
        for k in 0..400 {
            let p = DVec3::new(k as f64 * 1.37, k as f64 * 0.71, k as f64 * 0.13);
            let c = git.display_colour(p, Footprint::POINT);
            across += (git.display_colour(p + DVec3::X * 0.01, Footprint::POINT) - c).length();
            up += (git.display_colour(p + DVec3::Z * 0.01, Footprint::POINT) - c).length();
        }
        assert!(up > 6.0 * across, "up {up}, across {across}");
    }

    #[test]
    fn bad_parameters_are_refused_by_name() {
        let name = |p: GitParams| match Git::new(p) {
            Err(crate::TextureError::InvalidParameter { name, .. }) => name,
            Err(crate::TextureError::Noise(e)) => panic!("{e}"),
            other => panic!("{other:?}"),
        };
        let d = GitParams::default();
        assert_eq!(name(GitParams { txtscale: 0.0, ..d }), "txtscale");
        assert_eq!(
            name(GitParams {
                txtscale: f64::NAN,
                ..d
            }),
            "txtscale"
        );
        assert_eq!(
            name(GitParams {
                stretch: DVec3::new(1.0, 0.0, 1.0),
                ..d
            }),
            "stretch"
        );
        let mut e = d;
        e.ellipsoid.sigma[1] = -1.0;
        assert_eq!(name(e), "sigma");
        assert!(
            Git::new(GitParams {
                octaves: f64::NAN,
                ..d
            })
            .is_err()
        );
        assert!(
            Git::new(GitParams {
                lacunarity: 0.5,
                ..d
            })
            .is_err()
        );
    }
}
