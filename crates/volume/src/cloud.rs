//! Ebert's volumetric procedural implicit clouds: the cumulus procedure and
//! its variants (cirrus with a jet stream, stratus, cirrostratus, mackerel sky).
//!
//! Ebert 2001, "Volumetric Procedural Implicit Functions" and "Cloud
//! Modeling": a turbulent perturbation of the point, a displacement of the
//! world point by `parms[4]·turb` along `(1, −1, 1)`, the implicit density
//! `m` of the primitives there, and
//!
//! `density = (parms[1]·(parms[3]·m + (1 − parms[3])·turb·m))^{parms[2]}`.
//!
//! Ebert's y axis is up; natura's is z, so the source's `(x, y, z)` is
//! natura's `(x, z, y)` throughout (the displacement diagonal becomes
//! `(1, 1, −1)`). Errata corrected: the swirl constant printed `01047196` is
//! `0.01047196 = 2π/600` (one turn per 600 frames); the per-frame constants,
//! cached in the listing behind a flag that is never reset, are a pure
//! function of the frame here ([`FrameConstants`]); the notes' pseudo-code adds
//! the turbulence (`blend·m + (1 − blend)·turb`) while the code and slides
//! multiply it by `m`, which keeps all density inside the primitives: both
//! are offered ([`BlendForm`]), the product by default; the implicit sum is
//! clamped to `[0, 1]` before shaping (the source leaves it unclamped, so
//! overlapping primitives would exceed 1).

use glam::Vec3;
use natura_core::Aabb;

use crate::density::{Density, expand};
use crate::detail::{Detail, DetailParams};
use crate::error::{Result, finite3, in_range, non_negative, positive};
use crate::gas::GasNoise;
use crate::implicit::Implicit;

/// The per-frame constants of Ebert's cumulus and cirrus procedures, a pure
/// function of the frame number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameConstants {
    /// The frame.
    pub frame: u32,
    /// Swirl angle `θ = (frame mod 600)·0.01047196` (rad): one turn per 600 frames.
    pub theta: f32,
    /// The drift of the turbulence space (source `path_x, path_y, path_z`, in natura axes).
    pub path: Vec3,
    /// The noise amplitude of the x perturbation, `0.5 + 0.01·frame`.
    pub scalar_x: f32,
    /// The noise amplitude of the source-z (natura y) perturbation, `0.0073·frame`.
    pub scalar_z: f32,
}

/// The swirl period in frames.
pub const SWIRL_PERIOD: u32 = 600;

impl FrameConstants {
    /// The constants of `frame`.
    #[must_use]
    pub fn new(frame: u32) -> Self {
        let theta = (frame % SWIRL_PERIOD) as f64 * 0.010_471_96;
        let s = theta.sin();
        let f = f64::from(frame);
        // Source: path_x = sin θ·0.005·f, path_y (up) = 0.01215·f, path_z = sin θ·0.0035·f.
        let path = Vec3::new(
            (s * 0.005 * f) as f32,
            (s * 0.0035 * f) as f32,
            (0.01215 * f) as f32,
        );
        Self {
            frame,
            theta: theta as f32,
            path,
            scalar_x: (0.5 + f * 0.010) as f32,
            scalar_z: (f * 0.0073) as f32,
        }
    }
}

/// How turbulence and the implicit density are blended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum BlendForm {
    /// `blend·m + (1 − blend)·turb·m` (the source's code and slides): zero
    /// wherever the implicit density is zero.
    #[default]
    Product,
    /// `blend·m + (1 − blend)·turb` (the source's pseudo-code): gas outside the
    /// primitives too.
    Additive,
}

/// A predominant wind that shears the cloud along `vector`, more with height
/// (Ebert's cirrus `warp(jet_stream, pnt_w)` and the jet-stream animation).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct JetStream {
    /// Wind displacement at full amount and the top of the cloud (m).
    pub vector: Vec3,
    /// Amount in `[0, 1]` (animate it with [`crate::animate::ease`]); 0 is no warp.
    pub amount: f32,
}

/// Mackerel-sky modulation: turbulent sine waves in x and y multiply the density.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Mackerel {
    /// Wave numbers along x and y (rad/m).
    pub wave_number: [f32; 2],
    /// CloudPhase perturbation by turbulence (rad per unit turbulence).
    pub turbulence: f32,
}

/// Parameters of an Ebert cloud; `Default` is the source's cumulus.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct CloudParams {
    /// `parms[1]`, density scale (cumulus 0.2–0.4; default 0.3).
    pub density_scale: f32,
    /// `parms[2]`, the exponent (wispiness; cumulus 0.5). Larger: wispier.
    pub exponent: f32,
    /// `parms[3]`, implicit vs turbulence blend in `[0, 1]` (cumulus 0.4;
    /// larger is smoother).
    pub blend: f32,
    /// `parms[4]`, turbulent displacement of the world point before the
    /// implicit evaluation (m per unit turbulence; cumulus 0.7).
    pub displacement: f32,
    /// Size of the turbulent space: cloud-space point = world point ×
    /// `noise_frequency` (1/m). Smaller gives fewer, larger wisps.
    pub noise_frequency: f32,
    /// Additive or product blend.
    pub blend_form: BlendForm,
    /// The frame (drives [`FrameConstants`]).
    pub frame: u32,
    /// Cirrus jet stream, if any.
    pub jet_stream: Option<JetStream>,
    /// Mackerel modulation, if any.
    pub mackerel: Option<Mackerel>,
    /// Erosion by noise octaves down to the pixel footprint of a camera
    /// ([`crate::detail`]: Schneider 2015's erosion of the thin parts, the
    /// finest of Ebert 2003, ch. 9's microstructure); `None`: Ebert's
    /// procedure alone, bit for bit.
    pub detail: Option<DetailParams>,
}

impl Default for CloudParams {
    /// The cumulus of Ebert's Figure 1: `parms = (·, 0.3, 0.5, 0.4, 0.7)`.
    fn default() -> Self {
        Self {
            density_scale: 0.3,
            exponent: 0.5,
            blend: 0.4,
            displacement: 0.7,
            noise_frequency: 1.0,
            blend_form: BlendForm::Product,
            frame: 0,
            jet_stream: None,
            mackerel: None,
            detail: None,
        }
    }
}

impl CloudParams {
    /// Cumulus (the default).
    #[must_use]
    pub fn cumulus() -> Self {
        Self::default()
    }

    /// Cirrus: thinner and wispier (smaller density scale, larger exponent),
    /// sheared along a jet stream `vector`.
    #[must_use]
    pub fn cirrus(vector: Vec3) -> Self {
        Self {
            density_scale: 0.2,
            exponent: 1.5,
            blend: 0.3,
            noise_frequency: 2.0,
            jet_stream: Some(JetStream {
                vector,
                amount: 1.0,
            }),
            ..Self::default()
        }
    }

    /// Stratus: thicker and less wispy than cirrus, a larger turbulent feature
    /// size, a smaller exponent and higher density.
    #[must_use]
    pub fn stratus() -> Self {
        Self {
            density_scale: 0.45,
            exponent: 0.35,
            blend: 0.6,
            noise_frequency: 0.5,
            ..Self::default()
        }
    }

    /// Cirrostratus: a thin veil, smooth but faintly streaked.
    #[must_use]
    pub fn cirrostratus() -> Self {
        Self {
            density_scale: 0.15,
            exponent: 0.9,
            blend: 0.5,
            noise_frequency: 1.5,
            ..Self::default()
        }
    }

    /// Mackerel sky: stratus modulated by turbulent sine waves in x and y.
    #[must_use]
    pub fn mackerel(wave_length_m: f32) -> Self {
        let k = std::f32::consts::TAU / wave_length_m;
        Self {
            mackerel: Some(Mackerel {
                wave_number: [k, k * 0.8],
                turbulence: 2.0,
            }),
            exponent: 0.6,
            ..Self::stratus()
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter) naming the bad field
    /// (as [`DetailParams::validate`] for the detail's).
    pub fn validate(&self) -> Result<()> {
        positive("density_scale", self.density_scale)?;
        positive("exponent", self.exponent)?;
        in_range("blend", self.blend, 0.0, 1.0, "must lie in [0, 1]")?;
        non_negative("displacement", self.displacement)?;
        positive("noise_frequency", self.noise_frequency)?;
        if let Some(j) = self.jet_stream {
            finite3("jet_stream.vector", j.vector)?;
            in_range(
                "jet_stream.amount",
                j.amount,
                0.0,
                1.0,
                "must lie in [0, 1]",
            )?;
        }
        if let Some(m) = self.mackerel {
            finite3(
                "mackerel.wave_number",
                Vec3::new(m.wave_number[0], m.wave_number[1], m.turbulence),
            )?;
        }
        if let Some(d) = &self.detail {
            d.validate()?;
        }
        Ok(())
    }
}

/// An Ebert cloud: implicit primitives (macrostructure) with turbulence
/// (microstructure), evaluated by the cumulus procedure.
#[derive(Clone, Debug)]
pub struct Cloud {
    params: CloudParams,
    frame: FrameConstants,
    implicit: Implicit,
    noise: GasNoise,
    bounds: Aabb,
    margin: Vec3,
    detail: Option<Detail>,
}

impl Cloud {
    /// The cloud of `implicit` primitives with `params` and noise `seed`.
    ///
    /// # Errors
    ///
    /// As [`CloudParams::validate`].
    pub fn new(implicit: Implicit, params: CloudParams, seed: u64) -> Result<Self> {
        params.validate()?;
        let noise = GasNoise::new(seed, 4)?;
        // Everything that moves the evaluation point away from the world point.
        let mut margin = Vec3::splat(params.displacement);
        if let Some(j) = params.jet_stream {
            margin += (j.vector.abs() + Vec3::new(0.2, 0.25, 0.3)) * j.amount;
        }
        let bounds = match params.blend_form {
            BlendForm::Product => expand(&implicit.bounds(), margin),
            BlendForm::Additive => expand(&implicit.bounds(), margin * 2.0 + Vec3::ONE),
        };
        crate::density::check_bounds("cloud", &bounds)?;
        let detail = match &params.detail {
            Some(d) => Some(Detail::new(d, seed ^ 0x0063_6c6f_7564)?),
            None => None,
        };
        Ok(Self {
            detail,
            frame: FrameConstants::new(params.frame),
            params,
            implicit,
            noise,
            bounds,
            margin,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &CloudParams {
        &self.params
    }

    /// The primitives.
    #[must_use]
    pub fn implicit(&self) -> &Implicit {
        &self.implicit
    }

    /// The same cloud at another frame (constants recomputed).
    #[must_use]
    pub fn at_frame(&self, frame: u32) -> Self {
        let mut c = self.clone();
        c.params.frame = frame;
        c.frame = FrameConstants::new(frame);
        c
    }

    /// Ebert's cumulus procedure at world point `pw`, returning
    /// `(density, implicit density m, turbulence)`.
    #[must_use]
    pub fn evaluate(&self, pw: Vec3) -> (f32, f32, f32) {
        let pc = pw * self.params.noise_frequency;
        let pc = self.perturb(pc, self.noise.noise(pc));
        let turb = self.noise.turbulence(pc);
        let (d, m) = self.shape(pw, turb);
        (d, m, turb)
    }

    /// The cloud-space point `pc` perturbed by the noise `peach` found there
    /// (the source's drift along the path and its noise displacement).
    #[inline]
    fn perturb(&self, mut pc: Vec3, peach: f32) -> Vec3 {
        let f = &self.frame;
        pc.x = pc.x - f.path.x + peach * f.scalar_x;
        pc.z = pc.z - f.path.z + 0.5 * peach;
        pc.y = pc.y + f.path.y - peach * f.scalar_z;
        pc
    }

    /// The density and implicit density at world point `pw` given the
    /// turbulence `turb` of its perturbed cloud-space point.
    #[inline]
    fn shape(&self, pw: Vec3, turb: f32) -> (f32, f32) {
        let p = &self.params;
        let amount = p.displacement * turb;
        // Source (x += a, y += −a... in y-up): (+a, −a, +a) → natura (+a, +a, −a).
        let mut q = pw + Vec3::new(amount, amount, -amount);
        if let Some(j) = p.jet_stream {
            let jet = j.vector + Vec3::new(0.2, 0.25, 0.3) * turb;
            q = warp(q, jet, j.amount, self.relative_height(q));
        }
        let m = self.implicit.eval(q).clamp(0.0, 1.0);
        let blended = match p.blend_form {
            BlendForm::Product => p.blend * m + (1.0 - p.blend) * turb * m,
            BlendForm::Additive => p.blend * m + (1.0 - p.blend) * turb,
        };
        let mut d = (p.density_scale * blended).clamp(0.0, 1.0);
        if let Some(mk) = p.mackerel {
            let a = mk.turbulence * turb;
            let sx = 0.5 + 0.5 * (mk.wave_number[0] * pw.x + a).sin();
            let sy = 0.5 + 0.5 * (mk.wave_number[1] * pw.y + a).sin();
            d *= sx * sy;
        }
        (d.powf(p.exponent), m)
    }

    /// The density `d` at `p` eroded by the detail, if any (never above `d`,
    /// so the bounds hold).
    #[inline]
    fn eroded(&self, p: Vec3, d: f32) -> f32 {
        match &self.detail {
            Some(f) => f.erode(p, d, self.max_density()),
            None => d,
        }
    }

    /// Height of `p` within the primitives' box, `0` at the bottom, `1` at the top.
    fn relative_height(&self, p: Vec3) -> f32 {
        let b = self.implicit.bounds();
        ((p.z - b.min.z) / (b.max.z - b.min.z)).clamp(0.0, 1.0)
    }
}

/// The jet-stream warp: the evaluation point moves by `−amount·height·vector`
/// (inverse mapping, so the visible cloud moves by `+`); amount 0 is the identity.
#[inline]
#[must_use]
pub fn warp(p: Vec3, vector: Vec3, amount: f32, height: f32) -> Vec3 {
    p - vector * (amount * height)
}

impl Density for Cloud {
    fn density(&self, p: Vec3) -> f32 {
        if !self.bounds.contains(p) {
            return 0.0;
        }
        self.eroded(p, self.evaluate(p).0)
    }
    fn bounds(&self) -> Aabb {
        self.bounds
    }
    fn bound_in(&self, region: &Aabb) -> f32 {
        if self.params.blend_form == BlendForm::Additive {
            return self.max_density();
        }
        let m = self.implicit.bound_in(region, self.margin).min(1.0);
        if m <= 0.0 {
            0.0
        } else {
            (self.params.density_scale * m)
                .min(1.0)
                .powf(self.params.exponent)
        }
    }
    fn max_density(&self) -> f32 {
        self.params
            .density_scale
            .min(1.0)
            .powf(self.params.exponent)
    }

    /// The cumulus procedure at many points: the perturbing noise and the
    /// turbulence through [`GasNoise::noise_batch`] and
    /// [`GasNoise::turbulence_batch`] (`natura-noise`'s SIMD point kernel),
    /// the implicit primitives and the shaping point by point. It agrees
    /// with [`density`](Density::density) within `10⁻⁵` absolute on the
    /// tests' clouds (the kernel's `f32` noise differs from the point
    /// path's `f64` by up to `2·10⁻⁵` of its bound; the shaping exponent
    /// below 1 could amplify that where the density nears zero).
    ///
    /// # Errors
    ///
    /// [`VolumeError::SizeMismatch`](crate::VolumeError::SizeMismatch) if
    /// the slices differ in length.
    fn density_batch(&self, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) -> Result<()> {
        crate::density::check_batch(x, y, z, out)?;
        const N: usize = 64;
        let k = self.params.noise_frequency;
        let (mut cx, mut cy, mut cz) = ([0.0f32; N], [0.0f32; N], [0.0f32; N]);
        let mut v = [0.0f32; N];
        for (c, o) in out.chunks_mut(N).enumerate() {
            let m = o.len();
            let r = c * N..c * N + m;
            for (i, j) in r.clone().enumerate() {
                cx[i] = x[j] * k;
                cy[i] = y[j] * k;
                cz[i] = z[j] * k;
            }
            self.noise
                .noise_batch(&cx[..m], &cy[..m], &cz[..m], &mut v[..m])?;
            for i in 0..m {
                let pc = self.perturb(Vec3::new(cx[i], cy[i], cz[i]), v[i]);
                (cx[i], cy[i], cz[i]) = (pc.x, pc.y, pc.z);
            }
            self.noise
                .turbulence_batch(&cx[..m], &cy[..m], &cz[..m], &mut v[..m])?;
            for (i, j) in r.enumerate() {
                let pw = Vec3::new(x[j], y[j], z[j]);
                o[i] = if self.bounds.contains(pw) {
                    self.eroded(pw, self.shape(pw, v[i]).0)
                } else {
                    0.0
                };
            }
        }
        Ok(())
    }
}

/// A cloud of `primitives` with `params` and noise `seed`, in one call.
///
/// # Errors
///
/// As [`Implicit::new`] and [`Cloud::new`].
pub fn cloud(
    primitives: Vec<crate::implicit::ImplicitPrimitive>,
    params: CloudParams,
    seed: u64,
) -> Result<Cloud> {
    Cloud::new(Implicit::new(primitives)?, params, seed)
}

/// The nine-sphere cumulus of Ebert's Figure 1 (a layout in that spirit: a
/// broad base of five spheres, three above, one crown), about 10 m across.
#[must_use]
pub fn nine_sphere_cumulus() -> Vec<crate::implicit::ImplicitPrimitive> {
    use crate::implicit::ImplicitPrimitive as P;
    vec![
        P::sphere(Vec3::new(0.0, 0.0, 2.0), 3.0),
        P::sphere(Vec3::new(-3.0, 0.5, 1.6), 2.5),
        P::sphere(Vec3::new(3.0, -0.5, 1.7), 2.6),
        P::sphere(Vec3::new(0.5, 2.5, 1.5), 2.3),
        P::sphere(Vec3::new(-0.5, -2.5, 1.5), 2.3),
        P::sphere(Vec3::new(-1.5, 0.5, 4.0), 2.4),
        P::sphere(Vec3::new(1.8, 0.0, 4.2), 2.3),
        P::sphere(Vec3::new(0.0, -1.0, 4.3), 2.0),
        P::sphere(Vec3::new(0.2, 0.3, 6.0), 2.0),
    ]
}

/// Ebert's Figure 4 layout: a cirrostratus layer from one large elliptical
/// primitive (a veil 60 m across, 3 m thick, at 12 m) with lower cirrus from
/// three cylindrical primitives beneath it.
#[must_use]
pub fn cirrostratus_primitives() -> Vec<crate::implicit::ImplicitPrimitive> {
    use crate::implicit::ImplicitPrimitive as P;
    vec![
        P::ellipsoid(Vec3::new(0.0, 0.0, 12.0), Vec3::new(30.0, 22.0, 1.5)),
        P::cylinder(Vec3::new(-22.0, -8.0, 7.0), Vec3::new(4.0, -12.0, 7.5), 2.0).with_weight(0.8),
        P::cylinder(Vec3::new(-10.0, 4.0, 6.5), Vec3::new(18.0, 0.0, 7.0), 1.8).with_weight(0.8),
        P::cylinder(Vec3::new(2.0, 12.0, 7.2), Vec3::new(24.0, 9.0, 7.8), 1.6).with_weight(0.7),
    ]
}
