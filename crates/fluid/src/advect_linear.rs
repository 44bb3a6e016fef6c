//! Lane kernels of linear semi-Lagrangian advection on bounded grids.
//!
//! The fast path of [`crate::advect`] for its commonest case: plain
//! semi-Lagrangian steps, linear interpolation, non-periodic samplers (every
//! bounded solver). A row of samples is processed 16 at a time: the start
//! points, the back-trace (Euler or RK2, [`crate::advect::TraceIntegrator`]), the
//! per-axis clamp, integer cell and fraction, and the bi/trilinear fetches
//! are one branch-free loop over lanes, compiled for AVX-512, AVX2 + FMA or
//! the baseline after run-time detection ([`natura_core::simd`]). Bounds
//! checks disappear because every cell base index is clamped to the last
//! valid base (a no-op after the per-axis clamps) and the 2ᵈ corners are read
//! from equally long shifted slices, so LLVM can emit gathers.
//!
//! Every value is computed with the same operations in the same order as the
//! general [`crate::interp::Sampler::linear`] and
//! [`crate::advect::backtrace`], so the results are bit-identical to the
//! general path (tested); paths that end in a solid are clipped by the same
//! scalar code (Fedkiw et al. 2001, §4, Fig. 2).

use natura_core::simd::{self, Kernel, Simd};

use crate::advect::{Solids, TraceIntegrator, VelSampler, trace_step};
use crate::grid::CellKind;
use crate::interp::Sampler;

/// `2²³`: adding it to a non-negative integer-valued `f32` below `2²³` puts
/// the integer in the low mantissa bits.
const TWO23: f32 = 8_388_608.0;

/// Lanes per chunk.
const L: usize = 16;

type Lanes = [f32; L];

/// A non-periodic component with at least two samples along x and z (and
/// along y in 3-D), prepared for the lane kernels.
#[derive(Clone, Copy, Debug)]
struct Lin<'a> {
    d: &'a [f32],
    nx: u32,
    sz: u32,
    off: [f32; 3],
    hi: [f32; 3],
}

impl<'a> Lin<'a> {
    /// The lane view of `s`, or `None` if `s` is periodic, flat along x or
    /// z, flat along y exactly when `three` (3-D) or too large for `u32`
    /// indices.
    fn new(s: &Sampler<'a>, three: bool) -> Option<Self> {
        let n = s.n;
        if s.periodic || n[0] < 2 || n[2] < 2 || (n[1] >= 2) != three {
            return None;
        }
        if s.data.len() >= (u32::MAX / 2) as usize || n.iter().any(|&v| v >= 1 << 23) {
            return None;
        }
        let u = |v: usize| u32::try_from(v).ok();
        Some(Self {
            d: s.data,
            nx: u(n[0])?,
            sz: u(n[0] * n[1])?,
            off: s.off,
            hi: std::array::from_fn(|a| n[a].saturating_sub(1) as f32),
        })
    }

    /// Lower index and weight along axis `a`: [`Sampler`]'s non-periodic
    /// linear axis rule (`n ≥ 2`), written so that it vectorises: `floor`
    /// instead of a truncating cast (the same value on the clamped,
    /// non-negative coordinate) and the integer read from the bits of
    /// `2²³ + i` (exact for `i < 2²³`), because `as` casts are scalarised.
    /// A NaN coordinate gives a NaN weight, as in the general code.
    #[inline(always)]
    fn axis(&self, a: usize, p: f32) -> (u32, f32) {
        let s = (p - self.off[a]).clamp(0.0, self.hi[a]);
        let f = s.floor().min(self.hi[a] - 1.0);
        let i0 = (f + TWO23).to_bits().wrapping_sub(TWO23.to_bits());
        (i0, s - f)
    }

    /// `out[l]` = the multilinear interpolant at `(x[l], y[l], z[l])`.
    #[inline(always)]
    fn sample<const THREE: bool>(&self, x: &Lanes, y: &Lanes, z: &Lanes, out: &mut Lanes) {
        let d = self.d;
        let (nx, sz) = (self.nx as usize, self.sz as usize);
        let span = if THREE { sz + nx + 1 } else { sz + 1 };
        // `new` guarantees at least two samples along each used axis, so
        // `d.len() > span`; the largest base is `d.len() − span − 1`.
        let Some(m) = d.len().checked_sub(span + 1) else {
            return;
        };
        let mm = m as u32;
        let m = mm as usize + 1;
        let c00 = &d[..m];
        let c01 = &d[1..1 + m];
        let cz0 = &d[sz..sz + m];
        let cz1 = &d[sz + 1..sz + 1 + m];
        // Lane arithmetic (vectorises): cell base and fractions per lane.
        let mut base = [0u32; L];
        let mut tx = [0.0f32; L];
        let mut ty = [0.0f32; L];
        let mut tz = [0.0f32; L];
        for l in 0..L {
            let (x0, fx) = self.axis(0, x[l]);
            let (z0, fz) = self.axis(2, z[l]);
            let (y0, fy) = if THREE { self.axis(1, y[l]) } else { (0, 0.0) };
            base[l] = (z0 * self.sz + y0 * self.nx + x0).min(mm);
            tx[l] = fx;
            ty[l] = fy;
            tz[l] = fz;
        }
        // Fetches (scalar loads, no bounds checks: `base ≤ mm < m`).
        if THREE {
            let cy0 = &d[nx..nx + m];
            let cy1 = &d[nx + 1..nx + 1 + m];
            let cyz0 = &d[sz + nx..sz + nx + m];
            let cyz1 = &d[sz + nx + 1..sz + nx + 1 + m];
            for l in 0..L {
                let b = base[l] as usize;
                let a = c00[b] + (c01[b] - c00[b]) * tx[l];
                let bb = cy0[b] + (cy1[b] - cy0[b]) * tx[l];
                let c = cz0[b] + (cz1[b] - cz0[b]) * tx[l];
                let e = cyz0[b] + (cyz1[b] - cyz0[b]) * tx[l];
                let lo = a + (bb - a) * ty[l];
                let hi = c + (e - c) * ty[l];
                out[l] = lo + (hi - lo) * tz[l];
            }
        } else {
            for l in 0..L {
                let b = base[l] as usize;
                let a = c00[b] + (c01[b] - c00[b]) * tx[l];
                let c = cz0[b] + (cz1[b] - cz0[b]) * tx[l];
                out[l] = a + (c - a) * tz[l];
            }
        }
    }
}

/// The velocity components as lane views (`None` off the active axes).
#[derive(Clone, Copy, Debug)]
struct Vel<'a> {
    comps: [Option<Lin<'a>>; 3],
}

impl Vel<'_> {
    #[inline(always)]
    fn at<const THREE: bool>(&self, p: &[Lanes; 3], out: &mut [Lanes; 3]) {
        for a in 0..3 {
            match &self.comps[a] {
                Some(c) => c.sample::<THREE>(&p[0], &p[1], &p[2], &mut out[a]),
                None => out[a] = [0.0; L],
            }
        }
    }
}

/// One band of rows: trace each sample back, clip at solids, sample every
/// source at the foot and write the rows of `outs`.
struct Band<'a, 'b, 'c, const THREE: bool> {
    vel: &'b Vel<'a>,
    srcs: &'b [Lin<'a>],
    outs: &'b mut [&'c mut [f32]],
    solids: Option<&'b Solids<'b>>,
    geo: Geo,
}

/// The band's place in the sample grid and the step.
#[derive(Clone, Copy, Debug)]
struct Geo {
    /// Samples per row and rows per y-line of the sample grid.
    n0: usize,
    n1: usize,
    /// Index of the band's first row.
    r0: usize,
    off: [f32; 3],
    dt_h: f32,
    tracer: TraceIntegrator,
}

impl<const THREE: bool> Kernel for Band<'_, '_, '_, THREE> {
    type Out = ();

    #[inline(always)]
    fn call(self) {
        let Geo {
            n0,
            n1,
            r0,
            off,
            dt_h,
            tracer,
        } = self.geo;
        let rows = self.outs.first().map_or(0, |o| o.len() / n0);
        for rr in 0..rows {
            let r = r0 + rr;
            let py = (r % n1) as f32 + off[1];
            let pz = (r / n1) as f32 + off[2];
            for i0 in (0..n0).step_by(L) {
                let w = L.min(n0 - i0);
                let mut p = [[0.0f32; L]; 3];
                for (l, v) in p[0].iter_mut().enumerate() {
                    *v = (i0 + l) as f32 + off[0];
                }
                p[1] = [py; L];
                p[2] = [pz; L];
                let mut v = [[0.0f32; L]; 3];
                self.vel.at::<THREE>(&p, &mut v);
                let mut q = [[0.0f32; L]; 3];
                match tracer {
                    TraceIntegrator::Euler => {
                        for a in 0..3 {
                            for l in 0..L {
                                q[a][l] = trace_step(p[a][l], v[a][l], dt_h);
                            }
                        }
                    }
                    TraceIntegrator::Rk2 => {
                        let mut mid = [[0.0f32; L]; 3];
                        for a in 0..3 {
                            for l in 0..L {
                                mid[a][l] = trace_step(p[a][l], v[a][l], 0.5 * dt_h);
                            }
                        }
                        self.vel.at::<THREE>(&mid, &mut v);
                        for a in 0..3 {
                            for l in 0..L {
                                q[a][l] = trace_step(p[a][l], v[a][l], dt_h);
                            }
                        }
                    }
                }
                if let Some(s) = self.solids {
                    // The cell of each foot (vectorised `Solids::is_solid`
                    // index); only feet in solid cells go through the scalar
                    // clip, which repeats that test and checks the start.
                    let nc = s.dims.n();
                    let top: [f32; 3] = std::array::from_fn(|a| nc[a].saturating_sub(1) as f32);
                    let mut cell = [0u32; L];
                    for l in 0..L {
                        let c: [u32; 3] = std::array::from_fn(|a| {
                            let f = q[a][l].max(0.0).floor().min(top[a]);
                            (f + TWO23).to_bits().wrapping_sub(TWO23.to_bits())
                        });
                        cell[l] = (c[2] * nc[1] as u32 + c[1]) * nc[0] as u32 + c[0];
                    }
                    for l in 0..w {
                        if s.kinds[cell[l] as usize] == CellKind::Solid {
                            let from = [p[0][l], p[1][l], p[2][l]];
                            let to = [q[0][l], q[1][l], q[2][l]];
                            let c = s.clip(from, to);
                            for a in 0..3 {
                                q[a][l] = c[a];
                            }
                        }
                    }
                }
                let mut val = [0.0f32; L];
                for (src, out) in self.srcs.iter().zip(self.outs.iter_mut()) {
                    src.sample::<THREE>(&q[0], &q[1], &q[2], &mut val);
                    let o = &mut out[rr * n0 + i0..rr * n0 + i0 + w];
                    o.copy_from_slice(&val[..w]);
                }
            }
        }
    }
}

/// Semi-Lagrangian linear advection of the fields `srcs` (all with the same
/// sample geometry) into `dsts` through `vel`, sharing one back-trace per
/// sample. Returns `false` (and touches nothing) when the lane path does not
/// apply: periodic or flat-in-x/z grids, mixed 2-D/3-D geometry, or `u32`
/// overflow; the caller then runs the general code.
pub(crate) fn sl_linear(
    dsts: &mut [&mut [f32]],
    srcs: &[Sampler<'_>],
    vel: &VelSampler<'_>,
    dt_h: f32,
    tracer: TraceIntegrator,
    solids: Option<&Solids<'_>>,
) -> bool {
    let Some(first) = srcs.first() else {
        return true;
    };
    let (n, off) = (first.n, first.off);
    if dsts.len() != srcs.len()
        || srcs.iter().any(|s| s.n != n || s.off != off)
        || dsts.iter().any(|d| d.len() != n[0] * n[1] * n[2])
    {
        return false;
    }
    let three = n[1] >= 2;
    let Some(lins) = srcs
        .iter()
        .map(|s| Lin::new(s, three))
        .collect::<Option<Vec<_>>>()
    else {
        return false;
    };
    let (comps, active) = vel.parts();
    if active != [true, three, true] {
        return false;
    }
    let mut vc = [None; 3];
    for a in 0..3 {
        if active[a] {
            match Lin::new(&comps[a], three) {
                Some(l) => vc[a] = Some(l),
                None => return false,
            }
        }
    }
    let v = Vel { comps: vc };
    let simd = Simd::best();
    let band_rows = (4096 / n[0]).max(1);
    crate::chunks::for_bands(dsts, n[0] * band_rows, |band, outs| {
        let geo = Geo {
            n0: n[0],
            n1: n[1],
            r0: band * band_rows,
            off,
            dt_h,
            tracer,
        };
        if three {
            simd::run(
                simd,
                Band::<true> {
                    vel: &v,
                    srcs: &lins,
                    outs,
                    solids,
                    geo,
                },
            );
        } else {
            simd::run(
                simd,
                Band::<false> {
                    vel: &v,
                    srcs: &lins,
                    outs,
                    solids,
                    geo,
                },
            );
        }
    });
    true
}
