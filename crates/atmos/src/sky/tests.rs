//! Sky tests: LUT model against the ray-marched reference, colours of noon
//! and sunset, physical sanity, determinism and bad input.

use glam::{DVec3, Vec3};

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
    Dir3::from_angles(elev_deg.to_radians(), az_deg.to_radians()).unwrap()
}

/// An oracle: with multiple scattering off, the LUT sky equals the
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

mod batch {
    //! The batch (SIMD) paths against the scalar ones, and the fast `acos`.
    use glam::Vec3;

    use super::*;
    use crate::simd::Simd;
    use crate::sky::SkyCamera;
    use crate::sky::batch::{L, fast_acos};

    /// A&S 4.4.46 in `f32` against `f64::acos` on a dense grid (2²¹ + 1 points
    /// and the endpoints): the bound stated on `fast_acos`.
    #[test]
    fn fast_acos_error_bound() {
        let n = 1 << 21;
        let mut worst: f64 = 0.0;
        for k in 0..=n {
            let x = -1.0 + 2.0 * k as f64 / n as f64;
            let xf = x as f32;
            let err = (f64::from(fast_acos(xf)) - f64::from(xf).acos()).abs();
            worst = worst.max(err);
        }
        assert!(worst <= 5e-7, "max |error| {worst:e} rad");
        assert!(worst > 0.0);
        assert_eq!(fast_acos(1.0), 0.0);
        assert!((fast_acos(-1.0) - std::f32::consts::PI).abs() < 1e-6);
        // Out of range inputs clamp instead of giving NaN.
        assert_eq!(fast_acos(1.5), 0.0);
    }

    fn test_dirs(n: usize) -> Vec<Vec3> {
        let mut v: Vec<Vec3> = (0..n)
            .map(|i| {
                let el = -1.5 + 3.0 * ((i * 37) % n) as f64 / n as f64;
                let az = std::f64::consts::TAU * (i as f64 * 0.618_034).fract();
                Dir3::from_angles(el, az).unwrap().as_vec3()
            })
            .collect();
        // Invalid inputs scattered through the chunks, and exact poles.
        v[3] = Vec3::ZERO;
        v[20] = Vec3::new(f32::NAN, 0.0, 1.0);
        v[21] = Vec3::new(0.0, 2.0, 0.0);
        v[40] = Vec3::Z;
        v[41] = Vec3::NEG_Z;
        v[42] = Vec3::new(0.0, 0.0, f32::INFINITY);
        v
    }

    fn bits(v: Vec3) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    /// The batch lookups equal the scalar ones bit for bit, at every SIMD
    /// level this CPU has, for lengths that are not multiples of the chunk.
    #[test]
    fn batch_equals_scalar_bit_for_bit_at_every_simd_level() {
        let a = atm(true, Evaluation::Rgb);
        let v = a.sky_view(CAM, dir(8.0, 30.0)).unwrap();
        let n = 5 * L + 7;
        let dirs = test_dirs(n);
        let dist: Vec<f32> = (0..n)
            .map(|i| match i % 11 {
                0 => f32::NAN,
                1 => -5.0,
                2 => 1e9,
                _ => 70_000.0 * ((i * 13) % n) as f32 / n as f32,
            })
            .collect();
        let mut levels = 0;
        for simd in Simd::supported() {
            levels += 1;
            let mut out = vec![Vec3::splat(-1.0); n];
            v.radiance_batch_with(simd, &dirs, &mut out).unwrap();
            let mut ap = vec![ApSample::NONE; n];
            v.aerial_perspective_batch_with(simd, &dirs, &dist, &mut ap)
                .unwrap();
            for i in 0..n {
                assert_eq!(
                    bits(out[i]),
                    bits(v.radiance_f32(dirs[i])),
                    "{simd:?} radiance {i} {}",
                    dirs[i]
                );
                let s = v.aerial_perspective_f32(dirs[i], dist[i]);
                assert_eq!(bits(ap[i].in_scatter), bits(s.in_scatter), "{simd:?} {i}");
                assert_eq!(
                    bits(ap[i].transmittance),
                    bits(s.transmittance),
                    "{simd:?} {i}"
                );
            }
            assert_eq!(out[3], Vec3::ZERO);
            assert_eq!(ap[20], ApSample::NONE);
            assert_eq!(ap[0], ApSample::NONE, "NaN distance");
        }
        assert!(levels >= 1);
        let mut out = vec![Vec3::ZERO; n - 1];
        assert!(v.radiance_batch(&dirs, &mut out).is_err());
        let mut ap = vec![ApSample::NONE; n];
        assert!(
            v.aerial_perspective_batch(&dirs, &dist[..n - 1], &mut ap)
                .is_err()
        );
    }

    /// The pre-batch per-pixel shading, in `f64` where it was: the oracle for
    /// the row kernels of `render`.
    fn reference_pixel(v: &SkyView, camera: &SkyCamera, x: usize, y: usize, g: &Ground) -> Vec3 {
        let Some(d) = camera.direction(x, y) else {
            return Vec3::ZERO;
        };
        if let Some(t) = v.ground_distance(d) {
            return v.ground_radiance(d, t, g);
        }
        v.radiance_f32(d) + v.sun_disc_f32(d)
    }

    /// `render` (SIMD rows, `f32` ground intersection) against per-pixel
    /// scalar shading: every pixel
    /// within 1e-4 relative per channel (on a floor of 1e-3 of the image's
    /// peak; measured worst 7e-6), and identical bits at every SIMD level and
    /// thread count.
    #[test]
    fn render_matches_per_pixel_shading_and_is_deterministic() {
        let a = atm(true, Evaluation::Rgb);
        let v = a.sky_view(CAM, dir(6.0, 80.0)).unwrap();
        let g = Ground {
            albedo: Vec3::new(0.2, 0.15, 0.1),
        };
        let (w, h) = (157, 93);
        for p in [
            SkyProjection::Pinhole {
                fov_y: 0.8,
                yaw: 1.3,
                pitch: 0.02,
            },
            SkyProjection::Fisheye,
            SkyProjection::Panorama {
                min_elevation: -0.3,
                max_elevation: 1.2,
            },
        ] {
            let img = v.render(p, w, h, Some(g), true).unwrap();
            let camera = p.camera(w, h).unwrap();
            let px = img.pixels();
            let peak = px
                .as_slice()
                .iter()
                .fold(0.0f32, |m, c| m.max(c.max_element()));
            for y in 0..h {
                for x in 0..w {
                    let r = reference_pixel(&v, &camera, x, y, &g);
                    let got = px[(x, y)];
                    let floor = Vec3::splat(1e-3 * peak).max(r.abs());
                    let rel = ((got - r).abs() / floor).max_element();
                    assert!(rel < 1e-4, "{p:?} ({x}, {y}): {got} vs {r}");
                }
            }
            // Every SIMD level and thread count gives the same bits.
            for simd in Simd::supported() {
                for threads in [1, 2] {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .unwrap();
                    let mut grid = natura_core::Grid2::new(w, h, Vec3::ZERO).unwrap();
                    pool.install(|| v.render_rows(simd, &camera, &mut grid, Some(g), true));
                    assert!(
                        grid.as_slice()
                            .iter()
                            .zip(px.as_slice())
                            .all(|(a, b)| bits(*a) == bits(*b)),
                        "{p:?} {simd:?} {threads} threads"
                    );
                }
            }
        }
    }
}

/// The sky's framings are natura-core's cameras, oriented as documented: the
/// dome's centre is the zenith with north up and east on the left; the
/// panorama's middle column looks towards −x, its edges towards +x, its rows
/// span the elevation window; the pinhole looks at its yaw and pitch.
#[test]
fn framings_are_oriented_as_documented() {
    let dome = SkyProjection::Fisheye.camera(101, 101).unwrap();
    let zenith = dome.direction(50, 50).unwrap();
    assert!((zenith - Vec3::Z).length() < 1e-3);
    assert!(dome.direction(50, 0).unwrap().y > 0.99, "north is up");
    assert!(dome.direction(0, 50).unwrap().x > 0.99, "east is left");
    assert!(dome.direction(0, 0).is_none(), "corners see nothing");

    let (lo, hi) = (-0.3f64, 1.2f64);
    let pano = SkyProjection::Panorama {
        min_elevation: lo,
        max_elevation: hi,
    }
    .camera(360, 90)
    .unwrap();
    let mid = pano.direction(180, 45).unwrap();
    assert!(mid.x < -0.5 && mid.y.abs() < 0.02, "{mid}");
    let edge = pano.direction(0, 45).unwrap();
    assert!(edge.x > 0.5 && edge.y.abs() < 0.02, "{edge}");
    let top = pano.direction(10, 0).unwrap().z.asin();
    let bottom = pano.direction(10, 89).unwrap().z.asin();
    let half_row = (hi - lo) / 180.0;
    assert!((f64::from(top) - (hi - half_row)).abs() < 1e-5, "{top}");
    assert!(
        (f64::from(bottom) - (lo + half_row)).abs() < 1e-5,
        "{bottom}"
    );

    let (yaw, pitch) = (1.3f64, 0.2f64);
    let pin = SkyProjection::Pinhole {
        fov_y: 0.8,
        yaw,
        pitch,
    }
    .camera(64, 64)
    .unwrap();
    let c = pin.direction(32, 32).unwrap().as_dvec3();
    let want = DVec3::new(
        pitch.cos() * yaw.cos(),
        pitch.cos() * yaw.sin(),
        pitch.sin(),
    );
    assert!((c - want).length() < 0.02, "{c}");
}
