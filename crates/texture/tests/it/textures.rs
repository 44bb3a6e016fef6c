//! Every texture: finite and in gamut for every valid parameter set
//! (proptest), deterministic, bit-identical on 1 and 2 threads.

use crate::common;

use common::{Rng, all_textures, pool};
use glam::DVec3;
use natura_core::NoProgress;
use natura_texture::air::*;
use natura_texture::earth::*;
use natura_texture::fire::*;
use natura_texture::giants::*;
use natura_texture::multicolor::*;
use natura_texture::water::*;
use natura_texture::{Footprint, SolidTexture, preview};
use proptest::prelude::*;

/// Samples `t` at points spread over `[−r, r]³` and on the unit sphere, with
/// point and wide footprints, and asserts every sample is valid.
fn check(t: &dyn SolidTexture, seed: u64, r: f64) -> Result<(), TestCaseError> {
    let mut rng = Rng(seed);
    for i in 0..24 {
        let p = if i % 2 == 0 { rng.p3(r) } else { rng.unit() };
        let fp = match i % 4 {
            0 => Footprint::POINT,
            1 => Footprint::new(10f64.powf(rng.range(-6.0, 1.0))).unwrap(),
            2 => Footprint::new(1e-3).unwrap(),
            _ => Footprint::new(rng.range(0.0, 3.0)).unwrap(),
        };
        let s = t.sample(p, fp);
        prop_assert!(s.is_valid(), "{} at {p} fp {:?}: {s:?}", t.name(), fp);
        let g = t.height_gradient(p, fp);
        prop_assert!(g.is_finite(), "{} gradient at {p}: {g}", t.name());
    }
    Ok(())
}

fn colour() -> impl Strategy<Value = DVec3> {
    (0.0..=1.0f64, 0.0..=1.0f64, 0.0..=1.0f64).prop_map(|(a, b, c)| DVec3::new(a, b, c))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn puffy_valid(seed in any::<u64>(), txt in 0.01..10.0f64, sky in colour(), cloud in colour(),
                   oct in 1.0..12.0f64, h in -0.5..2.0f64, lac in 1.5..3.0f64, thr in -2.0..0.99f64) {
        let t = PuffyClouds::new(PuffyCloudsParams {
            seed, txtscale: txt, skycolor: sky, cloudcolor: cloud, octaves: oct, h, lacunarity: lac, threshold: thr,
        }).unwrap();
        check(&t, seed, 5.0)?;
    }

    #[test]
    fn planet_clouds_valid(seed in any::<u64>(), dist in 0.0..3.0f64, rescale in 0.1..5.0f64, vl in any::<bool>(),
                           fbm_field in any::<bool>(), h in 0.0..1.5f64, lac in 1.7..2.5f64, oct in 1.0..10.0f64,
                           offset in -0.9..2.0f64) {
        let t = PlanetClouds::new(PlanetCloudsParams {
            seed, distortion: dist, rescale,
            basis: if vl { CloudBasis::VariableLacunarity } else { CloudBasis::Perlin },
            distortion_field: if fbm_field { CloudDistortion::Fbm } else { CloudDistortion::Noise },
            h, lacunarity: lac, octaves: oct, offset,
        }).unwrap();
        check(&t, seed, 3.0)?;
    }

    #[test]
    fn cyclone_valid(seed in any::<u64>(), rad in 0.1..2.0f64, twist in -2.0..2.0f64, scale in -2.0..2.0f64,
                     offset in -2.0..2.0f64, h in 0.0..1.5f64, oct in 1.0..8.0f64, lac in 1.7..2.5f64,
                     dist in 0.0..2.0f64, pow in 1.0..4.0f64, eye in 0.01..1.0f64, eye_pow in 0.0..8.0f64) {
        let t = Cyclone::new(CycloneParams {
            seed, max_radius: rad, twist, scale, offset, h, octaves: oct, lacunarity: lac, distortion: dist,
            radial_power: pow, eye_radius: eye, eye_power: eye_pow,
        }).unwrap();
        check(&t, seed, 3.0)?;
    }

    #[test]
    fn venus_valid(seed in any::<u64>(), offset in -2.0..2.0f64, scale in -2.0..2.0f64, twist in -2.0..2.0f64,
                   h in 0.0..1.5f64, oct in 1.0..10.0f64, lac in 1.7..2.5f64, dist in 0.0..2.0f64, c in colour()) {
        let t = Venus::new(VenusParams {
            seed, offset, scale, twist, h, octaves: oct, lacunarity: lac, distortion: dist, colour: c,
        }).unwrap();
        check(&t, seed, 3.0)?;
    }

    #[test]
    fn flame_valid(seed in any::<u64>(), dist in 0.0..2.0f64, cs in -3.0..3.0f64, co in -2.0..2.0f64,
                   oct in 1.0..10.0f64, fh in -3.0..3.0f64, fa in -2.0..2.0f64, ridged in any::<bool>()) {
        let t = Flame::new(FlameParams {
            seed, distortion: dist, chaosscale: cs, chaosoffset: co, octaves: oct, flameheight: fh,
            flameamplitude: fa, basis: if ridged { FlameBasis::Ridged } else { FlameBasis::AbsOfSum },
        }).unwrap();
        check(&t, seed, 800.0)?;
    }

    #[test]
    fn water_valid(seed in any::<u64>(), km in -3.0..3.0f64, oct in 1.0..6.0f64, h in -1.0..4.0f64,
                   lac in 1.7..3.0f64, sx in 0.1..10.0f64, sy in 0.1..10.0f64,
                   wkm in -1.0..1.0f64, txt in 0.1..5.0f64, wf in 0.1..5.0f64, wa in 0.0..3.0f64,
                   mw in 0.0..2.0f64, ratio in 1.0..16.0f64) {
        let r = Ripples::new(RipplesParams { seed, km, octaves: oct, h, lacunarity: lac, scale: DVec3::new(sx, sy, 1.0) }).unwrap();
        check(&r, seed, 5.0)?;
        let w = WindyWave::new(WindyWaveParams {
            seed, km: wkm, txtscale: txt, windfreq: wf, windamp: wa, minwind: mw, ripple_ratio: ratio,
        }).unwrap();
        check(&w, seed, 5.0)?;
    }

    #[test]
    fn strata_valid(seed in any::<u64>(), txt in 0.1..5.0f64, z in -5.0..5.0f64, turb in -1.0..1.0f64,
                    offset in -2.0..2.0f64, oct in 1.0..10.0f64) {
        let t = Strata::new(StrataParams { seed, txtscale: txt, zscale: z, turbscale: turb, offset, octaves: oct }).unwrap();
        check(&t, seed, 5.0)?;
    }

    #[test]
    fn terran_valid(seed in any::<u64>(), mf in any::<bool>(), h in 0.0..1.2f64, lac in 1.7..2.5f64,
                    oct in 1.0..9.0f64, omega in 0.3..1.0f64, dist in 0.0..1.0f64, bump in -0.2..0.2f64,
                    offset in -1.0..1.0f64, sea in -1.0..1.0f64, mtn in 0.0..2.0f64, lat in 0.0..2.0f64,
                    nonlin in -3.0..3.0f64, pert in -2.0..2.0f64, mexp in 0.0..5.0f64, ice in -1.0..1.5f64,
                    depth in -30.0..30.0f64, dmax in 0.0..2.0f64, mlim in 0.0..1.0f64, mscale in 1.0..50.0f64,
                    mdim in 0.0..1.0f64, mmag in -0.1..0.1f64, ocean in colour(), icec in colour()) {
        let mut params = TerranParams {
            seed,
            continents: if mf { Continents::VectorMultifractal } else { Continents::Fbm },
            dist_scale: dist, bump_scale: bump, offset, sea_level: sea, mtn_scale: mtn, lat_scale: lat,
            nonlinear: nonlin, pert_scale: pert, map_exp: mexp, ice_caps: ice, depth_scale: depth,
            depth_max: dmax, mottle_limit: mlim, mottle_scale: mscale, mottle_dim: mdim, mottle_mag: mmag,
            ocean_colour: ocean, ice_colour: icec,
            ..TerranParams::default()
        };
        params.spectral.h = h;
        params.spectral.lacunarity = lac;
        params.spectral.octaves = oct;
        params.multifractal.spectral.h = omega;
        params.multifractal.spectral.octaves = oct;
        let t = Terran::new(params).unwrap();
        check(&t, seed, 2.0)?;
    }

    #[test]
    fn luna_valid(seed in any::<u64>(), h in 0.0..1.2f64, oct in 1.0..9.0f64, lac in 1.7..2.5f64, c in colour(),
                  hc in colour(), mb in -1.0..1.0f64, mc in -1.0..1.0f64, thr in -1.0..1.0f64,
                  ha in -0.05..0.05f64, ma in -0.05..0.05f64, peak in 0.001..0.01f64, d1 in 0.0..0.01f64,
                  d2 in 0.001..0.02f64, d3 in 0.001..0.1f64, ph in -0.01..0.01f64, rh in -0.01..0.01f64) {
        let t = Luna::new(LunaParams {
            seed, lacunarity: lac, octaves: oct, h, colour: c, highland_color: hc, maria_basecolor: mb,
            maria_color: mc, highland_threshold: thr, highland_altitude: ha, maria_altitude: ma,
            peak_rad: peak, inner_rad: peak + d1, rim_rad: peak + d1 + d2, outer_rad: peak + d1 + d2 + d3,
            peak_ht: ph, rim_ht: rh,
        }).unwrap();
        check(&t, seed, 1.5)?;
    }

    #[test]
    fn giants_valid(seed in any::<u64>(), bands in -5.0..5.0f64, turb in -1.0..1.0f64, freq in 0.5..10.0f64,
                    h in 0.0..1.2f64, oct in 1.0..9.0f64, dist in 0.0..2.0f64, zonal in 0.5..5.0f64,
                    saturn in any::<bool>(), inner in 0.5..2.0f64, width in 0.1..2.0f64, fd in 0.0..1.2f64,
                    ds in -2.0..2.0f64, off in -1.0..1.0f64, ir in 0.0..1.0f64, or in 0.0..1.0f64,
                    ts in 0.5..20.0f64, c in colour()) {
        let g = GasGiant::new(GasGiantParams {
            seed, bands, turbulence: turb, frequency: freq, h, octaves: oct, distortion: dist,
            zonal_stretch: zonal, colours: if saturn { Bands::Saturn } else { Bands::Jupiter },
        }).unwrap();
        check(&g, seed, 2.0)?;
        let r = Rings::new(RingsParams {
            seed, inner_rad: inner, outer_rad: inner + width, f_dim: fd, octaves: oct, density_scale: ds,
            offset: off, inner_rolloff: ir, outer_rolloff: or, text_scale: ts, colour: c,
            ..RingsParams::default()
        }).unwrap();
        check(&r, seed, 4.0)?;
    }

    #[test]
    fn multicolor_and_ridge_valid(seed in any::<u64>(), txt in 0.1..5.0f64, h in 0.3..1.2f64,
                                  oct in 1.0..8.0f64, shift in -1.0..1.0f64, scale in 0.0..2.0f64,
                                  sea in -1.0..1.0f64, period in 0.1..5.0f64, pert in -1.0..1.0f64) {
        let m = Multicolor::new(MulticolorParams { seed, txtscale: txt }).unwrap();
        check(&m, seed, 3.0)?;
        let mut altitude = natura_noise::StatsByAltitudeParams { shift, scale, sea_level: sea, ..Default::default() };
        altitude.spectral.h = h;
        altitude.spectral.octaves = oct;
        let r = Ridge::new(RidgeParams { seed, altitude, axis: DVec3::new(1.0, 0.3, 0.0), period, perturbation: pert }).unwrap();
        check(&r, seed, 3.0)?;
    }
}

#[test]
fn every_texture_is_deterministic() {
    let a = all_textures(11);
    let b = all_textures(11);
    let mut rng = Rng(5);
    for ((name, ta), (_, tb)) in a.iter().zip(&b) {
        for _ in 0..20 {
            let p = rng.p3(2.0);
            let fp = Footprint::new(rng.range(0.0, 0.01)).unwrap();
            let (x, y) = (ta.sample(p, fp), tb.sample(p, fp));
            assert_eq!(
                x.colour.to_array().map(f64::to_bits),
                y.colour.to_array().map(f64::to_bits),
                "{name}"
            );
            assert_eq!(x.opacity.to_bits(), y.opacity.to_bits(), "{name}");
            assert_eq!(x.height.to_bits(), y.height.to_bits(), "{name}");
            // And a repeated call gives the same bits.
            assert_eq!(ta.sample(p, fp), x, "{name}");
        }
    }
    // A different seed gives a different texture.
    let c = all_textures(12);
    for ((name, ta), (_, tc)) in a.iter().zip(&c) {
        let differs = (0..20).any(|i| {
            let p = DVec3::new(0.3 + 0.1 * f64::from(i), 0.7, -0.2 + 0.1 * f64::from(i));
            ta.sample(p, Footprint::POINT) != tc.sample(p, Footprint::POINT)
        });
        assert!(differs, "{name} ignores its seed");
    }
}

#[test]
fn swatches_are_bit_identical_on_one_and_two_threads() {
    for (name, t) in all_textures(3) {
        let one = pool(1).install(|| preview::sphere(t.as_ref(), 24, false, &NoProgress).unwrap());
        let two = pool(2).install(|| preview::sphere(t.as_ref(), 24, false, &NoProgress).unwrap());
        let bits = |i: &natura_core::Image| -> Vec<u32> {
            i.pixels()
                .as_slice()
                .iter()
                .flat_map(|c| c.to_array().map(f32::to_bits))
                .collect()
        };
        assert_eq!(bits(&one), bits(&two), "{name}");
        assert!(one.first_non_finite().is_none(), "{name}");
    }
}

#[test]
fn bad_parameters_are_refused_by_name() {
    let err = |e: natura_texture::TextureError| e.to_string();
    let e = err(PuffyClouds::new(PuffyCloudsParams {
        threshold: 1.0,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("threshold"), "{e}");
    let e = err(PuffyClouds::new(PuffyCloudsParams {
        octaves: 0.0,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("octaves"), "{e}");
    let e = err(PuffyClouds::new(PuffyCloudsParams {
        octaves: 65.0,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("octaves"), "{e}");
    let e = err(PlanetClouds::new(PlanetCloudsParams {
        offset: -1.0,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("offset"), "{e}");
    let e = err(Cyclone::new(CycloneParams {
        max_radius: 0.0,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("max_radius"), "{e}");
    let e = err(Venus::new(VenusParams {
        twist: f64::NAN,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("twist"), "{e}");
    let e = err(Flame::new(FlameParams {
        chaosscale: f64::INFINITY,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("chaosscale"), "{e}");
    let e = err(Ripples::new(RipplesParams {
        scale: DVec3::new(1.0, -1.0, 1.0),
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("scale.y"), "{e}");
    let e = err(Terran::new(TerranParams {
        ocean_colour: DVec3::splat(1.5),
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("ocean_colour"), "{e}");
    let e = err(Luna::new(LunaParams {
        rim_rad: 0.005,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("rim_rad"), "{e}");
    let e = err(Rings::new(RingsParams {
        outer_rad: 1.0,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("outer_rad"), "{e}");
    let e = err(GasGiant::new(GasGiantParams {
        frequency: -1.0,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("frequency"), "{e}");
    let e = err(Multicolor::new(MulticolorParams {
        txtscale: 0.0,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("txtscale"), "{e}");
    let e = err(Ridge::new(RidgeParams {
        axis: DVec3::ZERO,
        ..Default::default()
    })
    .unwrap_err());
    assert!(e.contains("axis"), "{e}");
    assert!(Footprint::new(f64::NAN).is_err());
}

/// The cyclone's clouds spiral on the sphere: round each circle about the
/// storm's axis, the twisted density is the untwisted storm's (`twist = 0`:
/// a half turn everywhere) turned by an angle read off the fields
/// themselves (the lag of best correlation), and that angle, measured from
/// the rim's, grows towards the eye — `π(1 − r)³` under the shader's cubic
/// law. Seen from the side the spiral sits on the limb, so the swatch
/// looks from above the pole ([`preview::sphere_from`]).
#[test]
fn cyclone_spirals_tighter_towards_the_eye() {
    use std::f64::consts::{PI, TAU};
    let twisted = Cyclone::new(CycloneParams::default()).unwrap();
    let straight = Cyclone::new(CycloneParams {
        twist: 0.0,
        ..Default::default()
    })
    .unwrap();
    let n = 1440;
    let profile = |c: &Cyclone, r: f64| -> Vec<f64> {
        let z = (1.0 - r * r).sqrt();
        let v: Vec<f64> = (0..n)
            .map(|k| {
                let phi = TAU * f64::from(k) / f64::from(n);
                c.density(
                    DVec3::new(r * phi.cos(), r * phi.sin(), z),
                    Footprint::POINT,
                )
            })
            .collect();
        let mean = v.iter().sum::<f64>() / f64::from(n);
        v.iter().map(|x| x - mean).collect()
    };
    let mut last = f64::INFINITY;
    for r in [0.15, 0.3, 0.45, 0.6, 0.75, 0.9] {
        let (a, b) = (profile(&twisted, r), profile(&straight, r));
        // twisted(φ) = straight(φ + lag): the lag of best correlation.
        let best = (0..n)
            .max_by(|&i, &j| {
                let c = |s: u32| -> f64 {
                    (0..n)
                        .map(|k| a[k as usize] * b[((k + s) % n) as usize])
                        .sum()
                };
                c(i).total_cmp(&c(j))
            })
            .unwrap();
        let lag = TAU * f64::from(best) / f64::from(n);
        let expected = PI * (1.0 - (1.0 - r).powi(3));
        let miss = (lag - expected + PI).rem_euclid(TAU) - PI;
        assert!(
            miss.abs() < 1f64.to_radians(),
            "r {r}: lag {lag}, law {expected}"
        );
        // Turned from the rim's angle (π) by more the nearer the eye.
        let from_rim = PI - lag;
        assert!(
            from_rim < last && from_rim > 0.0,
            "r {r}: {from_rim} after {last}"
        );
        last = from_rim;
        if r == 0.15 {
            assert!(from_rim > 1.5, "near the eye the clouds turn by {from_rim}");
        }
    }
}

/// The sphere seen from `−y` is [`preview::sphere`]'s picture, bit for
/// bit; from the pole it shows the texture's other face; a zero eye is refused.
#[test]
fn sphere_from_matches_the_default_view() {
    let c = Cyclone::new(CycloneParams::default()).unwrap();
    let side = preview::sphere(&c, 48, false, &NoProgress).unwrap();
    let same = preview::sphere_from(&c, 48, false, DVec3::NEG_Y * 3.0, &NoProgress).unwrap();
    assert_eq!(side.pixels().as_slice(), same.pixels().as_slice());
    let top = preview::sphere_from(&c, 48, false, DVec3::Z, &NoProgress).unwrap();
    assert_ne!(side.pixels().as_slice(), top.pixels().as_slice());
    for bad in [DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 1.0)] {
        assert!(preview::sphere_from(&c, 48, false, bad, &NoProgress).is_err());
    }
}
