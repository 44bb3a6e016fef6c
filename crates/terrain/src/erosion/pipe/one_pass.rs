//! The fused sweep: the whole step (conservative transport) as one pass per
//! chunk of rows, with the halo rows each chunk needs of its neighbours
//! computed first from the untouched state. It calls the same row functions
//! as the three passes ([`super::row_kernels`]), in an order that reads each row
//! of every plane from memory once per step; the tests hold it to the three
//! passes' bits on one and on two threads.

use natura_core::HeightField;

use super::grid::{Outflows, Rows, Step, opt_rows};
use super::row_kernels::{UpdateRows, flux_pass_row, transport_pass_row, update_pass_row};
use super::{PipeModel, replay};
use crate::bands;
use crate::erosion::Edges;

impl PipeModel {
    /// Rows `[y0, y1)` of each chunk of the fused sweep: about `chunk_rows`
    /// rows each, depending only on the grid size (never on the thread count).
    fn chunks(&self, chunk_rows: usize) -> Vec<(usize, usize)> {
        let ny = self.ny;
        // At most eight chunks: halos cost rows, and two to eight cores share them.
        let rows = chunk_rows.max(ny / 8).max(1);
        let n = ny.div_ceil(rows).max(1);
        (0..n).map(|k| (k * ny / n, (k + 1) * ny / n)).collect()
    }

    /// The step as one sweep per chunk of rows. Within a chunk, iteration
    /// `t` runs pass A (rain, fluxes) on row `t`, pass B (depth, velocity,
    /// erosion, evaporation) on row `t − 1` and the conservative transport
    /// (pass C) on row `t − 2`, so each row of every plane is read from
    /// memory once per step while its neighbours are still in cache. Water,
    /// fluxes and sediment are updated in place: pass A of row `t` reads the
    /// old water of row `t − 1` before pass B overwrites it, and `d₁` and the
    /// post-erosion sediment live in four-row rings. What a chunk needs of
    /// the rows just outside it (old water, `d₁`, new fluxes, post-erosion
    /// sediment) is computed first, from the untouched state, by [`halo`].
    pub(super) fn step_fused(&mut self, c: &Step, hf: &HeightField, chunk_rows: usize) {
        let nx = self.nx;
        let chunks = self.chunks(chunk_rows);
        let periodic = self.p.edges == Edges::Periodic;
        let bed = hf.heights().as_slice();
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        // Halo index of the boundary below each chunk (none below row 0 unless periodic).
        let mut bounds = Vec::new();
        let mut below = Vec::with_capacity(chunks.len());
        for &(y0, _) in &chunks {
            if y0 > 0 || periodic {
                below.push(Some(bounds.len()));
                bounds.push(y0);
            } else {
                below.push(None);
            }
        }
        let halos: Vec<Halo> = {
            let state = State {
                water: &self.water,
                sediment: &self.sediment,
                flux: &self.flux,
                bed,
                erod,
            };
            bands::run(bounds, |yb| halo(c, &state, yb))
        };
        let [u, v] = &mut self.vel;
        let [f0, f1, f2, f3] = &mut self.flux;
        let planes = [
            self.water.as_mut_slice(),
            self.sediment.as_mut_slice(),
            f0.as_mut_slice(),
            f1.as_mut_slice(),
            f2.as_mut_slice(),
            f3.as_mut_slice(),
            self.bed.as_mut_slice(),
            u.as_mut_slice(),
            v.as_mut_slice(),
        ];
        let mut parts = planes.map(|p| split_rows(p, nx, &chunks).into_iter());
        let n = chunks.len();
        let jobs: Vec<_> = (0..n)
            .map(|k| {
                let planes: [&mut [f32]; 9] =
                    std::array::from_fn(|i| parts[i].next().expect("one part per chunk"));
                let lower = below[k].map(|h| &halos[h]);
                let upper = if k + 1 < n {
                    below[k + 1].map(|h| &halos[h])
                } else {
                    below[0].map(|h| &halos[h])
                };
                (chunks[k], planes, lower, upper)
            })
            .collect();
        let results = bands::run(jobs, |((y0, y1), planes, lower, upper)| {
            sweep(c, y0, y1, planes, bed, erod, lower, upper)
        });
        let (mut out_w, mut out_s) = (Vec::new(), Vec::new());
        for (e, w, s) in results {
            self.ledger.evaporated += e;
            out_w.extend(w);
            out_s.extend(s);
        }
        replay(&mut self.ledger.outflow_water, &out_w);
        replay(&mut self.ledger.outflow_sediment, &out_s);
    }
}

/// Splits a row-major plane `nx` wide into the rows of each chunk.
fn split_rows<'a>(
    mut p: &'a mut [f32],
    nx: usize,
    chunks: &[(usize, usize)],
) -> Vec<&'a mut [f32]> {
    let mut parts = Vec::with_capacity(chunks.len());
    if p.is_empty() {
        // A plane not kept (u, v): an empty part per chunk.
        parts.resize_with(chunks.len(), || &mut [][..]);
        return parts;
    }
    for &(y0, y1) in chunks {
        let (a, b) = std::mem::take(&mut p).split_at_mut((y1 - y0) * nx);
        parts.push(a);
        p = b;
    }
    parts
}

/// The state a halo is computed from (untouched during the halo pass).
struct State<'a> {
    water: &'a [f32],
    sediment: &'a [f32],
    flux: &'a [Vec<f32>; 4],
    bed: &'a [f32],
    erod: Option<&'a [f32]>,
}

/// What the chunks on either side of the boundary below row `yb` need of
/// each other's rows: rows `yb − 1` (index 0) and `yb` (index 1, wrapped) of
/// the old water, `d₁`, the new fluxes and the post-erosion sediment.
struct Halo {
    w: [Vec<f32>; 2],
    d1: [Vec<f32>; 2],
    f: [[Vec<f32>; 4]; 2],
    s1: [Vec<f32>; 2],
}

/// Computes the halo of the boundary below row `yb` from the untouched
/// state: pass A on rows `yb − 2 … yb + 1` (those that exist) and pass B on
/// rows `yb − 1` and `yb`, with the same row functions as the sweep, so the
/// values are bit-identical to the ones the owning chunk computes.
fn halo(c: &Step, state: &State<'_>, yb: usize) -> Halo {
    let nx = c.nx;
    let row = |g: &[f32], j: usize| g[j * nx..(j + 1) * nx].to_vec();
    let rs: [Option<usize>; 4] = std::array::from_fn(|s| c.row_at(yb as isize + s as isize - 2));
    let mut fa: [Option<[Vec<f32>; 4]>; 4] = Default::default();
    let mut d1a: [Vec<f32>; 4] = Default::default();
    for s in 0..4 {
        if let Some(r) = rs[s] {
            let mut f = state.flux.each_ref().map(|p| row(p, r));
            let mut d1 = vec![0.0f32; nx];
            let [a, b, cc, d] = &mut f;
            flux_pass_row(
                c,
                c.rows(state.water, r),
                c.rows(state.bed, r),
                [a, b, cc, d],
                &mut d1,
            );
            fa[s] = Some(f);
            d1a[s] = d1;
        }
    }
    let mut s1: [Vec<f32>; 2] = Default::default();
    for (h, s) in [(0usize, 1usize), (1, 2)] {
        let r = rs[s].expect("the rows on both sides of a boundary exist");
        let frows = |k: usize| Rows {
            b: fa[s - 1].as_ref().map(|f| f[k].as_slice()),
            c: fa[s].as_ref().map_or(&[][..], |f| f[k].as_slice()),
            t: fa[s + 1].as_ref().map(|f| f[k].as_slice()),
        };
        let g = r * nx..(r + 1) * nx;
        let ins = UpdateRows {
            d1: &d1a[s],
            f: std::array::from_fn(frows),
            s0: &state.sediment[g.clone()],
            bed: c.rows(state.bed, r),
            erod: state.erod.map(|e| &e[g.clone()]),
        };
        let mut scratch: [Vec<f32>; 2] = std::array::from_fn(|_| vec![0.0f32; nx]);
        let mut out = vec![0.0f32; nx];
        let [w, b] = &mut scratch;
        update_pass_row(
            c,
            &ins,
            [w, b, &mut out, &mut [], &mut []],
            r,
            &mut Vec::new(),
        );
        s1[h] = out;
    }
    let rl = rs[1].expect("row below the boundary");
    let rh = rs[2].expect("row above the boundary");
    let [_, f1, f2, _] = fa;
    Halo {
        w: [row(state.water, rl), row(state.water, rh)],
        d1: [std::mem::take(&mut d1a[1]), std::mem::take(&mut d1a[2])],
        f: [
            f1.expect("row below the boundary"),
            f2.expect("row above the boundary"),
        ],
        s1,
    }
}

/// One chunk `[y0, y1)` of the fused step (see [`PipeModel::step_fused`]);
/// `planes` are the chunk's rows of water, sediment, the four fluxes, the
/// new bed, u and v (empty when not kept). Returns the water evaporated and the
/// per-cell water and sediment outflows through open edges, in row order.
#[allow(clippy::too_many_arguments)]
fn sweep(
    c: &Step,
    y0: usize,
    y1: usize,
    planes: [&mut [f32]; 9],
    bed: &[f32],
    erod: Option<&[f32]>,
    lower: Option<&Halo>,
    upper: Option<&Halo>,
) -> (f64, Outflows, Outflows) {
    let nx = c.nx;
    let [w, s, f0, f1, f2, f3, bn, u, v] = planes;
    let mut f = [f0, f1, f2, f3];
    let mut d1r = vec![0.0f32; 4 * nx];
    let mut s1r = vec![0.0f32; 4 * nx];
    let loc = |y: usize| (y - y0) * nx..(y - y0 + 1) * nx;
    let ring = |y: usize| (y % 4) * nx..(y % 4 + 1) * nx;
    let mut evaporated = 0.0f64;
    let (mut out_w, mut out_s) = (Vec::new(), Vec::new());
    for t in y0..y1 + 2 {
        if t < y1 {
            // Pass A on row t (reads the old water of rows t − 1 … t + 1).
            let wr = around(
                t,
                y0,
                y1,
                w,
                loc,
                lower.map(|h| h.w[0].as_slice()),
                upper.map(|h| h.w[1].as_slice()),
            );
            let [a, b, cc, d] = &mut f;
            flux_pass_row(
                c,
                wr,
                c.rows(bed, t),
                [
                    &mut a[loc(t)],
                    &mut b[loc(t)],
                    &mut cc[loc(t)],
                    &mut d[loc(t)],
                ],
                &mut d1r[ring(t)],
            );
        }
        if t > y0 && t - 1 < y1 {
            // Pass B on row y = t − 1 (new fluxes of rows y − 1 … y + 1 are known).
            let y = t - 1;
            let ins = UpdateRows {
                d1: &d1r[ring(y)],
                f: flux_rows(y, y0, y1, nx, &f, lower, upper),
                s0: &s[loc(y)],
                bed: c.rows(bed, y),
                erod: erod.map(|e| &e[y * nx..(y + 1) * nx]),
            };
            let outs = [
                &mut w[loc(y)],
                &mut bn[loc(y)],
                &mut s1r[ring(y)],
                opt_rows(u, loc(y)),
                opt_rows(v, loc(y)),
            ];
            evaporated += update_pass_row(c, &ins, outs, y, &mut out_w);
        }
        if t >= y0 + 2 {
            // Pass C on row y = t − 2 (post-erosion sediment of rows y − 1 … y + 1 is known).
            let y = t - 2;
            let d1 = around(
                y,
                y0,
                y1,
                &d1r,
                ring,
                lower.map(|h| h.d1[0].as_slice()),
                upper.map(|h| h.d1[1].as_slice()),
            );
            let fr = flux_rows(y, y0, y1, nx, &f, lower, upper);
            let s1 = around(
                y,
                y0,
                y1,
                &s1r,
                ring,
                lower.map(|h| h.s1[0].as_slice()),
                upper.map(|h| h.s1[1].as_slice()),
            );
            transport_pass_row(c, d1, fr, s1, &mut s[loc(y)], y, &mut out_s);
        }
    }
    (evaporated, out_w, out_s)
}

/// A plane's rows around `y` from the chunk `[y0, y1)` (`inside`, indexed by
/// `at`) or the halos `lo` and `hi`.
fn around<'a>(
    y: usize,
    y0: usize,
    y1: usize,
    inside: &'a [f32],
    at: impl Fn(usize) -> std::ops::Range<usize>,
    lo: Option<&'a [f32]>,
    hi: Option<&'a [f32]>,
) -> Rows<'a> {
    Rows {
        b: if y == y0 {
            lo
        } else {
            Some(&inside[at(y - 1)])
        },
        c: &inside[at(y)],
        t: if y + 1 == y1 {
            hi
        } else {
            Some(&inside[at(y + 1)])
        },
    }
}
/// The four flux planes' rows around `y` in the chunk `[y0, y1)`.
fn flux_rows<'a>(
    y: usize,
    y0: usize,
    y1: usize,
    nx: usize,
    f: &'a [&mut [f32]; 4],
    lower: Option<&'a Halo>,
    upper: Option<&'a Halo>,
) -> [Rows<'a>; 4] {
    let loc = |y: usize| (y - y0) * nx..(y - y0 + 1) * nx;
    std::array::from_fn(|k| {
        around(
            y,
            y0,
            y1,
            f[k],
            loc,
            lower.map(|h| h.f[0][k].as_slice()),
            upper.map(|h| h.f[1][k].as_slice()),
        )
    })
}
