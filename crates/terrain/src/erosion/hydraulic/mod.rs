//! Musgrave–Kolb–Mace hydraulic (fluvial) erosion, corrected to conserve mass
//! (Musgrave et al. 1989, §4.1, Musgrave 1993, §2.4.1).
//!
//! Each cell carries altitude `a`, water `w` and suspended sediment `s`. Water
//! moves to neighbours whose water *surface* `a + w` is lower; moving water of
//! volume `Δw` can carry `C_s = K_c·Δw` sediment. Over capacity, the excess is
//! partly deposited (`K_d`); under capacity, the bed is eroded (`K_s`).
//!
//! **Errata corrected (all decided once, here):**
//! 1. Over capacity, deposition lands at `v`, the cell the water leaves
//!    (Musgrave 1993, §2.4.1 and both texts' prose), not at `u` as Musgrave et al. 1989, §4.1 prints.
//! 2. Erosion *lowers* `v`: `a_v ← a_v − K_s(C_s − s_v)`. Musgrave et al. 1989, §4.1 lowers `u`,
//!    Musgrave 1993, §2.4.1 *raises* `v` (creating material). With our choice every branch
//!    conserves `a + s` exactly: settle `K_d s + (1−K_d)s = s`; over capacity
//!    `C_s + K_d(s−C_s) + (1−K_d)(s−C_s) = s`; erosion `−e + s + e = s`.
//! 3. The printed `Δw = min(w_v, (w_v + a_v) − (w_u + a_u))` moves the *whole*
//!    surface difference, which for two cells **swaps** their levels instead of
//!    equalising them, so water sloshes back and forth — a likely source of the
//!    instability the author reports (Musgrave 1993, §2.4.1). We move
//!    `ΔW = min(w_v, transfer · max_u d_u)` with `transfer = ½` by default
//!    (equalising); `transfer = 1` is the printed rule.
//! 4. The 2-D split, unspecified beyond "proportional to their respective
//!    differences in overall elevation" (Musgrave et al. 1989, §4.1): `ΔW` and the sediment sent
//!    are split among all lower neighbours in proportion to their surface
//!    drops `d_u`, computed from the state at time `t` (Jacobi, gather form), so
//!    the result is independent of visiting order and thread count.
//! 5. Boundaries and evaporation are unspecified: [`Edges`] chooses, open edges
//!    count outflow; `evaporation` defaults to 0 (the sources have none).
//! 6. Optional guard (default on, our stabilisation): erosion at `v` never digs
//!    below the bed of the lowest receiving neighbour.
//!
//! Rain (Musgrave et al. 1989, §4.1): every `rain_period` = 65 steps, `0.001·a` of water
//! on every cell (altitude-proportional: the adiabatic effect), clamped at 0
//! for negative altitudes. Defaults `K_c = 5, K_d = 0.1, K_s = 0.3` (Musgrave et al. 1989, Plate 9;
//! Musgrave 1993, §2.4.1).

mod model;

use model::Rates;
use natura_core::{Grid2, HeightField};

use super::{Edges, Erodibility, Neighbourhood, check_model_size, check_softness};
use crate::bands;
use crate::error::{Result, in_range, invalid, non_negative};

/// How much rain falls on a cell when it rains.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum RainLaw {
    /// The same depth everywhere, metres.
    Uniform {
        /// Depth of water added, metres.
        depth_m: f64,
    },
    /// `base_m + k · max(a, 0)`: linear in altitude (Musgrave et al. 1989, §4.1; Plate 9 uses `k = 0.001`, base 0).
    AltitudeLinear {
        /// Water per metre of altitude.
        k: f64,
        /// Water added at altitude 0, metres.
        base_m: f64,
    },
}

impl RainLaw {
    /// Rain depth on a cell of altitude `a`, metres.
    #[inline]
    #[must_use]
    pub fn depth(self, a: f32) -> f32 {
        match self {
            RainLaw::Uniform { depth_m } => depth_m as f32,
            RainLaw::AltitudeLinear { k, base_m } => (base_m + k * f64::from(a.max(0.0))) as f32,
        }
    }

    fn validate(self) -> Result<()> {
        match self {
            RainLaw::Uniform { depth_m } => non_negative("RainLaw::Uniform::depth_m", depth_m),
            RainLaw::AltitudeLinear { k, base_m } => {
                non_negative("RainLaw::AltitudeLinear::k", k)?;
                non_negative("RainLaw::AltitudeLinear::base_m", base_m)?;
                if k > 1.0 {
                    return Err(invalid(
                        "RainLaw::AltitudeLinear::k",
                        k,
                        "must be ≤ 1 (rain deeper than the terrain is high)",
                    ));
                }
                Ok(())
            }
        }
    }
}

/// Parameters of [`MusgraveHydraulic`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct MusgraveParams {
    /// Sediment capacity constant `K_c` (sediment per unit of moving water). Default 5.
    pub k_c: f64,
    /// Deposition constant `K_d ∈ [0, 1]`. Default 0.1.
    pub k_d: f64,
    /// Soil softness `K_s ∈ [0, 1]`. Default 0.3.
    pub k_s: f64,
    /// The rain law. Default `AltitudeLinear { k: 0.001, base_m: 0 }`.
    pub rain: RainLaw,
    /// Rain falls on steps `t ≡ 0 (mod rain_period)`, `t = 0, 1, …`; 0 disables rain. Default 65.
    pub rain_period: u32,
    /// Fraction of the largest surface drop that leaves a cell per step, `(0, 1]`:
    /// ½ equalises (default), 1 is the printed (level-swapping) rule.
    pub transfer: f64,
    /// Fraction of water evaporated per step, `[0, 1]`. Default 0 (the sources have none).
    pub evaporation: f64,
    /// Never erode a cell below its lowest receiving neighbour's bed. Default on.
    pub erosion_guard: bool,
    /// Neighbours. Default 8.
    pub neighbourhood: Neighbourhood,
    /// Edges. Default closed.
    pub edges: Edges,
}

impl Default for MusgraveParams {
    fn default() -> Self {
        Self {
            k_c: 5.0,
            k_d: 0.1,
            k_s: 0.3,
            rain: RainLaw::AltitudeLinear {
                k: 0.001,
                base_m: 0.0,
            },
            rain_period: 65,
            transfer: 0.5,
            evaporation: 0.0,
            erosion_guard: true,
            neighbourhood: Neighbourhood::Eight,
            edges: Edges::Closed,
        }
    }
}

impl MusgraveParams {
    /// `K_c ≥ 0` (≤ 1000), `K_d, K_s ∈ [0, 1]`, `transfer ∈ (0, 1]`, `evaporation ∈ [0, 1]`, a valid rain law.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        non_negative("MusgraveParams::k_c", self.k_c)?;
        in_range("MusgraveParams::k_c", self.k_c, 0.0, 1000.0)?;
        in_range("MusgraveParams::k_d", self.k_d, 0.0, 1.0)?;
        in_range("MusgraveParams::k_s", self.k_s, 0.0, 1.0)?;
        if !(self.transfer > 0.0 && self.transfer <= 1.0) {
            return Err(invalid(
                "MusgraveParams::transfer",
                self.transfer,
                "must lie in (0, 1]",
            ));
        }
        in_range("MusgraveParams::evaporation", self.evaporation, 0.0, 1.0)?;
        self.rain.validate()
    }
}

/// Running totals of everything that enters and leaves a hydraulic model, metres³
/// per unit cell area (sums of depths over cells).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MassLedger {
    /// Σ(terrain + sediment) when the model was built.
    pub initial_material: f64,
    /// Σ water when the model was built.
    pub initial_water: f64,
    /// Rain added so far.
    pub rain: f64,
    /// Water evaporated so far.
    pub evaporated: f64,
    /// Water that flowed off open edges.
    pub outflow_water: f64,
    /// Sediment that flowed off open edges.
    pub outflow_sediment: f64,
}

/// Corrected Musgrave–Kolb–Mace hydraulic erosion on a field of fixed size.
#[derive(Debug)]
pub struct MusgraveHydraulic {
    p: MusgraveParams,
    nx: usize,
    ny: usize,
    water: Grid2<f32>,
    sediment: Grid2<f32>,
    erodibility: Option<Erodibility>,
    step: u64,
    ledger: MassLedger,
    // Pass-1 scratch: new altitude, kept water, kept sediment, water sent, sediment sent.
    a1: Grid2<f32>,
    w_keep: Grid2<f32>,
    s_keep: Grid2<f32>,
    w_sent: Grid2<f32>,
    s_sent: Grid2<f32>,
    frac: Vec<Vec<f32>>,
}

impl MusgraveHydraulic {
    /// A dry model (no water, no sediment) for fields the size of `hf`.
    ///
    /// # Errors
    ///
    /// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`](crate::TerrainError::BadSize) if
    /// `hf` is smaller than 3 × 3 samples, and [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) or
    /// [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming `height` for a NaN, infinite or
    /// out-of-range height (beyond ±[`MAX_HEIGHT`](crate::erosion::MAX_HEIGHT)).
    pub fn new(p: MusgraveParams, hf: &HeightField) -> Result<Self> {
        p.validate()?;
        check_model_size("hydraulic erosion", hf)?;
        let (nx, ny) = (hf.nx(), hf.ny());
        let z = || Grid2::new(nx, ny, 0.0f32);
        let ledger = MassLedger {
            initial_material: hf.heights().sum(),
            ..Default::default()
        };
        Ok(Self {
            p,
            nx,
            ny,
            water: z()?,
            sediment: z()?,
            erodibility: None,
            step: 0,
            ledger,
            a1: z()?,
            w_keep: z()?,
            s_keep: z()?,
            w_sent: z()?,
            s_sent: z()?,
            frac: (0..8).map(|_| vec![0.0f32; nx * ny]).collect(),
        })
    }

    /// Scales the softness `K_s` per cell.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if the erodibility map is not the
    /// field's size.
    pub fn with_erodibility(mut self, e: Erodibility) -> Result<Self> {
        check_softness(&e, self.nx, self.ny, self.p.k_s)?;
        self.erodibility = Some(e);
        Ok(self)
    }

    /// Sets the initial water depth (e.g. a flood); refuses negative or non-finite depths.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if `water` is not the field's size, and
    /// [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) or [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) for a
    /// negative or non-finite depth.
    pub fn set_water(&mut self, water: Grid2<f32>) -> Result<()> {
        crate::error::same_size("water", &water, self.nx, self.ny)?;
        crate::error::check_grid("water", &water)?;
        if let Some((x, y, &v)) = water.find(|&v| v < 0.0) {
            return Err(invalid(
                "water",
                format!("{v} at cell ({x}, {y})"),
                "must be >= 0",
            ));
        }
        self.ledger.initial_water += water.sum() - self.water.sum();
        self.water = water;
        Ok(())
    }

    /// Water depth per cell, metres.
    #[must_use]
    pub fn water(&self) -> &Grid2<f32> {
        &self.water
    }

    /// Suspended sediment per cell, metres of material.
    #[must_use]
    pub fn sediment(&self) -> &Grid2<f32> {
        &self.sediment
    }

    /// The mass ledger.
    #[must_use]
    pub fn ledger(&self) -> MassLedger {
        self.ledger
    }

    /// Steps taken so far.
    #[must_use]
    pub fn steps(&self) -> u64 {
        self.step
    }

    stepped_model!(
        "hydraulic erosion",
        "hydraulic",
        "One step: rain (on schedule), transport, evaporation."
    );

    /// One step: rain on schedule, then what leaves each cell and where
    /// ([`Self::send`]), then what each cell gathers ([`Self::gather`]).
    fn step_unchecked(&mut self, hf: &mut HeightField) {
        let p = self.p.clone();
        if p.rain_period > 0 && self.step.is_multiple_of(u64::from(p.rain_period)) {
            self.rain(&p, hf);
        }
        let hood = Hood::new(&p, self.nx, self.ny);
        self.send(&p, &hood, hf);
        self.gather(&p, &hood);
        hf.heights_mut()
            .as_mut_slice()
            .copy_from_slice(self.a1.as_slice());
        self.step += 1;
    }

    /// Adds one rainfall to every cell, booked in the ledger.
    fn rain(&mut self, p: &MusgraveParams, hf: &HeightField) {
        let a = hf.heights().as_slice();
        let mut added = 0.0f64;
        for (w, &h) in self.water.as_mut_slice().iter_mut().zip(a) {
            let r = p.rain.depth(h);
            *w += r;
            added += f64::from(r);
        }
        self.ledger.rain += added;
    }

    /// Pass 1, per cell from the state at time `t` only: the new bed, the
    /// water and sediment that stay, those sent, and the fraction sent to
    /// each neighbour (in proportion to its surface drop); what leaves
    /// through open edges is booked in the ledger.
    #[allow(clippy::needless_range_loop)]
    fn send(&mut self, p: &MusgraveParams, hood: &Hood<'_>, hf: &HeightField) {
        let (nx, ny) = (self.nx, self.ny);
        let k = Rates {
            capacity: p.k_c as f32,
            deposition: p.k_d as f32,
            softness: p.k_s as f32,
            transfer: p.transfer as f32,
            guard: p.erosion_guard,
        };
        let a = hf.heights().as_slice();
        let w = self.water.as_slice();
        let s = self.sediment.as_slice();
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        let [f0, f1, f2, f3, f4, f5, f6, f7] = &mut self.frac[..] else {
            unreachable!("eight planes")
        };
        let outs = [
            self.a1.as_mut_slice(),
            self.w_keep.as_mut_slice(),
            self.s_keep.as_mut_slice(),
            self.w_sent.as_mut_slice(),
            self.s_sent.as_mut_slice(),
            f0.as_mut_slice(),
            f1.as_mut_slice(),
            f2.as_mut_slice(),
            f3.as_mut_slice(),
            f4.as_mut_slice(),
            f5.as_mut_slice(),
            f6.as_mut_slice(),
            f7.as_mut_slice(),
        ];
        let open = p.edges == Edges::Open;
        let outflow: Vec<(f64, f64)> = bands::map_bands(nx, ny, outs, |y0, y1, o| {
            let mut out_w = 0.0f64;
            let mut out_s = 0.0f64;
            for y in y0..y1 {
                for x in 0..nx {
                    let i = y * nx + x;
                    let r = (y - y0) * nx + x;
                    let (av, wv, sv) = (a[i], w[i], s[i]);
                    let level = av + wv;
                    let mut drops = [0.0f32; 8];
                    let mut total = 0.0f32;
                    let mut biggest = 0.0f32;
                    let mut lowest_bed = f32::INFINITY;
                    for k in 0..hood.len() {
                        let d = match hood.nbr(x, y, i, k) {
                            Some(j) => {
                                let d = level - (a[j] + w[j]);
                                if d > 0.0 {
                                    lowest_bed = lowest_bed.min(a[j]);
                                }
                                d
                            }
                            // Open edge: a water-free bed at v's level continues outward.
                            None if open => {
                                lowest_bed = lowest_bed.min(av);
                                wv
                            }
                            None => 0.0,
                        };
                        if d > 0.0 {
                            drops[k] = d;
                            total += d;
                            biggest = biggest.max(d);
                        }
                    }
                    let soft = erod.map_or(k.softness, |e| k.softness * e[i]);
                    let c = k.transport(av, wv, sv, total, biggest, lowest_bed, soft);
                    o[0][r] = c.bed;
                    o[1][r] = c.water_kept;
                    o[2][r] = c.sediment_kept;
                    o[3][r] = c.water_sent;
                    o[4][r] = c.sediment_sent;
                    let inv = if total > 0.0 { 1.0 / total } else { 0.0 };
                    for k in 0..8 {
                        let f = drops[k] * inv;
                        o[5 + k][r] = f;
                        if f > 0.0 && k < hood.len() && open && hood.nbr(x, y, i, k).is_none() {
                            out_w += f64::from(c.water_sent * f);
                            out_s += f64::from(c.sediment_sent * f);
                        }
                    }
                }
            }
            (out_w, out_s)
        });
        for (ow, os) in outflow {
            self.ledger.outflow_water += ow;
            self.ledger.outflow_sediment += os;
        }
    }

    /// Pass 2: each cell keeps what stayed and gathers what its neighbours
    /// sent it (Jacobi, gather form: independent of order and threads);
    /// evaporation is booked in the ledger.
    fn gather(&mut self, p: &MusgraveParams, hood: &Hood<'_>) {
        let (nx, ny) = (self.nx, self.ny);
        let (wk, sk, ws, ss) = (
            self.w_keep.as_slice(),
            self.s_keep.as_slice(),
            self.w_sent.as_slice(),
            self.s_sent.as_slice(),
        );
        let frac: Vec<&[f32]> = self.frac.iter().map(Vec::as_slice).collect();
        let frac = &frac;
        let evap = p.evaporation as f32;
        let evaporated: Vec<f64> = bands::map_bands(
            nx,
            ny,
            [self.water.as_mut_slice(), self.sediment.as_mut_slice()],
            |y0, y1, [wo, so]| {
                let mut ev = 0.0f64;
                for y in y0..y1 {
                    for x in 0..nx {
                        let i = y * nx + x;
                        let r = (y - y0) * nx + x;
                        let mut wn = wk[i];
                        let mut sn = sk[i];
                        for k in 0..hood.len() {
                            if let Some(j) = hood.nbr(x, y, i, k) {
                                let f = frac[hood.opposite[k]][j];
                                if f > 0.0 {
                                    wn += ws[j] * f;
                                    sn += ss[j] * f;
                                }
                            }
                        }
                        let lost = wn * evap;
                        ev += f64::from(lost);
                        wo[r] = wn - lost;
                        so[r] = sn;
                    }
                }
                ev
            },
        );
        self.ledger.evaporated += evaporated.iter().sum::<f64>();
    }
}

/// A cell's neighbours: index deltas for interior cells, the edge rule
/// elsewhere, and each direction's opposite.
struct Hood<'p> {
    p: &'p MusgraveParams,
    offsets: &'static [(i32, i32, f32)],
    deltas: Vec<isize>,
    opposite: Vec<usize>,
    nx: usize,
    ny: usize,
}

impl<'p> Hood<'p> {
    fn new(p: &'p MusgraveParams, nx: usize, ny: usize) -> Self {
        let offsets = p.neighbourhood.offsets();
        let deltas = offsets
            .iter()
            .map(|&(dx, dy, _)| dy as isize * nx as isize + dx as isize)
            .collect();
        let opposite = offsets
            .iter()
            .map(|&(dx, dy, _)| {
                offsets
                    .iter()
                    .position(|&(ex, ey, _)| ex == -dx && ey == -dy)
                    .unwrap_or(0)
            })
            .collect();
        Self {
            p,
            offsets,
            deltas,
            opposite,
            nx,
            ny,
        }
    }

    /// Directions.
    #[inline]
    fn len(&self) -> usize {
        self.offsets.len()
    }

    /// The neighbour of cell `i = (x, y)` in direction `k`, if any.
    #[inline]
    fn nbr(&self, x: usize, y: usize, i: usize, k: usize) -> Option<usize> {
        let (nx, ny) = (self.nx, self.ny);
        if x > 0 && y > 0 && x < nx - 1 && y < ny - 1 {
            Some((i as isize + self.deltas[k]) as usize)
        } else {
            let (dx, dy, _) = self.offsets[k];
            self.p.edges.resolve(x, y, dx, dy, nx, ny)
        }
    }
}

#[cfg(test)]
mod tests;
