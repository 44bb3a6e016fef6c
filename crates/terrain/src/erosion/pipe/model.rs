//! The virtual-pipe model's arithmetic, written once: the per-cell
//! equations of one step (Mei et al. 2007, §3: water increment, outflow
//! flux, water surface and velocity update, erosion and deposition,
//! sediment transportation, evaporation), with the conservative transport
//! that replaces the paper's semi-Lagrangian one, which does not conserve
//! sediment (it creates and destroys material wherever the flow converges
//! or diverges).
//!
//! The reference passes ([`super::reference`]) call these functions once
//! per cell, resolving the grid's edges; the row kernels ([`super::row_kernels`])
//! call them in plain loops over the interior of a row, which the compiler
//! vectorises. Every choice is a compare and select (no `f32::min`/`max`
//! NaN rule, no branch around a division), so the inlined functions stay
//! branch-free and both paths give the same bits.

use super::PipeParams;

/// The model's coefficients for one step, derived from [`PipeParams`] and
/// the cell size `l`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Coefficients {
    /// Rain per step `Δt·r`, metres.
    pub rain: f32,
    /// Flux response `Δt·A·g/l`.
    pub kflux: f32,
    /// `Δt`, seconds.
    pub dt: f32,
    /// Cell area `l²`.
    pub area: f32,
    /// Cell size `l`, metres.
    pub cell: f32,
    /// `K_c`.
    pub kc: f32,
    /// `K_s`.
    pub ks: f32,
    /// `K_d`.
    pub kd: f32,
    /// Evaporated fraction per step `K_e·Δt`.
    pub evap: f32,
    /// Floor on `sin α`.
    pub min_tilt: f32,
    /// `1 / depth_ref`.
    pub inv_dref: f32,
    /// `Δt / l²`.
    pub dt_area: f32,
    /// `1 / (2l)`.
    pub inv_2cell: f32,
    /// Velocity cap `l / Δt` (one cell per step).
    pub vmax: f32,
    /// `Δt / l`: cells travelled per step per m/s.
    pub sl_step: f32,
}

impl Coefficients {
    /// The coefficients of `p` on cells of size `l`.
    pub(super) fn new(p: &PipeParams, l: f32) -> Self {
        let dt = p.dt as f32;
        Self {
            rain: (p.rain_m_per_s * p.dt) as f32,
            kflux: (p.dt * p.pipe_area * p.gravity / f64::from(l)) as f32,
            dt,
            area: l * l,
            cell: l,
            kc: p.k_c as f32,
            ks: p.k_s as f32,
            kd: p.k_d as f32,
            evap: (p.k_e * p.dt) as f32,
            min_tilt: p.min_tilt as f32,
            inv_dref: 1.0 / p.depth_ref as f32,
            dt_area: (p.dt / (f64::from(l) * f64::from(l))) as f32,
            inv_2cell: (0.5 / f64::from(l)) as f32,
            vmax: l / dt,
            sl_step: dt / l,
        }
    }

    /// The water surface of a neighbour after the rain: bed `b` plus water
    /// `w` plus `Δt·r`.
    #[inline(always)]
    pub(super) fn head(&self, b: f32, w: f32) -> f32 {
        b + w + self.rain
    }

    /// Steps 1 and 2 for one cell: the water increment `d₁ = d + Δt·r`
    /// and the outflow fluxes through its four pipes (L, R, B, T),
    /// `f ← max(0, f + Δt·A·g·Δh/l)` scaled by `K = min(1, d₁·l²/(Σf·Δt))`.
    /// `d` and `b` are the cell's water and bed, `f` its fluxes of the last
    /// step, `hn(k)` the water surface of neighbour `k` (its
    /// [`head`](Self::head), `+∞` behind a closed edge, the cell's own bed
    /// behind an open one). Returns `d₁` and the new fluxes.
    #[inline(always)]
    pub(super) fn outflow(
        &self,
        d: f32,
        b: f32,
        f: [f32; 4],
        hn: impl Fn(usize) -> f32,
    ) -> (f32, [f32; 4]) {
        let d1 = d + self.rain;
        let h = b + d1;
        let mut nf = [0.0f32; 4];
        let mut sum = 0.0;
        for k in 0..4 {
            let v = fmax(f[k] + self.kflux * (h - hn(k)), 0.0);
            nf[k] = v;
            sum += v;
        }
        // Divided unconditionally (see `per_flux`).
        let q = d1 * self.area / (sum * self.dt);
        let scale = if sum * self.dt > d1 * self.area {
            q
        } else {
            1.0
        };
        for v in &mut nf {
            *v *= scale;
        }
        (d1, nf)
    }

    /// `K_s` scaled by an erodibility `e`.
    #[inline(always)]
    pub(super) fn ks_times(&self, e: f32) -> f32 {
        self.ks * e
    }

    /// Steps 3, 4 and 6 for one cell: the new depth from the net flux, the
    /// velocity from the average through-flux (capped at one cell per
    /// step), the capacity `C = K_c·sin α·|v|` (α from central differences
    /// of the bed, floored at `min_tilt`, ramped to 0 in films thinner than
    /// `depth_ref`), dissolution `K_s(C − s)` or deposition `K_d(s − C)`,
    /// and evaporation `d ← d(1 − K_e·Δt)` (taken before the transport,
    /// which reads only `d₁` and the fluxes).
    #[inline(always)]
    pub(super) fn update(&self, c: &CellIn) -> CellOut {
        let [fl, fr, fb, ft] = c.fo;
        let [in_l, in_r, in_b, in_t] = c.fin;
        let out = fl + fr + fb + ft;
        let d2 = fmax(c.d1 + (in_l + in_r + in_b + in_t - out) * self.dt_area, 0.0);
        let mean_d = 0.5 * (c.d1 + d2);
        let wet = mean_d > 1e-6;
        // One division for both components, computed for every cell and
        // masked by a multiply: a division under the `wet` condition is
        // turned into a branch that keeps the AVX2 build scalar. (A dry
        // cell's velocity is ±0.)
        let inv = 1.0 / (self.cell * pick(wet, mean_d, 1.0));
        let inv = inv * pick(wet, 1.0, 0.0);
        let vu = clamp(0.5 * (in_l - fl + fr - in_r) * inv, self.vmax);
        let vv = clamp(0.5 * (in_b - fb + ft - in_t) * inv, self.vmax);
        // Local tilt from central differences of the bed.
        let [bl, br, bb, bt] = c.bn;
        let gx = (br - bl) * self.inv_2cell;
        let gy = (bt - bb) * self.inv_2cell;
        let g2 = gx * gx + gy * gy;
        let sin_a = fmax((g2 / (1.0 + g2)).sqrt(), self.min_tilt);
        let speed = (vu * vu + vv * vv).sqrt();
        let cap = self.kc * sin_a * speed * fmin(d2 * self.inv_dref, 1.0);
        let s = c.s;
        let e = c.ks * (cap - s);
        let dep = self.kd * (s - cap);
        let erode = cap > s;
        let lost = d2 * self.evap;
        CellOut {
            w: d2 - lost,
            b: pick(erode, c.bed - e, c.bed + dep),
            s: pick(erode, s + e, s - dep),
            u: vu,
            v: vv,
            lost,
        }
    }

    /// `Δt / (d₁·l²)`, the fraction of a cell's water a unit flux carries
    /// away in one step (0 for a dry cell): one division per cell, shared by
    /// its four pipes.
    #[inline(always)]
    pub(super) fn per_flux(&self, d1: f32) -> f32 {
        // Divided unconditionally (a dry cell's infinity is selected away):
        // a division under a condition keeps the AVX2 build scalar.
        let q = self.dt_area / d1;
        if d1 > 0.0 { q } else { 0.0 }
    }

    /// Fraction of a cell's water that leaves through a pipe of flux `f`
    /// this step, given the cell's [`per_flux`](Self::per_flux) `q`.
    #[inline(always)]
    pub(super) fn frac(q: f32, f: f32) -> f32 {
        fmin(f * q, 1.0)
    }

    /// Conservative transport, what a neighbour sends: the fraction of its
    /// sediment `s` equal to the fraction of its water `d₁` that its pipe
    /// of flux `f` toward the cell carries.
    #[inline(always)]
    pub(super) fn carried(&self, s: f32, d1: f32, f: f32) -> f32 {
        s * Self::frac(self.per_flux(d1), f)
    }

    /// Conservative transport for one cell: it keeps the part of its
    /// sediment `s` whose water stays (`d₁` its water, `fo` its four
    /// outflows) and gains what its neighbours send (`from`, each their
    /// [`carried`](Self::carried), 0 where there is none).
    #[inline(always)]
    pub(super) fn transported(&self, s: f32, d1: f32, fo: [f32; 4], from: [f32; 4]) -> f32 {
        let q = self.per_flux(d1);
        let mut keep = 1.0f32;
        let mut gained = 0.0f32;
        for k in 0..4 {
            keep -= Self::frac(q, fo[k]);
            gained += from[k];
        }
        s * fmax(keep, 0.0) + gained
    }

    /// The paper's semi-Lagrangian transport: the point a cell's sediment
    /// comes from, `x − v·Δt` in cell units.
    #[inline(always)]
    pub(super) fn back_trace(&self, x: f32, y: f32, u: f32, v: f32) -> (f32, f32) {
        (x - u * self.sl_step, y - v * self.sl_step)
    }
}

/// Bilinear interpolation of the corner values `g[y][x]` at `(tx, ty)`.
#[inline(always)]
pub(super) fn bilinear(g: [[f32; 2]; 2], tx: f32, ty: f32) -> f32 {
    let a = g[0][0] + (g[0][1] - g[0][0]) * tx;
    let b = g[1][0] + (g[1][1] - g[1][0]) * tx;
    a + (b - a) * ty
}

/// Pass-B inputs of one cell.
pub(super) struct CellIn {
    /// Water after the rain, `d₁`.
    pub d1: f32,
    /// The cell's outflows to L, R, B, T.
    pub fo: [f32; 4],
    /// Inflows from the L, R, B, T neighbours.
    pub fin: [f32; 4],
    /// Suspended sediment.
    pub s: f32,
    /// Bed height.
    pub bed: f32,
    /// Bed of the L, R, B, T neighbours (the cell's own across an edge).
    pub bn: [f32; 4],
    /// `K_s` at the cell.
    pub ks: f32,
}

/// Pass-B outputs of one cell.
pub(super) struct CellOut {
    /// Water after evaporation.
    pub w: f32,
    /// New bed height.
    pub b: f32,
    /// Sediment after erosion or deposition.
    pub s: f32,
    /// Velocity, x component.
    pub u: f32,
    /// Velocity, y component.
    pub v: f32,
    /// Water evaporated.
    pub lost: f32,
}

/// `a.min(b)` for non-NaN operands as one compare and select: `f32::min`'s
/// NaN rule costs a blend sequence per vector on AVX2, enough for LLVM to
/// leave whole kernels scalar there.
#[inline(always)]
pub(super) fn fmin(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// `a.max(b)` for non-NaN operands as one compare and select (see [`fmin`]).
#[inline(always)]
pub(super) fn fmax(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// `x.clamp(-m, m)` without `clamp`'s bounds assertion (which blocks
/// vectorisation); the same comparisons, so NaN passes through alike.
#[inline(always)]
fn clamp(x: f32, m: f32) -> f32 {
    let x = if x < -m { -m } else { x };
    if x > m { m } else { x }
}

/// `if m { a } else { b }` as a bit blend: a select LLVM keeps as a vector
/// blend on AVX2 instead of turning it into a branch.
#[inline(always)]
fn pick(m: bool, a: f32, b: f32) -> f32 {
    let mask = u32::from(m).wrapping_neg();
    f32::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}
