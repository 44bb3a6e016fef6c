//! The fast mode's choice of how to count light scattered more than once,
//! and that choice prepared for one scene.

use glam::Vec3;

use super::MediumParams;
use super::cache::{CacheParams, EyeBasis, ScatterCache};
use super::model::{MediumOctaves, ScatterOctaves};
use crate::density::Density;
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
    /// ([`ScatterCache`], where the model and its error are described); the
    /// environment's light by the default octaves.
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
}

impl Multiple {
    /// Prepares `choice` for `density` in the transport `medium` lit by a
    /// sun toward unit `sun`.
    pub(crate) fn new(
        choice: &Scattering,
        density: &dyn Density,
        medium: &MediumParams,
        sun: Option<Vec3>,
    ) -> Result<Self> {
        Ok(match choice {
            Scattering::Single => Self {
                octaves: MediumOctaves::new(ScatterOctaves::SINGLE, 1.0),
                cache: None,
            },
            Scattering::Octaves(o) => Self {
                octaves: MediumOctaves::new(*o, medium.albedo),
                cache: None,
            },
            Scattering::Cache(c) => Self {
                octaves: MediumOctaves::new(ScatterOctaves::default(), medium.albedo),
                cache: sun
                    .map(|s| ScatterCache::new(density, medium, s, c).map(Box::new))
                    .transpose()?,
            },
        })
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

    /// The environment's in-scatter factor at optical depth `tau` straight up.
    #[inline]
    pub(crate) fn ambient(&self, tau: f32) -> f32 {
        self.octaves.ambient(tau)
    }
}
