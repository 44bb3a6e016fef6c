//! Special functions the closed-form optical depths need: the scaled
//! complementary error function `erfcx`, the relative exponential
//! `(1 − e^{−x})/x`, and an adaptive Gauss–Kronrod quadrature used as the
//! oracle in tests and as the fallback for short segments.

/// `1/√π`.
const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// `e^{x²}` with the rounding error of `x²` folded back in (`x² = hi + lo`).
#[inline]
fn exp_x2(x: f64) -> f64 {
    let hi = x * x;
    let lo = x.mul_add(x, -hi);
    libm::exp(hi) * libm::exp(lo)
}

/// Returns the scaled complementary error function `erfcx(x) = e^{x²}·erfc(x)`.
///
/// Finite for every `x ≥ −26.6` (beyond that `2e^{x²}` overflows and the result is
/// `+∞`). For `x ≥ 10` a continued fraction is used, so the value stays accurate
/// where `erfc` alone underflows (x ≳ 26.5): this is what lets a thin,
/// Earth-like radial atmosphere be integrated without the "ozone hole"
/// (Musgrave 1993, §4.1.6.4, where the `erf` difference saturates).
#[must_use]
pub fn erfcx(x: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x < 0.0 {
        // erfc(−x) = 2 − erfc(x)  ⇒  erfcx(x) = 2e^{x²} − erfcx(−x).
        return 2.0 * exp_x2(x) - erfcx(-x);
    }
    if x < 10.0 {
        return exp_x2(x) * libm::erfc(x);
    }
    if x.is_infinite() {
        return 0.0;
    }
    // Laplace's continued fraction erfc(x) = e^{−x²}/√π · 1/(x + (1/2)/(x + 1/(x + (3/2)/(x + …)))),
    // evaluated bottom-up; 40 terms are exact to rounding for x ≥ 10.
    let mut f = x;
    for n in (1..=40).rev() {
        f = x + (n as f64 * 0.5) / f;
    }
    FRAC_1_SQRT_PI / f
}

/// Returns `(1 − e^{−x})/x` (and its limit 1 at `x = 0`), accurate for every finite `x`.
///
/// This is the factor that turns the exponential-mist integral into a robust
/// closed form: never `(e^{−z₁} − e^{−z₂})/(z₂ − z₁)`.
#[inline]
#[must_use]
pub fn exprel_neg(x: f64) -> f64 {
    if x.abs() < 1e-5 {
        // Series 1 − x/2 + x²/6 − x³/24: error below 1e-21 here.
        1.0 - x * (0.5 - x * (1.0 / 6.0 - x / 24.0))
    } else {
        -libm::expm1(-x) / x
    }
}

/// 15-point Kronrod nodes (positive half, descending) and weights, with the
/// embedded 7-point Gauss weights.
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

fn gk15(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = f(c);
    let mut k = fc * WGK[7];
    let mut g = fc * WG[3];
    for i in 0..7 {
        let x = h * XGK[i];
        let s = f(c - x) + f(c + x);
        k += WGK[i] * s;
        if i % 2 == 1 {
            g += WG[i / 2] * s;
        }
    }
    (k * h, ((k - g) * h).abs())
}

/// Returns `∫_a^b f` by adaptive Gauss–Kronrod (7/15) bisection to the relative
/// tolerance `rel_tol` (or absolute `1e-300`), with at most `max_depth` levels.
///
/// Used as the quadrature oracle in tests and for the numeric references.
pub fn integrate(
    mut f: impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    rel_tol: f64,
    max_depth: u32,
) -> f64 {
    #[allow(clippy::too_many_arguments)]
    fn rec(
        f: &mut impl FnMut(f64) -> f64,
        a: f64,
        b: f64,
        whole: (f64, f64),
        tol: f64,
        depth: u32,
        budget: &mut u32,
    ) -> f64 {
        let (v, err) = whole;
        // Stop at the tolerance, at the rounding floor of this piece, or when out of budget.
        if err <= tol || err <= 50.0 * f64::EPSILON * v.abs() || depth == 0 || *budget == 0 {
            return v;
        }
        *budget -= 1;
        let m = 0.5 * (a + b);
        let l = gk15(f, a, m);
        let r = gk15(f, m, b);
        rec(f, a, m, l, 0.5 * tol, depth - 1, budget)
            + rec(f, m, b, r, 0.5 * tol, depth - 1, budget)
    }
    if a == b {
        return 0.0;
    }
    let first = gk15(&mut f, a, b);
    let tol = (rel_tol * first.0.abs()).max(1e-300);
    let mut budget = 20_000;
    rec(&mut f, a, b, first, tol, max_depth, &mut budget)
}

/// 8-point Gauss–Legendre nodes (positive half) and weights on `[−1, 1]`.
const GL8_X: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GL8_W: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// Returns `∫_a^b f` by 8-point Gauss–Legendre (exact for degree-15 polynomials).
#[inline]
pub(crate) fn gauss_legendre8(mut f: impl FnMut(f64) -> f64, a: f64, b: f64) -> f64 {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let mut s = 0.0;
    for i in 0..4 {
        let x = h * GL8_X[i];
        s += GL8_W[i] * (f(c - x) + f(c + x));
    }
    s * h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erfcx_matches_definition_and_asymptote() {
        // Where e^{x²}·erfc(x) is representable, the two agree; across the switch at 10 too.
        for i in 0..=250 {
            let x = -3.0 + i as f64 * 0.1;
            let direct = libm::exp(x * x) * libm::erfc(x);
            let v = erfcx(x);
            assert!(
                (v - direct).abs() <= 2e-13 * direct,
                "x={x}: {v} vs {direct}"
            );
        }
        let below = erfcx(10.0 - 1e-12);
        let above = erfcx(10.0);
        assert!((below - above).abs() < 1e-12 * above);
        // Large x: erfcx(x) ~ 1/(x√π)·(1 − 1/(2x²) + 3/(4x⁴) − 15/(8x⁶)).
        for x in [30.0, 100.0, 1e4, 1e8] {
            let y: f64 = 1.0 / (2.0 * x * x);
            let asym = FRAC_1_SQRT_PI / x * (1.0 - y + 3.0 * y * y - 15.0 * y * y * y);
            assert!(
                (erfcx(x) - asym).abs() < 2e-10 * asym.max(1e-300) / (x * x / 900.0).powi(4),
                "{x}"
            );
        }
        assert_eq!(erfcx(f64::INFINITY), 0.0);
        assert!(erfcx(f64::NAN).is_nan());
        assert!((erfcx(0.0) - 1.0).abs() < 1e-16);
    }

    #[test]
    fn exprel_is_smooth_through_zero() {
        assert_eq!(exprel_neg(0.0), 1.0);
        for x in [
            1e-300, -1e-300, 1e-12, -1e-12, 9.9e-6, 1.01e-5, 0.1, -0.1, 5.0, 700.0,
        ] {
            let exact = if x == 0.0 { 1.0 } else { -libm::expm1(-x) / x };
            let v = exprel_neg(x);
            assert!(
                (v - exact).abs() <= 1e-15 * exact.abs(),
                "{x}: {v} vs {exact}"
            );
        }
    }

    #[test]
    fn quadrature_is_exact_on_known_integrals() {
        let v = integrate(|x| (-x * x).exp(), -5.0, 5.0, 1e-13, 30);
        let exact = std::f64::consts::PI.sqrt() * libm::erf(5.0);
        assert!((v - exact).abs() < 1e-13);
        let g = gauss_legendre8(|x| x.powi(15) + 3.0 * x.powi(4), 0.0, 1.0);
        assert!((g - (1.0 / 16.0 + 3.0 / 5.0)).abs() < 1e-15);
    }
}
