//! Semi-Lagrangian advection and its error-correcting upgrades.
//!
//! Stable Fluids' method of characteristics (Stam 1999, §2.2
//! and App. A): each sample's new value is the old field interpolated at the
//! point a particle starting there came from, `w2(x) = w1(p(x, −dt))`. It is
//! unconditionally stable; with linear interpolation it never creates new
//! extrema (Stam 1999, §2.2). The back-trace is explicit Euler or the midpoint
//! second-order Runge–Kutta the paper uses (Stam 1999, §3.2).
//!
//! Beyond the papers, [`AdvectionScheme::MacCormack`] (Selle, Fedkiw, Kim, Liu &
//! Rossignac 2008) and [`AdvectionScheme::Bfecc`] (Kim, Liu, Llamas & Rossignac 2005)
//! estimate the semi-Lagrangian error by advecting backwards and compensate
//! half of it; both clamp to the range of the semi-Lagrangian stencil so they
//! stay unconditionally stable and create no new extrema.
//!
//! Paths that end inside a solid are clipped at the solid's surface (Smoke
//! Fig. 2, Fedkiw et al. 2001, §4), so values are never fetched from inside an obstacle.

use natura_core::Grid3;

use crate::chunks;
use crate::grid::{CellKind, Dims, MacVelocity};
use crate::interp::{AxisW, Interpolation, Sampler};

/// The advection scheme.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum AdvectionScheme {
    /// Plain semi-Lagrangian (Stam 1999): one back-trace and interpolation.
    #[default]
    SemiLagrangian,
    /// MacCormack (Selle et al. 2008): forward + backward SL, half-error
    /// correction, reverting to SL where the result leaves the stencil range.
    MacCormack,
    /// Back and forth error compensation and correction (Kim et al. 2005),
    /// clamped to the stencil range of the final semi-Lagrangian step.
    Bfecc,
}

/// The integrator of the back-traced path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum TraceIntegrator {
    /// One explicit Euler step `x − dt·u(x)`.
    Euler,
    /// Midpoint RK2 (Stam 1999, §3.2): `x − dt·u(x − ½dt·u(x))`.
    #[default]
    Rk2,
}

/// How a field is carried by the flow.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct Advection {
    /// Semi-Lagrangian or an error-correcting variant.
    pub scheme: AdvectionScheme,
    /// Back-trace integrator.
    pub tracer: TraceIntegrator,
    /// Interpolation of the advected field.
    pub interpolation: Interpolation,
}

/// Samples a velocity field (metres/second) at positions in cell units.
#[derive(Clone, Copy, Debug)]
pub(crate) struct VelSampler<'a> {
    comps: [Sampler<'a>; 3],
    active: [bool; 3],
}

impl<'a> VelSampler<'a> {
    /// A sampler of a MAC field.
    pub fn mac(vel: &'a MacVelocity) -> Self {
        let dims = vel.dims();
        let comps = std::array::from_fn(|a| face_sampler(vel.comp(a), a));
        Self {
            comps,
            active: std::array::from_fn(|a| dims.active(a)),
        }
    }

    /// A sampler of a collocated (cell-centred) periodic field.
    pub fn collocated(comps: &'a [Grid3<f32>; 3], dims: Dims) -> Self {
        Self {
            comps: std::array::from_fn(|a| centre_sampler(&comps[a], true)),
            active: std::array::from_fn(|a| dims.active(a)),
        }
    }

    /// Velocity at `p` (cell units), in metres per second.
    #[inline(always)]
    pub fn at(&self, p: [f32; 3]) -> [f32; 3] {
        std::array::from_fn(|a| {
            if self.active[a] {
                self.comps[a].linear(p)
            } else {
                0.0
            }
        })
    }
}

impl<'a> VelSampler<'a> {
    /// The component samplers and which axes are active.
    pub(crate) fn parts(&self) -> ([Sampler<'a>; 3], [bool; 3]) {
        (self.comps, self.active)
    }

    /// Per component and axis, the linear weights at the grid coordinates
    /// `i + off[e]`, `i < n[e]`: the velocity at every sample point of a
    /// grid without per-point index arithmetic ([`Self::at_grid`]).
    pub(crate) fn grid_weights(&self, n: [usize; 3], off: [f32; 3]) -> [[Vec<AxisW>; 3]; 3] {
        std::array::from_fn(|b| {
            std::array::from_fn(|e| {
                if !self.active[b] {
                    return Vec::new();
                }
                (0..n[e])
                    .map(|i| self.comps[b].axis_weights(e, i as f32 + off[e]))
                    .collect()
            })
        })
    }

    /// Velocity at grid point `(i, j, k)` of the grid `w` was built for;
    /// bit-identical to [`Self::at`] at that point.
    #[inline(always)]
    pub(crate) fn at_grid(
        &self,
        w: &[[Vec<AxisW>; 3]; 3],
        i: usize,
        j: usize,
        k: usize,
    ) -> [f32; 3] {
        std::array::from_fn(|b| {
            if self.active[b] {
                let y = if self.comps[b].n[1] == 1 {
                    (0, 0, 0.0)
                } else {
                    w[b][1][j]
                };
                self.comps[b].linear_w(w[b][0][i], y, w[b][2][k])
            } else {
                0.0
            }
        })
    }
}

/// A sampler of face component `a` (its own axis offset 0, others ½).
pub(crate) fn face_sampler(g: &Grid3<f32>, a: usize) -> Sampler<'_> {
    let (x, y, z) = g.dims();
    let mut off = [0.5; 3];
    off[a] = 0.0;
    Sampler::new(g.as_slice(), [x, y, z], off, false)
}

/// A sampler of a cell-centred grid.
pub(crate) fn centre_sampler(g: &Grid3<f32>, periodic: bool) -> Sampler<'_> {
    let (x, y, z) = g.dims();
    Sampler::new(g.as_slice(), [x, y, z], [0.5; 3], periodic)
}

/// Answers "is this point inside a solid cell?" for path clipping.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Solids<'a> {
    pub kinds: &'a [CellKind],
    pub dims: Dims,
}

impl Solids<'_> {
    #[inline]
    fn is_solid(&self, p: [f32; 3]) -> bool {
        let n = self.dims.n();
        let c: [usize; 3] = std::array::from_fn(|a| (p[a].max(0.0) as usize).min(n[a] - 1));
        self.kinds[self.dims.idx(c[0], c[1], c[2])] == CellKind::Solid
    }

    /// Clips the segment `from → to` at the first solid cell it enters
    /// (Fedkiw et al. 2001, Fig. 2): marches in steps of at most ¼ cell, then bisects.
    #[inline(always)]
    pub(crate) fn clip(&self, from: [f32; 3], to: [f32; 3]) -> [f32; 3] {
        if !self.is_solid(to) || self.is_solid(from) {
            return to;
        }
        self.clip_slow(from, to)
    }

    #[cold]
    #[inline(never)]
    fn clip_slow(&self, from: [f32; 3], to: [f32; 3]) -> [f32; 3] {
        let d: [f32; 3] = std::array::from_fn(|a| to[a] - from[a]);
        let len = d.iter().map(|v| v.abs()).fold(0.0f32, f32::max);
        let steps = ((len * 4.0).ceil() as usize).clamp(1, 4096);
        let at = |t: f32| -> [f32; 3] { std::array::from_fn(|a| from[a] + d[a] * t) };
        let mut lo = 0.0f32;
        let mut hi = 1.0f32;
        for s in 1..=steps {
            let t = s as f32 / steps as f32;
            if self.is_solid(at(t)) {
                hi = t;
                break;
            }
            lo = t;
        }
        for _ in 0..12 {
            let mid = 0.5 * (lo + hi);
            if self.is_solid(at(mid)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        at(lo)
    }
}

/// One step of a back-trace along one axis: the foot `p − s·v` of a step of
/// `s` cells per unit velocity (`dt/h` for a whole step, half of it to the
/// RK2 midpoint; Stam 1999, §3.2). The scalar and the lane tracers both
/// step through this.
#[inline(always)]
pub(crate) fn trace_step(p: f32, v: f32, s: f32) -> f32 {
    p - s * v
}

/// Traces `p` (cell units) back through `vel` for `dt_h = dt / h` seconds per metre.
#[inline(always)]
pub(crate) fn backtrace(
    p: [f32; 3],
    vel: &VelSampler<'_>,
    dt_h: f32,
    tracer: TraceIntegrator,
    solids: Option<&Solids<'_>>,
) -> [f32; 3] {
    backtrace_from(p, vel.at(p), vel, dt_h, tracer, solids)
}

/// [`backtrace`] given the velocity `v1 = vel.at(p)` at the start point.
#[inline(always)]
fn backtrace_from(
    p: [f32; 3],
    v1: [f32; 3],
    vel: &VelSampler<'_>,
    dt_h: f32,
    tracer: TraceIntegrator,
    solids: Option<&Solids<'_>>,
) -> [f32; 3] {
    let q = match tracer {
        TraceIntegrator::Euler => std::array::from_fn(|a| trace_step(p[a], v1[a], dt_h)),
        TraceIntegrator::Rk2 => {
            let mid: [f32; 3] = std::array::from_fn(|a| trace_step(p[a], v1[a], 0.5 * dt_h));
            let v2 = vel.at(mid);
            std::array::from_fn(|a| trace_step(p[a], v2[a], dt_h))
        }
    };
    match solids {
        Some(s) => s.clip(p, q),
        None => q,
    }
}

/// One semi-Lagrangian pass: `dst[x] = src(backtrace(x))`. Optionally
/// records the linear stencil range at each back-traced point.
fn sl_pass(
    dst: &mut [f32],
    range: Option<(&mut [f32], &mut [f32])>,
    src: &Sampler<'_>,
    vel: &VelSampler<'_>,
    dt_h: f32,
    adv: &Advection,
    solids: Option<&Solids<'_>>,
) {
    if range.is_none()
        && adv.interpolation == Interpolation::Linear
        && crate::advect_linear::sl_linear(&mut [&mut *dst], &[*src], vel, dt_h, adv.tracer, solids)
    {
        return;
    }
    sl_pass_general(dst, range, src, vel, dt_h, adv, solids);
}

/// [`sl_pass`] without the lane fast path: the general code (and its oracle).
pub(crate) fn sl_pass_general(
    dst: &mut [f32],
    range: Option<(&mut [f32], &mut [f32])>,
    src: &Sampler<'_>,
    vel: &VelSampler<'_>,
    dt_h: f32,
    adv: &Advection,
    solids: Option<&Solids<'_>>,
) {
    let n = src.n;
    let off = src.off;
    let pos = |r: usize, i: usize| {
        [
            i as f32 + off[0],
            (r % n[1]) as f32 + off[1],
            (r / n[1]) as f32 + off[2],
        ]
    };
    // The start velocity of every path is read at grid points: weights per axis.
    let w = vel.grid_weights(n, off);
    let w = &w;
    match range {
        None => chunks::for_chunks(dst, n[0], |r, row| {
            let (j, k) = (r % n[1], r / n[1]);
            for (i, out) in row.iter_mut().enumerate() {
                let v1 = vel.at_grid(w, i, j, k);
                let q = backtrace_from(pos(r, i), v1, vel, dt_h, adv.tracer, solids);
                *out = src.sample(q, adv.interpolation);
            }
        }),
        Some((lo, hi)) => {
            // Three outputs per row: zip the range buffers row by row.
            let mut lohi: Vec<(f32, f32)> = vec![(0.0, 0.0); dst.len()];
            chunks::for_chunks2(dst, &mut lohi, n[0], |r, row, rr| {
                let (j, k) = (r % n[1], r / n[1]);
                for (i, (out, lh)) in row.iter_mut().zip(rr.iter_mut()).enumerate() {
                    let v1 = vel.at_grid(w, i, j, k);
                    let q = backtrace_from(pos(r, i), v1, vel, dt_h, adv.tracer, solids);
                    *out = src.sample(q, adv.interpolation);
                    *lh = src.stencil_range(q);
                }
            });
            for ((l, h), (a, b)) in lo.iter_mut().zip(hi.iter_mut()).zip(lohi) {
                *l = a;
                *h = b;
            }
        }
    }
}

/// Advects the samples of `src` (geometry given by the sampler) through
/// `vel` for `dt_h = dt/h`, writing `dst` (same geometry).
pub(crate) fn advect(
    dst: &mut [f32],
    src: &Sampler<'_>,
    vel: &VelSampler<'_>,
    dt_h: f32,
    adv: &Advection,
    solids: Option<&Solids<'_>>,
) {
    match adv.scheme {
        AdvectionScheme::SemiLagrangian => sl_pass(dst, None, src, vel, dt_h, adv, solids),
        AdvectionScheme::MacCormack => {
            let len = dst.len();
            let mut lo = vec![0.0f32; len];
            let mut hi = vec![0.0f32; len];
            sl_pass(dst, Some((&mut lo, &mut hi)), src, vel, dt_h, adv, solids);
            let fwd = dst.to_vec();
            let mut back = vec![0.0f32; len];
            let fwd_s = Sampler::new(&fwd, src.n, src.off, src.periodic);
            sl_pass(&mut back, None, &fwd_s, vel, -dt_h, adv, solids);
            for c in 0..len {
                let v = fwd[c] + 0.5 * (src.data[c] - back[c]);
                dst[c] = if v < lo[c] || v > hi[c] { fwd[c] } else { v };
            }
        }
        AdvectionScheme::Bfecc => {
            let len = dst.len();
            let mut fwd = vec![0.0f32; len];
            sl_pass(&mut fwd, None, src, vel, dt_h, adv, solids);
            let mut back = vec![0.0f32; len];
            let fwd_s = Sampler::new(&fwd, src.n, src.off, src.periodic);
            sl_pass(&mut back, None, &fwd_s, vel, -dt_h, adv, solids);
            let tilde: Vec<f32> = (0..len)
                .map(|c| src.data[c] + 0.5 * (src.data[c] - back[c]))
                .collect();
            let tilde_s = Sampler::new(&tilde, src.n, src.off, src.periodic);
            let mut lo = vec![0.0f32; len];
            let mut hi = vec![0.0f32; len];
            // Stencil range from the original field at the same back-traced points.
            sl_pass(
                &mut back,
                Some((&mut lo, &mut hi)),
                src,
                vel,
                dt_h,
                adv,
                solids,
            );
            sl_pass(dst, None, &tilde_s, vel, dt_h, adv, solids);
            for c in 0..len {
                dst[c] = dst[c].clamp(lo[c], hi[c].max(lo[c]));
            }
        }
    }
}

/// Advects several fields that share one sample geometry (the samplers'
/// `n` and `off`) through the same velocity: with plain semi-Lagrangian
/// advection every path is traced once and each field sampled at its foot,
/// bit-identical to calling [`advect`] per field. Other schemes advect
/// field by field.
pub(crate) fn advect_many(
    dsts: &mut [&mut [f32]],
    srcs: &[Sampler<'_>],
    vel: &VelSampler<'_>,
    dt_h: f32,
    adv: &Advection,
    solids: Option<&Solids<'_>>,
) {
    debug_assert_eq!(dsts.len(), srcs.len());
    let shared = srcs
        .windows(2)
        .all(|w| w[0].n == w[1].n && w[0].off == w[1].off);
    if adv.scheme != AdvectionScheme::SemiLagrangian || srcs.len() < 2 || !shared {
        for (d, s) in dsts.iter_mut().zip(srcs) {
            advect(d, s, vel, dt_h, adv, solids);
        }
        return;
    }
    if adv.interpolation == Interpolation::Linear
        && crate::advect_linear::sl_linear(dsts, srcs, vel, dt_h, adv.tracer, solids)
    {
        return;
    }
    let (n, off) = (srcs[0].n, srcs[0].off);
    let w = vel.grid_weights(n, off);
    let w = &w;
    let mut feet = vec![[0.0f32; 3]; n[0] * n[1] * n[2]];
    chunks::for_chunks(&mut feet, n[0], |r, row| {
        let (j, k) = (r % n[1], r / n[1]);
        for (i, q) in row.iter_mut().enumerate() {
            let p = [i as f32 + off[0], j as f32 + off[1], k as f32 + off[2]];
            let v1 = vel.at_grid(w, i, j, k);
            *q = backtrace_from(p, v1, vel, dt_h, adv.tracer, solids);
        }
    });
    let feet = &feet;
    for (d, s) in dsts.iter_mut().zip(srcs) {
        chunks::for_chunks(d, n[0], |r, row| {
            let fr = &feet[r * n[0]..r * n[0] + row.len()];
            for (o, &q) in row.iter_mut().zip(fr) {
                *o = s.sample(q, adv.interpolation);
            }
        });
    }
}

/// Advects a cell-centred scalar grid through a MAC velocity field.
///
/// `dt` in seconds, `h` the cell size in metres. With `solids`, paths are
/// clipped at solid cells. Returns the advected grid (same size as `src`).
///
/// # Errors
///
/// Returns [`FluidError::SizeMismatch`](crate::FluidError::SizeMismatch) if the field and the velocity grid differ
/// in size, and [`FluidError::InvalidParameter`](crate::FluidError::InvalidParameter) for a non-finite `dt`.
pub fn advect_scalar(
    src: &Grid3<f32>,
    vel: &MacVelocity,
    h: f32,
    dt: f32,
    adv: &Advection,
    solids: Option<&Grid3<CellKind>>,
) -> crate::Result<Grid3<f32>> {
    let dims = vel.dims();
    crate::grid::check_cell_grid(src, dims, "advected scalar")?;
    crate::error::finite("dt", f64::from(dt))?;
    crate::error::positive("h", f64::from(h))?;
    let mut out = src.clone();
    let vs = VelSampler::mac(vel);
    let sol = solids.map(|k| Solids {
        kinds: k.as_slice(),
        dims,
    });
    advect(
        out.as_mut_slice(),
        &centre_sampler(src, false),
        &vs,
        dt / h,
        adv,
        sol.as_ref(),
    );
    Ok(out)
}

/// Advects every component of a MAC velocity field through itself (face
/// midpoints traced back, Fedkiw et al. 2001, §4). Flat axes are left at zero.
///
/// # Errors
///
/// Returns [`FluidError::Core`](crate::FluidError::Core) if a result grid cannot be allocated.
/// Returns [`FluidError::InvalidParameter`](crate::FluidError::InvalidParameter) for a non-finite `dt`.
pub fn advect_velocity(
    vel: &MacVelocity,
    h: f32,
    dt: f32,
    adv: &Advection,
    solids: Option<&Grid3<CellKind>>,
) -> crate::Result<MacVelocity> {
    crate::error::finite("dt", f64::from(dt))?;
    crate::error::positive("h", f64::from(h))?;
    let dims = vel.dims();
    let mut out = vel.clone();
    let vs = VelSampler::mac(vel);
    let sol = solids.map(|k| Solids {
        kinds: k.as_slice(),
        dims,
    });
    for a in 0..3 {
        if !dims.active(a) {
            continue;
        }
        advect(
            out.comp_mut(a).as_mut_slice(),
            &face_sampler(vel.comp(a), a),
            &vs,
            dt / h,
            adv,
            sol.as_ref(),
        );
    }
    Ok(out)
}

/// Returns the back-traced position (metres) of a point at `p` (metres),
/// exactly as the advection routines compute it, clipped at solids.
pub fn trace_back(
    p: glam::Vec3,
    vel: &MacVelocity,
    h: f32,
    dt: f32,
    tracer: TraceIntegrator,
    solids: Option<&Grid3<CellKind>>,
) -> glam::Vec3 {
    let vs = VelSampler::mac(vel);
    let sol = solids.map(|k| Solids {
        kinds: k.as_slice(),
        dims: vel.dims(),
    });
    let q = backtrace((p / h).to_array(), &vs, dt / h, tracer, sol.as_ref());
    glam::Vec3::from_array(q) * h
}
