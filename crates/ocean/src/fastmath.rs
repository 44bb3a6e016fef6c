//! Branch-free `f32` sine and cosine for the per-frame phase factors.
//!
//! Written as plain arithmetic and selects so the compiler vectorises the
//! loops that call it; the phase itself is reduced in `f64` first (see
//! [`phase`]) so long times stay accurate.

/// Returns `(sin θ, cos θ)` for `θ ∈ [−π, π]`, absolute error below 2e-7.
///
/// Quadrant reduction by π/2 (Cody–Waite split constant), then the minimax
/// polynomials of Cephes' `sinf`/`cosf` on [−π/4, π/4].
#[inline(always)]
pub(crate) fn sin_cos(theta: f32) -> (f32, f32) {
    const TWO_OVER_PI: f32 = std::f32::consts::FRAC_2_PI;
    const PIO2_HI: f32 = 1.570_312_5;
    const PIO2_LO: f32 = 4.838_268e-4;
    // Round to nearest with the 1.5·2²³ trick, which vectorises on plain SSE2.
    const MAGIC: f32 = 12_582_912.0;
    let qm = theta * TWO_OVER_PI + MAGIC;
    let q = qm - MAGIC;
    let r = (theta - q * PIO2_HI) - q * PIO2_LO;
    let r2 = r * r;
    let s = r + r * r2 * (-1.666_665_5e-1 + r2 * (8.332_161e-3 + r2 * -1.951_529_6e-4));
    let c =
        1.0 - 0.5 * r2 + r2 * r2 * (4.166_664_6e-2 + r2 * (-1.388_731_6e-3 + r2 * 2.443_315_7e-5));
    // `qm`'s mantissa holds 2²² + q, so its low bits are q's (mod 4); reading
    // them from the bits, and flipping signs by xor, keeps the loop free of
    // float → int conversions and branches, so it vectorises.
    let qi = qm.to_bits();
    let swap = qi & 1 != 0;
    let (a, b) = (if swap { c } else { s }, if swap { s } else { c });
    let sa = f32::from_bits(a.to_bits() ^ ((qi & 2) << 30));
    let cb = f32::from_bits(b.to_bits() ^ ((qi.wrapping_add(1) & 2) << 30));
    (sa, cb)
}

/// Returns 2π·frac(`cycles`) in `[−π, π]` as `f32`: the phase of a wave that
/// has run `cycles` periods, reduced in `f64` so large times keep precision.
#[inline(always)]
pub(crate) fn phase(cycles: f64) -> f32 {
    // Round to nearest with the 1.5·2⁵² trick (vectorises without SSE4.1's
    // `roundpd`); exact for |cycles| < 2⁵¹.
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    let nearest = (cycles + MAGIC) - MAGIC;
    ((cycles - nearest) * std::f64::consts::TAU) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sin_cos_is_accurate_over_the_range() {
        let n = 200_001;
        let mut worst = 0.0f64;
        for i in 0..n {
            let t = -std::f64::consts::PI + std::f64::consts::TAU * i as f64 / (n - 1) as f64;
            let (s, c) = sin_cos(t as f32);
            let tf = f64::from(t as f32);
            worst = worst
                .max((f64::from(s) - tf.sin()).abs())
                .max((f64::from(c) - tf.cos()).abs());
        }
        assert!(worst < 2e-7, "worst error {worst}");
    }

    #[test]
    fn phase_reduces_large_cycle_counts() {
        for &(c, want) in &[
            (0.25, 0.5 * std::f64::consts::PI),
            (1e7 + 0.25, 0.5 * std::f64::consts::PI),
            (-3.5, std::f64::consts::PI),
        ] {
            let p = f64::from(phase(c));
            assert!((p.abs() - want.abs()).abs() < 1e-6, "{c} → {p}");
        }
        assert_eq!(phase(12.0), 0.0);
    }
}
