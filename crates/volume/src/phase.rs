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
    /// [`CloudPhase::Cloud`] without the core of its forward peak, renormalised:
    /// its Draine lobe and the part of its Henyey–Greenstein lobe more than
    /// `cut_deg` from the forward direction. The phase function the fast
    /// mode's transport medium scatters with when it treats the peak's core
    /// as unscattered light (see [`CloudPhase::peak_core`]).
    CloudWithoutCore {
        /// Droplet diameter (µm).
        diameter_um: f32,
        /// The core's half-angle (degrees), in `(0, 90]`.
        cut_deg: f32,
    },
}

/// The core of a phase function's forward peak, split off by
/// [`CloudPhase::peak_core`]: the part of the peak's Henyey–Greenstein
/// lobe within `cos_cut` of the forward direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakCore {
    /// The core's share of all scattering, `f·c` (`f` the peak's, `c` the
    /// share of the peak's lobe within the cut).
    pub weight: f32,
    /// The peak lobe's asymmetry.
    pub g: f32,
    /// The cosine of the core's half-angle.
    pub cos_cut: f32,
    /// The share `c` of the lobe within the cut.
    pub lobe_share: f32,
    /// The core's mean cosine.
    pub mean_cosine: f32,
    /// The phase function of the other `1 − f·c`, normalised.
    pub rest: CloudPhase,
}

impl PeakCore {
    /// The core's phase function at `cos_theta`, normalised over the sphere:
    /// `HG(g, cos θ)/c` within the cut, zero outside.
    #[inline]
    #[must_use]
    pub fn eval(&self, cos_theta: f32) -> f32 {
        if cos_theta >= self.cos_cut {
            henyey_greenstein(self.g, cos_theta) / self.lobe_share
        } else {
            0.0
        }
    }
}

/// The half-angle of the forward peak's core that the fast mode treats as
/// unscattered (degrees): [`CloudPhase::peak_core`] at this angle is
/// [`MediumParams::without_forward_peak`](crate::transport::MediumParams::without_forward_peak)'s
/// split. About the angular resolution of the multiple-scattering cache's
/// spherical harmonics (band 7: `180°/8`).
pub const PEAK_CORE_DEG: f32 = 20.0;

/// The share of a Henyey–Greenstein lobe of asymmetry `g` at cosines below
/// `mu`: `(1 − g²)/(2g)·(1/√s − 1/(1 + g))` with `s = 1 + g² − 2gμ`.
#[must_use]
pub fn hg_share_below(g: f32, mu: f32) -> f32 {
    let (g, mu) = (f64::from(g), f64::from(mu.clamp(-1.0, 1.0)));
    if g.abs() < 1e-6 {
        return ((mu + 1.0) / 2.0) as f32;
    }
    let s = 1.0 + g * g - 2.0 * g * mu;
    ((1.0 - g * g) / (2.0 * g) * (1.0 / s.sqrt() - 1.0 / (1.0 + g))) as f32
}

/// `∫ μ·HG(g, μ) dω` over the cosines below `mu`: the first moment of
/// that part, `(1 − g²)/(4g²)·[(1 + g²)/√s + √s]` between `s = 1 + g² − 2gμ`
/// and `(1 + g)²` (the whole sphere gives `g`).
#[must_use]
pub fn hg_moment_below(g: f32, mu: f32) -> f32 {
    let (g, mu) = (f64::from(g), f64::from(mu.clamp(-1.0, 1.0)));
    if g.abs() < 1e-6 {
        return ((mu * mu - 1.0) / 4.0) as f32;
    }
    let h = |s: f64| (1.0 + g * g) / s.sqrt() + s.sqrt();
    let s = 1.0 + g * g - 2.0 * g * mu;
    ((1.0 - g * g) / (4.0 * g * g) * (h(s) - h((1.0 + g) * (1.0 + g)))) as f32
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
            CloudPhase::CloudWithoutCore {
                diameter_um,
                cut_deg,
            } => {
                CloudPhase::Cloud { diameter_um }.validate()?;
                if !(cut_deg > 0.0 && cut_deg <= 90.0) {
                    return Err(crate::VolumeError::InvalidParameter {
                        name: "cut_deg",
                        value: cut_deg.to_string(),
                        expected: "the peak core's half-angle, in (0, 90] degrees",
                    });
                }
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
            CloudPhase::CloudWithoutCore {
                diameter_um,
                cut_deg,
            } => {
                let r = WithoutCore::new(diameter_um, cut_deg);
                let hg = if cos_theta < r.cos_cut {
                    (1.0 - r.w_d) * henyey_greenstein(r.g_hg, cos_theta)
                } else {
                    0.0
                };
                (hg + r.w_d * draine(r.g_d, r.alpha, cos_theta)) / r.total
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
            CloudPhase::CloudWithoutCore {
                diameter_um,
                cut_deg,
            } => {
                let r = WithoutCore::new(diameter_um, cut_deg);
                ((1.0 - r.w_d) * hg_moment_below(r.g_hg, r.cos_cut)
                    + r.w_d * draine_mean_cosine(r.g_d, r.alpha))
                    / r.total
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
            CloudPhase::Draine { .. }
            | CloudPhase::Cloud { .. }
            | CloudPhase::CloudWithoutCore { .. } => {
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

    /// The core of the forward peak, within `cut_deg` of the forward
    /// direction, split off: the part of the peak's lobe
    /// ([`CloudPhase::peak_lobe`]) narrow enough to count as unscattered,
    /// and the phase function of the rest, which keeps the lobe's wider
    /// part ([`CloudPhase::CloudWithoutCore`]). `None` without a peak.
    ///
    /// Why not the whole lobe: a Henyey–Greenstein lobe of `g ≈ 0.97` (the
    /// peak of 5 µm droplets) is narrow in the mean but has wide wings, 7 %
    /// of it beyond 20° and 0.6 % beyond 90°, where at right angles the
    /// lobe is a third of the whole phase function. Treated as unscattered,
    /// that light never turns toward a viewer at the side after its first
    /// peak scatterings; kept in the medium, it does.
    #[must_use]
    pub fn peak_core(&self, cut_deg: f32) -> Option<PeakCore> {
        let CloudPhase::Cloud { diameter_um } = *self else {
            return None;
        };
        let (g, ..) = cloud_fit(diameter_um);
        let (f, _) = self.peak_lobe()?;
        let cos_cut = cut_deg.to_radians().cos();
        let below = hg_share_below(g, cos_cut);
        let lobe_share = 1.0 - below;
        // The core's first moment: the lobe's `g` less its part below the cut.
        let mean_cosine = (g - hg_moment_below(g, cos_cut)) / lobe_share;
        Some(PeakCore {
            weight: f * lobe_share,
            g,
            cos_cut,
            lobe_share,
            mean_cosine,
            rest: CloudPhase::CloudWithoutCore {
                diameter_um,
                cut_deg,
            },
        })
    }

    /// The lobes this phase function mixes: `(g, α, weight, u₀)` of two
    /// Draine lobes (`α = 0` is Henyey–Greenstein; the second's weight is 0
    /// for a single lobe), each drawn from its Henyey–Greenstein inverse CDF
    /// over `u ∈ [u₀, 1)` (`u₀ > 0` keeps the cosines below a cut).
    fn lobes(&self) -> [(f32, f32, f32, f32); 2] {
        match *self {
            CloudPhase::Isotropic => [(0.0, 0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 0.0)],
            CloudPhase::HenyeyGreenstein(g) => [(g, 0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 0.0)],
            CloudPhase::DualHenyeyGreenstein {
                forward,
                back,
                weight,
            } => [(forward, 0.0, 1.0 - weight, 0.0), (back, 0.0, weight, 0.0)],
            CloudPhase::Draine { g, alpha } => [(g, alpha, 1.0, 0.0), (0.0, 0.0, 0.0, 0.0)],
            CloudPhase::Cloud { diameter_um } => {
                let (g_hg, g_d, alpha, w_d) = cloud_fit(diameter_um);
                [(g_hg, 0.0, 1.0 - w_d, 0.0), (g_d, alpha, w_d, 0.0)]
            }
            CloudPhase::CloudWithoutCore {
                diameter_um,
                cut_deg,
            } => {
                let r = WithoutCore::new(diameter_um, cut_deg);
                let u0 = 1.0 - r.below;
                let tail = (1.0 - r.w_d) * r.below;
                [
                    (r.g_hg, 0.0, tail / r.total, u0),
                    (r.g_d, r.alpha, r.w_d / r.total, 0.0),
                ]
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
        let (g, alpha, _, u0) = if second.2 > 0.0 && next() < second.2 {
            second
        } else {
            first
        };
        let cos = loop {
            let c = sample_hg_cos(g, u0 + (1.0 - u0) * next());
            if alpha <= 0.0 || next() * (1.0 + alpha) < 1.0 + alpha * c * c {
                break c;
            }
        };
        direction_about(d, cos, next())
    }
}

/// [`CloudPhase::CloudWithoutCore`]'s parts: the cloud fit's lobes, the
/// cut, the share of the peak's lobe below it, and the normalisation
/// `w_D + (1 − w_D)·below` of what is left.
struct WithoutCore {
    g_hg: f32,
    g_d: f32,
    alpha: f32,
    w_d: f32,
    cos_cut: f32,
    below: f32,
    total: f32,
}

impl WithoutCore {
    fn new(diameter_um: f32, cut_deg: f32) -> Self {
        let (g_hg, g_d, alpha, w_d) = cloud_fit(diameter_um);
        let cos_cut = cut_deg.to_radians().cos();
        let below = hg_share_below(g_hg, cos_cut);
        Self {
            g_hg,
            g_d,
            alpha,
            w_d,
            cos_cut,
            below,
            total: w_d + (1.0 - w_d) * below,
        }
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
            CloudPhase::CloudWithoutCore {
                diameter_um: 5.0,
                cut_deg: 20.0,
            },
            CloudPhase::CloudWithoutCore {
                diameter_um: 20.0,
                cut_deg: 5.0,
            },
            CloudPhase::CloudWithoutCore {
                diameter_um: 50.0,
                cut_deg: 90.0,
            },
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
    fn the_peak_core_and_the_rest_make_up_the_cloud_phase() {
        for (d, cut) in [(5.0f32, 20.0f32), (20.0, 20.0), (5.0, 3.0), (50.0, 60.0)] {
            let p = CloudPhase::Cloud { diameter_um: d };
            let core = p.peak_core(cut).unwrap();
            core.rest.validate().unwrap();
            let (f, g) = p.peak_lobe().unwrap();
            assert_eq!(core.g, g);
            assert!((core.weight - f * core.lobe_share).abs() < 1e-7);
            // p = w·core + (1 − w)·rest at every angle, on both sides of the cut.
            let c = cut.to_radians().cos();
            for mu in [-1.0f32, -0.3, 0.0, 0.5, c - 1e-3, c + 1e-3, 0.999, 1.0] {
                let sum = core.weight * core.eval(mu) + (1.0 - core.weight) * core.rest.eval(mu);
                assert!(
                    (sum - p.eval(mu)).abs() <= 2e-4 * p.eval(mu),
                    "{d} {cut} {mu}"
                );
            }
            let g_sum =
                core.weight * core.mean_cosine + (1.0 - core.weight) * core.rest.mean_cosine();
            assert!((g_sum - p.mean_cosine()).abs() < 1e-5, "{d} {cut}");
            assert!(core.mean_cosine > g, "{core:?}");
            if cut >= 20.0 {
                assert!(core.lobe_share > 0.9, "{core:?}");
            }
        }
        // 5 µm droplets: 7.2 % of the peak's lobe lies beyond 20°.
        let core = CloudPhase::Cloud { diameter_um: 5.0 }
            .peak_core(20.0)
            .unwrap();
        assert!((1.0 - core.lobe_share - 0.072).abs() < 1e-3, "{core:?}");
        assert!(CloudPhase::HenyeyGreenstein(0.9).peak_core(20.0).is_none());
        for cut in [0.0f32, -5.0, 90.5, f32::NAN] {
            let bad = CloudPhase::CloudWithoutCore {
                diameter_um: 10.0,
                cut_deg: cut,
            };
            let e = bad.validate().unwrap_err().to_string();
            assert!(e.contains("cut_deg"), "{e}");
        }
        let bad = CloudPhase::CloudWithoutCore {
            diameter_um: 4.0,
            cut_deg: 20.0,
        };
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("diameter_um")
        );
    }

    #[test]
    fn the_hg_shares_and_moments_below_a_cosine_match_quadrature() {
        for g in [-0.5f32, 0.0, 0.3, 0.9, 0.97, 0.995] {
            for mu in [-1.0f32, -0.2, 0.5, 0.94, 1.0] {
                // Midpoint rule over [−1, mu] in t with x = mu − (mu + 1)t³,
                // which crowds the nodes toward mu (a forward peak).
                let n = 1_000_000;
                let (mut s, mut m) = (0.0f64, 0.0f64);
                let span = f64::from(mu) + 1.0;
                for i in 0..n {
                    let t = (f64::from(i) + 0.5) / f64::from(n);
                    let x = f64::from(mu) - span * t * t * t;
                    let h = 3.0 * span * t * t / f64::from(n);
                    let (gg, xx) = (f64::from(g), x);
                    let p = (1.0 - gg * gg)
                        / (4.0 * std::f64::consts::PI * (1.0 + gg * gg - 2.0 * gg * xx).powf(1.5));
                    s += p * 2.0 * std::f64::consts::PI * h;
                    m += p * x * 2.0 * std::f64::consts::PI * h;
                }
                assert!(
                    (f64::from(hg_share_below(g, mu)) - s).abs() < 1e-4,
                    "{g} {mu}"
                );
                assert!(
                    (f64::from(hg_moment_below(g, mu)) - m).abs() < 1e-4,
                    "{g} {mu}"
                );
            }
            assert!((hg_share_below(g, 1.0) - 1.0).abs() < 1e-6);
            assert!((hg_moment_below(g, 1.0) - g).abs() < 1e-6);
        }
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
            CloudPhase::CloudWithoutCore {
                diameter_um: 5.0,
                cut_deg: 20.0,
            },
            CloudPhase::CloudWithoutCore {
                diameter_um: 20.0,
                cut_deg: 3.0,
            },
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
