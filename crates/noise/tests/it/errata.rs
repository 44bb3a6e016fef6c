//! Errata of the sources that natura-noise corrects, each pinned by a test
//! that tells the corrected reading from the printed one.

use glam::DVec3;
use natura_noise::*;

/// Musgrave 1993, §5.2: the dissertation's C `VLNoise(p, scale)` is
/// `N(scale·p + DNoise(p))`; the section's pseudo-code adds a `+0.5`
/// misregistration and no scale. natura follows the C: checked here against
/// that formula built independently (the gradient `DNoise` by central
/// differences of the basis, not the basis's analytic gradient), and shown
/// to differ from the pseudo-code's `N(p + 0.5 + DNoise(p))`.
#[test]
fn vl_noise_is_the_c_form_not_the_pseudo_code() {
    let basis = Perlin::new(29);
    let scale = 1.5;
    let vl = VlNoise::vl_noise(basis, scale).unwrap();
    let dnoise = |p: DVec3| {
        let h = 1e-5;
        let d = |e: DVec3| (basis.eval3(p + e * h) - basis.eval3(p - e * h)) / (2.0 * h);
        DVec3::new(d(DVec3::X), d(DVec3::Y), d(DVec3::Z))
    };
    let (mut worst_c, mut mean_pseudo) = (0.0f64, 0.0f64);
    let n = 2000;
    for i in 0..n {
        let t = i as f64;
        let p = DVec3::new(
            (t * 0.618_034).fract() * 40.0 - 20.0,
            (t * 0.414_214).fract() * 40.0 - 20.0,
            (t * 0.732_051).fract() * 40.0 - 20.0,
        );
        let v = vl.eval3(p);
        let c_form = basis.eval3(scale * p + dnoise(p));
        let pseudo = basis.eval3(p + DVec3::splat(0.5) + dnoise(p));
        worst_c = worst_c.max((v - c_form).abs());
        mean_pseudo += (v - pseudo).abs() / f64::from(n);
    }
    assert!(worst_c < 1e-6, "C form: worst difference {worst_c}");
    assert!(
        mean_pseudo > 0.1,
        "pseudo-code: mean difference {mean_pseudo}"
    );
}
