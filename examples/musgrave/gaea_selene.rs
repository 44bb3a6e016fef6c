//! Plates 4.3 and 4.4 of `figures_musgrave`, "Gaea & Selene": an
//! Earth-like planet in its radial atmosphere with its moon behind it, the
//! planet's limb occulting part of the moon, and a close-up of the
//! occultation, where the moon's pale grey is seen through the planet's air
//! and turns orange (extinction) while the air against black space is blue
//! (scattering). natura-texture's Gaea and Selene, each lit by the same
//! sun; the moon is what the planet's rays that miss it see behind its
//! atmosphere (`Planet::radiance_over`). The source's star field is left
//! out.

use natura::core::Image;
use natura::core::glam::DVec3;
use natura::texture::View;
use natura::texture::planet::{Planet, PlanetParams, SurfaceParams, TraceSettings, direction};

use crate::common::Exit;
use crate::landscape::supersampled;
use crate::umbra::gaea_from_orbit;

type R<T> = Result<T, Exit>;

/// The whole scene (Pl. 4.3) and the close-up of the occultation (Pl. 4.4).
pub(crate) fn pair(seed: u64, quick: bool) -> R<Vec<Image>> {
    let (w, h) = if quick { (240, 160) } else { (960, 640) };
    let sun = direction(0.35, 1.55);
    let gaea = Planet::new(gaea_from_orbit(seed, sun))?;
    let mut m = PlanetParams::selene();
    if let SurfaceParams::Luna(l) = &mut m.surface {
        l.seed = seed;
    }
    m.light.sun = sun;
    let selene = Planet::new(m)?;

    let view = gaea.orbit_view(1.8e7, 0.3, 0.35, 0.7, w, h)?;
    let eye = view.eye();
    // The moon 3·10⁷ m beyond the planet's centre, seen just past its
    // upper-right limb, so the limb crosses the moon's disc.
    let forward = -eye.normalize();
    let right = forward.cross(DVec3::Z).normalize();
    let up = right.cross(forward);
    let beyond = eye.length() + 3.0e7;
    let limb = (gaea.radius() / eye.length()).asin();
    let moon_angle = (selene.radius() / beyond).asin();
    let a = limb + 0.2 * moon_angle;
    let side = (right * 0.75 + up * 0.66).normalize();
    let moon = eye + (forward * a.cos() + side * a.sin()) * beyond;
    let settings = TraceSettings::default();
    let look = |view: &View, ss: usize| {
        let alpha = view.pixel_angle() / ss as f64;
        supersampled(view.width(), view.height(), ss, |px, py| {
            let d = view.direction(f64::from(px), f64::from(py));
            let behind = |d: DVec3| selene.radiance(eye - moon, d, alpha, &settings);
            gaea.radiance_over(eye, d, alpha, &settings, &behind)
                .as_vec3()
        })
    };
    let whole = look(&view, 1)?;
    // The close-up: the moon's centre, at a field a third of its disc's.
    let detail = View::look_at(eye, moon, DVec3::Z, 3.0 * moon_angle, w, h)?;
    let close = look(&detail, if quick { 1 } else { 2 })?;
    Ok(vec![whole, close])
}
