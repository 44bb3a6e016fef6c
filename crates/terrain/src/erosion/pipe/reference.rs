//! The reference path: every cell through the model's per-cell equations
//! ([`super::model`]) with its neighbours resolved through closed, open or
//! periodic edges, and one step as the paper's sequence of three passes over
//! the grid (rain and outflow fluxes; depth, velocity, erosion or deposition
//! and evaporation; sediment transport), each a gather over row bands.
//!
//! The same passes, given [`Path::Rows`](super::Path::Rows), send the
//! interior of each row through the row kernels of [`super::row_kernels`] instead
//! (the grid's edge cells always come here); the tests hold the two to the
//! same bits.

use natura_core::HeightField;

use super::grid::{B, L, Outflows, R, Rows, Step, T};
use super::model::{CellIn, Coefficients, bilinear};
use super::row_kernels::{
    UpdateRows, flux_pass_row, semi_lagrangian_pass_row, transport_pass_row, update_pass_row,
};
use super::{PipeModel, SedimentTransport, replay};
use crate::bands;
use crate::erosion::Edges;

/// Steps 1 and 2 for cell `x` of a row: returns `d₁` and updates the cell's
/// four fluxes.
#[inline]
pub(super) fn flux_cell(
    c: &Step,
    x: usize,
    water: Rows<'_>,
    bed: Rows<'_>,
    f: [&mut f32; 4],
) -> f32 {
    let open = c.edges == Edges::Open;
    let hn = |k| match (c.nb(bed, x, k), c.nb(water, x, k)) {
        (Some(b), Some(w)) => c.k.head(b, w),
        // Across an open edge the water surface drops to the cell's bed;
        // across a closed one no water flows.
        _ if open => bed.c[x],
        _ => f32::INFINITY,
    };
    let old = [*f[0], *f[1], *f[2], *f[3]];
    let (d1, new) = c.k.outflow(water.c[x], bed.c[x], old, hn);
    for (o, v) in f.into_iter().zip(new) {
        *o = v;
    }
    d1
}

/// Steps 3, 4 and 6 for cell `x` of the row `ins`: writes water, bed and
/// sediment; returns the water evaporated, the water lost through open
/// edges and the velocity.
#[inline]
pub(super) fn update_cell(
    c: &Step,
    x: usize,
    ins: &UpdateRows<'_>,
    [wo, bo, so]: [&mut f32; 3],
) -> (f32, f64, [f32; 2]) {
    let f = &ins.f;
    let get = |k: usize, dir: usize| c.nb(f[dir], x, k).unwrap_or(0.0);
    let mut out_w = 0.0f64;
    if c.edges == Edges::Open {
        for (k, fk) in f.iter().enumerate() {
            if c.nb(ins.bed, x, k).is_none() {
                out_w += f64::from(fk.c[x] * c.k.dt / c.k.area);
            }
        }
    }
    let bed = ins.bed.c[x];
    let bn = |k: usize| c.nb(ins.bed, x, k).unwrap_or(bed);
    let cell = CellIn {
        d1: ins.d1[x],
        fo: [f[L].c[x], f[R].c[x], f[B].c[x], f[T].c[x]],
        fin: [get(L, R), get(R, L), get(B, T), get(T, B)],
        s: ins.s0[x],
        bed,
        bn: [bn(L), bn(R), bn(B), bn(T)],
        ks: ins.erod.map_or(c.k.ks, |e| c.k.ks_times(e[x])),
    };
    let o = c.k.update(&cell);
    [*wo, *bo, *so] = [o.w, o.b, o.s];
    (o.lost, out_w, [o.u, o.v])
}

/// Conservative transport for cell `x`: the new sediment and what left
/// through open edges.
#[inline]
pub(super) fn transport_cell(
    c: &Step,
    x: usize,
    d1: Rows<'_>,
    f: &[Rows<'_>; 4],
    s1: Rows<'_>,
) -> (f32, f64) {
    let q = c.k.per_flux(d1.c[x]);
    let mut out_s = 0.0f64;
    let mut from = [0.0f32; 4];
    for k in 0..4 {
        // The neighbour's pipe toward this cell is the opposite one (`k ^ 1`).
        match (c.nb(d1, x, k), c.nb(f[k ^ 1], x, k), c.nb(s1, x, k)) {
            (Some(dj), Some(fj), Some(sj)) => from[k] = c.k.carried(sj, dj, fj),
            _ => out_s += f64::from(s1.c[x] * Coefficients::frac(q, f[k].c[x])),
        }
    }
    let fo = [f[L].c[x], f[R].c[x], f[B].c[x], f[T].c[x]];
    (c.k.transported(s1.c[x], d1.c[x], fo, from), out_s)
}

/// The paper's semi-Lagrangian transport for cell `(x, y)`: the sediment
/// `s1` sampled where the velocity `(u, v)` traces back to.
#[inline]
pub(super) fn semi_lagrangian_cell(
    c: &Step,
    u: &[f32],
    v: &[f32],
    s1: &[f32],
    x: usize,
    y: usize,
) -> f32 {
    let i = y * c.nx + x;
    let (px, py) = c.k.back_trace(x as f32, y as f32, u[i], v[i]);
    sample(s1, c.nx, c.ny, px, py, c.edges == Edges::Periodic)
}

/// Bilinear sample of a row-major grid in cell units, clamped (or wrapped).
fn sample(g: &[f32], nx: usize, ny: usize, x: f32, y: f32, wrap: bool) -> f32 {
    let (fx, fy) = (x.floor(), y.floor());
    let idx = |i: i64, n: usize| {
        if wrap {
            i.rem_euclid(n as i64) as usize
        } else {
            i.clamp(0, n as i64 - 1) as usize
        }
    };
    let (x0, x1) = (idx(fx as i64, nx), idx(fx as i64 + 1, nx));
    let (y0, y1) = (idx(fy as i64, ny), idx(fy as i64 + 1, ny));
    let at = |x: usize, y: usize| g[y * nx + x];
    bilinear(
        [[at(x0, y0), at(x1, y0)], [at(x0, y1), at(x1, y1)]],
        x - fx,
        y - fy,
    )
}

impl PipeModel {
    /// The step as three passes over the grid (rain and fluxes; depth,
    /// velocity, erosion and evaporation; sediment transport), each a gather
    /// over row bands. With `c.simd` the interior of each row goes through
    /// the row kernels; without it every cell takes the per-cell path above.
    pub(super) fn step_passes(&mut self, c: &Step, hf: &HeightField) {
        let (nx, ny) = (self.nx, self.ny);
        self.water1.resize(nx * ny, 0.0);
        self.sediment1.resize(nx * ny, 0.0);
        let bed = hf.heights().as_slice();
        self.flux_pass(c, bed);
        self.update_pass(c, bed);
        self.transport_pass(c);
    }

    /// Rain and outflow fluxes (in place: each cell owns its 4 pipes), the
    /// depth after rain and outflow into `water1`.
    fn flux_pass(&mut self, c: &Step, bed: &[f32]) {
        let (nx, ny) = (self.nx, self.ny);
        let water = &self.water;
        let [fl, fr, fb, ft] = &mut self.flux;
        let outs = [
            self.water1.as_mut_slice(),
            fl.as_mut_slice(),
            fr.as_mut_slice(),
            fb.as_mut_slice(),
            ft.as_mut_slice(),
        ];
        bands::map_bands(nx, ny, outs, |y0, y1, [d1o, fl, fr, fb, ft]| {
            for y in y0..y1 {
                let r = (y - y0) * nx..(y - y0 + 1) * nx;
                flux_pass_row(
                    c,
                    c.rows(water, y),
                    c.rows(bed, y),
                    [
                        &mut fl[r.clone()],
                        &mut fr[r.clone()],
                        &mut fb[r.clone()],
                        &mut ft[r.clone()],
                    ],
                    &mut d1o[r],
                );
            }
        });
    }

    /// Depth, velocity, erosion / deposition, evaporation: the new water,
    /// bed and velocity, the post-erosion sediment into `sediment1`.
    fn update_pass(&mut self, c: &Step, bed: &[f32]) {
        let (nx, ny) = (self.nx, self.ny);
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        // The three passes always compute u and v (the semi-Lagrangian transport reads them).
        for p in &mut self.vel {
            p.resize(nx * ny, 0.0);
        }
        let results: Vec<(f64, Outflows)> = {
            let d1 = &self.water1;
            let f = &self.flux;
            let s0 = &self.sediment;
            let [u, v] = &mut self.vel;
            let outs = [
                self.water.as_mut_slice(),
                self.bed.as_mut_slice(),
                self.sediment1.as_mut_slice(),
                u.as_mut_slice(),
                v.as_mut_slice(),
            ];
            bands::map_bands(nx, ny, outs, |y0, y1, [wo, bo, so, uo, vo]| {
                let mut evaporated = 0.0f64;
                let mut out_w = Vec::new();
                for y in y0..y1 {
                    let r = (y - y0) * nx..(y - y0 + 1) * nx;
                    let g = y * nx..(y + 1) * nx;
                    let ins = UpdateRows {
                        d1: &d1[g.clone()],
                        f: std::array::from_fn(|k| c.rows(&f[k], y)),
                        s0: &s0[g.clone()],
                        bed: c.rows(bed, y),
                        erod: erod.map(|e| &e[g.clone()]),
                    };
                    let outs = [
                        &mut wo[r.clone()],
                        &mut bo[r.clone()],
                        &mut so[r.clone()],
                        &mut uo[r.clone()],
                        &mut vo[r],
                    ];
                    evaporated += update_pass_row(c, &ins, outs, y, &mut out_w);
                }
                (evaporated, out_w)
            })
        };
        let mut out_w = Vec::new();
        for (e, o) in results {
            self.ledger.evaporated += e;
            out_w.extend(o);
        }
        replay(&mut self.ledger.outflow_water, &out_w);
    }

    /// Sediment transport, conservative or semi-Lagrangian, from
    /// `sediment1` into the sediment.
    fn transport_pass(&mut self, c: &Step) {
        let (nx, ny) = (self.nx, self.ny);
        let s1 = &self.sediment1;
        let d1 = &self.water1;
        let f = &self.flux;
        let (u, v) = (&self.vel[0], &self.vel[1]);
        let transport = self.p.transport;
        let outflow_s: Vec<Outflows> =
            bands::map_bands(nx, ny, [self.sediment.as_mut_slice()], |y0, y1, [so]| {
                let mut out_s = Vec::new();
                for y in y0..y1 {
                    let row = &mut so[(y - y0) * nx..(y - y0 + 1) * nx];
                    match transport {
                        SedimentTransport::Conservative => transport_pass_row(
                            c,
                            c.rows(d1, y),
                            std::array::from_fn(|k| c.rows(&f[k], y)),
                            c.rows(s1, y),
                            row,
                            y,
                            &mut out_s,
                        ),
                        SedimentTransport::SemiLagrangian => {
                            semi_lagrangian_pass_row(c, u, v, s1, y, row);
                        }
                    }
                }
                out_s
            });
        replay(&mut self.ledger.outflow_sediment, &outflow_s.concat());
    }
}
