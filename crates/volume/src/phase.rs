//! CloudPhase functions for clouds and gases, `1/(4π)`-normalised, with sampling.
//!
//! The angle is between the propagation directions before and after
//! scattering; for a camera ray `d` and a light toward `l`, `cos θ = d·l`.

use std::f32::consts::PI;

use glam::Vec3;

use crate::error::{Result, in_range};

const INV_4PI: f32 = 1.0 / (4.0 * PI);

/// Henyey–Greenstein `(1 − g²)/(4π(1 + g² − 2g cos θ)^{3/2})` (Henyey & Greenstein 1941,
/// eq. 3): natura-atmos' phase function, in `f32`.
pub use natura_atmos::scatter::henyey_greenstein_f32 as henyey_greenstein;

/// Draine's phase function `HG(g)·(1 + α cos²θ)/(1 + α(1 + 2g²)/3)`
/// (Jendersie & d'Eon 2023, eq. 4; α = 0 is Henyey–Greenstein, g = 0, α = 1 Rayleigh).
#[inline]
#[must_use]
pub fn draine(g: f32, alpha: f32, cos_theta: f32) -> f32 {
    henyey_greenstein(g, cos_theta) * (1.0 + alpha * cos_theta * cos_theta)
        / (1.0 + alpha * (1.0 + 2.0 * g * g) / 3.0)
}

/// The mean cosine of Draine's function: `g(1 + α(3 + 2g²)/5)/(1 + α(1 + 2g²)/3)`.
#[inline]
#[must_use]
pub fn draine_mean_cosine(g: f32, alpha: f32) -> f32 {
    g * (1.0 + alpha * (3.0 + 2.0 * g * g) / 5.0) / (1.0 + alpha * (1.0 + 2.0 * g * g) / 3.0)
}

/// A phase function.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum CloudPhase {
    /// `1/(4π)`.
    Isotropic,
    /// Henyey–Greenstein with asymmetry `g ∈ (−1, 1)`.
    HenyeyGreenstein(f32),
    /// `(1 − w)·HG(g_forward) + w·HG(g_back)`: a forward peak and a back lobe.
    DualHenyeyGreenstein {
        /// Forward asymmetry (usually > 0).
        forward: f32,
        /// Backward asymmetry (usually < 0).
        back: f32,
        /// Weight of the back lobe in `[0, 1]`.
        weight: f32,
    },
    /// Draine's phase function with asymmetry `g ∈ (−1, 1)` and `alpha ≥ 0`
    /// (Jendersie & d'Eon 2023, eq. 4).
    Draine {
        /// Asymmetry parameter (not the mean cosine unless `alpha = 0`).
        g: f32,
        /// DensityShaping parameter `α ≥ 0` (0: Henyey–Greenstein).
        alpha: f32,
    },
    /// The HG + Draine blend fitted to Mie scattering by water droplets of
    /// the given diameter in µm, `[5, 50]` (Jendersie & d'Eon 2023, eqs. 4–8).
    Cloud {
        /// Droplet diameter (µm).
        diameter_um: f32,
    },
}

impl Default for CloudPhase {
    /// The cloud phase for 20 µm droplets (typical cumulus).
    fn default() -> Self {
        CloudPhase::Cloud { diameter_um: 20.0 }
    }
}

/// The four parameters of the HG + Draine fit for droplet diameter `d` (µm):
/// `(g_HG, g_D, α, w_D)`.
#[must_use]
pub fn cloud_fit(d: f32) -> (f32, f32, f32, f32) {
    let g_hg = (-0.099_056_7 / (d - 1.671_54)).exp();
    let g_d = (-2.206_79 / (d + 3.910_29) - 0.428_934).exp();
    let alpha = (3.624_89 - 8.292_88 / (d + 5.528_25)).exp();
    let w_d = (-0.599_085 / (d - 0.641_583) - 0.665_888).exp();
    (g_hg, g_d, alpha, w_d)
}

impl CloudPhase {
    /// Checks the parameters.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter) for `|g| ≥ 1`, a weight outside
    /// `[0, 1]`, a diameter outside `[5, 50]` µm, or NaN.
    pub fn validate(&self) -> Result<()> {
        const G: &str = "asymmetry must lie in [−0.99, 0.99]";
        match *self {
            CloudPhase::Isotropic => {}
            CloudPhase::HenyeyGreenstein(g) => {
                in_range("g", g, -0.99, 0.99, G)?;
            }
            CloudPhase::DualHenyeyGreenstein {
                forward,
                back,
                weight,
            } => {
                in_range("forward", forward, -0.99, 0.99, G)?;
                in_range("back", back, -0.99, 0.99, G)?;
                in_range("weight", weight, 0.0, 1.0, "must lie in [0, 1]")?;
            }
            CloudPhase::Draine { g, alpha } => {
                in_range("g", g, -0.99, 0.99, G)?;
                in_range("alpha", alpha, 0.0, 1e3, "must lie in [0, 1000]")?;
            }
            CloudPhase::Cloud { diameter_um } => {
                in_range(
                    "diameter_um",
                    diameter_um,
                    5.0,
                    50.0,
                    "must lie in [5, 50] µm",
                )?;
            }
        }
        Ok(())
    }

    /// The phase function at `cos_theta`, per steradian.
    #[inline]
    #[must_use]
    pub fn eval(&self, cos_theta: f32) -> f32 {
        match *self {
            CloudPhase::Isotropic => INV_4PI,
            CloudPhase::HenyeyGreenstein(g) => henyey_greenstein(g, cos_theta),
            CloudPhase::DualHenyeyGreenstein {
                forward,
                back,
                weight,
            } => {
                (1.0 - weight) * henyey_greenstein(forward, cos_theta)
                    + weight * henyey_greenstein(back, cos_theta)
            }
            CloudPhase::Draine { g, alpha } => draine(g, alpha, cos_theta),
            CloudPhase::Cloud { diameter_um } => {
                let (g_hg, g_d, alpha, w_d) = cloud_fit(diameter_um);
                (1.0 - w_d) * henyey_greenstein(g_hg, cos_theta)
                    + w_d * draine(g_d, alpha, cos_theta)
            }
        }
    }

    /// The mean cosine (the effective asymmetry `g`).
    #[must_use]
    pub fn mean_cosine(&self) -> f32 {
        match *self {
            CloudPhase::Isotropic => 0.0,
            CloudPhase::HenyeyGreenstein(g) => g,
            CloudPhase::DualHenyeyGreenstein {
                forward,
                back,
                weight,
            } => (1.0 - weight) * forward + weight * back,
            CloudPhase::Draine { g, alpha } => draine_mean_cosine(g, alpha),
            CloudPhase::Cloud { diameter_um } => {
                let (g_hg, g_d, alpha, w_d) = cloud_fit(diameter_um);
                (1.0 - w_d) * g_hg + w_d * draine_mean_cosine(g_d, alpha)
            }
        }
    }

    /// The same function with its asymmetry scaled by `c` (the octave
    /// method's `c^i`; isotropic is unchanged).
    #[must_use]
    pub fn scaled(&self, c: f32) -> CloudPhase {
        match *self {
            CloudPhase::Isotropic => CloudPhase::Isotropic,
            CloudPhase::HenyeyGreenstein(g) => CloudPhase::HenyeyGreenstein(g * c),
            CloudPhase::DualHenyeyGreenstein {
                forward,
                back,
                weight,
            } => CloudPhase::DualHenyeyGreenstein {
                forward: forward * c,
                back: back * c,
                weight,
            },
            CloudPhase::Draine { .. } | CloudPhase::Cloud { .. } => {
                CloudPhase::HenyeyGreenstein(self.mean_cosine() * c)
            }
        }
    }

    /// The forward diffraction peak split off: `(f, rest)` with `f` the
    /// fraction of scattering into a lobe a fraction of a degree wide and
    /// `rest` the normalised phase function of the other `1 − f`
    /// (`(0, self)` for a phase function without such a lobe). For
    /// [`CloudPhase::Cloud`] the peak is the fit's Henyey–Greenstein lobe
    /// (`g ≥ 0.97` over the fit's range of diameters) and the rest its Draine lobe.
    #[must_use]
    pub fn forward_peak(&self) -> (f32, CloudPhase) {
        match *self {
            CloudPhase::Cloud { diameter_um } => {
                let (_, g_d, alpha, w_d) = cloud_fit(diameter_um);
                (1.0 - w_d, CloudPhase::Draine { g: g_d, alpha })
            }
            p => (0.0, p),
        }
    }

    /// The forward diffraction peak as a Henyey–Greenstein lobe: `(f, g)`,
    /// the fraction of scattering into it and its asymmetry, when this phase
    /// function has one (see [`CloudPhase::forward_peak`]).
    #[must_use]
    pub fn peak_lobe(&self) -> Option<(f32, f32)> {
        match *self {
            CloudPhase::Cloud { diameter_um } => {
                let (g_hg, _, _, w_d) = cloud_fit(diameter_um);
                Some((1.0 - w_d, g_hg))
            }
            _ => None,
        }
    }

    /// The lobes this phase function mixes: `(g, α, weight)` of two Draine
    /// lobes (`α = 0` is Henyey–Greenstein; the second's weight is 0 for a
    /// single lobe).
    fn lobes(&self) -> [(f32, f32, f32); 2] {
        match *self {
            CloudPhase::Isotropic => [(0.0, 0.0, 1.0), (0.0, 0.0, 0.0)],
            CloudPhase::HenyeyGreenstein(g) => [(g, 0.0, 1.0), (0.0, 0.0, 0.0)],
            CloudPhase::DualHenyeyGreenstein {
                forward,
                back,
                weight,
            } => [(forward, 0.0, 1.0 - weight), (back, 0.0, weight)],
            CloudPhase::Draine { g, alpha } => [(g, alpha, 1.0), (0.0, 0.0, 0.0)],
            CloudPhase::Cloud { diameter_um } => {
                let (g_hg, g_d, alpha, w_d) = cloud_fit(diameter_um);
                [(g_hg, 0.0, 1.0 - w_d), (g_d, alpha, w_d)]
            }
        }
    }

    /// Draws a new direction about the unit direction `d` exactly from the
    /// phase function (solid-angle density [`CloudPhase::eval`]), with
    /// uniforms in `[0, 1)` from `next`: a lobe of the mixture by its weight,
    /// a Henyey–Greenstein lobe by its inverse CDF (Pharr et al. 2023,
    /// §11.3.1), and a Draine lobe `HG(g)·(1 + α cos²θ)/K` by rejection from
    /// `HG(g)`, accepting with probability `(1 + α cos²θ)/(1 + α)` (von
    /// Neumann 1951; the acceptance rate is `(1 + α(1 + 2g²)/3)/(1 + α)`,
    /// at least ⅓). Exact sampling keeps a path's weight the albedo's
    /// alone: a proposal's weights `p/pdf`, each of mean 1, multiply over
    /// the hundreds of scatterings of a path through thick cloud into a
    /// heavy-tailed estimate.
    #[must_use]
    pub fn sample(&self, d: Vec3, next: &mut impl FnMut() -> f32) -> Vec3 {
        let [first, second] = self.lobes();
        let (g, alpha, _) = if second.2 > 0.0 && next() < second.2 {
            second
        } else {
            first
        };
        let cos = loop {
            let c = sample_hg_cos(g, next());
            if alpha <= 0.0 || next() * (1.0 + alpha) < 1.0 + alpha * c * c {
                break c;
            }
        };
        direction_about(d, cos, next())
    }
}

/// The unit direction at `cos` from the unit `axis`, at azimuth `2πu`.
fn direction_about(axis: Vec3, cos: f32, u: f32) -> Vec3 {
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u;
    let (t, b) = axis.any_orthonormal_pair();
    (t * (sin * phi.cos()) + b * (sin * phi.sin()) + axis * cos).normalize()
}

/// A direction drawn about the unit `axis` from the Henyey–Greenstein lobe
/// of asymmetry `g` (solid-angle density `HG(g, cos θ)`), from uniforms
/// `u ∈ [0, 1)²` (Pharr et al. 2023, §11.3.1).
#[must_use]
pub fn sample_hg(g: f32, axis: Vec3, u: [f32; 2]) -> Vec3 {
    direction_about(axis, sample_hg_cos(g, u[0]), u[1])
}

/// Inverse-CDF sample of the HG cosine (Pharr et al. 2023, §11.3.1).
#[inline]
fn sample_hg_cos(g: f32, u: f32) -> f32 {
    if g.abs() < 1e-3 {
        return 1.0 - 2.0 * u;
    }
    let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u);
    ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn integrate(p: &CloudPhase) -> (f64, f64) {
        // ∫ p dω = 2π ∫ p(μ) dμ, midpoint rule in t with 1 − μ = 2t³, which
        // crowds the nodes into the forward peak (dμ = 6t² dt).
        let n = 400_000;
        let (mut s, mut m) = (0.0f64, 0.0f64);
        for i in 0..n {
            let t = (i as f64 + 0.5) / n as f64;
            let mu = 1.0 - 2.0 * t * t * t;
            let w = 6.0 * t * t;
            let v = f64::from(p.eval(mu as f32)) * w;
            s += v;
            m += v * mu;
        }
        let k = 2.0 * std::f64::consts::PI / n as f64;
        (s * k, m * k)
    }

    #[test]
    fn every_phase_is_normalised_and_has_its_mean_cosine() {
        for p in [
            CloudPhase::Isotropic,
            CloudPhase::HenyeyGreenstein(0.6),
            CloudPhase::HenyeyGreenstein(-0.3),
            CloudPhase::DualHenyeyGreenstein {
                forward: 0.8,
                back: -0.3,
                weight: 0.2,
            },
            CloudPhase::Draine {
                g: 0.594,
                alpha: 27.0,
            },
            CloudPhase::Cloud { diameter_um: 5.0 },
            CloudPhase::Cloud { diameter_um: 20.0 },
            CloudPhase::Cloud { diameter_um: 50.0 },
        ] {
            p.validate().unwrap();
            let (norm, mean) = integrate(&p);
            assert!((norm - 1.0).abs() < 2e-3, "{p:?}: ∫p = {norm}");
            assert!(
                (mean - f64::from(p.mean_cosine())).abs() < 3e-3,
                "{p:?}: {mean}"
            );
        }
    }

    #[test]
    fn cloud_phase_is_strongly_forward_like_mie() {
        let p = CloudPhase::Cloud { diameter_um: 20.0 };
        let g = p.mean_cosine();
        assert!((0.8..0.95).contains(&g), "{g}");
        assert!(p.eval(1.0) > 100.0 * p.eval(0.0));
        assert!(CloudPhase::Cloud { diameter_um: 2.0 }.validate().is_err());
        assert!(CloudPhase::HenyeyGreenstein(f32::NAN).validate().is_err());
    }

    #[test]
    fn the_forward_peak_and_the_rest_make_up_the_cloud_phase() {
        for d in [5.0f32, 20.0, 50.0] {
            let p = CloudPhase::Cloud { diameter_um: d };
            let (f, rest) = p.forward_peak();
            let (g_hg, ..) = cloud_fit(d);
            assert!((0.3..0.7).contains(&f) && g_hg >= 0.97, "{d}: {f} {g_hg}");
            // p = f·HG(g_hg) + (1 − f)·rest, at every angle.
            for mu in [-1.0f32, -0.3, 0.0, 0.5, 0.9, 0.99, 1.0] {
                let sum = f * henyey_greenstein(g_hg, mu) + (1.0 - f) * rest.eval(mu);
                assert!((sum - p.eval(mu)).abs() <= 1e-4 * p.eval(mu), "{d} {mu}");
            }
            let g = f * g_hg + (1.0 - f) * rest.mean_cosine();
            assert!((g - p.mean_cosine()).abs() < 1e-5);
        }
        assert_eq!(CloudPhase::HenyeyGreenstein(0.5).forward_peak().0, 0.0);
        assert!(
            CloudPhase::Draine {
                g: 0.5,
                alpha: -1.0
            }
            .validate()
            .is_err()
        );
    }

    #[test]
    fn sampling_follows_the_phase_function() {
        // A histogram of the sampled cosines against the phase function
        // integrated over each bin (exact sampling: no weights).
        let d = Vec3::new(0.3, -0.4, 0.866).normalize();
        for p in [
            CloudPhase::Isotropic,
            CloudPhase::HenyeyGreenstein(0.7),
            CloudPhase::DualHenyeyGreenstein {
                forward: 0.8,
                back: -0.4,
                weight: 0.3,
            },
            CloudPhase::Cloud { diameter_um: 5.0 },
            CloudPhase::Cloud { diameter_um: 15.0 },
            CloudPhase::Draine {
                g: 0.6,
                alpha: 20.0,
            },
            CloudPhase::Draine {
                g: -0.2,
                alpha: 500.0,
            },
        ] {
            let n = 400_000usize;
            let bins = 16usize;
            let mut hist = vec![0usize; bins];
            let mut mean = 0.0f64;
            let mut state = 0x1234_5678u32;
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                (state >> 8) as f32 / (1u32 << 24) as f32
            };
            for _ in 0..n {
                let o = p.sample(d, &mut next);
                assert!((o.length() - 1.0).abs() < 1e-4);
                let c = o.dot(d).clamp(-1.0, 1.0);
                mean += f64::from(c);
                hist[(((c + 1.0) * 0.5 * bins as f32) as usize).min(bins - 1)] += 1;
            }
            mean /= n as f64;
            assert!(
                (mean - f64::from(p.mean_cosine())).abs() < 0.005,
                "{p:?}: {mean}"
            );
            for (k, &h) in hist.iter().enumerate() {
                // 2π ∫ p dμ over the bin, by the midpoint rule in `s` with
                // `μ = hi − (hi − lo)s³`, which crowds the nodes toward the
                // bin's upper end (the forward peak of the last bin).
                let m = 4000;
                let width = 2.0 / bins as f64;
                let hi = -1.0 + width * (k + 1) as f64;
                let expect: f64 = (0..m)
                    .map(|i| {
                        let t = (i as f64 + 0.5) / m as f64;
                        let mu = hi - width * t * t * t;
                        let dmu = 3.0 * width * t * t / m as f64;
                        2.0 * std::f64::consts::PI * f64::from(p.eval(mu as f32)) * dmu
                    })
                    .sum::<f64>()
                    * n as f64;
                let sigma = expect.sqrt().max(1.0);
                assert!(
                    (h as f64 - expect).abs() < 5.0 * sigma + 1e-3 * expect,
                    "{p:?} bin {k}: {h} against {expect:.0}"
                );
            }
        }
    }
}
