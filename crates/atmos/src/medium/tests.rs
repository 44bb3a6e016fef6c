//! Oracle tests for the aerial-perspective media: closed forms against
//! adaptive quadrature, additivity, symmetry, horizontal-ray limits and the
//! "ozone hole" regression of Musgrave 1993, §4.1.6.4.

use glam::DVec3;
use proptest::prelude::*;

use super::*;
use crate::special::integrate;

const R_EARTH: f64 = 6_371_000.0;
const H_EARTH: f64 = 8_000.0;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

fn quad_column(rho: impl Fn(DVec3) -> f64, a: DVec3, b: DVec3) -> f64 {
    let d = a.distance(b);
    let u = (b - a) / d;
    integrate(|t| rho(a + u * t), 0.0, d, 1e-13, 40)
}

fn mist() -> ExponentialMist {
    ExponentialMist::new(
        DVec3::new(1e-4, 2e-4, 5e-4),
        DVec3::splat(0.8),
        100.0,
        1000.0,
    )
    .unwrap()
}

fn earth() -> RadialAtmosphere {
    RadialAtmosphere::new(DVec3::ONE, DVec3::ONE, DVec3::ZERO, R_EARTH, H_EARTH).unwrap()
}

#[test]
fn homogeneous_bounds_monotone_multiplicative() {
    let fog = HomogeneousFog::new(DVec3::new(1e-3, 2e-3, 0.0), DVec3::splat(0.5)).unwrap();
    let a = DVec3::ZERO;
    let mut last = DVec3::ONE;
    for i in 0..50 {
        let b = DVec3::new(i as f64 * 100.0, 0.0, 0.0);
        let t = fog.transmittance(a, b);
        assert!(t.min_element() >= 0.0 && t.max_element() <= 1.0);
        assert!(t.cmple(last).all());
        last = t;
    }
    assert_eq!(fog.transmittance(a, a), DVec3::ONE);
    let (b, c) = (DVec3::new(300.0, 0.0, 0.0), DVec3::new(300.0, 700.0, 0.0));
    let split = fog.transmittance(a, b) * fog.transmittance(b, c);
    let whole = fog.transmittance(a, c);
    // a→b→c is not straight, so compare lengths: σ(δ₁+δ₂) = σ(δ₁)σ(δ₂).
    let straight = fog.transmittance(a, DVec3::new(1000.0, 0.0, 0.0));
    assert!((split - straight).abs().max_element() < 1e-15);
    assert!(whole.x > split.x);
    // A channel without extinction stays clear even to infinity (0·∞ = 0).
    let inf = fog.attenuation_to_infinity(a, Dir3::X);
    assert_eq!(inf.transmittance, DVec3::new(0.0, 0.0, 1.0));
    assert_eq!(inf.apply(DVec3::ONE), DVec3::new(0.5, 0.5, 1.0));
}

#[test]
fn mist_horizontal_limits_are_continuous() {
    let m = mist();
    let a = DVec3::new(0.0, 0.0, 350.0);
    let b0 = DVec3::new(5000.0, 0.0, 350.0);
    let tau0 = m.column(a, b0);
    assert!((tau0 - 5000.0 * m.density(350.0)).abs() < 1e-9 * tau0);
    for dz in [1e-300, 1e-12, 1e-6, -1e-6, -1e-12, -1e-300] {
        let t = m.column(a, b0 + DVec3::new(0.0, 0.0, dz));
        assert!(t.is_finite());
        assert!(
            (t - tau0).abs() / tau0 <= dz.abs() / 1000.0 + 1e-15,
            "Δ={dz}"
        );
    }
}

#[test]
fn mist_upward_ray_to_infinity() {
    let m = mist();
    let a = DVec3::new(10.0, -3.0, 250.0);
    for elev in [0.01f64, 0.2, 1.0, 1.5] {
        let d = Dir3::from_angles(elev, 0.4).unwrap();
        let far = m.column(a, a + d.get() * 1e30);
        let inf = m.column_to_infinity(a, d);
        let closed = m.density(250.0) * 1000.0 / elev.sin();
        assert!(
            rel(far, closed) < 1e-9 && rel(inf, closed) < 1e-12,
            "{elev}"
        );
    }
    assert_eq!(m.column_to_infinity(a, Dir3::X), f64::INFINITY);
    assert_eq!(m.column_to_infinity(a, Dir3::DOWN), f64::INFINITY);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, .. ProptestConfig::default() })]

    /// Closed form = quadrature, symmetric, additive, from −2H to 20H.
    #[test]
    fn mist_matches_quadrature(
        x1 in -5e3f64..5e3, y1 in -5e3f64..5e3, z1 in -1900.0f64..20_000.0,
        x2 in -5e3f64..5e3, y2 in -5e3f64..5e3, z2 in -1900.0f64..20_000.0,
        f in 0.0f64..1.0,
    ) {
        let m = mist();
        let (a, b) = (DVec3::new(x1, y1, z1), DVec3::new(x2, y2, z2));
        let closed = m.column(a, b);
        let quad = quad_column(|p| m.density(p.z), a, b);
        prop_assert!(rel(closed, quad) < 1e-9, "{} vs {}", closed, quad);
        prop_assert!(rel(closed, m.column(b, a)) < 1e-12);
        let c = a.lerp(b, f);
        prop_assert!(rel(m.column(a, c) + m.column(c, b), closed) < 1e-12);
        let t = m.transmittance(a, b);
        prop_assert!(t.min_element() >= 0.0 && t.max_element() <= 1.0);
        let split = m.transmittance(a, c) * m.transmittance(c, b);
        prop_assert!((split - t).abs().max_element() < 1e-12);
    }

    /// The radial closed form equals quadrature of ρ(|x − c|) along
    /// arbitrary segments: straddling the closest point, before it, after it.
    #[test]
    fn radial_matches_quadrature(
        h1 in 0.0f64..60_000.0, h2 in 0.0f64..60_000.0,
        th1 in -0.02f64..0.02, th2 in -0.02f64..0.02, ph in 0.0f64..1.0,
    ) {
        let atm = earth();
        let p = |h: f64, th: f64| DVec3::new((R_EARTH + h) * th.sin() * ph.cos(),
            (R_EARTH + h) * th.sin() * ph.sin(), (R_EARTH + h) * th.cos());
        let (a, b) = (p(h1, th1), p(h2, th2));
        let closed = atm.column(a, b);
        // Integrand peaks sharply near the ground for long chords: split the quadrature.
        let quad = quad_column(|q| atm.density(q), a, b);
        if quad > 1e-12 {
            prop_assert!(rel(closed, quad) < 1e-9, "{} vs {} ({} {})", closed, quad, h1, h2);
        }
        prop_assert!(rel(closed, atm.column(b, a)) < 1e-9 || quad < 1e-12);
    }
}

#[test]
fn radial_segment_cases_match_quadrature() {
    let atm = earth();
    let top = R_EARTH + 1000.0;
    // Horizontal chord at 1 km altitude: before, straddling, after the tangent point.
    let p = |s: f64| DVec3::new(s, 0.0, top);
    for (s1, s2) in [
        (-300e3, -50e3),
        (-300e3, 200e3),
        (10e3, 400e3),
        (-1.0, 2.0),
        (5.0, 5.001),
        (-2e6, -1.9e6),
    ] {
        let closed = atm.column(p(s1), p(s2));
        let quad = quad_column(|q| atm.density(q), p(s1), p(s2));
        assert!(rel(closed, quad) < 1e-9, "[{s1}, {s2}] {closed} vs {quad}");
    }
}

/// Earth numbers (R = 6371 km, H = 8 km, kR = 19.95).
#[test]
fn radial_earth_columns() {
    let atm = earth();
    assert!((atm.k() * R_EARTH - 19.95).abs() < 0.01);
    let up = atm.column_to_infinity(DVec3::new(0.0, 0.0, R_EARTH), Dir3::UP);
    assert!((up / 1000.0 - 7.990).abs() < 0.001, "vertical column {up}");
    // Full tangent column at h = 0: √(2πRH)·1 = 565.90 km-equivalent.
    let tangent = atm.column(
        DVec3::new(-3e7, 0.0, R_EARTH),
        DVec3::new(3e7, 0.0, R_EARTH),
    );
    let expect = (2.0 * std::f64::consts::PI * R_EARTH * H_EARTH).sqrt();
    assert!(rel(tangent, expect) < 1e-9, "{tangent} vs {expect}");
    assert!((tangent / 1000.0 - 565.90).abs() < 0.01);
    // Tangent altitude 5 km and 20 km.
    for (h, km) in [(5000.0, 302.83), (20_000.0, 46.27)] {
        let o = DVec3::new(-3e7, 0.0, R_EARTH + h);
        let c = atm.column_to_infinity(o, Dir3::X) / 1000.0;
        assert!((c - km).abs() < 0.01, "{h}: {c}");
    }
}

/// The grazing test: the radial (Gaussian) model equals numeric
/// integration of the true exponential atmosphere `e^{−(r−R)/H}` for grazing
/// rays, to < 0.1 % for full tangent columns.
#[test]
fn radial_matches_exponential_atmosphere_for_grazing_rays() {
    let atm = earth();
    let exp_rho = |q: DVec3| (-(q.length() - R_EARTH) / H_EARTH).exp();
    for (h, rel_tol) in [
        (0.0, 1e-3),
        (2000.0, 1e-3),
        (5000.0, 1.5e-3),
        (20_000.0, 7e-3),
    ] {
        let a = DVec3::new(-1.5e6, 0.0, R_EARTH + h);
        let b = DVec3::new(1.5e6, 0.0, R_EARTH + h);
        let gauss = atm.column(a, b);
        let mut exact = 0.0;
        for k in 0..30 {
            let (s0, s1) = (-1.5e6 + k as f64 * 1e5, -1.5e6 + (k + 1) as f64 * 1e5);
            exact += integrate(
                |s| exp_rho(DVec3::new(s, 0.0, R_EARTH + h)),
                s0,
                s1,
                1e-12,
                30,
            );
        }
        assert!(rel(gauss, exact) < rel_tol, "h={h}: {gauss} vs {exact}");
    }
}

/// No ozone hole. A planet seen from 2R, 4R, 100R: τ > 0, finite, continuous.
/// A naive `erf` difference (the source's eq. 4.1.13 with corrected arguments) fails.
#[test]
fn no_ozone_hole() {
    let atm = earth();
    let naive = |o: DVec3, d: DVec3| -> f64 {
        let k = atm.k();
        let s1 = o.dot(d);
        let rp2 = o.cross(d).length_squared();
        let t = atm.ground_hit(o, Dir3::new(d).unwrap()).unwrap();
        0.886_226_925_452_758 / k
            * (-k * k * (rp2 - R_EARTH * R_EARTH)).exp()
            * (libm::erf(k * (s1 + t)) - libm::erf(k * s1))
    };
    let mut naive_failed = false;
    for dist in [2.0, 4.0, 100.0] {
        let eye = DVec3::new(0.0, 0.0, dist * R_EARTH);
        let half = (1.0 / dist).asin() * 0.995;
        let n = 400;
        let mut prev: Option<f64> = None;
        for i in 0..n {
            let ang = half * i as f64 / (n - 1) as f64;
            let d = DVec3::new(ang.sin(), 0.0, -ang.cos());
            let tau = atm.column_to_infinity(eye, Dir3::new(d).unwrap());
            assert!(
                tau.is_finite() && tau > 0.0,
                "dist {dist} angle {ang}: {tau}"
            );
            if let Some(p) = prev {
                let ratio = tau / p;
                assert!(ratio > 0.8 && ratio < 1.25, "jump {p} → {tau}");
            }
            prev = Some(tau);
            let nv = naive(eye, d);
            if nv.is_nan() || nv <= 0.0 || rel(nv, tau) > 0.01 {
                naive_failed = true;
            }
        }
    }
    assert!(
        naive_failed,
        "the naive erf form should show the ozone hole"
    );
    // Misses are finite for any closest approach, including far above.
    for rp in [0.0, 1.0, 1e3, 1e5, 1e7, 1e9] {
        let o = DVec3::new(-1e10, 0.0, R_EARTH + rp);
        let t = atm.column_to_infinity(o, Dir3::X);
        assert!(t.is_finite() && t >= 0.0, "{rp}: {t}");
    }
}

#[test]
fn umbra_switches_day_and_night() {
    let day = RadialAtmosphere::new(
        DVec3::new(1e-5, 3e-5, 2e-4),
        DVec3::new(1.0, 0.8, 0.5),
        DVec3::ZERO,
        R_EARTH,
        H_EARTH,
    )
    .unwrap();
    let night = RadialAtmosphere::new(
        DVec3::new(1e-5, 3e-5, 2e-4) * 0.1,
        DVec3::new(0.0, 0.0, 0.02),
        DVec3::ZERO,
        R_EARTH,
        H_EARTH,
    )
    .unwrap();
    let eps = 10.0;
    let u = Umbra::new(day, night, DVec3::ZERO, R_EARTH, eps, Dir3::X).unwrap();
    // Inside the cylinder on the night side → night; day side never.
    assert!(u.in_shadow(DVec3::new(-R_EARTH - 100.0, 0.0, R_EARTH + 5.0)));
    assert!(!u.in_shadow(DVec3::new(-R_EARTH - 100.0, 0.0, R_EARTH + eps + 1.0)));
    assert!(!u.in_shadow(DVec3::new(R_EARTH + 100.0, 0.0, 0.0)));
    assert!(!u.in_shadow(DVec3::new(1.0, 0.0, R_EARTH + 1.0)));
    // A segment entirely in the shadow uses night parameters; entirely lit uses day.
    let a = DVec3::new(-1000.0, 0.0, R_EARTH + 2.0);
    let b = DVec3::new(-50_000.0, 0.0, R_EARTH + 3.0);
    assert_eq!(u.optical_depth(a, b), night.optical_depth(a, b));
    let (c, d) = (
        DVec3::new(1000.0, 0.0, R_EARTH + 2.0),
        DVec3::new(1000.0, 50_000.0, R_EARTH + 2000.0),
    );
    assert_eq!(u.optical_depth(c, d), day.optical_depth(c, d));
    // A crossing segment is split exactly: optical depth is the sum of the parts.
    let e = DVec3::new(-2000.0, 0.0, R_EARTH + 5000.0);
    let f = DVec3::new(-2000.0, 0.0, R_EARTH - 1000.0 + 1.0);
    let tau = u.optical_depth(e, f);
    assert!(tau.x < day.optical_depth(e, f).x && tau.x > night.optical_depth(e, f).x);
    let tr = u.transmittance(e, f);
    assert!(tr.min_element() >= 0.0 && tr.max_element() <= 1.0);
    assert!(Umbra::new(day, night, DVec3::ZERO, R_EARTH, 0.0, Dir3::X).is_err());
}

#[test]
fn bad_parameters_are_refused() {
    let c = DVec3::ONE;
    assert!(HomogeneousFog::new(DVec3::new(-1.0, 0.0, 0.0), c).is_err());
    assert!(HomogeneousFog::new(DVec3::new(f64::NAN, 0.0, 0.0), c).is_err());
    assert!(ExponentialMist::new(c, c, 0.0, 0.0).is_err());
    assert!(ExponentialMist::new(c, c, f64::NAN, 1.0).is_err());
    assert!(ExponentialMist::new(c, c, 0.0, -5.0).is_err());
    assert!(RadialAtmosphere::new(c, c, DVec3::ZERO, -1.0, 8000.0).is_err());
    assert!(RadialAtmosphere::new(c, c, DVec3::ZERO, 6e6, f64::INFINITY).is_err());
    assert!(RadialAtmosphere::new(c, c, DVec3::new(f64::NAN, 0.0, 0.0), 6e6, 8e3).is_err());
}
