//! Sky tests: LUT model against the ray-marched reference, colours of noon
//! and sunset, physical sanity, determinism and bad input.

use glam::DVec3;

use super::*;

fn atm(ms: bool, eval: Evaluation) -> Atmosphere {
    let p = AtmosphereParams {
        multiple_scattering: ms,
        evaluation: eval,
        ..AtmosphereParams::default()
    };
    Atmosphere::new(p).unwrap()
}

const CAM: DVec3 = DVec3::new(0.0, 0.0, 500.0);

fn dir(elev_deg: f64, az_deg: f64) -> Dir3 {
    Dir3::from_angles(elev_deg.to_radians(), az_deg.to_radians())
}

/// The oracle: with multiple scattering off, the LUT sky equals the
/// ray-marched single-scattering sky (Nishita 1993) within 4% (luminance-weighted).
#[test]
fn lut_sky_matches_ray_marched_single_scattering() {
    let a = atm(false, Evaluation::Rgb);
    let settings = MarchSettings {
        view_steps: 256,
        light_steps: 64,
    };
    let mut worst: f64 = 0.0;
    for sun_el in [2.0, 10.0, 35.0, 80.0] {
        let sun = dir(sun_el, 0.0);
        let view = a.sky_view(CAM, sun).unwrap();
        for el in [3.0, 10.0, 30.0, 60.0, 89.0] {
            for az in [0.0, 40.0, 90.0, 150.0, 180.0] {
                let d = dir(el, az);
                let lut = view.radiance(d).as_dvec3();
                let reference = a.sky_radiance_marched(CAM, d, sun, settings).unwrap();
                let err = (lut - reference).abs() / reference.max(DVec3::splat(1e-12));
                worst = worst.max(err.max_element());
                assert!(
                    err.max_element() < 0.04,
                    "sun {sun_el}° view ({el}°, {az}°): {lut} vs {reference}"
                );
            }
        }
    }
    assert!(worst > 0.0);
}

#[test]
fn zenith_bluer_than_horizon_at_noon_and_horizon_redder_at_sunset() {
    for eval in [Evaluation::Rgb, Evaluation::Spectral] {
        let a = atm(true, eval);
        let noon = a.sky_view(CAM, dir(70.0, 0.0)).unwrap();
        let zen = noon.radiance(Dir3::UP);
        let hor = noon.radiance(dir(1.0, 90.0));
        let blue = |c: glam::Vec3| c.z / (c.x + c.y + c.z);
        let red = |c: glam::Vec3| c.x / (c.x + c.y + c.z);
        assert!(zen.z > zen.y && zen.y > zen.x, "{eval:?} zenith {zen}");
        assert!(
            blue(zen) > blue(hor),
            "{eval:?}: zenith {zen} horizon {hor}"
        );
        let sunset = a.sky_view(CAM, dir(1.0, 0.0)).unwrap();
        let hs = sunset.radiance(dir(2.0, 0.0));
        let zs = sunset.radiance(Dir3::UP);
        assert!(
            red(hs) > red(zs),
            "{eval:?}: sunset horizon {hs} zenith {zs}"
        );
        // Sunlight is reddened at sunset, white-ish at noon.
        let t_noon = a.sun_transmittance(CAM, dir(70.0, 0.0)).unwrap();
        let t_set = a.sun_transmittance(CAM, dir(1.0, 0.0)).unwrap();
        assert!(
            t_set.x > t_set.y && t_set.y > t_set.z && t_set.z < 0.3 * t_noon.z,
            "{t_set}"
        );
        // Twilight: the sun 4° below the horizon still lights the sky, dimly.
        let tw = a.sky_view(CAM, dir(-4.0, 0.0)).unwrap();
        let z = tw.radiance(Dir3::UP);
        assert!(
            z.max_element() > 0.0 && z.max_element() < 0.1 * zs.max_element(),
            "{z} vs {zs}"
        );
        assert_eq!(
            a.sun_transmittance(CAM, dir(-4.0, 0.0)).unwrap(),
            DVec3::ZERO
        );
    }
}

#[test]
fn multiple_scattering_brightens_and_blues_the_low_sun_sky() {
    let single = atm(false, Evaluation::Rgb);
    let multi = atm(true, Evaluation::Rgb);
    let sun = dir(3.0, 0.0);
    let s = single.sky_view(CAM, sun).unwrap().radiance(Dir3::UP);
    let m = multi.sky_view(CAM, sun).unwrap().radiance(Dir3::UP);
    assert!(m.z > s.z && m.x > s.x, "{s} vs {m}");
}

#[test]
fn aerial_perspective_volume_matches_marching() {
    let a = atm(true, Evaluation::Rgb);
    let sun = dir(25.0, 30.0);
    let view = a.sky_view(CAM, sun).unwrap();
    for (el, az, d) in [
        (-1.0, 10.0, 5_000.0),
        (0.5, 100.0, 30_000.0),
        (-0.3, 200.0, 60_000.0),
        (5.0, 0.0, 1_000.0),
    ] {
        let v = dir(el, az);
        let lut = view.aerial_perspective(v, d).unwrap();
        let ex = a
            .aerial_perspective_marched(CAM, CAM + v.get() * d, sun, 512)
            .unwrap();
        let et = (lut.transmittance.as_dvec3() - ex.transmittance)
            .abs()
            .max_element();
        let el_ = ((lut.in_scatter.as_dvec3() - ex.in_scatter).abs() / ex.in_scatter).max_element();
        assert!(
            et < 0.01,
            "T ({el},{az},{d}): {} vs {}",
            lut.transmittance,
            ex.transmittance
        );
        assert!(
            el_ < 0.05,
            "S ({el},{az},{d}): {} vs {}",
            lut.in_scatter,
            ex.in_scatter
        );
    }
    // Zero distance: nothing; beyond the volume: exact fallback, still bounded.
    let z = view.aerial_perspective(dir(0.0, 0.0), 0.0).unwrap();
    assert_eq!(z.transmittance, glam::Vec3::ONE);
    assert_eq!(z.in_scatter, glam::Vec3::ZERO);
    let far = view.aerial_perspective(dir(0.2, 0.0), 150_000.0).unwrap();
    assert!(far.transmittance.max_element() < 1.0 && far.transmittance.min_element() >= 0.0);
    assert!(view.aerial_perspective(dir(0.0, 0.0), -1.0).is_err());
    assert!(view.aerial_perspective(dir(0.0, 0.0), f64::NAN).is_err());
    // Transmittance falls and in-scatter grows with distance.
    let mut last = glam::Vec3::ONE;
    for k in 0..40 {
        let s = view
            .aerial_perspective(dir(0.3, 70.0), k as f64 * 1500.0)
            .unwrap();
        assert!(s.transmittance.cmple(last + glam::Vec3::splat(1e-6)).all());
        last = s.transmittance;
    }
}

#[test]
fn lambertian_ground_and_sky_are_consistent() {
    // The sun disc integrates to the irradiance; the ground's radiance under it is E·cosθ·ρ/π.
    let a = atm(true, Evaluation::Rgb);
    let sun = dir(40.0, 0.0);
    let e = a.sun_irradiance(CAM, sun).unwrap();
    let ts = a.params().sun_angular_radius;
    let (n, mut acc) = (200, DVec3::ZERO);
    let sun_v = sun.get();
    let t1 = sun_v.cross(DVec3::Z).normalize();
    let t2 = sun_v.cross(t1);
    for i in 0..n {
        let th = (i as f64 + 0.5) / n as f64 * ts;
        for k in 0..64 {
            let ph = (k as f64 + 0.5) / 64.0 * std::f64::consts::TAU;
            let d =
                Dir3::new(sun_v * th.cos() + (t1 * ph.cos() + t2 * ph.sin()) * th.sin()).unwrap();
            acc += a.sun_radiance(CAM, d, sun).unwrap()
                * th.sin()
                * (ts / n as f64)
                * (std::f64::consts::TAU / 64.0);
        }
    }
    assert!(((acc - e).abs() / e).max_element() < 0.01, "{acc} vs {e}");
    // Limb darkening: the centre is brighter than near the edge, bluer channels darken more.
    let centre = a.sun_radiance(CAM, sun, sun).unwrap();
    let edge_d = Dir3::new(sun_v * (0.95 * ts).cos() + t1 * (0.95 * ts).sin()).unwrap();
    let edge = a.sun_radiance(CAM, edge_d, sun).unwrap();
    assert!(edge.x < centre.x && edge.z / centre.z < edge.x / centre.x);
    assert_eq!(
        a.sun_radiance(CAM, dir(40.0, 5.0), sun).unwrap(),
        DVec3::ZERO
    );
    // Sky irradiance on the ground is a sensible fraction of the sun's.
    let view = a.sky_view(CAM, sun).unwrap();
    let sky_e = view.sky_irradiance().as_dvec3();
    let sun_e = e * 40f64.to_radians().sin();
    let ratio = sky_e.y / sun_e.y;
    assert!(ratio > 0.05 && ratio < 0.5, "{ratio}");
    assert!(
        sky_e.z / sun_e.z > sky_e.x / sun_e.x,
        "skylight is bluer than sunlight"
    );
}

#[test]
fn sunlit_atmosphere_is_a_medium() {
    let a = atm(true, Evaluation::Rgb);
    let m = a.sunlit(dir(30.0, 0.0));
    let p0 = DVec3::new(0.0, 0.0, 100.0);
    let p1 = DVec3::new(20_000.0, 0.0, 100.0);
    let p2 = DVec3::new(40_000.0, 0.0, 100.0);
    let t01 = m.transmittance(p0, p1);
    let t12 = m.transmittance(p1, p2);
    let t02 = m.transmittance(p0, p2);
    assert!(t02.min_element() > 0.0 && t02.max_element() < 1.0);
    // Not collinear in planet space (curvature), so only approximately multiplicative.
    assert!(
        ((t01 * t12) - t02).abs().max_element() < 2e-3,
        "{} vs {t02}",
        t01 * t12
    );
    let up = m.optical_depth_to_infinity(p0, Dir3::UP);
    let side = m.optical_depth_to_infinity(p0, Dir3::X);
    assert!(side.z > 10.0 * up.z && up.z > 0.0 && up.is_finite());
    let att = m.attenuation(p0, p1);
    assert!((att.transmittance - t01).abs().max_element() < 1e-3);
    assert!(att.in_scatter.min_element() > 0.0);
}

#[test]
fn spectral_and_rgb_models_agree_roughly() {
    let rgb = atm(true, Evaluation::Rgb);
    let spe = atm(true, Evaluation::Spectral);
    assert_eq!(spe.wavelengths().len(), SPECTRAL_BANDS);
    let sun = dir(45.0, 0.0);
    let a = rgb.sky_view(CAM, sun).unwrap().radiance(dir(45.0, 180.0));
    let b = spe.sky_view(CAM, sun).unwrap().radiance(dir(45.0, 180.0));
    let la = natura_core::colour::luminance(a);
    let lb = natura_core::colour::luminance(b);
    assert!((la / lb - 1.0).abs() < 0.3, "{a} vs {b}");
}

#[test]
fn deterministic_across_thread_counts() {
    let build = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let a = atm(true, Evaluation::Rgb);
            let v = a.sky_view(CAM, dir(12.0, 0.0)).unwrap();
            let mut out = Vec::new();
            for k in 0..50 {
                let d = dir(-5.0 + k as f64 * 1.9, k as f64 * 7.0);
                out.push(v.radiance(d).to_array().map(f32::to_bits));
                out.push(
                    v.aerial_perspective(d, 1000.0 * k as f64)
                        .unwrap()
                        .in_scatter
                        .to_array()
                        .map(f32::to_bits),
                );
            }
            out
        })
    };
    assert_eq!(build(1), build(2));
}

#[test]
fn bad_input_is_refused() {
    let d = AtmosphereParams::default();
    let bad = [
        AtmosphereParams {
            top_radius_m: d.bottom_radius_m,
            ..d
        },
        AtmosphereParams {
            rayleigh: RayleighParams {
                scale_height_m: -1.0,
                ..d.rayleigh
            },
            ..d
        },
        AtmosphereParams {
            mie: MieParams {
                g: f64::NAN,
                ..d.mie
            },
            ..d
        },
        AtmosphereParams {
            lut: LutSettings {
                sky_view: (0, 10),
                ..d.lut
            },
            ..d
        },
        AtmosphereParams {
            ground_albedo: 1.5,
            ..d
        },
    ];
    for p in bad {
        assert!(Atmosphere::new(p).is_err(), "{p:?}");
    }
    let a = atm(false, Evaluation::Rgb);
    assert!(a.sky_view(DVec3::new(0.0, 0.0, -100.0), Dir3::UP).is_err());
    assert!(
        a.sky_view(DVec3::new(f64::NAN, 0.0, 10.0), Dir3::UP)
            .is_err()
    );
    let bad = MarchSettings {
        view_steps: 0,
        light_steps: 1,
    };
    assert!(
        a.sky_radiance_marched(CAM, Dir3::UP, Dir3::UP, bad)
            .is_err()
    );
}
