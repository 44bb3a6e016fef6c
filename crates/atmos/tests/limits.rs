//! Out-of-range input to the sky and the mirage is refused by name: a
//! camera under the planet, a temperature profile outside physical ranges,
//! a tracer allowed to keep unbounded paths.

use glam::DVec3;
use natura_atmos::AtmosError;
use natura_atmos::mirage::{GrinTracer, MAX_GRIN_STEPS, StratifiedAir, TemperatureProfile};
use natura_atmos::sky::{Atmosphere, AtmosphereParams};

fn named<T: std::fmt::Debug>(r: Result<T, AtmosError>, field: &str) -> String {
    match r {
        Err(e @ AtmosError::InvalidParameter { name, .. }) => {
            assert_eq!(name, field, "{e}");
            e.to_string()
        }
        other => panic!("expected a refusal naming `{field}`, got {other:?}"),
    }
}

#[test]
fn a_camera_below_the_planet_is_refused() {
    let atm = Atmosphere::new(AtmosphereParams::default()).unwrap();
    let sun = Atmosphere::sun_at_elevation_deg(20.0).unwrap();
    assert!(atm.sky_view(DVec3::new(0.0, 0.0, 300.0), sun).is_ok());
    // Far below the ground, past the planet's centre: above the ground on
    // the other side, but not a place the local frame describes.
    for z in [-1e9, -2e7, -10.0] {
        let msg = named(atm.sky_view(DVec3::new(0.0, 0.0, z), sun), "camera");
        assert!(msg.contains("below the ground"), "{msg}");
    }
    named(atm.sky_view(DVec3::new(0.0, 0.0, f64::NAN), sun), "camera");
}

fn hot(excess_k: f64, decay_m: f64, lapse_k_per_m: f64) -> TemperatureProfile {
    TemperatureProfile::HotSurface {
        air_k: 293.15,
        excess_k,
        decay_m,
        lapse_k_per_m,
    }
}

#[test]
fn temperature_profiles_are_held_to_physical_ranges() {
    let p = 101_325.0;
    assert!(StratifiedAir::new(hot(40.0, 0.3, 0.0065), p).is_ok());
    let msg = named(StratifiedAir::new(hot(1e300, 0.3, 0.0065), p), "excess_k");
    assert!(msg.contains("1e300") || msg.contains("10⁴"), "{msg}");
    named(StratifiedAir::new(hot(-400.0, 0.3, 0.0065), p), "excess_k");
    named(StratifiedAir::new(hot(40.0, 1e-300, 0.0065), p), "decay_m");
    named(
        StratifiedAir::new(hot(40.0, 0.3, 1e300), p),
        "lapse_k_per_m",
    );
    named(
        StratifiedAir::new(hot(40.0, 0.3, 0.0065), 1e300),
        "pressure_pa",
    );
    let inv = |ground_k, jump_k, thickness_m| TemperatureProfile::Inversion {
        ground_k,
        jump_k,
        height_m: 20.0,
        thickness_m,
        lapse_k_per_m: 0.0065,
    };
    named(StratifiedAir::new(inv(1e300, 10.0, 4.0), p), "ground_k");
    named(StratifiedAir::new(inv(273.15, 1e300, 4.0), p), "jump_k");
    named(
        StratifiedAir::new(inv(273.15, 10.0, 1e-300), p),
        "thickness_m",
    );
}

#[test]
fn the_tracer_refuses_an_unbounded_step_count() {
    let t = GrinTracer {
        max_steps: usize::MAX,
        ..GrinTracer::default()
    };
    let msg = named(t.validate(), "max_steps");
    assert!(msg.contains("10⁷"), "{msg}");
    let t = GrinTracer {
        max_steps: MAX_GRIN_STEPS,
        ..GrinTracer::default()
    };
    assert!(t.validate().is_ok());
}
