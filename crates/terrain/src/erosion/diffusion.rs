//! Diffusive erosion ("dry creep", Musgrave 1993, §2.4.3): bioturbation and rain splash
//! move material to neighbours regardless of slope direction — a progressive
//! low-pass filter, the explicit (FTCS) heat equation
//! `a_u(t+1) = a_u(t) + c_d · Σ_{v∈N(u)} (a_v(t) − a_u(t))`.
//!
//! **Erratum.** Musgrave 1993, §2.4.3 prints `a^u_{t+1} = c_d(a^v_t − a^u_t)`, omitting the
//! `a^u_t +` term (as printed, every step would replace the terrain by a
//! difference). Its wording "as a function of local slope … without regard to
//! local slope" means a symmetric exchange, which is what we implement.
//! Stability and positivity need `|N|·c_d ≤ 1` (the classic 2-D FTCS limit
//! `c_d ≤ ¼` on four neighbours); `validate` enforces it. The sources give no
//! value; the default `c_d = 0.1` is well inside the limit.

use natura_core::{Grid2, HeightField};

use super::{
    Edges, Erodibility, Neighbourhood, check_conserving_edges, check_erodibility, check_model_size,
    check_neighbour_rate,
};
use crate::bands;
use crate::error::{Result, invalid};

/// Parameters of [`Diffusion`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct DiffusionParams {
    /// Diffusion coefficient per step `c_d` (= κ·Δt / Δx²), in `(0, 1/neighbours]`.
    pub rate: f64,
    /// Neighbours (equal weights). Default 4.
    pub neighbourhood: Neighbourhood,
    /// Closed or periodic edges.
    pub edges: Edges,
}

impl Default for DiffusionParams {
    fn default() -> Self {
        Self {
            rate: 0.1,
            neighbourhood: Neighbourhood::Four,
            edges: Edges::Closed,
        }
    }
}

impl DiffusionParams {
    /// Refuses a rate outside `(0, 1/neighbours]` and open edges.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        check_neighbour_rate(
            "DiffusionParams::rate",
            self.rate,
            self.neighbourhood,
            "FTCS stability",
        )?;
        check_conserving_edges("DiffusionParams::edges", self.edges, "diffusion")
    }
}

/// Diffusive creep on a height field of fixed size.
#[derive(Debug)]
pub struct Diffusion {
    p: DiffusionParams,
    nx: usize,
    ny: usize,
    next: Grid2<f32>,
    erodibility: Option<Erodibility>,
}

impl Diffusion {
    /// A model for fields the size of `hf` (at least 3 × 3, finite).
    ///
    /// # Errors
    ///
    /// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`](crate::TerrainError::BadSize) if
    /// `hf` is smaller than 3 × 3 samples, and [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) or
    /// [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming `height` for a NaN, infinite or
    /// out-of-range height (beyond ±[`MAX_HEIGHT`](crate::erosion::MAX_HEIGHT)).
    pub fn new(p: DiffusionParams, hf: &HeightField) -> Result<Self> {
        p.validate()?;
        check_model_size("diffusion", hf)?;
        Ok(Self {
            p,
            nx: hf.nx(),
            ny: hf.ny(),
            next: Grid2::new(hf.nx(), hf.ny(), 0.0)?,
            erodibility: None,
        })
    }

    /// Scales the exchange between two cells by the smaller of their erodibilities.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if the erodibility map is not the
    /// field's size.
    pub fn with_erodibility(mut self, e: Erodibility) -> Result<Self> {
        check_erodibility(Some(&e), self.nx, self.ny)?;
        if f64::from(e.max()) * self.p.rate * self.p.neighbourhood.count() as f64 > 1.0 {
            return Err(invalid(
                "erodibility",
                e.max(),
                "max × rate × neighbours must be ≤ 1 (stability)",
            ));
        }
        self.erodibility = Some(e);
        Ok(self)
    }

    stepped_model!("diffusion", "diffusion", "One synchronous step.");

    fn step_unchecked(&mut self, hf: &mut HeightField) {
        let (nx, ny) = (self.nx, self.ny);
        let c = self.p.rate as f32;
        let src = hf.heights().as_slice();
        let erod = self.erodibility.as_ref().map(|e| e.map().as_slice());
        let p = &self.p;
        let eight = p.neighbourhood == Neighbourhood::Eight;
        bands::map_bands(nx, ny, [self.next.as_mut_slice()], |y0, y1, [out]| {
            for y in y0..y1 {
                let row = &mut out[(y - y0) * nx..(y - y0 + 1) * nx];
                if y == 0 || y == ny - 1 || erod.is_some() {
                    for (x, v) in row.iter_mut().enumerate() {
                        *v = general(src, erod, x, y, nx, ny, p, c);
                    }
                    continue;
                }
                let up = &src[(y - 1) * nx..y * nx];
                let mid = &src[y * nx..(y + 1) * nx];
                let dn = &src[(y + 1) * nx..(y + 2) * nx];
                let n = nx - 2;
                let o = &mut row[1..nx - 1];
                let (ml, mc, mr, uc, dc) =
                    (&mid[..n], &mid[1..=n], &mid[2..], &up[1..=n], &dn[1..=n]);
                if eight {
                    let (ul, ur, dl, dr) = (&up[..n], &up[2..], &dn[..n], &dn[2..]);
                    for i in 0..n {
                        let a = mc[i];
                        let s = (ml[i] - a)
                            + (mr[i] - a)
                            + (uc[i] - a)
                            + (dc[i] - a)
                            + (ul[i] - a)
                            + (ur[i] - a)
                            + (dl[i] - a)
                            + (dr[i] - a);
                        o[i] = a + c * s;
                    }
                } else {
                    for i in 0..n {
                        let a = mc[i];
                        o[i] = a + c * ((ml[i] - a) + (mr[i] - a) + (uc[i] - a) + (dc[i] - a));
                    }
                }
                row[0] = general(src, erod, 0, y, nx, ny, p, c);
                row[nx - 1] = general(src, erod, nx - 1, y, nx, ny, p, c);
            }
        });
        std::mem::swap(hf.heights_mut(), &mut self.next);
    }
}

#[allow(clippy::too_many_arguments)]
fn general(
    src: &[f32],
    erod: Option<&[f32]>,
    x: usize,
    y: usize,
    nx: usize,
    ny: usize,
    p: &DiffusionParams,
    c: f32,
) -> f32 {
    let i = y * nx + x;
    let a = src[i];
    let mut s = 0.0f32;
    for &(dx, dy, _) in p.neighbourhood.offsets() {
        if let Some(k) = p.edges.resolve(x, y, dx, dy, nx, ny) {
            s += match erod {
                None => src[k] - a,
                Some(e) => e[i].min(e[k]) * (src[k] - a),
            };
        }
    }
    a + c * s
}

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::NoProgress;

    #[test]
    fn fourier_mode_decays_exactly() {
        let (n, m) = (32usize, 16usize);
        let (kx, ky) = (
            2.0 * std::f64::consts::PI * 3.0 / n as f64,
            2.0 * std::f64::consts::PI * 2.0 / m as f64,
        );
        let mut hf = HeightField::from_fn(n, m, 1.0, |i, j| {
            (100.0 * (kx * i as f64 + ky * j as f64).cos()) as f32
        })
        .unwrap();
        let p = DiffusionParams {
            rate: 0.2,
            edges: Edges::Periodic,
            ..Default::default()
        };
        let mut d = Diffusion::new(p, &hf).unwrap();
        let steps = 5;
        d.run(&mut hf, steps, &NoProgress).unwrap();
        let g = (1.0 - 0.2 * (4.0 - 2.0 * kx.cos() - 2.0 * ky.cos())).powi(steps as i32);
        for j in 0..m {
            for i in 0..n {
                let want = 100.0 * g * (kx * i as f64 + ky * j as f64).cos();
                let got = f64::from(hf.heights()[(i, j)]);
                assert!((got - want).abs() < 1e-3, "({i},{j}) {got} vs {want}");
            }
        }
    }

    #[test]
    fn conserves_smooths_and_keeps_constants() {
        let mut hf =
            HeightField::from_fn(20, 13, 1.0, |i, j| ((i * 7 + j * 13) % 5) as f32).unwrap();
        let var = |h: &HeightField| {
            let m = h.heights().mean();
            h.heights()
                .as_slice()
                .iter()
                .map(|&v| (f64::from(v) - m).powi(2))
                .sum::<f64>()
        };
        let (m0, v0) = (hf.heights().sum(), var(&hf));
        for nb in [Neighbourhood::Four, Neighbourhood::Eight] {
            let mut d = Diffusion::new(
                DiffusionParams {
                    rate: 0.12,
                    neighbourhood: nb,
                    ..Default::default()
                },
                &hf,
            )
            .unwrap();
            d.run(&mut hf, 10, &NoProgress).unwrap();
        }
        assert!((hf.heights().sum() - m0).abs() < 1e-4 * m0);
        assert!(var(&hf) < v0);
        let mut flat = HeightField::flat(9, 9, 1.0, 3.5).unwrap();
        Diffusion::new(DiffusionParams::default(), &flat)
            .unwrap()
            .run(&mut flat, 5, &NoProgress)
            .unwrap();
        assert!(flat.heights().as_slice().iter().all(|&v| v == 3.5));
        assert!(
            DiffusionParams {
                rate: 0.3,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
        assert!(
            DiffusionParams {
                rate: -0.1,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
    }
}
