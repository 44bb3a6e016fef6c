//! A planet refuses what it cannot render, naming what the user set:
//! tolerances finer than the scene resolves, step counts without bound, an
//! eye inside the planet, a sun of infinite brightness, scales whose
//! detail octaves run out of range, views of absurd altitude.

use glam::DVec3;
use natura_core::NoProgress;
use natura_texture::TextureError;
use natura_texture::planet::{
    GroundViewParams, MAX_TRACE_STEPS, Planet, PlanetDetailParams, PlanetParams, SurfaceParams,
    TraceSettings,
};
use natura_texture::view::View;

fn gaea_with(edit: impl FnOnce(&mut PlanetParams)) -> Result<Planet, TextureError> {
    let mut p = PlanetParams::gaea();
    edit(&mut p);
    Planet::new(p)
}

fn terrain(p: &mut PlanetParams) -> &mut natura_texture::planet::TerrainParams {
    match &mut p.surface {
        SurfaceParams::Terrain(t) => t,
        _ => unreachable!("gaea has terrain"),
    }
}

fn named<T: std::fmt::Debug>(r: Result<T, TextureError>, field: &str) -> String {
    match r {
        Err(e @ TextureError::InvalidParameter { name, .. }) => {
            assert_eq!(name, field, "{e}");
            e.to_string()
        }
        other => panic!("expected a refusal naming `{field}`, got {other:?}"),
    }
}

#[test]
fn trace_settings_that_cannot_finish_are_refused() {
    let planet = gaea_with(|_| ()).unwrap();
    let view = planet.orbit_view(1.55e7, 0.35, 0.25, 0.62, 8, 6).unwrap();
    let endless = TraceSettings {
        epsilon: 0.0,
        min_epsilon_m: 1e-300,
        max_steps: u32::MAX,
        supersample: 2,
    };
    let msg = named(planet.render(&view, &endless, &NoProgress), "max_steps");
    assert!(msg.contains("1048576"), "{msg}");
    // Within the step bound, a tolerance finer than f64 resolves at this
    // distance from the centre could never be met.
    let fine = TraceSettings {
        max_steps: MAX_TRACE_STEPS,
        ..endless
    };
    let msg = named(planet.render(&view, &fine, &NoProgress), "min_epsilon_m");
    assert!(msg.contains("1e-300") && msg.contains("2⁻⁴⁶"), "{msg}");
    // No rays a pixel, or more than the preview's bound, are refused.
    for supersample in [0, 17] {
        let bad = TraceSettings {
            supersample,
            ..TraceSettings::default()
        };
        named(planet.render(&view, &bad, &NoProgress), "supersample");
    }
    // The defaults render, and no ray takes more steps than it is allowed.
    assert!(
        planet
            .render(&view, &TraceSettings::default(), &NoProgress)
            .is_ok()
    );
    let s = TraceSettings {
        max_steps: 16,
        ..TraceSettings::default()
    };
    let eye = view.eye();
    let mut hits = 0;
    for y in 0..view.height() {
        for x in 0..view.width() {
            if let Some(h) = planet.trace(eye, view.pixel(x, y), view.pixel_angle(), &s) {
                assert!(h.steps <= s.max_steps, "{} steps", h.steps);
                hits += 1;
            }
        }
    }
    assert!(hits > 0);
}

#[test]
fn an_eye_inside_the_planet_is_refused() {
    let planet = gaea_with(|_| ()).unwrap();
    let r = planet.radius();
    for eye in [
        DVec3::ZERO,
        DVec3::new(0.0, 0.5 * r, 0.0),
        DVec3::new(r - 1.0, 0.0, 0.0),
    ] {
        let view = View::look_at(eye, eye + DVec3::X, DVec3::Z, 0.8, 4, 4).unwrap();
        let msg = named(
            planet.render(&view, &TraceSettings::default(), &NoProgress),
            "eye",
        );
        assert!(msg.contains("above the planet's surface"), "{msg}");
    }
    // A smooth planet too.
    let venus = Planet::new(PlanetParams::venus()).unwrap();
    let view = View::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 0.8, 4, 4).unwrap();
    named(
        venus.render(&view, &TraceSettings::default(), &NoProgress),
        "eye",
    );
}

#[test]
fn planet_parameters_are_refused_by_the_name_the_user_set() {
    named(
        gaea_with(|p| p.light.sun_colour = DVec3::splat(1e300)),
        "sun_colour",
    );
    named(
        gaea_with(|p| terrain(p).texture_scale = 1e-300),
        "texture_scale",
    );
    named(gaea_with(|p| terrain(p).relief_m = 1e300), "relief_m");
    let msg = named(
        gaea_with(|p| {
            terrain(p).detail = Some(PlanetDetailParams {
                finest_m: 1e-300,
                ..PlanetDetailParams::default()
            });
        }),
        "detail.finest_m",
    );
    assert!(msg.contains("1e-300"), "{msg}");
    // Finite but past the frequency limit: 1 nm cells on Earth.
    named(
        gaea_with(|p| {
            terrain(p).detail = Some(PlanetDetailParams {
                finest_m: 1e-9,
                ..PlanetDetailParams::default()
            });
        }),
        "detail.finest_m",
    );
}

#[test]
fn views_are_refused_by_the_name_the_user_set() {
    let planet = gaea_with(|_| ()).unwrap();
    let msg = named(planet.orbit_view(1e300, 0.3, 0.2, 0.6, 8, 8), "altitude_m");
    assert!(msg.contains("10¹²"), "{msg}");
    named(planet.orbit_view(1e7, f64::NAN, 0.2, 0.6, 8, 8), "latitude");
    named(
        planet.orbit_view(1e7, 0.3, f64::NAN, 0.6, 8, 8),
        "longitude",
    );
    let g = |f: fn(&mut GroundViewParams)| {
        let mut g = GroundViewParams::default();
        f(&mut g);
        planet.ground_view(&g, 8, 8)
    };
    named(g(|g| g.search_radius_m = 1e300), "search_radius_m");
    named(g(|g| g.eye_height_m = 1e300), "eye_height_m");
}
