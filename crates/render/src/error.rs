//! The error type of `natura-render`.

/// Everything that can go wrong while describing, building or rendering a scene.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// A scene file could not be read or parsed (message names file, line and key).
    #[error("{0}")]
    Scene(String),
    /// A scene value is out of range.
    #[error("invalid scene value `{name}` = {value}: {reason}")]
    Invalid {
        /// Dotted key of the value.
        name: String,
        /// The value, formatted.
        value: String,
        /// What is allowed.
        reason: String,
    },
    /// From natura-core (I/O, sizes).
    #[error(transparent)]
    Core(#[from] natura_core::CoreError),
    /// From natura-noise.
    #[error("noise: {0}")]
    Noise(#[from] natura_noise::NoiseError),
    /// From natura-terrain.
    #[error(transparent)]
    Terrain(#[from] natura_terrain::TerrainError),
    /// From natura-trace.
    #[error(transparent)]
    Trace(#[from] natura_trace::TraceError),
    /// From natura-atmos.
    #[error(transparent)]
    Atmos(#[from] natura_atmos::AtmosError),
    /// From natura-ocean.
    #[error(transparent)]
    Ocean(#[from] natura_ocean::OceanError),
    /// From natura-volume.
    #[error(transparent)]
    Volume(#[from] natura_volume::VolumeError),
    /// From natura-plant (the forest's ecosystem and meshes).
    #[error(transparent)]
    Plant(#[from] natura_plant::PlantError),
}

impl RenderError {
    pub(crate) fn invalid(name: &str, value: impl std::fmt::Display, reason: &str) -> Self {
        RenderError::Invalid {
            name: name.to_owned(),
            value: value.to_string(),
            reason: reason.to_owned(),
        }
    }

    /// A terrain model's parameter error, re-named by the scene key of its
    /// sub-table: `StreamPowerParams::k` in `erosion.stream_power` becomes
    /// `erosion.stream_power.k`; any other error passes through.
    pub(crate) fn in_section(section: &str, e: natura_terrain::TerrainError) -> Self {
        match e {
            natura_terrain::TerrainError::InvalidParameter {
                name,
                value,
                reason,
            } => {
                let field = name.rsplit("::").next().unwrap_or(name);
                RenderError::Invalid {
                    name: format!("{section}.{field}"),
                    value,
                    reason,
                }
            }
            other => RenderError::Terrain(other),
        }
    }
}

/// Shorthand for `Result<T, RenderError>`.
pub type Result<T, E = RenderError> = std::result::Result<T, E>;

impl From<natura_core::check::ParamError> for RenderError {
    fn from(e: natura_core::check::ParamError) -> Self {
        RenderError::Invalid {
            name: e.name.to_owned(),
            value: e.value,
            reason: e.expected.to_owned(),
        }
    }
}
