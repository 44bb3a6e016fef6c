//! Plates 4.5 and 4.6 of `figures_musgrave`: a quarter-lit planet (the sun
//! at right angles to the view, so the terminator runs through the disc's
//! centre) in natura-texture's radial atmosphere, first with the
//! cylinder-umbra model alone (Pl. 4.5: the haze keeps its colour on the
//! day side and ends where it enters the planet's shadow cylinder, sharp at
//! the poles), then with the shaded atmosphere (Pl. 4.6: the haze dimmed by
//! the sun's cosine and lit by the sunlight that reaches it through the
//! air, blue at high noon and red towards the terminator).

use natura::core::glam::DVec3;
use natura::core::{Image, NoProgress};
use natura::texture::planet::{Planet, PlanetParams, SurfaceParams, TraceSettings, direction};

use crate::common::Exit;

type R<T> = Result<T, Exit>;

/// Gaea with its terrain and clouds from `seed`, lit by the sun in unit
/// direction `sun` and, as from orbit, by nothing but the night air's glow
/// on its night side.
pub(crate) fn gaea_from_orbit(seed: u64, sun: DVec3) -> PlanetParams {
    let mut p = PlanetParams::gaea();
    if let SurfaceParams::Terrain(t) = &mut p.surface {
        t.terran.seed = seed;
    }
    if let Some(c) = &mut p.clouds {
        c.clouds.seed = seed;
    }
    p.light.ambient = 0.0;
    p.light.sun = sun;
    p
}

/// The two plates, the umbra model's first.
pub(crate) fn pair(seed: u64, quick: bool) -> R<Vec<Image>> {
    let (w, h) = if quick { (200, 150) } else { (800, 600) };
    // The eye over latitude 0.3 rad, longitude 0; the sun 90° round.
    let (lat, lon) = (0.3, 0.0);
    [false, true]
        .into_iter()
        .map(|shaded| {
            let mut p = gaea_from_orbit(seed, direction(0.0, lon + std::f64::consts::FRAC_PI_2));
            if let Some(a) = &mut p.atmosphere {
                a.lambert_haze = shaded;
            }
            let planet = Planet::new(p)?;
            let view = planet.orbit_view(1.55e7, lat, lon, 0.62, w, h)?;
            Ok(planet.render(&view, &TraceSettings::default(), &NoProgress)?)
        })
        .collect()
}
