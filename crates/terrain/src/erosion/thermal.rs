//! Thermal weathering: material above the talus angle slides downhill
//! (Musgrave et al. 1989, §4.2, Musgrave 1993, §2.4.2, footnote Musgrave 1993, §2.4.3).
//!
//! For each cell `v` and neighbour `u` at distance `d`, with altitudes of the
//! previous step: if `a_v − a_u > T·d`, move `c_t·(a_v − a_u − T·d)` from `v`
//! to `u`. We evaluate it in gather form: each cell adds what its higher
//! neighbours send and subtracts what it sends to its lower neighbours, with
//! the pair term computed by the same expression from both sides, so material
//! is conserved (to f32 rounding) and the result is independent of order and
//! thread count.
//!
//! **Errata and choices.** Musgrave et al. 1989, §4.2 typesets the rule with swapped indices and
//! *adds* to `a_v`; we use the Musgrave 1993, §2.4.2 form (the neighbour `u` gains) plus
//! the matching loss at `v` that mass conservation requires and no source
//! writes. `T` is compared with a height difference; we store it as an angle
//! (radians) and compare `tan(angle)·distance`. The sources give **no value
//! for T**: we default to 33°, mid-range of the 30–40° angle of repose of loose
//! rubble. "Equitable distribution" (Musgrave et al. 1989, §4.2) is the per-neighbour rule above
//! (each over-steep neighbour independently receives `c_t·excess`), which obeys a
//! discrete maximum principle when `|N|·c_t ≤ 1` — the limit `validate` enforces.
//! The rate is named `talus_rate`, not `c_t`, which Musgrave et al. 1989 also use for the noise offset.

use natura_core::HeightField;

use super::{
    Edges, Erodibility, Neighbourhood, check_conserving_edges, check_erodibility, check_model_size,
    check_neighbour_rate,
};
use crate::bands;
use crate::error::{Result, invalid};

/// Parameters of [`Thermal`] weathering.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct ThermalParams {
    /// Talus angle (angle of repose), radians in `[0, π/2)`. Default 33° (see module docs).
    pub talus_angle: f64,
    /// Fraction of the excess moved per step (`c_t`). Default 0.001 (Musgrave et al. 1989, Plate 9).
    /// Must satisfy `neighbours · talus_rate · max erodibility ≤ 1`.
    pub talus_rate: f64,
    /// Neighbours exchanged with. Default 8.
    pub neighbourhood: Neighbourhood,
    /// Closed or periodic edges (material never leaves).
    pub edges: Edges,
}

impl Default for ThermalParams {
    fn default() -> Self {
        Self {
            talus_angle: 33f64.to_radians(),
            talus_rate: 0.001,
            neighbourhood: Neighbourhood::Eight,
            edges: Edges::Closed,
        }
    }
}

impl ThermalParams {
    /// Refuses a talus angle outside `[0°, 90°)`, a rate outside `(0, 1/neighbours]`
    /// and open edges.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        if !(self.talus_angle >= 0.0 && self.talus_angle < std::f64::consts::FRAC_PI_2) {
            return Err(invalid(
                "ThermalParams::talus_angle",
                self.talus_angle,
                "must lie in [0, π/2) radians (below 90°)",
            ));
        }
        check_neighbour_rate(
            "ThermalParams::talus_rate",
            self.talus_rate,
            self.neighbourhood,
            "for stability",
        )?;
        check_conserving_edges("ThermalParams::edges", self.edges, "thermal weathering")
    }
}

/// Thermal weathering on a height field of fixed size.
#[derive(Debug)]
pub struct Thermal {
    p: ThermalParams,
    nx: usize,
    ny: usize,
    cell: f32,
    next: natura_core::Grid2<f32>,
    erodibility: Option<Erodibility>,
}

impl Thermal {
    /// A model for fields the size of `hf` (at least 3 × 3, finite).
    ///
    /// # Errors
    ///
    /// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`](crate::TerrainError::BadSize) if
    /// `hf` is smaller than 3 × 3 samples, and [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) or
    /// [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming `height` for a NaN, infinite or
    /// out-of-range height (beyond ±[`MAX_HEIGHT`](crate::erosion::MAX_HEIGHT)).
    pub fn new(p: ThermalParams, hf: &HeightField) -> Result<Self> {
        p.validate()?;
        check_model_size("thermal weathering", hf)?;
        Ok(Self {
            p,
            nx: hf.nx(),
            ny: hf.ny(),
            cell: hf.cell_size(),
            next: natura_core::Grid2::new(hf.nx(), hf.ny(), 0.0)?,
            erodibility: None,
        })
    }

    /// Scales the rate per cell by `e` (material leaves a cell at its own rate).
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if the erodibility map is not the
    /// field's size.
    pub fn with_erodibility(mut self, e: Erodibility) -> Result<Self> {
        check_erodibility(Some(&e), self.nx, self.ny)?;
        let limit = 1.0 / (self.p.neighbourhood.count() as f64 * self.p.talus_rate);
        if f64::from(e.max()) > limit {
            return Err(invalid(
                "erodibility",
                e.max(),
                format!("max must be ≤ {limit} for this talus_rate (stability)"),
            ));
        }
        self.erodibility = Some(e);
        Ok(self)
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &ThermalParams {
        &self.p
    }

    stepped_model!("thermal weathering", "thermal", "One synchronous step.");

    fn step_unchecked(&mut self, hf: &mut HeightField) {
        let (nx, ny) = (self.nx, self.ny);
        let tan = self.p.talus_angle.tan() as f32;
        let t1 = tan * self.cell;
        let t2 = t1 * std::f32::consts::SQRT_2;
        let c = self.p.talus_rate as f32;
        let eight = self.p.neighbourhood == Neighbourhood::Eight;
        let src = hf.heights().as_slice();
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        let p = &self.p;
        bands::map_bands(nx, ny, [self.next.as_mut_slice()], |y0, y1, [out]| {
            for y in y0..y1 {
                let row = &mut out[(y - y0) * nx..(y - y0 + 1) * nx];
                if y == 0 || y == ny - 1 {
                    for (x, v) in row.iter_mut().enumerate() {
                        *v = border(src, erod, x, y, nx, ny, p, t1, t2, c);
                    }
                    continue;
                }
                let up = &src[(y - 1) * nx..y * nx];
                let mid = &src[y * nx..(y + 1) * nx];
                let dn = &src[(y + 1) * nx..(y + 2) * nx];
                match erod {
                    None => interior(up, mid, dn, &mut row[1..nx - 1], c, t1, t2, eight),
                    Some(e) => interior_erod(
                        [up, mid, dn],
                        [
                            &e[(y - 1) * nx..y * nx],
                            &e[y * nx..(y + 1) * nx],
                            &e[(y + 1) * nx..(y + 2) * nx],
                        ],
                        &mut row[1..nx - 1],
                        c,
                        t1,
                        t2,
                        eight,
                    ),
                }
                row[0] = border(src, erod, 0, y, nx, ny, p, t1, t2, c);
                row[nx - 1] = border(src, erod, nx - 1, y, nx, ny, p, t1, t2, c);
            }
        });
        std::mem::swap(hf.heights_mut(), &mut self.next);
    }
}

/// Net material received by a cell of height `a` from a neighbour of height `b`
/// (positive: `b` is over-steep above `a`; negative: `a` is over-steep above `b`).
#[inline(always)]
fn exchange(b: f32, a: f32, t: f32) -> f32 {
    let d = b - a;
    (d - t).max(0.0) - (-d - t).max(0.0)
}

#[inline(always)]
fn exchange_e(b: f32, eb: f32, a: f32, ea: f32, t: f32) -> f32 {
    let d = b - a;
    eb * (d - t).max(0.0) - ea * (-d - t).max(0.0)
}

#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn interior(
    up: &[f32],
    mid: &[f32],
    dn: &[f32],
    out: &mut [f32],
    c: f32,
    t1: f32,
    t2: f32,
    eight: bool,
) {
    let n = out.len();
    let (ul, uc, ur) = (&up[..n], &up[1..=n], &up[2..n + 2]);
    let (ml, mc, mr) = (&mid[..n], &mid[1..=n], &mid[2..n + 2]);
    let (dl, dc, dr) = (&dn[..n], &dn[1..=n], &dn[2..n + 2]);
    if eight {
        for i in 0..n {
            let a = mc[i];
            let axial = exchange(ml[i], a, t1)
                + exchange(mr[i], a, t1)
                + exchange(uc[i], a, t1)
                + exchange(dc[i], a, t1);
            let diag = exchange(ul[i], a, t2)
                + exchange(ur[i], a, t2)
                + exchange(dl[i], a, t2)
                + exchange(dr[i], a, t2);
            out[i] = a + c * (axial + diag);
        }
    } else {
        for i in 0..n {
            let a = mc[i];
            let axial = exchange(ml[i], a, t1)
                + exchange(mr[i], a, t1)
                + exchange(uc[i], a, t1)
                + exchange(dc[i], a, t1);
            out[i] = a + c * axial;
        }
    }
}

#[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
fn interior_erod(
    h: [&[f32]; 3],
    e: [&[f32]; 3],
    out: &mut [f32],
    c: f32,
    t1: f32,
    t2: f32,
    eight: bool,
) {
    let n = out.len();
    for i in 0..n {
        let x = i + 1;
        let (a, ea) = (h[1][x], e[1][x]);
        let mut s = exchange_e(h[1][x - 1], e[1][x - 1], a, ea, t1)
            + exchange_e(h[1][x + 1], e[1][x + 1], a, ea, t1)
            + exchange_e(h[0][x], e[0][x], a, ea, t1)
            + exchange_e(h[2][x], e[2][x], a, ea, t1);
        if eight {
            s += exchange_e(h[0][x - 1], e[0][x - 1], a, ea, t2)
                + exchange_e(h[0][x + 1], e[0][x + 1], a, ea, t2)
                + exchange_e(h[2][x - 1], e[2][x - 1], a, ea, t2)
                + exchange_e(h[2][x + 1], e[2][x + 1], a, ea, t2);
        }
        out[i] = a + c * s;
    }
}

#[allow(clippy::too_many_arguments)]
fn border(
    src: &[f32],
    erod: Option<&[f32]>,
    x: usize,
    y: usize,
    nx: usize,
    ny: usize,
    p: &ThermalParams,
    t1: f32,
    t2: f32,
    c: f32,
) -> f32 {
    let i = y * nx + x;
    let a = src[i];
    let mut s = 0.0f32;
    for &(dx, dy, dist) in p.neighbourhood.offsets() {
        if let Some(k) = p.edges.resolve(x, y, dx, dy, nx, ny) {
            let t = if dist > 1.0 { t2 } else { t1 };
            s += match erod {
                None => exchange(src[k], a, t),
                Some(e) => exchange_e(src[k], e[k], a, e[i], t),
            };
        }
    }
    a + c * s
}

/// The largest excess of any neighbour pair over the talus slope,
/// `max(a_v − a_u − tan(angle)·distance)` in metres (≤ 0 when every slope is at
/// or below the talus angle).
#[must_use]
pub fn max_talus_excess(hf: &HeightField, p: &ThermalParams) -> f32 {
    let (nx, ny) = (hf.nx(), hf.ny());
    let src = hf.heights().as_slice();
    let tan = p.talus_angle.tan() as f32 * hf.cell_size();
    let mut worst = f32::NEG_INFINITY;
    for y in 0..ny {
        for x in 0..nx {
            for &(dx, dy, dist) in p.neighbourhood.offsets() {
                if let Some(k) = p.edges.resolve(x, y, dx, dy, nx, ny) {
                    worst = worst.max(src[y * nx + x] - src[k] - tan * dist);
                }
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::NoProgress;

    fn spike(n: usize) -> HeightField {
        HeightField::from_fn(
            n,
            n,
            1.0,
            |i, j| if i == n / 2 && j == n / 2 { 50.0 } else { 0.0 },
        )
        .unwrap()
    }

    #[test]
    fn conserves_and_converges() {
        for edges in [Edges::Closed, Edges::Periodic] {
            for neighbourhood in [Neighbourhood::Four, Neighbourhood::Eight] {
                let p = ThermalParams {
                    talus_rate: 0.1,
                    edges,
                    neighbourhood,
                    ..Default::default()
                };
                let mut hf = spike(21);
                let m0 = hf.heights().sum();
                let (lo0, hi0) = hf.min_max();
                let mut t = Thermal::new(p.clone(), &hf).unwrap();
                let mut prev_hi = hi0;
                for _ in 0..50 {
                    t.step(&mut hf).unwrap();
                    let (lo, hi) = hf.min_max();
                    assert!(
                        hi <= prev_hi + 1e-5 && lo >= lo0 - 1e-5,
                        "maximum principle"
                    );
                    prev_hi = hi;
                }
                t.run(&mut hf, 2000, &NoProgress).unwrap();
                let m1 = hf.heights().sum();
                assert!(
                    (m1 - m0).abs() <= 1e-5 * m0,
                    "{edges:?} {neighbourhood:?}: {m0} → {m1}"
                );
                let excess = max_talus_excess(&hf, &p);
                assert!(
                    excess <= 1e-3,
                    "{edges:?} {neighbourhood:?}: excess {excess}"
                );
                assert!(hi0 > hf.min_max().1);
            }
        }
    }

    #[test]
    fn stable_terrain_is_a_fixed_point() {
        let p = ThermalParams::default();
        let slope = 0.5 * p.talus_angle.tan() as f32;
        let mut hf = HeightField::from_fn(10, 8, 2.0, |i, j| {
            slope * 2.0 * (i as f32 + 0.5 * j as f32) * 0.9
        })
        .unwrap();
        let before = hf.clone();
        Thermal::new(p, &hf)
            .unwrap()
            .run(&mut hf, 10, &NoProgress)
            .unwrap();
        assert_eq!(hf, before);
    }

    #[test]
    fn refuses_bad_input() {
        let hf = spike(8);
        for p in [
            ThermalParams {
                talus_angle: std::f64::consts::FRAC_PI_2,
                ..Default::default()
            },
            ThermalParams {
                talus_angle: -0.1,
                ..Default::default()
            },
            ThermalParams {
                talus_rate: 0.0,
                ..Default::default()
            },
            ThermalParams {
                talus_rate: 0.2,
                ..Default::default()
            },
            ThermalParams {
                talus_rate: f64::NAN,
                ..Default::default()
            },
            ThermalParams {
                edges: Edges::Open,
                ..Default::default()
            },
        ] {
            assert!(Thermal::new(p, &hf).is_err());
        }
        assert!(
            Thermal::new(
                ThermalParams::default(),
                &HeightField::flat(2, 9, 1.0, 0.0).unwrap()
            )
            .is_err()
        );
        let mut t = Thermal::new(ThermalParams::default(), &hf).unwrap();
        let mut bad = spike(8);
        bad.heights_mut()[(3, 5)] = f32::NAN;
        let err = t.step(&mut bad).unwrap_err();
        assert!(err.to_string().contains("(3, 5)"), "{err}");
        let mut other = spike(9);
        assert!(t.step(&mut other).is_err());
    }
}
