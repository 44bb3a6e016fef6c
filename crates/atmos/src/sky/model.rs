//! The physical atmosphere in `N` channels: coefficients, geometry, the
//! transmittance and multiple-scattering LUTs (Hillaire 2020 §5.2, §5.5), and
//! the ray marcher shared by the LUT builds and the Nishita 1993 reference.

use std::f64::consts::PI;

use natura_core::Progress;

use super::channels::{Channels, Lut2};
use super::data::{DOBSON_UNIT, OZONE_CROSS_SECTION, SOLAR_IRRADIANCE, lerp_table};
use super::params::{AtmosphereParams, Evaluation, MiePhase};
use crate::error::Result;
use crate::scatter::{
    ISOTROPIC, cornette_shanks, henyey_greenstein, rayleigh_coefficient, rayleigh_phase,
};
use crate::spectrum::{cie::XYZ_TO_SRGB, cmf_1931};

/// Number of spectral bands in [`Evaluation::Spectral`] (25 nm over 380–780 nm).
pub const SPECTRAL_BANDS: usize = 16;

/// The wavelengths (nm) of the three channels in [`Evaluation::Rgb`].
pub const RGB_WAVELENGTHS_NM: [f64; 3] = [680.0, 550.0, 440.0];

/// Distance from radius `r` along `mu` to the top sphere.
#[inline]
pub(crate) fn dist_top(r: f64, mu: f64, top: f64) -> f64 {
    let disc = (r * r * (mu * mu - 1.0) + top * top).max(0.0);
    (-r * mu + disc.sqrt()).max(0.0)
}

/// Distance from radius `r` along `mu` to the ground sphere (valid if it hits).
#[inline]
pub(crate) fn dist_bottom(r: f64, mu: f64, bottom: f64) -> f64 {
    let disc = (r * r * (mu * mu - 1.0) + bottom * bottom).max(0.0);
    (-r * mu - disc.sqrt()).max(0.0)
}

/// Whether the ray from radius `r` along `mu` meets the ground.
#[inline]
pub(crate) fn hits_ground(r: f64, mu: f64, bottom: f64) -> bool {
    mu < 0.0 && r * r * (mu * mu - 1.0) + bottom * bottom >= 0.0
}

/// Directions and steps per direction of a multiple-scattering texel.
const MS_DIRS: usize = 64;
const MS_STEPS: usize = 20;

/// A step of the march along one direction of an [`MsRow`].
struct MsStep<const N: usize> {
    tt: f64,
    rt: f64,
    sca: Channels<N>,
    ext: Channels<N>,
    seg_t: Channels<N>,
    /// Transmittance from the texel to the start of the step.
    thr: Channels<N>,
}

/// A direction of an [`MsRow`].
struct MsDir<const N: usize> {
    dir: glam::DVec3,
    dt: f64,
    /// Transmittance along the whole direction.
    thr: Channels<N>,
    /// The ground's normal where the direction meets it.
    ground_normal: Option<glam::DVec3>,
}

/// What the multiple-scattering texels of one radius share.
struct MsRow<const N: usize> {
    r: f64,
    dirs: Vec<MsDir<N>>,
    /// `MS_STEPS` per direction.
    steps: Vec<MsStep<N>>,
    /// The transfer factor `f_ms` (Hillaire 2020 §5.5), independent of the sun.
    fms: Channels<N>,
}

/// Constant `s` over a segment of extinction `ext`, transmittance
/// `seg_t` and length `dt`, integrated analytically (Hillaire 2015).
#[inline]
fn ms_segment<const N: usize>(
    s: Channels<N>,
    ext: Channels<N>,
    seg_t: Channels<N>,
    dt: f64,
) -> Channels<N> {
    s.zip(ext, |si, e| if e > 0.0 { si / e } else { si * dt })
        - (s * seg_t).zip(ext, |si, e| if e > 0.0 { si / e } else { 0.0 })
}

/// The physical atmosphere with `N` channels and its precomputed LUTs.
#[derive(Debug)]
pub(crate) struct Model<const N: usize> {
    pub p: AtmosphereParams,
    pub wavelengths: [f64; N],
    pub rayleigh: Channels<N>,
    pub mie_sca: Channels<N>,
    pub mie_ext: Channels<N>,
    pub ozone: Channels<N>,
    pub sun: Channels<N>,
    pub limb: Channels<N>,
    /// Rows of the channel → linear sRGB matrix.
    pub to_rgb: [[f64; N]; 3],
    pub trans: Lut2<N>,
    pub ms: Option<Lut2<N>>,
}

/// Spectral samples of the model's channels.
fn channels<const N: usize>(p: &AtmosphereParams) -> Result<([f64; N], [[f64; N]; 3])> {
    let mut lambda = [0.0; N];
    let mut to_rgb = [[0.0; N]; 3];
    match p.evaluation {
        Evaluation::Rgb => {
            for c in 0..N {
                lambda[c] = RGB_WAVELENGTHS_NM[c.min(2)];
                to_rgb[c.min(2)][c] = 1.0;
            }
        }
        Evaluation::Spectral => {
            let width = 400.0 / N as f64;
            let mut xyz = [glam::DVec3::ZERO; N];
            let mut ysum = 0.0;
            for (i, x) in xyz.iter_mut().enumerate() {
                let lo = 380.0 + width * i as f64;
                lambda[i] = lo + 0.5 * width;
                // Band-averaged CMFs at 1 nm.
                let n = width.round() as usize;
                for k in 0..n {
                    *x += cmf_1931(lo + k as f64 + 0.5)?;
                }
                ysum += x.y;
            }
            for (i, x) in xyz.iter().enumerate() {
                let rgb = XYZ_TO_SRGB * (*x / ysum);
                to_rgb[0][i] = rgb.x;
                to_rgb[1][i] = rgb.y;
                to_rgb[2][i] = rgb.z;
            }
        }
    }
    Ok((lambda, to_rgb))
}

impl<const N: usize> Model<N> {
    /// Builds the coefficients and the transmittance and multiple-scattering LUTs.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `params` fail
    /// [`AtmosphereParams::validate`](super::AtmosphereParams::validate) or name wavelengths
    /// outside the colour-matching table.
    pub fn new(p: AtmosphereParams, progress: &dyn Progress) -> Result<Self> {
        p.validate()?;
        let (wavelengths, to_rgb) = channels::<N>(&p)?;
        let r = &p.rayleigh;
        let mut rayleigh = Channels::ZERO;
        let mut mie_sca = Channels::ZERO;
        let mut mie_ext = Channels::ZERO;
        let mut ozone = Channels::ZERO;
        let mut sun = Channels::ZERO;
        let mut limb = Channels::ZERO;
        let ozone_peak = p.ozone.column_dobson * DOBSON_UNIT / p.ozone.half_width_m;
        for (c, &l) in wavelengths.iter().enumerate() {
            rayleigh.0[c] = rayleigh_coefficient(l, r.n_minus_1, r.number_density, r.king_factor)?;
            let ang = (l / 550.0).powf(-p.mie.angstrom_exponent);
            mie_sca.0[c] = p.mie.scattering * ang;
            mie_ext.0[c] = (p.mie.scattering + p.mie.absorption) * ang;
            ozone.0[c] = if p.ozone.enabled {
                ozone_peak * lerp_table(&OZONE_CROSS_SECTION, l)
            } else {
                0.0
            };
            sun.0[c] = lerp_table(&SOLAR_IRRADIANCE, l) * p.sun_intensity_scale;
            // Hestroffer & Magnan 1998 power law I(μ)/I(1) = μ^α, α = −0.023 + 0.292/λ[µm].
            limb.0[c] = -0.023 + 0.292 / (l * 1e-3);
        }
        let mut m = Model {
            p,
            wavelengths,
            rayleigh,
            mie_sca,
            mie_ext,
            ozone,
            sun,
            limb,
            to_rgb,
            trans: Lut2 {
                w: 2,
                h: 2,
                data: vec![[0.0; N]; 4],
            },
            ms: None,
        };
        let (tw, th) = p.lut.transmittance;
        progress.start("transmittance LUT", th as u64);
        m.trans = Lut2::build(
            tw,
            th,
            |x_mu, x_r| m.transmittance_texel(x_mu, x_r),
            progress,
        );
        progress.finish();
        if p.multiple_scattering {
            let (mw, mh) = p.lut.multiple_scattering;
            progress.start("multiple-scattering LUT", mh as u64);
            let ms = Lut2::build_rows(
                mw,
                mh,
                |y| m.ms_row(y),
                |row, x, _| m.ms_texel(row, x),
                progress,
            );
            progress.finish();
            m.ms = Some(ms);
        }
        Ok(m)
    }

    #[inline]
    pub fn bottom(&self) -> f64 {
        self.p.bottom_radius_m
    }

    #[inline]
    pub fn top(&self) -> f64 {
        self.p.top_radius_m
    }

    /// Relative densities (Rayleigh, Mie, ozone) at altitude `h` above the ground.
    #[inline]
    pub fn densities(&self, h: f64) -> (f64, f64, f64) {
        let rr = (-h / self.p.rayleigh.scale_height_m).exp();
        let rm = (-h / self.p.mie.scale_height_m).exp();
        let o = &self.p.ozone;
        let ro = (1.0 - (h - o.peak_altitude_m).abs() / o.half_width_m).max(0.0);
        (rr, rm, ro)
    }

    /// The Mie phase function.
    #[inline]
    pub fn mie_phase(&self, nu: f64) -> f64 {
        match self.p.mie.phase {
            MiePhase::HenyeyGreenstein => henyey_greenstein(self.p.mie.g, nu),
            MiePhase::CornetteShanks => cornette_shanks(self.p.mie.g, nu),
        }
    }

    /// Optical depth from `(r, mu)` over distance `d`, by composite 8-point
    /// Gauss–Legendre over `segments` equal pieces (all three densities per node).
    pub fn optical_depth(&self, r: f64, mu: f64, d: f64, segments: usize) -> Channels<N> {
        const X: [f64; 4] = [
            0.183_434_642_495_649_8,
            0.525_532_409_916_329,
            0.796_666_477_413_626_7,
            0.960_289_856_497_536_3,
        ];
        const W: [f64; 4] = [
            0.362_683_783_378_362,
            0.313_706_645_877_887_3,
            0.222_381_034_453_374_5,
            0.101_228_536_290_376_3,
        ];
        let seg = d / segments as f64;
        let half = 0.5 * seg;
        let (mut cr, mut cm, mut co) = (0.0, 0.0, 0.0);
        for k in 0..segments {
            let c = (k as f64 + 0.5) * seg;
            for i in 0..4 {
                for t in [c - half * X[i], c + half * X[i]] {
                    let rt = (t * t + 2.0 * r * mu * t + r * r).sqrt();
                    let (a, b, o) = self.densities(rt - self.bottom());
                    cr += W[i] * a;
                    cm += W[i] * b;
                    co += W[i] * o;
                }
            }
        }
        self.rayleigh * (cr * half) + self.mie_ext * (cm * half) + self.ozone * (co * half)
    }

    /// `(r, μ)` of transmittance-LUT coordinates (Bruneton & Neyret 2008 mapping).
    fn trans_r_mu(&self, x_mu: f64, x_r: f64) -> (f64, f64) {
        let (b, t) = (self.bottom(), self.top());
        let hh = (t * t - b * b).sqrt();
        let rho = hh * x_r;
        let r = (rho * rho + b * b).sqrt();
        let d_min = t - r;
        let d_max = rho + hh;
        let d = d_min + x_mu * (d_max - d_min);
        let mu = if d == 0.0 {
            1.0
        } else {
            ((hh * hh - rho * rho - d * d) / (2.0 * r * d)).clamp(-1.0, 1.0)
        };
        (r, mu)
    }

    fn transmittance_texel(&self, x_mu: f64, x_r: f64) -> Channels<N> {
        let (r, mu) = self.trans_r_mu(x_mu, x_r);
        let d = dist_top(r, mu, self.top());
        self.optical_depth(r, mu, d, 16).exp_neg()
    }

    /// Transmittance from `(r, mu)` to the top of the atmosphere (LUT; the ray
    /// must not meet the ground).
    #[inline]
    pub fn trans_top(&self, r: f64, mu: f64) -> Channels<N> {
        let (b, t) = (self.bottom(), self.top());
        let r = r.clamp(b, t);
        let hh = (t * t - b * b).sqrt();
        let rho = (r * r - b * b).max(0.0).sqrt();
        let d = dist_top(r, mu, t);
        let d_min = t - r;
        let d_max = rho + hh;
        let x_mu = if d_max > d_min {
            (d - d_min) / (d_max - d_min)
        } else {
            0.0
        };
        self.trans.sample(x_mu, rho / hh)
    }

    /// Sunlight transmittance at `(r, mu_s)`: 0 in the planet's shadow.
    #[inline]
    pub fn sun_trans_lut(&self, r: f64, mu_s: f64) -> Channels<N> {
        if hits_ground(r, mu_s, self.bottom()) {
            Channels::ZERO
        } else {
            self.trans_top(r, mu_s)
        }
    }

    /// Sunlight transmittance at `(r, mu_s)` by direct quadrature (reference).
    pub fn sun_trans_exact(&self, r: f64, mu_s: f64, segments: usize) -> Channels<N> {
        if hits_ground(r, mu_s, self.bottom()) {
            return Channels::ZERO;
        }
        if r >= self.top() && mu_s >= 0.0 {
            return Channels::ONE;
        }
        let d = dist_top(r, mu_s, self.top());
        self.optical_depth(r, mu_s, d, segments).exp_neg()
    }

    /// Multiple-scattering transfer `Ψ_ms` at `(r, mu_s)` (zero when disabled).
    #[inline]
    pub fn psi_ms(&self, r: f64, mu_s: f64) -> Channels<N> {
        match &self.ms {
            Some(lut) => {
                let x = 0.5 * (mu_s + 1.0);
                let y = (r - self.bottom()) / (self.top() - self.bottom());
                lut.sample(x, y)
            }
            None => Channels::ZERO,
        }
    }

    /// What the texels of one multiple-scattering LUT row (one radius)
    /// share: the march along each of the 64 directions does not depend on
    /// the sun, only the sunlight at each step does.
    fn ms_row(&self, x_r: f64) -> MsRow<N> {
        let (b, t) = (self.bottom(), self.top());
        let r = b + (t - b) * x_r.clamp(1e-4, 1.0 - 1e-4);
        let golden = PI * (3.0 - 5f64.sqrt());
        let mut dirs = Vec::with_capacity(MS_DIRS);
        let mut steps = Vec::with_capacity(MS_DIRS * MS_STEPS);
        let mut fms = Channels::ZERO;
        for i in 0..MS_DIRS {
            // Spherical Fibonacci directions: equal-area, deterministic.
            let mu = 1.0 - (2.0 * i as f64 + 1.0) / MS_DIRS as f64;
            let sin = (1.0 - mu * mu).sqrt();
            let phi = golden * i as f64;
            let dir = glam::DVec3::new(sin * phi.cos(), sin * phi.sin(), mu);
            let ground = hits_ground(r, mu, b);
            let t_max = if ground {
                dist_bottom(r, mu, b)
            } else {
                dist_top(r, mu, t)
            };
            let dt = t_max / MS_STEPS as f64;
            let mut thr = Channels::ONE;
            let mut f = Channels::ZERO;
            for k in 0..MS_STEPS {
                let tt = (k as f64 + 0.5) * dt;
                let rt = (tt * tt + 2.0 * r * mu * tt + r * r).sqrt();
                let (rr, rm, ro) = self.densities(rt - b);
                let sca = self.rayleigh * rr + self.mie_sca * rm;
                let ext = self.rayleigh * rr + self.mie_ext * rm + self.ozone * ro;
                let seg_t = (ext * dt).exp_neg();
                f += thr * ms_segment(sca, ext, seg_t, dt);
                steps.push(MsStep {
                    tt,
                    rt,
                    sca,
                    ext,
                    seg_t,
                    thr,
                });
                thr *= seg_t;
            }
            let ground_normal =
                ground.then(|| (glam::DVec3::new(0.0, 0.0, r) + dir * t_max).normalize());
            dirs.push(MsDir {
                dir,
                dt,
                thr,
                ground_normal,
            });
            fms += f;
        }
        MsRow {
            r,
            dirs,
            steps,
            fms: fms / MS_DIRS as f64,
        }
    }

    /// One multiple-scattering LUT texel (Hillaire 2020 §5.5, eqs. 5-10): the
    /// second-order isotropic luminance over 64 directions, amplified by the
    /// geometric series `1/(1 − f_ms)`, for unit sun illuminance; `row` is
    /// [`Self::ms_row`] of the texel's radius.
    fn ms_texel(&self, row: &MsRow<N>, x_mu_s: f64) -> Channels<N> {
        let (b, r) = (self.bottom(), row.r);
        let mu_s = 2.0 * x_mu_s - 1.0;
        let sun = glam::DVec3::new((1.0 - mu_s * mu_s).max(0.0).sqrt(), 0.0, mu_s);
        let mut l2 = Channels::ZERO;
        for (d, steps) in row.dirs.iter().zip(row.steps.chunks_exact(MS_STEPS)) {
            let nu = d.dir.dot(sun);
            let mut l = Channels::ZERO;
            for s in steps {
                let mu_st = ((r * mu_s + s.tt * nu) / s.rt).clamp(-1.0, 1.0);
                let sun_t = self.sun_trans_lut(s.rt, mu_st);
                l += s.thr * ms_segment(s.sca * sun_t * ISOTROPIC, s.ext, s.seg_t, d.dt);
            }
            if let Some(n) = d.ground_normal {
                let mu_g = n.dot(sun);
                if mu_g > 0.0 {
                    let tg = self.sun_trans_lut(b, mu_g);
                    l += d.thr * tg * (mu_g * self.p.ground_albedo / PI);
                }
            }
            l2 += l;
        }
        // Uniform sphere sampling with the isotropic phase: ∫(·)p_u dω = mean.
        let l2 = l2 / MS_DIRS as f64;
        l2.zip(row.fms, |l, f| l / (1.0 - f.min(0.999)))
    }

    /// Single (plus, if enabled, LUT multiple) scattering along the view ray
    /// from `(r, mu)` with sun cosine `mu_s` and view–sun cosine `nu`, over the
    /// segment boundaries `bound(0) = 0 < … < bound(k_max)`, with sunlight
    /// transmittance from `sun_t`. Calls `each(k, L, T)` at every boundary.
    #[allow(clippy::too_many_arguments)]
    pub fn march(
        &self,
        r: f64,
        mu: f64,
        mu_s: f64,
        nu: f64,
        k_max: usize,
        bound: impl Fn(usize) -> f64,
        sun_t: impl Fn(f64, f64) -> Channels<N>,
        mut each: impl FnMut(usize, Channels<N>, Channels<N>),
    ) -> (Channels<N>, Channels<N>) {
        let b = self.bottom();
        let pr = rayleigh_phase(nu);
        let pm = self.mie_phase(nu);
        let mut l = Channels::ZERO;
        let mut thr = Channels::ONE;
        let mut t0 = bound(0);
        for k in 1..=k_max {
            let t1 = bound(k);
            let dt = t1 - t0;
            if dt > 0.0 {
                let tt = 0.5 * (t0 + t1);
                let rt = (tt * tt + 2.0 * r * mu * tt + r * r).sqrt();
                let mu_st = ((r * mu_s + tt * nu) / rt).clamp(-1.0, 1.0);
                let (rr, rm, ro) = self.densities(rt - b);
                let sr = self.rayleigh * rr;
                let sm = self.mie_sca * rm;
                let ext = sr + self.mie_ext * rm + self.ozone * ro;
                let mut j = (sr * pr + sm * pm) * sun_t(rt, mu_st);
                if self.ms.is_some() {
                    j += (sr + sm) * self.psi_ms(rt, mu_st);
                }
                let j = j * self.sun;
                let seg_t = (ext * dt).exp_neg();
                // Analytic integration of constant J over the segment (Hillaire 2015).
                let add = j.zip(ext, |ji, e| if e > 0.0 { ji / e } else { ji * dt })
                    - (j * seg_t).zip(ext, |ji, e| if e > 0.0 { ji / e } else { 0.0 });
                l += thr * add;
                thr *= seg_t;
            }
            t0 = t1;
            each(k, l, thr);
        }
        (l, thr)
    }

    /// Converts channels to linear sRGB.
    #[inline]
    pub fn rgb(&self, s: Channels<N>) -> glam::DVec3 {
        let dot = |row: &[f64; N]| row.iter().zip(s.0).map(|(a, b)| a * b).sum::<f64>();
        glam::DVec3::new(
            dot(&self.to_rgb[0]),
            dot(&self.to_rgb[1]),
            dot(&self.to_rgb[2]),
        )
    }

    /// Length of the view ray inside the atmosphere from `(r, mu)`: `(t_start, t_end, hits_ground)`,
    /// or `None` if the ray misses the atmosphere (camera above the top looking away).
    pub fn view_extent(&self, r: f64, mu: f64) -> Option<(f64, f64, bool)> {
        let (b, t) = (self.bottom(), self.top());
        let mut t_start = 0.0;
        if r > t {
            // Enter the atmosphere first.
            let disc = r * r * (mu * mu - 1.0) + t * t;
            if mu >= 0.0 || disc < 0.0 {
                return None;
            }
            t_start = -r * mu - disc.sqrt();
        }
        if hits_ground(r, mu, b) {
            Some((t_start, dist_bottom(r, mu, b), true))
        } else {
            Some((t_start, dist_top(r, mu, t).max(t_start), false))
        }
    }
}
