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
                    value: short(&value),
                    reason,
                }
            }
            other => RenderError::Terrain(other),
        }
    }
}

/// A number as a user reads it: its shortest round-trip digits, in
/// scientific notation when very large or small (`1e300`, never 300 digits).
pub(crate) fn fmt_f64(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// As [`fmt_f64`] for an `f32` key (its own shortest digits, not the `f64`'s).
pub(crate) fn fmt_f32(v: f32) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A value formatted elsewhere, shortened if it is a long number.
pub(crate) fn short(value: &str) -> String {
    match value.trim().parse::<f64>() {
        Ok(v) if value.len() > 12 => fmt_f64(v),
        _ => value.to_owned(),
    }
}

/// A scene value in a range check: its number and how the user reads it.
pub(crate) trait SceneValue: Copy {
    /// The value as `f64`, for the comparison.
    fn to_f64(self) -> f64;
    /// The value as the user reads it.
    fn show(self) -> String;
}

impl SceneValue for f64 {
    fn to_f64(self) -> f64 {
        self
    }
    fn show(self) -> String {
        fmt_f64(self)
    }
}

impl SceneValue for f32 {
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    fn show(self) -> String {
        fmt_f32(self)
    }
}

impl SceneValue for u32 {
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    fn show(self) -> String {
        self.to_string()
    }
}

impl SceneValue for usize {
    fn to_f64(self) -> f64 {
        self as f64
    }
    fn show(self) -> String {
        self.to_string()
    }
}

/// Checks that `v` lies in `[lo, hi]`, saying so with the key, the value and
/// the bounds in the message.
pub(crate) fn in_range(name: &str, v: impl SceneValue, lo: f64, hi: f64) -> Result<()> {
    let x = v.to_f64();
    if x.is_finite() && x >= lo && x <= hi {
        Ok(())
    } else {
        Err(RenderError::Invalid {
            name: name.to_owned(),
            value: v.show(),
            reason: format!("must lie in [{}, {}]", fmt_f64(lo), fmt_f64(hi)),
        })
    }
}

/// Shorthand for `Result<T, RenderError>`.
pub type Result<T, E = RenderError> = std::result::Result<T, E>;

natura_core::from_param_error!(RenderError::Invalid, expected: reason, value: short);
