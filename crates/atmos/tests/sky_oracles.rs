//! natura-atmos: the pieces natura-render will compose
//! (sky, sunlight, aerial perspective, rainbow) agree with each other.

use glam::{DVec3, Vec3};
use natura_atmos::Dir3;
use natura_atmos::medium::Medium;
use natura_atmos::rainbow::{Rainbow, RainbowParams};
use natura_atmos::sky::{Atmosphere, AtmosphereParams, Ground, LutSettings, SkyProjection};

fn small() -> AtmosphereParams {
    AtmosphereParams {
        lut: LutSettings {
            transmittance: (128, 32),
            sky_view: (96, 54),
            aerial: (16, 32, 16),
            ..LutSettings::default()
        },
        ..AtmosphereParams::default()
    }
}

#[test]
fn lut_aerial_perspective_agrees_with_the_medium_trait() {
    let atm = Atmosphere::new(small()).unwrap();
    let sun = Dir3::from_angles(0.4, 1.0).unwrap();
    let cam = DVec3::new(0.0, 0.0, 400.0);
    let view = atm.sky_view(cam, sun).unwrap();
    let medium = atm.sunlit(sun);
    for (el, az, d) in [(-0.02, 0.3, 12_000.0), (0.01, 2.5, 40_000.0)] {
        let dir = Dir3::from_angles(el, az).unwrap();
        let lut = view.aerial_perspective(dir, d).unwrap();
        let m = medium.attenuation(cam, cam + dir.get() * d);
        assert!(
            (lut.transmittance.as_dvec3() - m.transmittance)
                .abs()
                .max_element()
                < 0.01
        );
        assert!(
            ((lut.in_scatter.as_dvec3() - m.in_scatter).abs() / m.in_scatter).max_element() < 0.06
        );
    }
}

#[test]
fn rendered_sky_is_deterministic_across_thread_counts() {
    let atm = Atmosphere::new(small()).unwrap();
    let view = atm
        .sky_view(
            DVec3::new(0.0, 0.0, 200.0),
            Dir3::from_angles(0.05, 0.0).unwrap(),
        )
        .unwrap();
    let proj = SkyProjection::Pinhole {
        fov_y: 1.0,
        yaw: 0.3,
        pitch: 0.0,
    };
    let ground = Some(Ground {
        albedo: Vec3::splat(0.2),
    });
    let render = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| view.render(proj, 64, 40, ground, true).unwrap())
    };
    let (a, b) = (render(1), render(2));
    let bits = |i: &natura_core::Image| -> Vec<u32> {
        i.pixels()
            .as_slice()
            .iter()
            .flat_map(|c| c.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(bits(&a), bits(&b));
    assert!(a.first_non_finite().is_none());
}

#[test]
fn rainbow_under_the_physical_sun() {
    let atm = Atmosphere::new(small()).unwrap();
    let sun = Dir3::from_angles(0.2, std::f64::consts::PI).unwrap();
    let e = atm.sun_irradiance(DVec3::new(0.0, 0.0, 2.0), sun).unwrap();
    let bow = Rainbow::new(&RainbowParams {
        rays_per_wavelength: 3000,
        ..RainbowParams::default()
    })
    .unwrap();
    let anti = sun.reversed().get();
    let side = anti.cross(DVec3::Z).normalize();
    let at = |deg: f64| {
        let a = deg.to_radians();
        Dir3::new(anti * a.cos() + side * a.sin()).unwrap()
    };
    let l_bow = bow.radiance(at(41.8), sun, e, 3e-4, 1500.0).unwrap();
    let l_band = bow.radiance(at(46.0), sun, e, 3e-4, 1500.0).unwrap();
    let l_in = bow.radiance(at(35.0), sun, e, 3e-4, 1500.0).unwrap();
    assert!(l_bow.y > l_in.y && l_in.y > l_band.y && l_band.y >= 0.0);
}
