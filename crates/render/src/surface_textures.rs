//! Solid textures on the terrain: Musgrave's sedimentary rock strata on the
//! rock (natura-texture's [`Strata`]) and a fine fBm grain on snow, grass
//! and scree, both band-limited at the pixel's footprint.
//!
//! The strata's fBm loses its octaves finer than the footprint through
//! natura-texture's [`Footprint`] (Musgrave 1993, §5.1.2); their bands,
//! periodic in altitude, fade to the colour map's mean where a pixel spans
//! more than half a band, so distant cliffs do not alias into stripes. Their
//! colours are scaled to the scene's rock albedo (the listing's tans and
//! buffs keep their contrast, the cliffs their brightness), and their hue
//! goes from the rock's own (`strata_tint` 0: the bands only as brightness,
//! for grey alpine rock) to the listing's (`strata_tint` 1: desert sandstone). The grain is an
//! fBm of Perlin noise summed over the octaves the footprint shows
//! (natura-noise's band-limited `eval3_band`, octave count from
//! [`Footprint::visible`]).

use glam::{DVec3, Vec3};
use natura_core::Seed;
use natura_core::colour::luminance;
use natura_noise::{Fbm, Perlin, Spectral};
use natura_texture::Footprint;
use natura_texture::earth::strata::STRATA_KNOTS;
use natura_texture::earth::{Strata, StrataParams};

use crate::error::{RenderError, Result};
use crate::scene::TexturesDesc;

/// The scene's surface textures (see the module docs).
#[derive(Debug)]
pub struct SurfaceTextures {
    strata: Strata,
    /// Mean linear colour of the strata's colour map.
    strata_mean: Vec3,
    strength: f32,
    tint: f32,
    /// Colour-map cycles per metre of altitude.
    cycles_per_m: f32,
    grain: Fbm<Perlin>,
    grain_strength: f32,
}

fn texture_error(e: natura_texture::TextureError) -> RenderError {
    RenderError::Invalid {
        name: "textures".to_owned(),
        value: String::new(),
        reason: e.to_string(),
    }
}

/// The rock strata of `desc` with sub-seeds of `seed` (the textures' seed):
/// the one texture both the surface's colours and the terraces' beds follow.
///
/// # Errors
///
/// [`RenderError::Invalid`] if natura-texture refuses the strata's parameters.
pub(crate) fn strata_of(desc: &TexturesDesc, seed: Seed) -> Result<Strata> {
    Strata::new(StrataParams {
        seed: seed.derive("strata").0.wrapping_add(desc.strata.seed),
        ..desc.strata
    })
    .map_err(texture_error)
}

impl SurfaceTextures {
    /// The textures of `desc` with sub-seeds of `seed`, or `None` when they are off.
    ///
    /// # Errors
    ///
    /// [`RenderError::Invalid`] if natura-texture refuses the strata's
    /// parameters; [`RenderError::Noise`] if the grain's fBm cannot be built.
    pub fn new(desc: &TexturesDesc, seed: Seed) -> Result<Option<Self>> {
        if !desc.enabled {
            return Ok(None);
        }
        let strata = strata_of(desc, seed)?;
        let n = STRATA_KNOTS.len() - 1;
        let strata_mean = (0..4 * n)
            .map(|k| {
                let i = (k as f64 + 0.5) / (4 * n) as f64;
                strata.colour(DVec3::new(0.0, 0.0, i), Footprint::POINT)
            })
            .sum::<DVec3>()
            .as_vec3()
            / (4 * n) as f32;
        let grain = Fbm::new(
            Perlin::new(seed.derive("grain").0),
            Spectral::default()
                .with_h(0.5)
                .with_lacunarity(2.0)
                .with_octaves(f64::from(desc.grain_octaves).max(1.0))
                .with_frequency(1.0 / f64::from(desc.grain_size_m)),
        )?;
        let s = &desc.strata;
        Ok(Some(Self {
            strata,
            strata_mean,
            strength: desc.strata_strength,
            tint: desc.strata_tint,
            cycles_per_m: (s.zscale * s.txtscale) as f32,
            grain,
            grain_strength: if desc.grain_octaves > 0.0 {
                desc.grain_strength
            } else {
                0.0
            },
        }))
    }

    /// The rock's colour at `p` for a pixel footprint of `footprint_m`
    /// metres: the strata, scaled to the brightness of `rock`, blended over
    /// it by the strength.
    #[must_use]
    pub fn rock(&self, p: Vec3, footprint_m: f32, rock: Vec3) -> Vec3 {
        if self.strength <= 0.0 {
            return rock;
        }
        let fp = Footprint::new(f64::from(footprint_m.max(0.0))).unwrap_or(Footprint::POINT);
        let c = self.strata.colour(p.as_dvec3(), fp).as_vec3();
        // Bands per footprint: fade to the mean from a half to two bands.
        let bands = footprint_m * self.cycles_per_m * (STRATA_KNOTS.len() - 3) as f32;
        let c = c.lerp(self.strata_mean, natura_core::smoothstep(0.5, 2.0, bands));
        let scale = luminance(rock) / luminance(self.strata_mean).max(1e-6);
        // The bands' brightness on the rock's own colour, tinted toward the
        // listing's tans and buffs by `tint`.
        let banded = rock * (luminance(c) * scale / luminance(rock).max(1e-6));
        let c = banded.lerp(c * scale, self.tint);
        rock.lerp(c, self.strength)
    }

    /// The grain's brightness factor at `p` for a footprint of `footprint_m`
    /// metres: `1 + strength·fBm`, the fBm over the octaves the footprint shows.
    #[must_use]
    pub fn grain(&self, p: Vec3, footprint_m: f32) -> f32 {
        if self.grain_strength <= 0.0 {
            return 1.0;
        }
        let fp = Footprint::new(f64::from(footprint_m.max(0.0))).unwrap_or(Footprint::POINT);
        let visible = fp.visible(self.grain.spectral());
        if visible <= 0.0 {
            return 1.0;
        }
        let g = self.grain.eval3_band(p.as_dvec3(), visible) as f32;
        1.0 + self.grain_strength * g.clamp(-1.0, 1.0)
    }
}
