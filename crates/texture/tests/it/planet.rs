//! Planets: sphere tracing against a brute-force march, cube-sphere edges,
//! precision at Earth scale, determinism across threads, bad input.

use crate::common;

use common::{Rng, pool};
use glam::DVec3;
use natura_core::{NoProgress, simd::Simd};
use natura_texture::Footprint;
use natura_texture::earth::{SphereView, Terran, TerranParams, TerranSphere};
use natura_texture::planet::{
    CubeMap, EARTH_RADIUS_M, Face, GroundViewParams, Planet, PlanetParams, SurfaceParams,
    TerrainParams, TraceSettings, direction,
};

fn tight() -> TraceSettings {
    TraceSettings {
        epsilon: 1e-4,
        min_epsilon_m: 1e-7,
        max_steps: 1_000_000,
        ..TraceSettings::default()
    }
}

fn gaea() -> Planet {
    let mut p = PlanetParams::gaea();
    if let SurfaceParams::Terrain(t) = &mut p.surface {
        t.terran.seed = 3;
    }
    Planet::new(p).unwrap()
}

/// Asserts the sphere-traced hit of each ray equals the brute-force march's
/// first crossing: never beyond it, and within `rel` of its footprint.
fn agree(
    planet: &Planet,
    o: DVec3,
    rays: &[DVec3],
    alpha: f64,
    step: impl Fn(f64) -> f64,
    rel: f64,
) -> usize {
    let mut hits = 0;
    for &d in rays {
        let fast = planet.trace(o, d, alpha, &tight());
        let probe = fast.map_or(1e7, |h| h.t);
        let brute = planet.trace_brute(o, d, alpha, step(probe));
        match (fast, brute) {
            (Some(f), Some(b)) => {
                let tol = rel * (b * alpha).max(1e-6);
                assert!(
                    (f.t - b).abs() <= tol,
                    "ray {d}: traced {} brute {b} (tol {tol})",
                    f.t
                );
                hits += 1;
            }
            (None, None) => {}
            (f, b) => panic!("ray {d}: traced {f:?} brute {b:?}"),
        }
    }
    hits
}

#[test]
fn sphere_traced_hits_agree_with_a_brute_force_march_from_orbit() {
    let planet = gaea();
    let view = planet.orbit_view(1.2e7, 0.3, 0.5, 0.7, 64, 48).unwrap();
    let rays: Vec<DVec3> = (0..48)
        .map(|i| view.pixel((i * 7) % 64, (i * 5) % 48))
        .chain([view.pixel(32, 24)])
        .collect();
    // Brute-force steps of a tenth of the footprint at the hit.
    let alpha = view.pixel_angle();
    let hits = agree(&planet, view.eye(), &rays, alpha, |t| 0.1 * t * alpha, 0.02);
    assert!(hits > 20, "{hits} rays met the planet");
}

#[test]
fn sphere_traced_hits_agree_with_a_brute_force_march_from_the_ground() {
    let planet = gaea();
    let g = GroundViewParams {
        search_radius_m: 200_000.0,
        pitch: -0.3,
        ..GroundViewParams::default()
    };
    let view = planet.ground_view(&g, 32, 24).unwrap();
    let alpha = view.pixel_angle();
    let rays: Vec<DVec3> = (0..10)
        .map(|i| view.pixel((i * 3) % 32, 12 + i % 12))
        .collect();
    let hits = agree(
        &planet,
        view.eye(),
        &rays,
        alpha,
        |t| (0.1 * t * alpha).max(1e-3),
        0.05,
    );
    assert!(hits >= 8, "{hits} rays met the ground");
}

#[test]
fn cube_face_edges_and_corners_are_bit_identical() {
    let planet = gaea();
    for n in [5usize, 16, 33] {
        let map = planet.cube_map(n, &NoProgress).unwrap();
        // Every sample of every face, keyed by its integer cube point: a
        // point shared by two or three faces must carry the same bits.
        let mut seen = std::collections::HashMap::new();
        let mut shared = 0;
        for f in &map.faces {
            for j in 0..n {
                for i in 0..n {
                    let key = f.face.lattice(n, i, j);
                    let h = f.height[(i, j)].to_bits();
                    let c = f.colour[(i, j)].to_array().map(f32::to_bits);
                    if let Some(&(h0, c0)) = seen.get(&key) {
                        assert_eq!((h0, c0), (h, c), "n={n} {:?} ({i}, {j})", f.face);
                        shared += 1;
                    } else {
                        seen.insert(key, (h, c));
                    }
                }
            }
        }
        // 12 edges of n − 2 inner samples shared once, 8 corners shared twice.
        assert_eq!(shared, 12 * (n - 2) + 8 * 2, "n={n}");
        assert_eq!(seen.len(), 6 * n * n - shared);
        assert!(map.faces.iter().any(|f| f.height.max() > 0.0), "some land");
    }
    // The faces tile the sphere: each direction is on exactly one face's lattice.
    assert_eq!(Face::PosZ.lattice(3, 1, 2), Face::PosX.lattice(3, 1, 0));
}

#[test]
fn one_centimetre_octave_resolves_a_millimetre_at_earth_radius() {
    let planet = gaea();
    assert_eq!(planet.radius(), EARTH_RADIUS_M);
    let relief = planet.relief().unwrap();
    // Find land (the detail octaves live on land).
    let mut rng = Rng(31);
    let dir = (0..10_000)
        .map(|_| rng.unit())
        .find(|&d| relief.height(d, relief.footprint(1.0)) > 100.0)
        .expect("land");
    let fine = relief.footprint(0.001);
    assert!(relief.visible(fine) > relief.terran().continents_spectral().octaves + 12.0);
    let east = DVec3::Z.cross(dir).normalize();
    let p = dir * EARTH_RADIUS_M;
    let mut differ = 0;
    for k in 0..20 {
        let a = (p + east * (0.001 * f64::from(k))).normalize();
        let b = (p + east * (0.001 * f64::from(k + 1))).normalize();
        let (ha, hb) = (relief.height(a, fine), relief.height(b, fine));
        if ha != hb {
            differ += 1;
        }
    }
    assert_eq!(differ, 20, "1 mm steps must change the height");
    // Without the 1 cm octave (footprint 1 m), the same millimetre changes the
    // height far less: the change is the centimetre octaves' detail.
    // And that detail is stable: the analytic slope matches 0.1 mm differences.
    let (_, g) = relief.height_grad(dir, fine);
    let slope = g.dot(east) / EARTH_RADIUS_M;
    let d = 1e-4;
    let fd = (relief.height((p + east * d).normalize(), fine)
        - relief.height((p - east * d).normalize(), fine))
        / (2.0 * d);
    assert!(
        (fd - slope).abs() < 1e-3 * (1.0 + slope.abs()),
        "{fd} vs {slope}"
    );
}

#[test]
fn renders_are_bit_identical_on_one_and_two_threads() {
    let planet = gaea();
    let view = planet.orbit_view(1.5e7, 0.2, 0.1, 0.7, 40, 30).unwrap();
    let s = TraceSettings::default();
    let one = pool(1).install(|| planet.render(&view, &s, &NoProgress).unwrap());
    let two = pool(2).install(|| planet.render(&view, &s, &NoProgress).unwrap());
    assert_eq!(one, two);
    assert!(one.first_non_finite().is_none());
    let cube1 = pool(1).install(|| planet.cube_map(9, &NoProgress).unwrap());
    let cube2 = pool(2).install(|| planet.cube_map(9, &NoProgress).unwrap());
    assert_eq!(cube1, cube2);
}

#[test]
fn every_planet_renders_finite_pixels() {
    for params in [
        PlanetParams::venus(),
        PlanetParams::jupiter(),
        PlanetParams::selene(),
    ] {
        let planet = Planet::new(params).unwrap();
        let view = planet
            .orbit_view(planet.radius() * 3.0, 0.3, 0.2, 0.8, 24, 24)
            .unwrap();
        let img = planet
            .render(&view, &TraceSettings::default(), &NoProgress)
            .unwrap();
        assert!(img.first_non_finite().is_none());
        let lit = img
            .pixels()
            .as_slice()
            .iter()
            .filter(|c| c.max_element() > 0.05)
            .count();
        assert!(lit > 50, "{lit} lit pixels");
    }
}

#[test]
fn clouds_shade_the_ground() {
    let mut with = PlanetParams::gaea();
    with.light.sun = direction(0.3, 0.2);
    let mut without = with;
    if let Some(c) = &mut without.clouds {
        c.shadows = false;
    }
    // Without the cloud layer drawn either way, compare the ground alone.
    let a = Planet::new(with).unwrap();
    let b = Planet::new(without).unwrap();
    let view = a.orbit_view(2e6, 0.3, 0.2, 0.3, 32, 32).unwrap();
    let s = TraceSettings::default();
    let ia = a.render(&view, &s, &NoProgress).unwrap();
    let ib = b.render(&view, &s, &NoProgress).unwrap();
    let sum = |i: &natura_core::Image| {
        i.pixels()
            .as_slice()
            .iter()
            .map(|c| f64::from(c.element_sum()))
            .sum::<f64>()
    };
    assert!(
        sum(&ia) < sum(&ib),
        "shadows darken: {} vs {}",
        sum(&ia),
        sum(&ib)
    );
}

#[test]
fn terran_batch_path_matches_the_point_path_at_every_simd_level() {
    let t = Terran::new(TerranParams::default()).unwrap();
    let view = SphereView::orbit(2.5, 0.3, 0.4, 0.9, 48, 36, DVec3::new(1.0, 0.5, 0.4)).unwrap();
    let r = TerranSphere::new(&t);
    let point = r.render_points(&view, &NoProgress).unwrap();
    let mut first: Option<natura_core::Image> = None;
    for simd in Simd::supported() {
        let batch = r.render_batch_with(simd, &view, &NoProgress).unwrap();
        for (a, b) in batch
            .pixels()
            .as_slice()
            .iter()
            .zip(point.pixels().as_slice())
        {
            assert!((*a - *b).abs().max_element() < 2e-3, "{a} vs {b}");
        }
        match &first {
            None => first = Some(batch),
            Some(f) => assert_eq!(f, &batch, "{simd:?}"),
        }
    }
}

#[test]
fn bad_input_is_refused_by_name() {
    let msg = |p: PlanetParams| Planet::new(p).unwrap_err().to_string();
    for r in [0.0, -5.0, f64::NAN, f64::INFINITY] {
        let e = msg(PlanetParams {
            radius_m: r,
            ..PlanetParams::gaea()
        });
        assert!(e.contains("radius_m"), "{e}");
    }
    let mut p = PlanetParams::gaea();
    if let SurfaceParams::Terrain(t) = &mut p.surface {
        t.terran.spectral.octaves = 70.0;
    }
    assert!(msg(p).contains("octaves"));
    let mut p = PlanetParams::gaea();
    if let SurfaceParams::Terrain(t) = &mut p.surface {
        t.relief_m = f64::NAN;
    }
    assert!(msg(p).contains("relief_m"));
    let mut p = PlanetParams::gaea();
    p.light.sun = DVec3::ZERO;
    assert!(msg(p).contains("sun"));
    let mut p = PlanetParams::gaea();
    if let Some(a) = &mut p.atmosphere {
        a.scale_height_m = -1.0;
    }
    assert!(msg(p).contains("scale_height_m"));
    let mut p = PlanetParams::gaea();
    p.surface = SurfaceParams::Terrain(TerrainParams {
        terran: TerranParams {
            continents: natura_texture::earth::Continents::VectorMultifractal,
            ..TerranParams::default()
        },
        ..TerrainParams::earth()
    });
    assert!(msg(p).contains("detail"));

    let planet = gaea();
    for n in [0usize, 1] {
        let e = planet.cube_map(n, &NoProgress).unwrap_err().to_string();
        assert!(e.contains("face_size"), "{e}");
    }
    let e = planet
        .cube_map(1 << 20, &NoProgress)
        .unwrap_err()
        .to_string();
    assert!(e.contains("face_size") && e.contains("cap"), "{e}");
    assert!(planet.equirect(0, 10, &NoProgress).is_err());
    assert!(planet.orbit_view(-1.0, 0.0, 0.0, 0.5, 8, 8).is_err());
    assert!(planet.orbit_view(1e7, 0.0, 0.0, 0.5, 0, 8).is_err());
    assert!(
        planet
            .ground_view(
                &GroundViewParams {
                    eye_height_m: 0.0,
                    ..Default::default()
                },
                8,
                8
            )
            .is_err()
    );
    assert!(Footprint::new(f64::INFINITY).is_err());
    let bad = TraceSettings {
        max_steps: 0,
        ..TraceSettings::default()
    };
    let view = planet.orbit_view(1e7, 0.0, 0.0, 0.5, 4, 4).unwrap();
    assert!(planet.render(&view, &bad, &NoProgress).is_err());
    // A NaN ray is no hit and no panic.
    assert!(
        planet
            .trace(DVec3::NAN, DVec3::X, 1e-3, &TraceSettings::default())
            .is_none()
    );
}

#[test]
fn an_unwritable_export_fails_before_writing_anything() {
    let planet = gaea();
    let map = planet.cube_map(4, &NoProgress).unwrap();
    let dir = std::path::Path::new("/nonexistent-natura-texture-dir");
    let e = map.write_exr(dir, "x").unwrap_err().to_string();
    assert!(e.contains("nonexistent-natura-texture-dir"), "{e}");
    // A writable directory receives all twelve files, which read back.
    let dir = std::env::temp_dir().join(format!("natura-texture-cube-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let paths = map.write_exr(&dir, "t").unwrap();
    assert_eq!(paths.len(), 12);
    let back = natura_core::io::exr::read_exr(&CubeMap::paths(&dir, "t")[0]).unwrap();
    assert_eq!(back.channel("Y").unwrap(), map.faces[0].height.as_slice());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Thin sunlit air seen against space has the colour of Rayleigh single
/// scattering: each channel's in-scattered light in proportion to its
/// extinction (blue/red = 33.1/5.8 for Earth's air). A blue fog colour
/// counted the air's blue twice (14 times the red, not 5.7) and tinted
/// brown continents lilac from orbit.
#[test]
fn thin_air_scatters_in_proportion_to_its_extinction() {
    let planet = gaea();
    let a = planet.params().atmosphere.unwrap();
    let s = planet.sun();
    let side = s.cross(DVec3::Z).normalize();
    for h in [40e3, 60e3] {
        // A ray grazing the subsolar point h above the sea, from space to space.
        let closest = s * (EARTH_RADIUS_M + h);
        let o = closest - side * 3.0 * EARTH_RADIUS_M;
        let l = planet.radiance(o, side, 1e-4, &TraceSettings::default());
        assert!(l.min_element() > 0.0, "lit haze at {h} m: {l}");
        let seen = l.z / l.x;
        let rayleigh = a.extinction.z / a.extinction.x;
        assert!(
            (seen / rayleigh - 1.0).abs() < 0.1,
            "blue/red {seen} at {h} m, extinction ratio {rayleigh}"
        );
    }
}

/// The coast is filtered at the pixel footprint: where a footprint straddles
/// it, the land fraction `normal_bump_and_land` gives is close to the
/// share of land a 16 × 16 supersampling of the same footprint finds (each
/// sub-sample with the octaves its own footprint shows), far closer than
/// the point-sampled step (whose error made coastlines a staircase of whole
/// pixels) and closer than a ramp of the gradient alone (which leaves out
/// the octaves too fine to sum); away from the coast it is 0 or 1 exactly.
#[test]
fn coast_is_filtered_at_the_footprint() {
    let planet = gaea();
    let relief = planet.relief().unwrap();
    let fp = relief.footprint(9000.0);
    let w = fp.width();
    let fine = natura_texture::Footprint::new(w / 16.0).unwrap();
    let mut rng = Rng(11);
    let (mut filtered_err, mut step_err, mut ramp_err, mut straddling) = (0.0, 0.0, 0.0, 0);
    for _ in 0..20_000 {
        let dir = rng.unit();
        let (_, b, land) = relief.normal_bump_and_land(dir * EARTH_RADIUS_M, fp);
        let chaos = relief.chaos_above_sea(b);
        assert!((0.0..=1.0).contains(&land));
        if land == 0.0 || land == 1.0 {
            assert_eq!(land == 1.0, chaos > 0.0);
            continue;
        }
        // The footprint's square on the tangent plane, supersampled.
        let u = dir.cross(DVec3::Z).normalize();
        let v = dir.cross(u);
        let mut inside = 0u32;
        for i in 0..16 {
            for j in 0..16 {
                let (a, c) = (
                    (f64::from(i) + 0.5) / 16.0 - 0.5,
                    (f64::from(j) + 0.5) / 16.0 - 0.5,
                );
                let q = (dir + (u * a + v * c) * w).normalize();
                inside += u32::from(relief.chaos_above_sea(relief.bump(q, fine)) > 0.0);
            }
        }
        let share = f64::from(inside) / 256.0;
        let (_, g) = relief.bump_grad(dir, fp);
        let along = (g - dir * dir.dot(g)).length() * w;
        let ramp = (0.5 + chaos / along).clamp(0.0, 1.0);
        filtered_err += (land - share).abs();
        step_err += (f64::from(u8::from(chaos > 0.0)) - share).abs();
        ramp_err += (ramp - share).abs();
        straddling += 1;
    }
    assert!(straddling > 20, "only {straddling} footprints on the coast");
    let n = f64::from(straddling);
    let (f, s, r) = (filtered_err / n, step_err / n, ramp_err / n);
    eprintln!("coast: filtered {f:.4}, gradient ramp {r:.4}, point-sampled {s:.4}");
    assert!(
        f < 0.15 && f < 0.85 * s && f < r,
        "filtered error {f}, gradient ramp {r}, point-sampled {s}"
    );
}
