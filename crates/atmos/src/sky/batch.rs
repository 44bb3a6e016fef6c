//! The per-pixel hot path of [`SkyView`] shared by the scalar lookups and the
//! batch kernels: the sky-view `(u, v)` mapping with a polynomial `acos`, the
//! bilinear sky-view and trilinear aerial-perspective lookups, and the
//! ray–planet intersection, written as single-lane `#[inline(always)]`
//! functions that the scalar methods call once and the batch kernels call in
//! loops over `L` lanes (vectorised by LLVM at the dispatched SIMD level,
//! see [`crate::simd`]). Because both paths run the same operations in the
//! same order, **the batch results equal the scalar ones bit for bit**.
//!
//! Layout: sky-view texels are RGB padded to a 16-byte [`Vec4`], aerial
//! texels a pair of them (in-scatter, transmittance; 32 bytes, the two
//! distance neighbours of a trilinear corner are adjacent). A lookup is then
//! a few aligned 4-wide loads and FMAs per corner, and neighbouring pixels hit
//! the same cache lines. A planar (struct-of-arrays) layout would instead need
//! one lane gather per channel per corner (24 for a sky lookup, 48 for an
//! aerial one), and gathers are no faster than scalar loads on current x86.

use std::f32::consts::PI;

use glam::{Vec3, Vec4};

use super::picture::{Ground, SkyCamera};
use super::view::{ApSample, SkyView};
use crate::error::{Result, invalid};
use crate::simd::{self, Kernel, Simd};

/// Lanes per batch chunk (one AVX-512 vector, two AVX2 vectors).
pub(crate) const L: usize = 16;

/// `acos(x)` for `x ∈ [−1, 1]` in `f32` by Abramowitz & Stegun 4.4.46: a
/// degree-7 polynomial times `√(1 − |x|)`, absolute error ≤ 2·10⁻⁸ rad in
/// exact arithmetic and ≤ 5·10⁻⁷ rad in `f32` (tested over a dense grid against
/// `f64::acos`). Branch-free, so it vectorises, and cheaper than
/// `f32::acos` (figures in `docs/performance.md`). Inputs outside `[−1, 1]`
/// are clamped.
#[inline(always)]
#[must_use]
// The coefficients are kept exactly as printed in A&S 4.4.46.
#[allow(clippy::excessive_precision)]
pub(crate) fn fast_acos(x: f32) -> f32 {
    let a = x.abs().min(1.0);
    let p = -0.001_262_491_1f32;
    let p = p * a + 0.006_670_090_1;
    let p = p * a - 0.017_088_125_6;
    let p = p * a + 0.030_891_881_0;
    let p = p * a - 0.050_174_304_6;
    let p = p * a + 0.088_978_987_4;
    let p = p * a - 0.214_598_801_6;
    let p = p * a + 1.570_796_305_0;
    let r = p * (1.0 - a).sqrt();
    if x < 0.0 { PI - r } else { r }
}

/// Per-view constants of the lane kernels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LaneConsts {
    /// Local zenith at the camera.
    pub up: Vec3,
    /// Sun direction.
    pub sun: Vec3,
    /// `cos` and `sin` of the sun's zenith angle.
    pub mu_s: f32,
    pub sin_s: f32,
    /// Zenith angle of the horizon (where the sky-view `v` mapping pivots).
    pub theta_h: f32,
    /// `R_cam² − R_ground²` over `R_cam²`: a view ray meets the ground iff `μ < 0` and `μ² ≥ k`.
    pub ground_k: f32,
    /// `(R_cam² − R_ground²)/R_cam`, m: ground distance is this over `−μ + √(μ² − k)`.
    pub ground_c: f32,
    /// `R_cam / R_ground` and `1 / R_ground` (the ground normal at a hit).
    pub rc_over_rg: f32,
    pub inv_rg: f32,
    /// Range of the aerial-perspective volume, m.
    pub ap_max: f32,
    /// LUT sizes.
    pub sky_w: u32,
    pub sky_h: u32,
    pub ap_na: u32,
    pub ap_nz: u32,
    pub ap_nd: u32,
}

impl LaneConsts {
    /// Placeholder while a view is being built.
    pub(crate) const ZERO: LaneConsts = LaneConsts {
        up: Vec3::Z,
        sun: Vec3::Z,
        mu_s: 1.0,
        sin_s: 0.0,
        theta_h: 0.0,
        ground_k: 0.0,
        ground_c: 0.0,
        rc_over_rg: 1.0,
        inv_rg: 0.0,
        ap_max: 1.0,
        sky_w: 2,
        sky_h: 2,
        ap_na: 2,
        ap_nz: 2,
        ap_nd: 2,
    };

    pub(crate) fn new(view: &SkyView, r_cam: f64, r_ground: f64) -> Self {
        let k = ((r_cam * r_cam - r_ground * r_ground) / (r_cam * r_cam)).max(0.0);
        let (na, nz, nd) = view.ap_dims;
        LaneConsts {
            up: view.up,
            sun: view.sun_f,
            mu_s: view.mu_s,
            sin_s: view.sin_s,
            theta_h: view.theta_h,
            ground_k: k as f32,
            ground_c: ((r_cam * r_cam - r_ground * r_ground).max(0.0) / r_cam) as f32,
            rc_over_rg: (r_cam / r_ground) as f32,
            inv_rg: (1.0 / r_ground) as f32,
            ap_max: view.ap_max,
            sky_w: view.sky_w as u32,
            sky_h: view.sky_h as u32,
            ap_na: na as u32,
            ap_nz: nz as u32,
            ap_nd: nd as u32,
        }
    }

    /// `(μ, ν)` (cosines to the zenith and to the sun) of a direction that
    /// should be unit length, or `None` if it is not (|d|² off by more than
    /// 2·10⁻³, or NaN/infinite).
    #[inline(always)]
    pub(crate) fn cosines(&self, d: Vec3) -> Option<(f32, f32)> {
        let (ok, mu, nu) = self.cosines_lane(d.x, d.y, d.z);
        ok.then_some((mu, nu))
    }

    /// Branch-free [`LaneConsts::cosines`]: `(valid, μ, ν)`, with harmless
    /// values substituted when invalid.
    #[inline(always)]
    pub(crate) fn cosines_lane(&self, x: f32, y: f32, z: f32) -> (bool, f32, f32) {
        let n2 = x * x + y * y + z * z;
        // NaN compares false, so NaN and infinite directions are invalid.
        let ok = (n2 - 1.0).abs() <= 2e-3;
        let mu = x * self.up.x + y * self.up.y + z * self.up.z;
        let nu = x * self.sun.x + y * self.sun.y + z * self.sun.z;
        let mu = if ok { mu.clamp(-1.0, 1.0) } else { 1.0 };
        let nu = if ok { nu } else { self.mu_s };
        (ok, mu, nu)
    }

    /// Sky-view LUT coordinates `(u, v) ∈ [0, 1]²` of `(μ, ν)`: `v` from the
    /// zenith angle, concentrating texels at the horizon `θ_h`, `u` from the
    /// azimuth relative to the sun, concentrating texels towards it (Hillaire
    /// 2020 §5.3).
    #[inline(always)]
    pub(crate) fn uv(&self, mu: f32, nu: f32) -> (f32, f32) {
        let st = (1.0 - mu * mu).max(0.0).sqrt();
        let denom = st * self.sin_s;
        let cos_phi = (nu - mu * self.mu_s) / denom;
        let cos_phi = if denom > 1e-6 {
            cos_phi.clamp(-1.0, 1.0)
        } else {
            1.0
        };
        let u = (fast_acos(cos_phi) * (1.0 / PI)).clamp(0.0, 1.0).sqrt();
        let theta = fast_acos(mu);
        let th = self.theta_h;
        let above = 0.5 * (1.0 - (1.0 - theta / th).max(0.0).sqrt());
        let below = 0.5 + 0.5 * ((theta - th) / (PI - th)).clamp(0.0, 1.0).sqrt();
        (u, if theta < th { above } else { below })
    }

    /// The volume's depth coordinate `w ∈ [0, 1]` of a distance (square-root
    /// mapping; negative distances count as 0, longer ones are clamped).
    #[inline(always)]
    pub(crate) fn depth(&self, distance_m: f32) -> f32 {
        (distance_m.max(0.0) / self.ap_max).min(1.0).sqrt()
    }

    /// Distance to the ground along a view with zenith cosine `μ`, or a
    /// negative number if the ray misses it.
    #[inline(always)]
    pub(crate) fn ground(&self, mu: f32) -> f32 {
        let disc = mu * mu - self.ground_k;
        let t = self.ground_c / (disc.max(0.0).sqrt() - mu);
        if mu < 0.0 && disc >= 0.0 { t } else { -1.0 }
    }

    /// The sky-view texel `k` at the cell's low corner and the bilinear weights.
    #[inline(always)]
    pub(crate) fn sky_cell(&self, u: f32, v: f32) -> (u32, f32, f32) {
        let (i, tx) = cell(u, self.sky_w);
        let (j, ty) = cell(v, self.sky_h);
        (j * self.sky_w + i, tx, ty)
    }

    /// The aerial-volume texel at the cell's low corner and the trilinear weights.
    #[inline(always)]
    pub(crate) fn ap_cell(&self, u: f32, v: f32, w: f32) -> (u32, f32, f32, f32) {
        let (ia, ta) = cell(u, self.ap_na);
        let (iz, tz) = cell(v, self.ap_nz);
        let (id, td) = cell(w, self.ap_nd);
        ((iz * self.ap_na + ia) * self.ap_nd + id, ta, tz, td)
    }

    /// Cosine of the sun on the ground at distance `t` along `(μ, ν)`.
    #[inline(always)]
    pub(crate) fn ground_cos(&self, mu: f32, nu: f32, t: f32) -> f32 {
        let s = t * self.inv_rg;
        let c = self.rc_over_rg;
        let n2 = c * c + 2.0 * c * s * mu + s * s;
        ((c * self.mu_s + s * nu) / n2.sqrt()).max(0.0)
    }
}

/// Splits `x ∈ [0, 1]` scaled to `[0, n − 1]` into a cell index `≤ n − 2`
/// and its fraction.
#[inline(always)]
fn cell(x: f32, n: u32) -> (u32, f32) {
    let f = x * (n - 1) as f32;
    // Clamp and floor in float, then read the integer out of the bits of
    // `fi + 2²³` (exact for integers in [0, 2²³)): a vector add, where the
    // saturating `as` casts are scalarised lane by lane before AVX-512.
    let fi = f.min((n - 2) as f32).max(0.0).floor();
    let i = (fi + 8_388_608.0).to_bits() - 0x4B00_0000;
    (i, f - fi)
}

impl SkyView {
    /// Bilinear sky-view lookup at `(u, v)`.
    #[inline(always)]
    pub(crate) fn sky_at(&self, u: f32, v: f32) -> Vec4 {
        let (k, tx, ty) = self.lanes.sky_cell(u, v);
        self.sky_fetch(k, tx, ty)
    }

    /// Bilinear sky-view interpolation in the cell at texel `k`.
    #[inline(always)]
    pub(crate) fn sky_fetch(&self, k: u32, tx: f32, ty: f32) -> Vec4 {
        let (k, w) = (k as usize, self.sky_w);
        let (r0, r1) = (&self.sky[k..k + 2], &self.sky[k + w..k + w + 2]);
        let a = r0[0].lerp(r0[1], tx);
        let b = r1[0].lerp(r1[1], tx);
        a.lerp(b, ty)
    }

    /// Trilinear aerial-perspective lookup at `(u, v, w)`: `(in-scatter, transmittance)`.
    #[inline(always)]
    pub(crate) fn ap_at(&self, u: f32, v: f32, w: f32) -> (Vec4, Vec4) {
        let (k, ta, tz, td) = self.lanes.ap_cell(u, v, w);
        self.ap_fetch(k, ta, tz, td)
    }

    /// Trilinear interpolation in the aerial-volume cell at texel `k`.
    #[inline(always)]
    pub(crate) fn ap_fetch(&self, k: u32, ta: f32, tz: f32, td: f32) -> (Vec4, Vec4) {
        let (na, _, nd) = self.ap_dims;
        let k = k as usize;
        let mut l = Vec4::ZERO;
        let mut t = Vec4::ZERO;
        for (dz, wz) in [(0, 1.0 - tz), (na * nd, tz)] {
            for (da, wa) in [(0, 1.0 - ta), (nd, ta)] {
                let c = &self.ap[k + dz + da..k + dz + da + 2];
                let wgt = wz * wa;
                l += c[0][0].lerp(c[1][0], td) * wgt;
                t += c[0][1].lerp(c[1][1], td) * wgt;
            }
        }
        (l, t)
    }

    /// [`SkyView::radiance_f32`] for every direction of `dirs`, into `out`
    /// (same length), with the widest SIMD level this CPU supports. Results
    /// equal the scalar method's bit for bit; invalid directions give black.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `out` and `dirs` differ in length.
    pub fn radiance_batch(&self, dirs: &[Vec3], out: &mut [Vec3]) -> Result<()> {
        self.radiance_batch_with(Simd::best(), dirs, out)
    }

    /// [`SkyView::radiance_batch`] at a chosen SIMD level (every level gives
    /// the same bits).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `out` and `dirs` differ in length.
    pub fn radiance_batch_with(&self, simd: Simd, dirs: &[Vec3], out: &mut [Vec3]) -> Result<()> {
        if dirs.len() != out.len() {
            return Err(invalid(
                "out",
                out.len(),
                "must have the same length as dirs",
            ));
        }
        simd::run(
            simd,
            RadianceKernel {
                view: self,
                dirs,
                out,
            },
        );
        Ok(())
    }

    /// [`SkyView::aerial_perspective_f32`] for every `(dirs[i], distances_m[i])`
    /// into `out` (all the same length), with the widest SIMD level this CPU
    /// supports. Results equal the scalar method's bit for bit: distances are
    /// clamped to the volume's range, and a non-unit or NaN direction or a NaN
    /// distance gives no attenuation ([`ApSample::NONE`]).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `dirs`, `distances_m` and `out` differ in
    /// length.
    pub fn aerial_perspective_batch(
        &self,
        dirs: &[Vec3],
        distances_m: &[f32],
        out: &mut [ApSample],
    ) -> Result<()> {
        self.aerial_perspective_batch_with(Simd::best(), dirs, distances_m, out)
    }

    /// [`SkyView::aerial_perspective_batch`] at a chosen SIMD level.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if `dirs`, `distances_m` and `out` differ in
    /// length.
    pub fn aerial_perspective_batch_with(
        &self,
        simd: Simd,
        dirs: &[Vec3],
        distances_m: &[f32],
        out: &mut [ApSample],
    ) -> Result<()> {
        if dirs.len() != out.len() || distances_m.len() != out.len() {
            return Err(invalid(
                "out",
                out.len(),
                "dirs, distances_m and out must have the same length",
            ));
        }
        simd::run(
            simd,
            ApKernel {
                view: self,
                dirs,
                distances_m,
                out,
            },
        );
        Ok(())
    }

    /// The lane quantities of up to `L` directions.
    #[inline(always)]
    fn lanes_of(&self, d: &[Vec3]) -> Lanes {
        let mut x = [0.0f32; L];
        let mut y = [0.0f32; L];
        let mut z = [0.0f32; L];
        for (i, v) in d.iter().enumerate() {
            x[i] = v.x;
            y[i] = v.y;
            z[i] = v.z;
        }
        Lanes::new(&self.lanes, &x, &y, &z)
    }

    /// Shades image row `y` of a `w × h` render into `row` (see [`SkyView::render`]).
    #[inline(always)]
    pub(crate) fn shade_row(
        &self,
        camera: &SkyCamera,
        y: usize,
        row: &mut [Vec3],
        ground: Option<&Ground>,
        sun_disc: bool,
    ) {
        let c = self.lanes;
        let w = row.len();
        for (chunk, out) in row.chunks_mut(L).enumerate() {
            let x0 = chunk * L;
            let (mut dx, mut dy, mut dz) = ([0.0f32; L], [0.0f32; L], [0.0f32; L]);
            fill_directions(camera, x0, y, w, &mut dx, &mut dy, &mut dz);
            let lanes = Lanes::new(&c, &dx, &dy, &dz);
            let mut t = [-1.0f32; L];
            let mut k = [0u32; L];
            let (mut ta, mut tz, mut td) = ([0.0f32; L], [0.0f32; L], [0.0f32; L]);
            let mut cos = [0.0f32; L];
            if ground.is_some() {
                for i in 0..L {
                    t[i] = c.ground(lanes.mu[i]);
                    (k[i], ta[i], tz[i], td[i]) = c.ap_cell(lanes.u[i], lanes.v[i], c.depth(t[i]));
                    cos[i] = c.ground_cos(lanes.mu[i], lanes.nu[i], t[i]);
                }
            }
            for (i, o) in out.iter_mut().enumerate() {
                if !lanes.ok[i] {
                    *o = Vec3::ZERO;
                    continue;
                }
                let d = Vec3::new(dx[i], dy[i], dz[i]);
                if let Some(g) = ground
                    && t[i] >= 0.0
                {
                    *o = if t[i] > c.ap_max {
                        // Beyond the volume (a high camera): exact march.
                        self.ground_radiance(d, t[i], g)
                    } else {
                        let e = self.sun_e * cos[i] + self.ambient;
                        let surface = g.albedo * e * std::f32::consts::FRAC_1_PI;
                        let (l, tr) = self.ap_fetch(k[i], ta[i], tz[i], td[i]);
                        tr.truncate() * surface + l.truncate()
                    };
                    continue;
                }
                let mut l = self
                    .sky_fetch(lanes.sk[i], lanes.stx[i], lanes.sty[i])
                    .truncate();
                if sun_disc && lanes.nu[i] >= self.cos_sun_radius {
                    l += self.sun_disc_f32(d);
                }
                *o = l;
            }
        }
    }

    /// Renders with the batch kernels (the body of [`SkyView::render`]).
    pub(crate) fn render_rows(
        &self,
        simd: Simd,
        camera: &SkyCamera,
        grid: &mut natura_core::Grid2<Vec3>,
        ground: Option<Ground>,
        sun_disc: bool,
    ) {
        let shade = |y: usize, row: &mut [Vec3]| {
            simd::run(
                simd,
                RowKernel {
                    view: self,
                    camera,
                    y,
                    row,
                    ground: ground.as_ref(),
                    sun_disc,
                },
            );
        };
        #[cfg(feature = "parallel")]
        grid.par_rows_mut(shade);
        #[cfg(not(feature = "parallel"))]
        for y in 0..grid.height() {
            shade(y, grid.row_mut(y));
        }
    }
}

struct RadianceKernel<'a> {
    view: &'a SkyView,
    dirs: &'a [Vec3],
    out: &'a mut [Vec3],
}

impl Kernel for RadianceKernel<'_> {
    type Out = ();
    #[inline(always)]
    fn call(self) {
        let v = self.view;
        for (d, o) in self.dirs.chunks(L).zip(self.out.chunks_mut(L)) {
            let lanes = v.lanes_of(d);
            for (i, o) in o.iter_mut().enumerate() {
                *o = if lanes.ok[i] {
                    v.sky_fetch(lanes.sk[i], lanes.stx[i], lanes.sty[i])
                        .truncate()
                } else {
                    Vec3::ZERO
                };
            }
        }
    }
}

struct ApKernel<'a> {
    view: &'a SkyView,
    dirs: &'a [Vec3],
    distances_m: &'a [f32],
    out: &'a mut [ApSample],
}

impl Kernel for ApKernel<'_> {
    type Out = ();
    #[inline(always)]
    fn call(self) {
        let v = self.view;
        let c = v.lanes;
        for ((d, dist), o) in self
            .dirs
            .chunks(L)
            .zip(self.distances_m.chunks(L))
            .zip(self.out.chunks_mut(L))
        {
            let lanes = v.lanes_of(d);
            let mut dl = [0.0f32; L];
            dl[..dist.len()].copy_from_slice(dist);
            let mut k = [0u32; L];
            let (mut ta, mut tz, mut td) = ([0.0f32; L], [0.0f32; L], [0.0f32; L]);
            let mut ok = lanes.ok;
            for i in 0..L {
                (k[i], ta[i], tz[i], td[i]) = c.ap_cell(lanes.u[i], lanes.v[i], c.depth(dl[i]));
                ok[i] &= !dl[i].is_nan();
            }
            for (i, o) in o.iter_mut().enumerate() {
                *o = if ok[i] {
                    let (l, t) = v.ap_fetch(k[i], ta[i], tz[i], td[i]);
                    ApSample {
                        transmittance: t.truncate(),
                        in_scatter: l.truncate(),
                    }
                } else {
                    ApSample::NONE
                };
            }
        }
    }
}

struct RowKernel<'a> {
    view: &'a SkyView,
    camera: &'a SkyCamera,
    y: usize,
    row: &'a mut [Vec3],
    ground: Option<&'a Ground>,
    sun_disc: bool,
}

impl Kernel for RowKernel<'_> {
    type Out = ();
    #[inline(always)]
    fn call(self) {
        self.view
            .shade_row(self.camera, self.y, self.row, self.ground, self.sun_disc);
    }
}

/// The lane quantities of `L` directions.
pub(crate) struct Lanes {
    pub ok: [bool; L],
    pub mu: [f32; L],
    pub nu: [f32; L],
    pub u: [f32; L],
    pub v: [f32; L],
    /// Sky-view cell and bilinear weights.
    pub sk: [u32; L],
    pub stx: [f32; L],
    pub sty: [f32; L],
}

impl Lanes {
    #[inline(always)]
    fn new(c: &LaneConsts, x: &[f32; L], y: &[f32; L], z: &[f32; L]) -> Self {
        let mut s = Lanes {
            ok: [false; L],
            mu: [0.0; L],
            nu: [0.0; L],
            u: [0.0; L],
            v: [0.0; L],
            sk: [0; L],
            stx: [0.0; L],
            sty: [0.0; L],
        };
        for i in 0..L {
            let (ok, mu, nu) = c.cosines_lane(x[i], y[i], z[i]);
            let (u, v) = c.uv(mu, nu);
            s.ok[i] = ok;
            s.mu[i] = mu;
            s.nu[i] = nu;
            s.u[i] = u;
            s.v[i] = v;
            (s.sk[i], s.stx[i], s.sty[i]) = c.sky_cell(u, v);
        }
        s
    }
}

/// Fills the directions of pixels `x0 .. x0 + L` of row `y` (zero past the
/// row's end and where the camera sees nothing, which the kernels treat as
/// invalid), each through the camera's own map.
#[inline(always)]
fn fill_directions(
    camera: &SkyCamera,
    x0: usize,
    y: usize,
    w: usize,
    dx: &mut [f32; L],
    dy: &mut [f32; L],
    dz: &mut [f32; L],
) {
    for i in 0..L.min(w - x0) {
        if let Some(d) = camera.direction(x0 + i, y) {
            (dx[i], dy[i], dz[i]) = (d.x, d.y, d.z);
        }
    }
}
