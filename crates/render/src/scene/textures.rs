//! The scene's `[textures]` section: natura-texture's solid textures on the
//! surface (rock strata on cliffs, a fine grain on snow, grass and scree),
//! band-limited at each pixel's footprint, and their checks.

use natura_texture::earth::StrataParams;
use serde::{Deserialize, Serialize};

use super::validate::in_range;
use crate::error::{RenderError, Result};

/// Solid textures on the terrain, band-limited at the pixel's footprint.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TexturesDesc {
    /// Whether to texture the surface at all (off: the plain material mapping).
    pub enabled: bool,
    /// Musgrave's sedimentary rock strata on the rock (natura-texture's
    /// [`StrataParams`], in metres: `txtscale` is 1 over the size of the
    /// layers' folds; the colour map repeats every `1/(zscale·txtscale)`
    /// metres of altitude; `seed` is added to the scene's).
    pub strata: StrataParams,
    /// How much the strata replace the rock's colour, 0 to 1 (their
    /// brightness follows the rock's albedo).
    pub strata_strength: f32,
    /// Hue of the strata, 0 (the rock's colour, the bands as brightness
    /// only) to 1 (the listing's tans and buffs).
    pub strata_tint: f32,
    /// Wavelength of the grain's largest octave, metres.
    pub grain_size_m: f32,
    /// Octaves of the grain (each half the wavelength of the last), at most;
    /// fewer where a pixel covers them.
    pub grain_octaves: f32,
    /// Brightness variation of the grain (0 = none; 0.3 is ±30 % at most).
    pub grain_strength: f32,
}

impl Default for TexturesDesc {
    fn default() -> Self {
        Self {
            enabled: true,
            strata: StrataParams {
                seed: 0,
                txtscale: 1.0 / 900.0,
                zscale: 2.0,
                turbscale: 0.3,
                offset: 0.0,
                octaves: 8.0,
            },
            strata_strength: 0.85,
            strata_tint: 0.3,
            grain_size_m: 6.0,
            grain_octaves: 10.0,
            grain_strength: 0.25,
        }
    }
}

impl TexturesDesc {
    /// Checks every key of the section (whether or not it is enabled).
    pub(crate) fn validate(&self) -> Result<()> {
        let s = &self.strata;
        in_range("textures.strata.txtscale", s.txtscale, 1e-7, 1e3)?;
        in_range("textures.strata.zscale", s.zscale, 0.0, 1e3)?;
        in_range("textures.strata.turbscale", s.turbscale, 0.0, 1e3)?;
        in_range("textures.strata.offset", s.offset, -1e6, 1e6)?;
        in_range("textures.strata.octaves", s.octaves, 0.0, 24.0)?;
        s.validate().map_err(|e| RenderError::Invalid {
            name: "textures.strata".to_owned(),
            value: format!("{s:?}"),
            reason: e.to_string(),
        })?;
        in_range(
            "textures.strata_strength",
            f64::from(self.strata_strength),
            0.0,
            1.0,
        )?;
        in_range(
            "textures.strata_tint",
            f64::from(self.strata_tint),
            0.0,
            1.0,
        )?;
        in_range(
            "textures.grain_size_m",
            f64::from(self.grain_size_m),
            1e-3,
            1e4,
        )?;
        in_range(
            "textures.grain_octaves",
            f64::from(self.grain_octaves),
            0.0,
            24.0,
        )?;
        in_range(
            "textures.grain_strength",
            f64::from(self.grain_strength),
            0.0,
            1.0,
        )?;
        Ok(())
    }
}
