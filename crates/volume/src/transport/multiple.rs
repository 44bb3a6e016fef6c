//! The fast mode's choice of how to count light scattered more than once,
//! and that choice prepared for one scene.

use glam::Vec3;

use super::cache::{CacheParams, EyeBasis, ScatterCache};
use super::cells::CellGrid;
use super::local::{LocalEye, LocalLight};
use super::model::{MediumOctaves, ScatterOctaves};
use super::{MediumParams, Scene};
use crate::error::Result;
use crate::phase::CloudPhase;

/// How the fast mode counts the light that has scattered more than once
/// (single scattering is exact in every choice).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Scattering {
    /// Not at all: Ebert's single scattering.
    Single,
    /// The octaves of Wrenninge et al. 2013 in the medium's form
    /// ([`MediumOctaves`]): no set-up, fitted on clouds, far off in thick or
    /// strongly forward-scattering media.
    Octaves(ScatterOctaves),
    /// The sun's multiply scattered light traced once per scene onto a grid
    /// ([`ScatterCache`], where the model and its error are described), with
    /// the light of the sky, the scene's surfaces and its glow on the same
    /// grid ([`local`](super::local)); with no local events, the sky's light
    /// by the ambient term and the default octaves.
    Cache(CacheParams),
}

impl Default for Scattering {
    /// The cache with its default settings.
    fn default() -> Self {
        Scattering::Cache(CacheParams::default())
    }
}

impl Scattering {
    /// Checks the choice's settings.
    ///
    /// # Errors
    ///
    /// As [`ScatterOctaves::validate`] or [`CacheParams::validate`].
    pub fn validate(&self) -> Result<()> {
        match self {
            Scattering::Single => Ok(()),
            Scattering::Octaves(o) => o.validate(),
            Scattering::Cache(c) => c.validate(),
        }
    }
}

/// A [`Scattering`] prepared for one scene.
#[derive(Clone, Debug)]
pub(crate) struct Multiple {
    /// The octaves (single scattering is one octave): the environment's
    /// light always, the sun's without a cache.
    octaves: MediumOctaves,
    /// The sun's cache.
    cache: Option<Box<ScatterCache>>,
    /// The light of the scene's surfaces and glow.
    local: Option<Box<LocalLight>>,
}

impl Multiple {
    /// Prepares `choice` for `scene` in the transport `medium` (its
    /// extinction `ratio` times the scene's).
    pub(crate) fn new(
        choice: &Scattering,
        scene: &Scene<'_>,
        medium: &MediumParams,
        ratio: f32,
    ) -> Result<Self> {
        Ok(match choice {
            Scattering::Single => Self {
                octaves: MediumOctaves::new(ScatterOctaves::SINGLE, 1.0),
                cache: None,
                local: None,
            },
            Scattering::Octaves(o) => Self {
                octaves: MediumOctaves::new(*o, medium.albedo),
                cache: None,
                local: None,
            },
            Scattering::Cache(c) => {
                c.validate()?;
                let sun = scene.sun_unit();
                let grid = if sun.is_some() || c.local > 0 {
                    Some(CellGrid::new(scene.density, medium.extinction, c.cells)?)
                } else {
                    None
                };
                let local = grid
                    .as_ref()
                    .filter(|_| c.local > 0)
                    .and_then(|g| LocalLight::new(scene, g.clone(), medium, ratio, c.local, c.seed))
                    .map(Box::new);
                let cache = sun
                    .zip(grid)
                    .map(|(s, g)| Box::new(ScatterCache::on_grid(g, medium, s.direction, c)));
                Self {
                    octaves: MediumOctaves::new(ScatterOctaves::default(), medium.albedo),
                    cache,
                    local,
                }
            }
        })
    }

    /// Whether the light of the scene's ground is traced (the environment's
    /// mean radiance then leaves it out).
    pub(crate) fn traces_ground(&self) -> bool {
        self.local.as_ref().is_some_and(|l| l.has_ground())
    }

    /// Whether the light of the scene's sky is traced (the environment's
    /// mean radiance then leaves it out).
    pub(crate) fn traces_sky(&self) -> bool {
        self.local.as_ref().is_some_and(|l| l.has_sky())
    }

    /// Whether the sun's factor needs the chord at optical depth `tau`
    /// toward the sun (the octaves' chord weight is 1 past `τ = 8`).
    #[inline]
    pub(crate) fn needs_chord(&self, tau: f32) -> bool {
        self.cache.is_none() && tau < 8.0
    }

    /// The cache's factors for an eye looking along unit `d` (constant
    /// along an eye ray; `None` without a cache).
    #[inline]
    pub(crate) fn eye(&self, d: Vec3) -> Option<EyeBasis> {
        self.cache.as_ref().map(|c| c.eye_basis(d))
    }

    /// The sun's in-scatter factor (per unit irradiance and scattering
    /// coefficient) at `p`, at optical depth `tau` toward the sun on a chord
    /// `chord` (octaves only), for an eye at cosine `mu` from the sun with
    /// the cache's factors `eye`: single scattering `p(μ)·e^{−τ}` plus the
    /// light scattered more than once.
    #[inline]
    pub(crate) fn sun(
        &self,
        phase: &CloudPhase,
        p: Vec3,
        eye: Option<&EyeBasis>,
        mu: f32,
        tau: f32,
        chord: f32,
    ) -> f32 {
        match (&self.cache, eye) {
            (Some(c), Some(e)) => phase.eval(mu) * (-tau).exp() + c.toward_eye(p, e),
            _ => self.octaves.sun(phase, mu, tau, chord),
        }
    }

    /// The factors of the surfaces' and glow's light for an eye looking
    /// along unit `d` (`None` without that light).
    #[inline]
    pub(crate) fn local_eye(&self, d: Vec3) -> Option<LocalEye> {
        self.local.as_ref().map(|l| l.eye(d))
    }

    /// The surfaces' and glow's light scattered toward the eye at `p`, per
    /// unit scattering coefficient, for the eye's factors `eye`.
    #[inline]
    pub(crate) fn local(&self, p: Vec3, eye: &LocalEye) -> Vec3 {
        self.local
            .as_ref()
            .map_or(Vec3::ZERO, |l| l.toward_eye(p, eye))
    }

    /// The environment's in-scatter factor at optical depth `tau` straight up.
    #[inline]
    pub(crate) fn ambient(&self, tau: f32) -> f32 {
        self.octaves.ambient(tau)
    }
}
