//! Detail down to the pixel: any density eroded by noise octaves that stop
//! at the footprint of a pixel at the sample's distance from the camera.
//!
//! A density with fixed octaves is soft near the camera: nothing in it is
//! finer than its last octave, however few metres a pixel covers there.
//! [`Detailed`] wraps a density and erodes it, in the manner of Schneider
//! 2015 (§"Modeling": the base shape eroded by high-frequency noise, "remap
//! the base by the detail", strongest where the base is thin so the core
//! keeps its shape; Ebert 2003, ch. 9, the same two-level idea: a
//! macrostructure with a noise microstructure), with octaves added down to
//! the footprint `w = |p − eye|·α` of a pixel of angular size `α` at the
//! point `p`:
//!
//! * the noise `D(q; w)` is natura-noise's band-limited fractal
//!   ([`FootprintFbm`], the model the terrain's detail tracer uses): octave
//!   `k` of wavelength `λ₀/2ᵏ` fades out over the octave below the Nyquist
//!   limit of samples `w` apart (Musgrave 1993, §6.3), so it has no energy
//!   the pixels cannot show;
//! * `n = clamp(½ + 1.6·D/B, 0, 1)` with `B` the fractal's bound; far from
//!   the camera, where no octave is left, `n = ½`, the noise's mean;
//! * with `b = ρ/ρ_max` the base relative to its maximum (full cloud) and
//!   the threshold `e = a·n·(1 − b)` (amplitude `a`), the eroded density is
//!   `ρ·clamp((b − e)/((1 − e)·b), 0, 1)`: Schneider's `remap(b, e, 1)`
//!   (`(b − e)/(1 − e)`, clamped at 0) rescaled to the base. For
//!   `a ∈ [0, 1]` the denominator is at least `b > 0`, so the result lies in
//!   `[0, ρ]`: erosion only removes density, and the base's
//!   [`bound_in`](Density::bound_in) stays a true upper bound. An amplitude
//!   above 1 would let the denominator change sign (density negative before
//!   the clamp, above the base after it); it is refused.
//! * the lookup point `q = p + δ(p)` is warped for wispy, streaked edges
//!   by curl noise (natura-noise's [`CurlNoise`]: the curl of a noise
//!   vector potential, Bridson et al. 2007, §2) at half the coarsest detail
//!   frequency, its size at most `warp·λ₀` (Schneider 2015, "Modeling",
//!   distorts the detail noise by curl noise for the same look). The curl
//!   has no divergence: it stirs the noise into streaks and curls without
//!   gathering it into knots or thinning it into holes, as the gradient of
//!   a potential (Perlin's `DNoise`) would, so the eroded cloud keeps its
//!   mean density under any warp. A warp compresses the noise along some
//!   direction by up to `1 + |∇δ|`, so the footprint that fades the octaves
//!   is widened by the bound [`WARP_STRETCH`]`·warp` of `|∇δ|`: the warped
//!   noise stays below the pixels' Nyquist limit.
//!
//! The field is one 3-D field for a given camera: the fast renderer and the
//! reference path tracer sample the same [`Detailed`] object, point by point
//! or in batches, and see the same bits (given a base whose batch path is
//! its point path). Only the fast mode's shadow tables and the cells of
//! its multiple-scattering cache, whose samples lie a cell apart, see the
//! detail band-limited to that spacing as well
//! ([`Density::density_batch_spaced`]): octaves they cannot resolve enter
//! them as the noise's mean.

use glam::{DVec3, Vec3};
use natura_core::Aabb;
use natura_noise::{CurlNoise, FootprintFbm, FootprintParams, Perlin, VectorField};

use crate::density::Density;
use crate::error::{Result, finite3, in_range, positive};

/// A bound on `|∇δ|/warp` of the warp `δ` (see the module docs): the
/// largest norm of the warp's Jacobian per unit of `warp`, measured over
/// random points of the lattice (0.92 over 2·10⁴ points), with a margin.
/// It widens the footprint so that the warped noise stays band-limited.
pub const WARP_STRETCH: f64 = 1.2;

/// Parameters of [`Detail`] and [`Detailed`]: the detail octaves, the
/// erosion, the warp, and the camera that defines the footprint.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct DetailParams {
    /// Wavelength `λ₀` of the coarsest detail octave (m, finite, > 0).
    pub feature_m: f32,
    /// Most octaves (each half the wavelength of the one before), however
    /// small the footprint; at most 24. The finest wavelength is
    /// `feature_m / 2^(octaves − 1)`.
    pub octaves: u32,
    /// Musgrave's `H` (in `[0, 2]`): octave `k` has amplitude `2^(−kH)`;
    /// smaller is rougher.
    pub h: f32,
    /// Strength `a` of the erosion in `[0, 1]` (0: the base unchanged, bit for bit).
    pub amplitude: f32,
    /// Size of the warp of the noise as a fraction of
    /// `feature_m`, in `[0, 1]` (0: no warp).
    pub warp: f32,
    /// The camera's position (m): the footprint is `|p − eye|·pixel_angle`.
    pub eye: [f32; 3],
    /// Angular size of a pixel (radians, in `(0, 1]`): the vertical field
    /// of view over the image's height.
    pub pixel_angle: f32,
}

impl Default for DetailParams {
    /// Detail for kilometre-scale layer clouds baked to 100 m voxels: octaves
    /// from 200 m down, `H = 1`, erosion 0.4, warp 0.15, seen from the origin
    /// with pixels of 0.8 mrad (a 50° view about 1080 pixels high).
    fn default() -> Self {
        Self {
            feature_m: 200.0,
            octaves: 10,
            h: 1.0,
            amplitude: 0.4,
            warp: 0.15,
            eye: [0.0; 3],
            pixel_angle: 8e-4,
        }
    }
}

impl DetailParams {
    /// Density samples per step of a march through detailed clouds
    /// ([`FastSettings::substeps`](crate::transport::FastSettings::substeps)):
    /// octaves finer than the samples along an eye ray fold onto the planes
    /// where neighbouring rays sample the density, combed streaks at the
    /// clouds' edges; three parts a step bring that folding from about 8 %
    /// of the clouds' mean radiance to under 1 % (measured on the
    /// [`Cloudscape`](crate::scene::Cloudscape)).
    pub const MARCH_SUBSTEPS: u32 = 3;

    /// These parameters seen from `eye` with pixels of `pixel_angle` radians.
    #[must_use]
    pub fn seen_from(self, eye: Vec3, pixel_angle: f32) -> Self {
        Self {
            eye: eye.to_array(),
            pixel_angle,
            ..self
        }
    }

    /// These parameters seen from `eye` by a march whose rays are
    /// `ray_angle` radians apart and whose steps grow by `step_growth`
    /// metres per metre of distance, each taken in
    /// [`DetailParams::MARCH_SUBSTEPS`] parts: the octaves stop at the
    /// rays' footprint, or at the parts' length where that is longer, so
    /// that neither the rays across nor the samples along them alias the
    /// detail.
    #[must_use]
    pub fn seen_by_march(self, eye: Vec3, ray_angle: f32, step_growth: f32) -> Self {
        let part = step_growth / Self::MARCH_SUBSTEPS as f32;
        self.seen_from(eye, ray_angle.max(part))
    }

    /// Checks every field.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`](crate::VolumeError::InvalidParameter)
    /// naming the first bad field: `feature_m` (finite, > 0), `octaves` (at
    /// most 24), `h` (in `[0, 2]`), `amplitude` (in `[0, 1]`: more would
    /// make the eroded density negative), `warp` (in `[0, 1]`), `eye`
    /// (finite), `pixel_angle` (in `(0, 1]`).
    pub fn validate(&self) -> Result<()> {
        positive("feature_m", self.feature_m)?;
        in_range(
            "octaves",
            self.octaves as f32,
            0.0,
            24.0,
            "must be at most 24",
        )?;
        in_range("h", self.h, 0.0, 2.0, "must lie in [0, 2]")?;
        in_range(
            "amplitude",
            self.amplitude,
            0.0,
            1.0,
            "must lie in [0, 1] (more would make the eroded density negative)",
        )?;
        in_range("warp", self.warp, 0.0, 1.0, "must lie in [0, 1]")?;
        finite3("eye", Vec3::from_array(self.eye))?;
        positive("pixel_angle", self.pixel_angle)?;
        in_range(
            "pixel_angle",
            self.pixel_angle,
            0.0,
            1.0,
            "must lie in (0, 1] radians",
        )?;
        Ok(())
    }
}

/// Points per chunk of the batch evaluation (stack scratch; the march
/// fetches 16 at a time).
const CHUNK: usize = 16;

/// The detail noise and erosion of [`DetailParams`] (see the module docs),
/// for densities that apply it themselves ([`Detailed`] wraps any density).
///
/// Every value is computed in batches of `f32` lanes (natura-noise's
/// [`FootprintFbm::fill_points3`] and [`Perlin::fill_points3`]), and a
/// point's value depends on that point alone: one point at a time or many
/// together give the same bits.
#[derive(Clone, Debug)]
pub struct Detail {
    params: DetailParams,
    fbm: FootprintFbm<Perlin>,
    /// The warp's field.
    curl: CurlNoise<Perlin>,
    eye: DVec3,
    /// `α·(1 + WARP_STRETCH·warp)`: footprint per metre of distance.
    angle: f64,
    /// `1.6 / B`, the noise's gain.
    gain: f32,
    /// `1/(2λ₀)`, the curl noise's frequency.
    warp_frequency: f64,
    /// `warp·λ₀ / B_c`, with `B_c` the curl's bound: metres of
    /// displacement per unit of the curl.
    warp_scale: f64,
    /// The footprint from which on no octave is left.
    far: f64,
}

impl Detail {
    /// The detail of `params` with noise `seed`.
    ///
    /// # Errors
    ///
    /// As [`DetailParams::validate`].
    pub fn new(params: &DetailParams, seed: u64) -> Result<Self> {
        params.validate()?;
        let fbm = FootprintFbm::new(
            Perlin::new(seed ^ 0x6465_7461_696c),
            &FootprintParams {
                amplitude: 1.0,
                h: f64::from(params.h),
                lacunarity: 2.0,
                octaves: params.octaves,
                wavelength: f64::from(params.feature_m),
            },
        )?;
        let bound = fbm.amplitude_between(0, fbm.octave_count());
        let curl = CurlNoise::new(Perlin::new(seed.wrapping_add(1) ^ 0x7761_7270));
        let warp = f64::from(params.warp);
        Ok(Self {
            eye: Vec3::from_array(params.eye).as_dvec3(),
            angle: f64::from(params.pixel_angle) * (1.0 + WARP_STRETCH * warp),
            gain: if bound > 0.0 {
                (1.6 / bound) as f32
            } else {
                0.0
            },
            warp_frequency: 0.5 / f64::from(params.feature_m),
            warp_scale: warp * f64::from(params.feature_m) / curl.bound(),
            far: fbm.far_footprint(),
            params: *params,
            fbm,
            curl,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &DetailParams {
        &self.params
    }

    /// The footprint that fades the octaves at `p` (m): `|p − eye|·α`
    /// widened by the warp's stretch bound `1 + `[`WARP_STRETCH`]`·warp`.
    #[inline]
    #[must_use]
    pub fn footprint(&self, p: Vec3) -> f64 {
        (p.as_dvec3() - self.eye).length() * self.angle
    }

    /// The warp `δ` (m) of the noise's lookup points `(x, y, z)` (at most
    /// `P`), added to them in place: the curl noise at half the coarsest
    /// detail frequency, scaled by its bound so that `|δ| ≤ warp·λ₀`.
    fn warp<const P: usize>(&self, x: &mut [f64], y: &mut [f64], z: &mut [f64]) {
        let m = x.len();
        let f = self.warp_frequency;
        let (mut qx, mut qy, mut qz) = ([0.0f64; P], [0.0f64; P], [0.0f64; P]);
        let (mut u, mut v, mut w) = ([0.0f32; P], [0.0f32; P], [0.0f32; P]);
        for i in 0..m {
            (qx[i], qy[i], qz[i]) = (x[i] * f, y[i] * f, z[i] * f);
        }
        // The slices are equally long: no error is possible.
        let _ = self.curl.fill_points3(
            &qx[..m],
            &qy[..m],
            &qz[..m],
            &mut u[..m],
            &mut v[..m],
            &mut w[..m],
        );
        for i in 0..m {
            x[i] += f64::from(u[i]) * self.warp_scale;
            y[i] += f64::from(v[i]) * self.warp_scale;
            z[i] += f64::from(w[i]) * self.warp_scale;
        }
    }

    /// The erosion noise `n ∈ [0, 1]` at `p`: `½` where the footprint leaves
    /// no octave, otherwise `clamp(½ + 1.6·D(p + δ(p); w)/B, 0, 1)`.
    #[must_use]
    pub fn noise(&self, p: Vec3) -> f32 {
        self.noise_drifting(p, Vec3::ZERO)
    }

    /// [`noise`](Self::noise) of the noise space moved by `drift` (m): the
    /// footprint at `p`, the noise looked up at `p + drift` (for a field
    /// that drifts with the wind, or steam that rises).
    #[must_use]
    pub fn noise_drifting(&self, p: Vec3, drift: Vec3) -> f32 {
        let mut n = [0.0f32];
        self.noise_chunk::<1>(&[p], drift, 0.0, &mut n);
        n[0]
    }

    /// [`noise_drifting`](Self::noise_drifting) at up to `P` points, the
    /// footprint at least `min_footprint` (m).
    fn noise_chunk<const P: usize>(
        &self,
        p: &[Vec3],
        drift: Vec3,
        min_footprint: f64,
        out: &mut [f32],
    ) {
        let (mut x, mut y, mut z) = ([0.0f64; P], [0.0f64; P], [0.0f64; P]);
        let (mut w, mut at) = ([0.0f64; P], [0usize; P]);
        let mut m = 0;
        for (i, o) in out.iter_mut().enumerate() {
            let fw = self.footprint(p[i]).max(min_footprint);
            *o = 0.5;
            if self.gain == 0.0 || fw >= self.far {
                continue;
            }
            let q = (p[i] + drift).as_dvec3();
            (x[m], y[m], z[m], w[m], at[m]) = (q.x, q.y, q.z, fw, i);
            m += 1;
        }
        if m == 0 {
            return;
        }
        if self.params.warp > 0.0 {
            self.warp::<P>(&mut x[..m], &mut y[..m], &mut z[..m]);
        }
        let mut d = [0.0f32; P];
        // The slices are equally long: no error is possible.
        let _ = self
            .fbm
            .fill_points3(&x[..m], &y[..m], &z[..m], &w[..m], &mut d[..m]);
        for i in 0..m {
            out[at[i]] = (0.5 + self.gain * d[i]).clamp(0.0, 1.0);
        }
    }

    /// The base density `base` at `p` eroded (see the module docs), with
    /// `full` the base's density of full cloud: in `[0, base]`, and `base`
    /// itself (bit for bit) where the amplitude is 0, the base is 0 or
    /// reaches `full`.
    #[must_use]
    pub fn erode(&self, p: Vec3, base: f32, full: f32) -> f32 {
        self.erode_drifting(p, Vec3::ZERO, base, full)
    }

    /// [`erode`](Self::erode) with the noise of
    /// [`noise_drifting`](Self::noise_drifting).
    #[must_use]
    pub fn erode_drifting(&self, p: Vec3, drift: Vec3, base: f32, full: f32) -> f32 {
        let mut b = [base];
        self.erode_chunk::<1>(&[p.x], &[p.y], &[p.z], drift, 0.0, &mut b, full);
        b[0]
    }

    /// [`erode_drifting`](Self::erode_drifting) at many points in place:
    /// `base[i]`, the base density at `(x[i], y[i], z[i])`, becomes its
    /// eroded value, bit for bit as one point at a time. Entries beyond the
    /// shortest slice are left as they are.
    pub fn erode_batch(
        &self,
        x: &[f32],
        y: &[f32],
        z: &[f32],
        drift: Vec3,
        base: &mut [f32],
        full: f32,
    ) {
        self.erode_batch_spaced(x, y, z, drift, 0.0, base, full);
    }

    /// [`erode_batch`](Self::erode_batch) for points sampled `spacing`
    /// metres apart (a march toward a light, a table's nodes): the octaves
    /// stop at the footprint of the spacing where it is wider than the
    /// pixel's, widened like the pixel's by the warp's stretch, so samples
    /// that cannot resolve an octave see its mean instead of aliasing it.
    /// A spacing of 0 is [`erode_batch`](Self::erode_batch) bit for bit.
    #[allow(clippy::too_many_arguments)]
    pub fn erode_batch_spaced(
        &self,
        x: &[f32],
        y: &[f32],
        z: &[f32],
        drift: Vec3,
        spacing: f32,
        base: &mut [f32],
        full: f32,
    ) {
        let min_footprint =
            f64::from(spacing.max(0.0)) * (1.0 + WARP_STRETCH * f64::from(self.params.warp));
        let len = base.len().min(x.len()).min(y.len()).min(z.len());
        for s in (0..len).step_by(CHUNK) {
            let r = s..(s + CHUNK).min(len);
            let (x, y, z) = (&x[r.clone()], &y[r.clone()], &z[r.clone()]);
            self.erode_chunk::<CHUNK>(x, y, z, drift, min_footprint, &mut base[r], full);
        }
    }

    /// [`erode_batch`](Self::erode_batch) over at most `P` points, the
    /// footprint at least `min_footprint`.
    #[allow(clippy::too_many_arguments)]
    fn erode_chunk<const P: usize>(
        &self,
        x: &[f32],
        y: &[f32],
        z: &[f32],
        drift: Vec3,
        min_footprint: f64,
        base: &mut [f32],
        full: f32,
    ) {
        let a = self.params.amplitude;
        if a <= 0.0 || full <= 0.0 {
            return;
        }
        let mut p = [Vec3::ZERO; P];
        let mut at = [0usize; P];
        let mut m = 0;
        for (i, &b) in base.iter().enumerate() {
            if b > 0.0 && b < full {
                (p[m], at[m]) = (Vec3::new(x[i], y[i], z[i]), i);
                m += 1;
            }
        }
        if m == 0 {
            return;
        }
        let mut n = [0.0f32; P];
        self.noise_chunk::<P>(&p[..m], drift, min_footprint, &mut n[..m]);
        for k in 0..m {
            let d = &mut base[at[k]];
            let b = *d / full;
            let e = a * n[k] * (1.0 - b);
            let keep = ((b - e) / ((1.0 - e) * b)).clamp(0.0, 1.0);
            *d *= keep;
        }
    }
}

/// A density eroded by [`Detail`] down to the pixel footprint (see the
/// module docs): the same bounds and upper bounds as the base, a density in
/// `[0, base]` everywhere.
#[derive(Clone, Debug)]
pub struct Detailed<D> {
    base: D,
    detail: Option<Detail>,
    /// The base's maximum density (full cloud).
    full: f32,
}

impl<D: Density> Detailed<D> {
    /// `base` eroded by the detail of `params` with noise `seed`.
    ///
    /// # Errors
    ///
    /// As [`DetailParams::validate`].
    pub fn new(base: D, params: &DetailParams, seed: u64) -> Result<Self> {
        let detail = Detail::new(params, seed)?;
        Ok(Self {
            full: base.max_density(),
            base,
            detail: Some(detail),
        })
    }

    /// `base` without detail: the same density, bit for bit (so a scene can
    /// hold one type whether or not its detail is on).
    #[must_use]
    pub fn without_detail(base: D) -> Self {
        Self {
            full: base.max_density(),
            base,
            detail: None,
        }
    }

    /// The base density.
    #[must_use]
    pub fn base(&self) -> &D {
        &self.base
    }

    /// The detail (`None` for [`without_detail`](Self::without_detail)).
    #[must_use]
    pub fn detail(&self) -> Option<&Detail> {
        self.detail.as_ref()
    }
}

impl<D: Density> Density for Detailed<D> {
    fn density(&self, p: Vec3) -> f32 {
        let d = self.base.density(p);
        match &self.detail {
            Some(f) => f.erode(p, d, self.full),
            None => d,
        }
    }
    fn bounds(&self) -> Aabb {
        self.base.bounds()
    }
    /// The base's bound: erosion only removes density.
    fn bound_in(&self, region: &Aabb) -> f32 {
        self.base.bound_in(region)
    }
    fn bound_near(&self, centre: Vec3, radius: f32) -> f32 {
        self.base.bound_near(centre, radius)
    }
    /// The base's: erosion only removes density.
    fn clear_along(&self, o: Vec3, d: Vec3, t: f32, t_max: f32) -> Option<(f32, f32)> {
        self.base.clear_along(o, d, t, t_max)
    }
    fn max_density(&self) -> f32 {
        self.full
    }
    /// The base's batch, eroded point by point: equal to
    /// [`density`](Density::density) bit for bit where the base's batch
    /// equals its point path.
    ///
    /// # Errors
    ///
    /// [`VolumeError::SizeMismatch`](crate::VolumeError::SizeMismatch) if
    /// the slices differ in length.
    fn density_batch(&self, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) -> Result<()> {
        self.base.density_batch(x, y, z, out)?;
        if let Some(f) = &self.detail {
            f.erode_batch(x, y, z, Vec3::ZERO, out, self.full);
        }
        Ok(())
    }
    /// The base's batch eroded with the octaves stopped at the footprint
    /// of `spacing` where it is wider than the pixel's
    /// ([`Detail::erode_batch_spaced`]).
    ///
    /// # Errors
    ///
    /// As [`density_batch`](Density::density_batch).
    fn density_batch_spaced(
        &self,
        x: &[f32],
        y: &[f32],
        z: &[f32],
        spacing: f32,
        out: &mut [f32],
    ) -> Result<()> {
        self.base.density_batch(x, y, z, out)?;
        if let Some(f) = &self.detail {
            f.erode_batch_spaced(x, y, z, Vec3::ZERO, spacing, out, self.full);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_march_stops_the_detail_at_the_longer_footprint() {
        let eye = Vec3::new(1.0, 2.0, 3.0);
        let p = DetailParams::default();
        // Rays 2 mrad apart, steps growing by 1 %: the parts (3.3 mrad) rule.
        let d = p.seen_by_march(eye, 2e-3, 0.01);
        assert_eq!(d.eye, [1.0, 2.0, 3.0]);
        assert_eq!(d.pixel_angle, 0.01 / DetailParams::MARCH_SUBSTEPS as f32);
        // Rays 5 mrad apart: the rays rule.
        assert_eq!(p.seen_by_march(eye, 5e-3, 0.01).pixel_angle, 5e-3);
    }

    fn displacement(d: &Detail, p: DVec3) -> DVec3 {
        let (mut x, mut y, mut z) = ([p.x], [p.y], [p.z]);
        d.warp::<1>(&mut x, &mut y, &mut z);
        DVec3::new(x[0], y[0], z[0]) - p
    }

    /// The warp's Jacobian norm per unit warp stays below [`WARP_STRETCH`]
    /// (central differences over random points), and its size is about
    /// `warp·λ₀`.
    #[test]
    fn warp_stretch_bounds_the_warp_jacobian() {
        let p = DetailParams {
            warp: 1.0,
            feature_m: 1.0,
            ..DetailParams::default()
        };
        let d = Detail::new(&p, 5).unwrap();
        let mut rng = 0x1234_5678_9abc_def0u64;
        let mut next = || {
            rng = rng
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (rng >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut worst, mut size) = (0.0f64, 0.0f64);
        let h = 1e-3;
        for _ in 0..20_000 {
            let x = DVec3::new(next(), next(), next()) * 200.0 - DVec3::splat(100.0);
            size = size.max(displacement(&d, x).length());
            let cols = [DVec3::X, DVec3::Y, DVec3::Z]
                .map(|e| (displacement(&d, x + e * h) - displacement(&d, x - e * h)) / (2.0 * h));
            let j = glam::DMat3::from_cols(cols[0], cols[1], cols[2]);
            // Spectral norm from the largest eigenvalue of JᵀJ (power iteration).
            let m = j.transpose() * j;
            let mut v = DVec3::new(1.0, 0.7, 0.3).normalize();
            for _ in 0..50 {
                v = (m * v).normalize_or_zero();
            }
            worst = worst.max((m * v).length().sqrt());
        }
        eprintln!("warp: largest |δ| {size:.3} λ₀, largest |∇δ| {worst:.3}");
        assert!(worst < WARP_STRETCH, "{worst}");
        assert!(worst > 0.5 * WARP_STRETCH, "{worst}");
        assert!((0.2..=1.0).contains(&size), "{size}");
    }

    /// A soft ball: density `1 − r/R` inside the radius `R` of 400 m.
    #[derive(Debug)]
    struct Soft;
    impl Density for Soft {
        fn density(&self, p: Vec3) -> f32 {
            (1.0 - p.length() / 400.0).max(0.0)
        }
        fn bounds(&self) -> Aabb {
            Aabb {
                min: Vec3::splat(-400.0),
                max: Vec3::splat(400.0),
            }
        }
        fn max_density(&self) -> f32 {
            1.0
        }
    }

    /// The soft ball eroded by the default detail seen from 300 m away,
    /// and points through it.
    fn spaced_case() -> (Detailed<Soft>, Vec<f32>, Vec<f32>, Vec<f32>) {
        let ball = Soft;
        let p = DetailParams::default().seen_from(Vec3::new(0.0, -700.0, 0.0), 8e-4);
        let d = Detailed::new(ball, &p, 3).unwrap();
        let n = 200;
        let xs: Vec<f32> = (0..n).map(|i| -390.0 + 3.9 * i as f32).collect();
        let ys: Vec<f32> = (0..n).map(|i| -50.0 + 0.5 * i as f32).collect();
        let zs: Vec<f32> = (0..n).map(|i| 30.0 - 0.2 * i as f32).collect();
        (d, xs, ys, zs)
    }

    /// Samples closer together than a pixel's footprint see every octave
    /// the pixels see: the spaced batch is the plain batch bit for bit.
    #[test]
    fn a_spacing_finer_than_the_pixels_changes_nothing() {
        let (d, xs, ys, zs) = spaced_case();
        let mut plain = vec![0.0f32; xs.len()];
        let mut spaced = plain.clone();
        d.density_batch(&xs, &ys, &zs, &mut plain).unwrap();
        // The nearest point is about 310 m away: a footprint of about 0.25 m.
        d.density_batch_spaced(&xs, &ys, &zs, 0.1, &mut spaced)
            .unwrap();
        assert_eq!(plain, spaced);
        d.density_batch_spaced(&xs, &ys, &zs, 0.0, &mut spaced)
            .unwrap();
        assert_eq!(plain, spaced);
    }

    /// Samples farther apart than the coarsest octave's Nyquist limit see
    /// the noise's mean, `n = ½`, everywhere: the base eroded by
    /// `e = a·½·(1 − b)`; and a spacing between leaves the coarse octaves,
    /// so the eroded density varies, but less than the pixels see it vary.
    #[test]
    fn a_spacing_coarser_than_the_detail_sees_its_mean() {
        let (d, xs, ys, zs) = spaced_case();
        let mut spaced = vec![0.0f32; xs.len()];
        d.density_batch_spaced(&xs, &ys, &zs, 1000.0, &mut spaced)
            .unwrap();
        let a = DetailParams::default().amplitude;
        let mut eroded = 0;
        for i in 0..xs.len() {
            let base = d.base().density(Vec3::new(xs[i], ys[i], zs[i]));
            let b = base;
            let e = a * 0.5 * (1.0 - b);
            let want = if b > 0.0 && b < 1.0 {
                base * ((b - e) / ((1.0 - e) * b)).clamp(0.0, 1.0)
            } else {
                base
            };
            assert!(
                (spaced[i] - want).abs() <= 1e-6,
                "{i}: {} {want}",
                spaced[i]
            );
            eroded += usize::from(spaced[i] < base);
        }
        assert!(eroded > 100, "{eroded}");
        // The spread about the mean erosion shrinks as the spacing grows.
        let spread = |spacing: f32| {
            let mut v = vec![0.0f32; xs.len()];
            d.density_batch_spaced(&xs, &ys, &zs, spacing, &mut v)
                .unwrap();
            v.iter()
                .zip(&spaced)
                .map(|(a, b)| f64::from(a - b).powi(2))
                .sum::<f64>()
        };
        let (fine, mid) = (spread(0.0), spread(60.0));
        assert!(fine > 0.0 && mid > 0.0 && mid < fine, "{fine} {mid}");
    }
}
