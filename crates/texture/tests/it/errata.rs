//! Each erratum of the sources that a texture corrects, pinned by a test.
//!
//! Some tests rebuild a texture's fractal by hand from natura-noise to check
//! the texture computes the corrected formula; they use the sub-seed names
//! the textures derive (`Seed(seed).derive("clouds")`, …).

use crate::common;

use common::Rng;
use glam::DVec3;
use natura_core::Seed;
use natura_noise::{
    DistNoise, Fbm, Field, GainConvention, Perlin, Spectral, VecNoise, VectorField,
};
use natura_texture::air::{
    Cyclone, CycloneParams, PlanetClouds, PlanetCloudsParams, Venus, VenusParams,
};
use natura_texture::earth::{
    Continents, Luna, LunaParams, Ridge, RidgeParams, Terran, TerranParams, tent,
};
use natura_texture::fire::{Flame, FlameBasis, FlameParams};
use natura_texture::multicolor::{Multicolor, MulticolorParams, fold};
use natura_texture::water::{Ripples, RipplesParams, WindyWave, WindyWaveParams};
use natura_texture::{Footprint, SolidTexture};

const P: Footprint = Footprint::POINT;

fn perlin(seed: u64, name: &str) -> Perlin {
    Perlin::new(Seed(seed).derive(name).0)
}

fn spectral(h: f64, lacunarity: f64, octaves: f64) -> Spectral {
    Spectral {
        h,
        lacunarity,
        octaves,
        frequency: 1.0,
        convention: GainConvention::H,
    }
}

/// Tent `F(x) = min(2x, 2 − 2x)`, not the printed pair `[2x, 2 − 2x]`.
#[test]
fn erratum_7_the_ridge_tent_is_a_minimum() {
    for (x, f) in [(0.0, 0.0), (0.25, 0.5), (0.5, 1.0), (0.75, 0.5), (1.0, 0.0)] {
        assert_eq!(tent(x), f);
    }
    // Continuous and never above 1.
    for i in 0..1000 {
        let x = f64::from(i) / 1000.0;
        assert!(tent(x) <= 1.0 && (tent(x) - tent(x + 1e-9)).abs() < 1e-8);
    }
    // On the crest the ridge is the fractal itself; where the tent is 0 only
    // the sea-level term c₀·Π of the cascade remains.
    let r = Ridge::new(RidgeParams {
        perturbation: 0.0,
        ..RidgeParams::default()
    })
    .unwrap();
    let crest = DVec3::new(0.5, 0.3, 0.2);
    let foot = DVec3::new(1.0, 0.3, 0.2);
    assert!((r.position(crest, P) - 0.5).abs() < 1e-12);
    assert_eq!(r.position(foot, P), 0.0);
    let sea = r.params().altitude.sea_level;
    assert_eq!(sea, 0.0);
    assert_eq!(r.height(foot, P), 0.0);
    assert!(r.height(crest, P) != 0.0);
}

/// `Planet_Clouds`: the distortion is applied, the density is normalised by
/// `1 + offset` (not `/1.0 + offset`), `H` is a spectral exponent (not the
/// raw gain `ω`), and the pseudo-code's cutoff is a negative offset.
#[test]
fn erratum_11_planet_clouds() {
    let d1 = PlanetClouds::new(PlanetCloudsParams::default()).unwrap();
    let d0 = PlanetClouds::new(PlanetCloudsParams {
        distortion: 0.0,
        ..Default::default()
    })
    .unwrap();
    let mut rng = Rng(3);
    let mut moved = 0;
    for _ in 0..200 {
        let p = rng.unit();
        // The distorted clouds are the undistorted ones at the displaced point.
        let q = d1.distorted(p, P);
        assert!((d1.value(p, P) - d0.value(q, P)).abs() < 1e-12);
        if (q - p).length() > 0.05 {
            moved += 1;
        }
    }
    assert!(
        moved > 100,
        "the distortion must move the point ({moved} of 200)"
    );
    // H, not ω: octave k has amplitude λ^(−0.7k).
    let f = Fbm::new(perlin(0, "clouds"), spectral(0.7, 2.0, 9.0)).unwrap();
    for _ in 0..20 {
        let p = rng.unit();
        assert!((d0.value(p, P) - f.eval3(p)).abs() < 1e-12);
    }
    // Density in [0, 1/(1 + offset)]: the precedence slip would add the offset.
    let half = PlanetClouds::new(PlanetCloudsParams {
        offset: 0.5,
        ..Default::default()
    })
    .unwrap();
    let mut top: f64 = 0.0;
    for _ in 0..2000 {
        let p = rng.p3(3.0);
        let d = half.density(p, P);
        assert!((0.0..=1.0 / 1.5 + 1e-15).contains(&d));
        top = top.max(d);
        if half.value(p, P) + 0.5 <= 0.0 {
            assert_eq!(d, 0.0);
        }
    }
    assert!(top > 0.5, "cover reaches near its ceiling ({top})");
    // The pseudo-code's cutoff c: (result − c)/(1 − c), here offset = −c.
    let cut = PlanetClouds::new(PlanetCloudsParams {
        offset: -0.2,
        ..Default::default()
    })
    .unwrap();
    for _ in 0..200 {
        let p = rng.unit();
        let r = cut.value(p, P);
        let want = if r < 0.2 {
            0.0
        } else {
            ((r - 0.2) / 0.8).min(1.0)
        };
        assert!((cut.density(p, P) - want.min(1.0)).abs() < 1e-12);
    }
}

/// `Cyclone`: no clouds outside the storm, an eye weight continuous at the
/// eye's rim for any storm radius.
#[test]
fn erratum_12_cyclone_eye() {
    for r in [0.5f64, 1.0, 1.7] {
        let c = Cyclone::new(CycloneParams {
            max_radius: r.min(1.0),
            ..Default::default()
        })
        .unwrap();
        let big = r.min(1.0);
        let eye = 0.1 * big;
        assert_eq!(c.eye_weight(big), 0.0);
        assert_eq!(c.eye_weight(big + 0.1), 0.0);
        assert_eq!(c.eye_weight(eye), 1.0);
        assert!(
            (c.eye_weight(eye * (1.0 - 1e-9)) - 1.0).abs() < 1e-7,
            "continuous at the rim"
        );
        assert_eq!(c.eye_weight(0.0), 0.0);
        let mut last = 0.0;
        for i in 0..=100 {
            let w = c.eye_weight(eye * f64::from(i) / 100.0);
            assert!(w >= last && (0.0..=1.0).contains(&w));
            last = w;
        }
    }
    let c = Cyclone::new(CycloneParams::default()).unwrap();
    let mut rng = Rng(5);
    for _ in 0..500 {
        let p = rng.unit();
        let d = c.density(p, P);
        assert!((0.0..=1.0).contains(&d));
        if Cyclone::radius(p) >= 1.0 {
            assert_eq!(d, 0.0);
        }
    }
    // Near the equator of the unit sphere (r → 1 = R) the storm ends.
    assert_eq!(c.density(DVec3::new(1.0, 0.0, 0.0), P), 0.0);
}

/// Venus and the cyclone: `H` semantics (not `ω`) and the twist measured on
/// the unit direction, so it does not depend on the sphere's radius.
#[test]
fn erratum_13_coriolis_uses_h_and_the_normalised_point() {
    let v = Venus::new(VenusParams {
        distortion: 0.0,
        octaves: 3.0,
        ..Default::default()
    })
    .unwrap();
    let mut rng = Rng(7);
    for _ in 0..50 {
        let p = rng.unit();
        let a = v.twisted(p) * 2.5;
        let b = v.twisted(p * 2.5);
        assert!((a - b).length() < 1e-12, "twist depends on direction only");
        assert!((v.twisted(p).z - p.z).abs() < 1e-15);
        assert!((v.twisted(p).truncate().length() - p.truncate().length()).abs() < 1e-12);
        assert!((Cyclone::radius(p) - Cyclone::radius(p * 7.0)).abs() < 1e-15);
    }
    // H = 0.65 means gain 2^−0.65 per octave (DistNoise with distortion 0 is Perlin).
    let basis = DistNoise::dist_noise(perlin(0, "venus"), 0.0).unwrap();
    let f = Fbm::new(basis, spectral(0.65, 2.0, 3.0)).unwrap();
    for _ in 0..20 {
        let p = rng.unit();
        let want = (1.0 + 0.6 * f.eval3(v.twisted(p))).abs();
        assert!((v.value(p, P) - want).abs() < 1e-12);
    }
    let no_twist = Venus::new(VenusParams {
        twist: 0.0,
        ..Default::default()
    })
    .unwrap();
    let p = DVec3::new(0.3, 0.4, 0.5);
    assert_eq!(no_twist.twisted(p), p);
}

/// `DistNoise` displaces along a vector of three independent noises, not
/// along (1, 1, 1) (the RenderMan listing's scalar `snoise`), and the vector
/// fBm distortion band-limits its octaves by the footprint.
#[test]
fn erratum_14_distortion_is_a_vector() {
    let v = VecNoise::new(perlin(0, "flame"));
    let mut rng = Rng(9);
    let mut skew = 0;
    for _ in 0..100 {
        let d = v.eval3(rng.p3(4.0) + DVec3::splat(0.5));
        let along = d.dot(DVec3::ONE.normalize()).abs();
        if along < 0.95 * d.length() {
            skew += 1;
        }
    }
    assert!(skew > 80, "offsets lie off the diagonal ({skew} of 100)");
    // The flame's DistfBm is fBm of that DistNoise.
    let flame = Flame::new(FlameParams {
        distortion: 1.0,
        ..Default::default()
    })
    .unwrap();
    let basis = DistNoise::dist_noise(perlin(0, "flame"), 1.0).unwrap();
    let f = Fbm::new(basis, spectral(0.5, 2.0, 7.0)).unwrap();
    for _ in 0..20 {
        let p = rng.p3(1.0);
        let pq = DVec3::new(p.x, p.y, p.z * (-p.z).exp());
        assert!((flame.chaos(p, P) - f.eval3(pq).abs()).abs() < 1e-12);
    }
    // The fBm-valued distortion fades with the footprint instead of aliasing.
    let clouds = PlanetClouds::new(PlanetCloudsParams {
        distortion_field: natura_texture::air::CloudDistortion::Fbm,
        ..Default::default()
    })
    .unwrap();
    let p = DVec3::new(0.2, 0.4, 0.9);
    assert_eq!(clouds.distorted(p, Footprint::new(100.0).unwrap()), p);
    let near = clouds.distorted(p, Footprint::new(1e-4).unwrap());
    assert!((near - clouds.distorted(p, P)).length() < 1e-3);
}

/// `terran`: octaves stepped by the lacunarity, `pert_scale` used, the mottle
/// adds to blue its own share, and the land spline is complete.
#[test]
fn erratum_15_terran() {
    let gaea = Terran::new(TerranParams::gaea()).unwrap();
    assert_eq!(gaea.params().continents, Continents::VectorMultifractal);
    for w in [1e-4, 1e-3, 3e-2] {
        let a = gaea.visible(Footprint::new(w).unwrap());
        let b = gaea.visible(Footprint::new(w / 2.0).unwrap());
        assert!(
            (b - a - 1.0).abs() < 1e-9,
            "one octave per halving at λ = 2: {a} {b}"
        );
    }
    // pert_scale = 0 (and nonlinear = 0): land colour ignores the chaos.
    let flat = Terran::new(TerranParams {
        pert_scale: 0.0,
        mottle_mag: 0.0,
        ..Default::default()
    })
    .unwrap();
    for lat in [0.1, 0.4, 0.7] {
        assert_eq!(
            flat.shade(0.2, lat, 0.0).colour,
            flat.shade(0.9, lat, 0.0).colour
        );
    }
    let t = Terran::new(TerranParams::default()).unwrap();
    assert_ne!(t.shade(0.2, 0.4, 0.0).colour, t.shade(0.9, 0.4, 0.0).colour);
    // Mottle: + mottle_mag·pert·(0.5, 0.175, 0.5) (blue gets its own share).
    let m = 0.8;
    let a = t.shade(0.3, 0.2, 0.0).display;
    let b = t.shade(0.3, 0.2, m).display;
    let d = b - a;
    let q = t.params();
    assert!(
        (d - DVec3::new(0.5, 0.175, 0.5) * (q.mottle_mag * m)).length() < 1e-12,
        "{d}"
    );
    // The land spline is the shader's complete 10-knot map: polar white at the top.
    assert_eq!(natura_texture::earth::terran::LAND_KNOTS.len(), 10);
    let snow = t.shade(0.01, 1.5, 0.0);
    assert!(snow.land && snow.display == DVec3::ONE);
}

/// `venus` (octaves passed), `ripples` (old argument order: `H = 3`) and
/// `windywave` (the wind is the large scale).
#[test]
fn erratum_16_venus_ripples_windywave() {
    let one = Venus::new(VenusParams {
        octaves: 1.0,
        ..Default::default()
    })
    .unwrap();
    let eight = Venus::new(VenusParams::default()).unwrap();
    let p = DVec3::new(0.3, -0.6, 0.74);
    assert_ne!(one.value(p, P), eight.value(p, P));
    let basis = DistNoise::dist_noise(perlin(0, "venus"), 1.0).unwrap();
    assert!((one.value(p, P) - (1.0 + 0.6 * basis.eval3(one.twisted(p))).abs()).abs() < 1e-12);

    let r = Ripples::new(RipplesParams::default()).unwrap();
    let n = perlin(0, "ripples");
    let mut rng = Rng(13);
    for _ in 0..20 {
        let p = rng.p3(5.0);
        let want = n.eval3(p) + 0.125 * n.eval3(p * 2.0);
        assert!((r.height(p, P) - want).abs() < 1e-12);
    }

    let w = WindyWave::new(WindyWaveParams::default()).unwrap();
    let (mut gw, mut gr) = (0.0, 0.0);
    let (mut vw, mut vr) = (Vec::new(), Vec::new());
    let q = w.params();
    for _ in 0..400 {
        let p = rng.p3(20.0);
        let h = 1e-4;
        let dw = (w.wind(p + DVec3::X * h, P) - w.wind(p - DVec3::X * h, P)) / (2.0 * h);
        gw += dw.abs();
        vw.push(w.wind(p, P));
        let ripple = |x: DVec3| w.height(x, P) / w.wind(x, P);
        let dr = (ripple(p + DVec3::X * h) - ripple(p - DVec3::X * h)) / (2.0 * h);
        gr += dr.abs();
        vr.push(ripple(p));
    }
    let sd = |v: &[f64]| {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / v.len() as f64).sqrt()
    };
    // Relative slope ∝ frequency: the wind varies more slowly than the
    // ripples (the listing's order would make it faster; the wind's |noise|
    // creases and extra octaves narrow the measured gap below the 8× of the
    // base frequencies).
    let wind_freq = gw / sd(&vw);
    let ripple_freq = gr / sd(&vr);
    assert!(
        ripple_freq > 2.0 * wind_freq,
        "wind {wind_freq} ripples {ripple_freq}"
    );
    assert!(vw.iter().all(|&x| x >= q.minwind));
}

/// `luna`: one fBm with `H = 0.7`, the outer rim without the zero
/// denominator, a continuous crater profile, rays in range.
#[test]
fn erratum_17_luna() {
    let l = Luna::new(LunaParams::default()).unwrap();
    let q = *l.params();
    let c = |pd: f64| l.crater(pd);
    let e = 1e-9;
    for (r, h) in [
        (q.peak_rad, 0.0),
        (q.inner_rad, 0.0),
        (q.rim_rad, q.rim_ht),
        (q.outer_rad, 0.0),
    ] {
        assert!((c(r - e).height - h).abs() < 1e-6, "left of {r}");
        assert!((c(r + e).height - h).abs() < 1e-6, "right of {r}");
        assert!(
            (c(r - e).lighten - c(r + e).lighten).abs() < 1e-6,
            "lighten at {r}"
        );
    }
    assert!((c(0.0).height - q.peak_ht).abs() < 1e-15);
    for i in 0..=1000 {
        let pd = 0.1 * f64::from(i) / 1000.0;
        let p = c(pd);
        assert!(p.height >= 0.0 && p.height.is_finite());
        if pd >= q.peak_rad && pd < q.inner_rad {
            assert_eq!(p.height, 0.0, "flat floor");
        }
        if pd >= q.outer_rad {
            assert_eq!((p.height, p.uu), (0.0, 0.0));
        }
    }
    for i in 0..2000 {
        let u = f64::from(i) / 2000.0;
        for pd in [0.0, 0.015, 0.02, 0.05, 0.2, 0.39, 0.4, 0.6] {
            let ray = l.rays(u, pd, 1e-4);
            assert!((0.0..=0.2).contains(&ray));
            if pd >= 0.4 || pd < q.rim_rad {
                assert_eq!(ray, 0.0);
            }
        }
    }
    // One fBm, H = 0.7: the maria chaos away from the pole is that fBm.
    let f = Fbm::new(perlin(0, "maria"), spectral(0.7, 2.0, 8.0)).unwrap();
    let p = DVec3::new(0.8, 0.6, 0.0);
    let radial = 1.0f64;
    assert!(radial >= 1.0);
    assert!((l.chaos(p, P) - f.eval3(p)).abs() < 1e-12);
}

/// `multicolor`: channels folded into [0, 1] (the listing's `1 − |c|` goes
/// negative), averaging to 50% grey.
#[test]
fn erratum_18_multicolor_fold() {
    assert_eq!(fold(0.3), 0.3);
    assert!((fold(1.3) - 0.7).abs() < 1e-12);
    assert!((fold(-0.3) - 0.3).abs() < 1e-12);
    assert!((fold(2.6) - 0.6).abs() < 1e-12);
    let mut rng = Rng(19);
    for _ in 0..10_000 {
        let x = rng.range(-50.0, 50.0);
        assert!((0.0..=1.0).contains(&fold(x)));
    }
    let m = Multicolor::new(MulticolorParams::default()).unwrap();
    let encode = |v: f64| {
        if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        }
    };
    let mut sum = DVec3::ZERO;
    let n = 3000;
    for _ in 0..n {
        let c = m.colour(rng.p3(50.0), Footprint::new(0.01).unwrap());
        sum += DVec3::new(encode(c.x), encode(c.y), encode(c.z));
    }
    let mean = sum / f64::from(n);
    for c in mean.to_array() {
        assert!((c - 0.5).abs() < 0.05, "mean display colour {mean}");
    }
}

/// `flame`: the listing's `|fBm|` by default; the text's ridged basis on request.
#[test]
fn erratum_19_flame_abs_of_sum_and_ridged_basis() {
    let listing = Flame::new(FlameParams::default()).unwrap();
    let ridged = Flame::new(FlameParams {
        basis: FlameBasis::Ridged,
        ..Default::default()
    })
    .unwrap();
    let basis = DistNoise::dist_noise(perlin(0, "flame"), 0.0).unwrap();
    let f = Fbm::new(basis, spectral(0.5, 2.0, 7.0)).unwrap();
    let ridge = Fbm::new(natura_noise::Ridged(basis), spectral(0.5, 2.0, 7.0)).unwrap();
    let w = ridge.octaves().weight_sum();
    let mut rng = Rng(21);
    let mut differ = 0;
    for _ in 0..100 {
        let p = rng.p3(2.0);
        let pq = DVec3::new(p.x, p.y, p.z * (-p.z).exp());
        assert!((listing.chaos(p, P) - f.eval3(pq).abs()).abs() < 1e-12);
        assert!((ridged.chaos(p, P) - ridge.eval3(pq) / w).abs() < 1e-12);
        assert!((0.0..=1.0).contains(&ridged.chaos(p, P)));
        if (listing.chaos(p, P) - ridged.chaos(p, P)).abs() > 1e-3 {
            differ += 1;
        }
    }
    assert!(differ > 90);
    // For fixed noise the colour index falls linearly with height.
    let p = DVec3::new(0.2, 0.3, 0.0);
    let i0 = listing.index(p, P) - 0.85 * listing.chaos(p, P);
    let p1 = DVec3::new(0.2, 0.3, 0.5);
    let i1 = listing.index(p1, P) - 0.85 * listing.chaos(p1, P);
    assert!((i0 - i1 - 0.8 * 0.5).abs() < 1e-12);
}

/// `luna`: the relief's slope stays bounded over the crater, its mare and
/// the globe (the listing's `vv = (x, 0, z)/radial` sent the rough detail's
/// lattice point to infinity at the pole, ringing the crater with moiré,
/// and its highland/mare displacement was a cliff at every shore), and the
/// height is finite everywhere.
#[test]
fn luna_relief_slope_is_bounded() {
    use std::f64::consts::{PI, TAU};
    let l = Luna::new(LunaParams::default()).unwrap();
    let h = |p: DVec3| l.sample(p, P).height;
    let at = |colat: f64, lon: f64| {
        DVec3::new(
            colat.sin() * lon.cos(),
            colat.sin() * lon.sin(),
            colat.cos(),
        )
    };
    // Walks in steps of `step` along the sphere; the steepest |Δh|/step.
    let step = 1e-4;
    let steepest = |path: &mut dyn Iterator<Item = DVec3>| {
        let mut prev: Option<(DVec3, f64)> = None;
        let mut worst = 0.0f64;
        for p in path {
            let v = h(p);
            assert!(v.is_finite(), "height at {p}");
            if let Some((q, u)) = prev {
                worst = worst.max((v - u).abs() / (p - q).length());
            }
            prev = Some((p, v));
        }
        worst
    };
    let mut worst = 0.0f64;
    // Rings round the crater's axis out to twice the outer rim.
    for i in 0..40 {
        let colat = PI * 0.1 * (f64::from(i) + 0.5) / 40.0;
        let n = (TAU * colat.sin() / step).ceil() as u32;
        let mut ring = (0..=n).map(|k| at(colat, TAU * f64::from(k) / f64::from(n)));
        worst = worst.max(steepest(&mut ring));
    }
    // Meridians from pole to pole, crossing the maria's shores.
    for k in 0..8 {
        let lon = TAU * f64::from(k) / 8.0 + 0.1;
        let n = (PI / step).ceil() as u32;
        let mut meridian = (0..=n).map(|j| at(PI * f64::from(j) / f64::from(n), lon));
        worst = worst.max(steepest(&mut meridian));
    }
    // The rough central peak reaches a slope of about 1.4; the listing's
    // shore cliffs and its pole-bound `vv` gave 12 and more.
    assert!(worst < 2.0, "steepest slope {worst}");
}
