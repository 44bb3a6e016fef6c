//! The fast renderer's settings: how the march steps, finds the optical
//! depth toward the lights and counts the light scattered more than once
//! (the march itself is in [`super::march`]).

use super::multiple::Scattering;

/// How the march finds the optical depth toward the lights.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Shadows {
    /// Ebert's 3-D shadow tables with this many nodes along the volume's longest axis.
    Table(usize),
    /// A direct shadow ray per sample with steps of this length (m).
    Rays(f32),
}

/// Settings of the fast renderer.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct FastSettings {
    /// Eye-ray step (m) at the eye.
    pub step: f32,
    /// Growth of the step with distance from the eye (m per m, `≥ 0`; 0:
    /// uniform steps). Kilometre-scale skies use it to spend samples near the eye.
    pub step_growth: f32,
    /// Shadow method.
    pub shadows: Shadows,
    /// How light scattered more than once is counted ([`Scattering::Single`]:
    /// Ebert's single scattering).
    pub scattering: Scattering,
    /// Strength of Schneider's painted powder term in `[0, 1]` (0: off, the
    /// default). It is not transport and takes the fast mode away from the
    /// reference: 6.8 % in the median image total at 0.2, 17.5 % at 0.5
    /// (see [`powder`](crate::transport::model::powder)).
    pub powder: f32,
    /// The march stops below this transmittance, in `[0, 1)`.
    pub min_transmittance: f32,
    /// Treat the core of the phase function's forward diffraction peak,
    /// within [`PEAK_CORE_DEG`](crate::phase::PEAK_CORE_DEG) of the forward
    /// direction, as transmitted light (the δ-M medium for everything but
    /// the core's own scattering of the sun along the eye ray, which stays
    /// in the exact medium: see the module docs); no effect on phase
    /// functions without such a peak.
    pub truncate_forward_peak: bool,
    /// Direct shadow rays toward the sun for the eye rays near it, instead
    /// of the table (`None`: the table everywhere; see [`NearSunRays`]).
    pub near_sun: Option<NearSunRays>,
    /// Density samples per step, in `1..=`[`MAX_SUBSTEPS`] (1: one, at the
    /// step's midpoint). With `n > 1` each step is cut into `n` equal parts,
    /// each with its own density and its own exact step integral, while
    /// the light reaching the step (the sun's optical depth, the cache, the
    /// ambient and local light, the glow) is looked up once, at the step's
    /// midpoint, and scaled by each part's density.
    ///
    /// The light varies on the scale of the shadow tables' nodes and the
    /// cache's cells; a density eroded by noise detail varies much faster.
    /// Sampled once per step, detail finer than the step folds along the
    /// eye rays into slices of the volume a step apart, which a picture
    /// shows as combed streaks at the edges; parts cost a density sample
    /// each and spare the lookups of the light.
    pub substeps: u32,
}

/// The most density samples per step of [`FastSettings::substeps`].
pub const MAX_SUBSTEPS: u32 = 16;

/// Direct shadow rays toward the sun for eye rays within an angle of it.
///
/// Near the sun a cloud's phase function is its forward peak, a fraction of
/// a degree wide, so what the eye sees there is the sunlight that reaches
/// each point of the eye ray, `e^{−τ_sun}`, point by point: a shadow table,
/// whose optical depths are interpolated between nodes hundreds of metres
/// apart on a kilometre-scale sky, smooths `τ_sun` over the cloud's
/// structure, and the mean of `e^{−τ}` over that structure exceeds `e^{−τ̄}`
/// (Jensen's inequality), so the table darkens the aureole through cloud
/// (figures in `docs/performance.md`). Away from the sun the phase function
/// is broad, it averages the light over many directions, and the table
/// serves. Between `within_deg` and 1.5 times it the two blend smoothly, so
/// no ring shows where one hands over to the other.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct NearSunRays {
    /// Eye rays within this angle of the sun (degrees, in `(0, 60]`) march
    /// their own shadow rays.
    pub within_deg: f32,
    /// The shadow rays' step (m).
    pub step: f32,
}

impl Default for FastSettings {
    /// Uniform steps of 0.1 m, one density sample each, a 64-node table,
    /// single scattering, no powder, stop at `T < 10⁻³`, the forward peak
    /// truncated.
    fn default() -> Self {
        Self {
            step: 0.1,
            step_growth: 0.0,
            shadows: Shadows::Table(64),
            scattering: Scattering::Single,
            powder: 0.0,
            min_transmittance: 1e-3,
            truncate_forward_peak: true,
            near_sun: None,
            substeps: 1,
        }
    }
}

impl FastSettings {
    /// These settings with multiple scattering ([`Scattering::default`]:
    /// the sun's light traced once onto a grid).
    #[must_use]
    pub fn multiple_scattering(self) -> Self {
        Self {
            scattering: Scattering::default(),
            ..self
        }
    }
}
