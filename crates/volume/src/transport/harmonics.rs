//! The spherical harmonics the multiple-scattering cache stores its light
//! in ([`super::cache`]): the real basis, the zonal harmonics about an
//! axis, a phase function's Legendre moments, Lanczos' σ-factors, and the
//! dot product that reads a cell. The cache's photons and its lookups call
//! these; nothing here knows about grids.

use glam::Vec3;

/// The highest spherical-harmonic band the cache stores.
pub const MAX_ORDER: usize = 7;
/// Most coefficients of the full series (bands `0..=MAX_ORDER`).
pub const MAX_COEFFS: usize = (MAX_ORDER + 1) * (MAX_ORDER + 1);
/// The highest band of the zonal tail.
pub const MAX_ZONAL: usize = 31;
/// Most coefficients per cell: the full series and the longest zonal tail.
pub(crate) const MAX_CELL: usize = MAX_COEFFS + MAX_ZONAL - 1;

/// The zonal harmonics `Y_l0` about an axis, `√((2l+1)/(4π))·P_l(μ)` at
/// `μ = d·axis`, of bands `order + 1 ..= zonal` into `out[0..zonal − order]`
/// (Legendre's three-term recurrence from `P₀ = 1`, `P₁ = μ`).
pub(crate) fn zonal_basis(order: usize, zonal: usize, mu: f32, out: &mut [f32]) {
    let mu = f64::from(mu);
    let (mut p0, mut p1) = (1.0f64, mu);
    for l in 2..=zonal {
        let p2 = ((2 * l - 1) as f64 * mu * p1 - (l - 1) as f64 * p0) / l as f64;
        p0 = p1;
        p1 = p2;
        if l > order {
            let k = ((2 * l + 1) as f64 / (4.0 * std::f64::consts::PI)).sqrt();
            out[l - order - 1] = (k * p2) as f32;
        }
    }
}

/// The real spherical harmonics `Y_lm(d)` of bands `0..=order` at unit `d`
/// into `out[l² + l + m]`, orthonormal on the sphere: the associated
/// Legendre functions by their three-term recurrence in `l` (with the
/// `sin^m θ` factor carried by `(x + iy)^m`, so no angle is computed) and
/// the normalisation `√((2l+1)/(4π)·(l−m)!/(l+m)!)`, times `√2` for
/// `m ≠ 0` (Sloan 2008, "Stupid Spherical Harmonics Tricks", §2 and
/// appendix A1; the sign convention of `m` does not matter here, since the
/// same basis scores and reads the cache).
pub fn sh_basis(order: usize, d: Vec3, out: &mut [f32; MAX_COEFFS]) {
    let (x, y, z) = (f64::from(d.x), f64::from(d.y), f64::from(d.z));
    let (mut cm, mut sm) = (1.0f64, 0.0f64);
    let mut pmm = 1.0f64;
    for m in 0..=order {
        if m > 0 {
            let (c, s) = (cm * x - sm * y, cm * y + sm * x);
            cm = c;
            sm = s;
            pmm *= (2 * m - 1) as f64;
        }
        let (mut p_prev, mut p) = (0.0f64, pmm);
        for l in m..=order {
            if l > m {
                let next =
                    ((2 * l - 1) as f64 * z * p - (l + m - 1) as f64 * p_prev) / (l - m) as f64;
                p_prev = p;
                p = next;
            }
            let k = norms()[l * l + l + m] * p;
            let at = l * l + l;
            if m == 0 {
                out[at] = k as f32;
            } else {
                let r = std::f64::consts::SQRT_2 * k;
                out[at + m] = (r * cm) as f32;
                out[at - m] = (r * sm) as f32;
            }
        }
    }
}

/// `√((2l+1)/(4π)·(l−m)!/(l+m)!)` at `l² + l + m` for `0 ≤ m ≤ l ≤
/// MAX_ORDER`, computed once: [`sh_basis`] runs at every scattering event
/// of the cache's photons.
fn norms() -> &'static [f64; MAX_COEFFS] {
    static NORMS: std::sync::OnceLock<[f64; MAX_COEFFS]> = std::sync::OnceLock::new();
    NORMS.get_or_init(|| {
        let mut t = [0.0f64; MAX_COEFFS];
        for l in 0..=MAX_ORDER {
            for m in 0..=l {
                let mut k = (2 * l + 1) as f64 / (4.0 * std::f64::consts::PI);
                for i in (l - m + 1)..=(l + m) {
                    k /= i as f64;
                }
                t[l * l + l + m] = k.sqrt();
            }
        }
        t
    })
}

/// The Legendre moments `χ_l = 2π ∫ p(μ) P_l(μ) dμ` of a phase function,
/// `l = 0..=MAX_ZONAL` (`χ₀ = 1`, `χ₁` the mean cosine; for
/// Henyey–Greenstein `g^l`), by the midpoint rule in `t` with
/// `1 − μ = 2t³`, which crowds the nodes into a forward peak.
#[must_use]
pub fn legendre_moments(phase: &crate::phase::CloudPhase) -> [f32; MAX_ZONAL + 1] {
    let n = 200_000;
    let mut m = [0.0f64; MAX_ZONAL + 1];
    for i in 0..n {
        let t = (i as f64 + 0.5) / n as f64;
        let mu = 1.0 - 2.0 * t * t * t;
        let w = 6.0 * t * t / n as f64 * 2.0 * std::f64::consts::PI;
        let p = f64::from(phase.eval(mu as f32)) * w;
        let (mut p0, mut p1) = (1.0, mu);
        m[0] += p;
        m[1] += p * mu;
        for (l, ml) in m.iter_mut().enumerate().skip(2) {
            let p2 = ((2 * l - 1) as f64 * mu * p1 - (l - 1) as f64 * p0) / l as f64;
            *ml += p * p2;
            p0 = p1;
            p1 = p2;
        }
    }
    // Normalised by the quadrature's own χ₀, as the phase integrates to 1.
    let mut out = [0.0f32; MAX_ZONAL + 1];
    for (o, v) in out.iter_mut().zip(&m) {
        *o = (v / m[0]) as f32;
    }
    out
}

/// Lanczos' σ-factor of band `l` of a series cut after band `order`,
/// `sinc(π l/(order + 1))`: it damps the ringing of the cut series
/// (Gibbs' phenomenon; Lanczos 1956, ch. IV §6; Sloan 2008, §4 on
/// windowing spherical harmonics), so a forward-peaked radiance seen
/// sideways or backwards is not driven negative and clamped.
#[must_use]
pub fn sigma_factor(l: usize, order: usize) -> f32 {
    if l == 0 {
        return 1.0;
    }
    let x = std::f32::consts::PI * l as f32 / (order + 1) as f32;
    x.sin() / x
}

/// `Σ a_i b_i` over `a`'s length (`b` at least as long), in eight lanes
/// the compiler keeps in vector registers.
#[inline]
pub(crate) fn dot(a: &[f32], b: &[f32]) -> f32 {
    let b = &b[..a.len()];
    let mut acc = [0.0f32; 8];
    let (ca, cb) = (a.chunks_exact(8), b.chunks_exact(8));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f32 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    let (lo, hi) = acc.split_at(4);
    (lo[0] + hi[0]) + (lo[1] + hi[1]) + (lo[2] + hi[2]) + (lo[3] + hi[3]) + tail
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::phase::CloudPhase;

    #[test]
    fn the_basis_is_orthonormal() {
        // Fibonacci-sphere quadrature of ∫ Y_i Y_j dω.
        let n = 200_000;
        let mut gram = vec![0.0f64; MAX_COEFFS * MAX_COEFFS];
        let ga = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let mut y = [0.0f32; MAX_COEFFS];
        for i in 0..n {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = ga * i as f64;
            let d = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
            sh_basis(MAX_ORDER, d, &mut y);
            for a in 0..MAX_COEFFS {
                for b in 0..MAX_COEFFS {
                    gram[a * MAX_COEFFS + b] += f64::from(y[a]) * f64::from(y[b]);
                }
            }
        }
        let w = 4.0 * std::f64::consts::PI / n as f64;
        for a in 0..MAX_COEFFS {
            for b in 0..MAX_COEFFS {
                let v = gram[a * MAX_COEFFS + b] * w;
                let want = if a == b { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 2e-3, "⟨Y{a}, Y{b}⟩ = {v}");
            }
        }
    }

    #[test]
    fn henyey_greenstein_moments_are_powers_of_g() {
        for g in [0.0f32, 0.3, 0.8, -0.3] {
            let m = legendre_moments(&CloudPhase::HenyeyGreenstein(g));
            for (l, v) in m.iter().enumerate() {
                let want = g.powi(l as i32);
                assert!((v - want).abs() < 2e-3, "g {g} l {l}: {v} vs {want}");
            }
        }
    }
}
