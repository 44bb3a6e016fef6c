//! Successive random additions (Voss; Musgrave et al. 1989, §2.1, Musgrave 1993, §2.2.2.3): an *unnested*
//! scheme with arbitrary lacunarity λ. Each generation resamples the previous
//! lattice by a factor λ with bilinear interpolation and adds Gaussian noise to
//! **all** points, the deviation shrinking by `λ^(−H)` per generation, until
//! the lattice is the target grid. Re-displacing old points removes most of
//! the creasing of nested midpoint schemes (Musgrave 1993, §1.2.1).
//!
//! Random numbers are indexed by `(generation, lattice point)`, so the result
//! is independent of evaluation order and thread count.

use natura_core::{Grid2, HeightField, Seed};

use crate::bands;
use crate::error::{Result, in_range, invalid, min_size, non_negative};

/// Parameters of [`successive_random_additions`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct SraParams {
    /// Hurst exponent `H ∈ (0, 1]`.
    pub h: f64,
    /// Lacunarity λ > 1: the resolution change per generation (any real value).
    pub lacunarity: f64,
    /// Standard deviation of generation 0 (the coarsest lattice), metres.
    pub sigma_m: f64,
}

impl Default for SraParams {
    fn default() -> Self {
        Self {
            h: 0.8,
            lacunarity: 2.0,
            sigma_m: 100.0,
        }
    }
}

impl SraParams {
    /// `h ∈ (0, 1]`, `lacunarity ∈ (1, 16]`, `sigma_m ≥ 0` and finite.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        if !(self.h > 0.0 && self.h <= 1.0) {
            return Err(invalid(
                "SraParams::h",
                self.h,
                "Hurst exponent must lie in (0, 1]",
            ));
        }
        if self.lacunarity.is_nan() || self.lacunarity <= 1.0 {
            return Err(invalid(
                "SraParams::lacunarity",
                self.lacunarity,
                "must be > 1",
            ));
        }
        in_range("SraParams::lacunarity", self.lacunarity, 1.0, 16.0)?;
        non_negative("SraParams::sigma_m", self.sigma_m)
    }

    /// Number of generations after the first lattice for a grid of `n` samples per side.
    #[must_use]
    pub fn generations(&self, n: usize) -> u32 {
        let extent = (n.max(2) - 1) as f64;
        (extent.ln() / self.lacunarity.ln()).ceil().max(1.0) as u32
    }
}

/// An `nx × ny` surface by successive random additions. Generation `g` has
/// lattice spacing `λ^(G−g)` cells and deviation `sigma_m · λ^(−H·g)`.
///
/// # Errors
///
/// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`](crate::TerrainError::BadSize)
/// for a size the method cannot make, and [`TerrainError::Core`](crate::TerrainError::Core) if the field
/// cannot be allocated.
pub fn successive_random_additions(
    nx: usize,
    ny: usize,
    cell_size: f32,
    p: &SraParams,
    seed: Seed,
) -> Result<HeightField> {
    p.validate()?;
    min_size("successive_random_additions", nx, ny, 1, 1)?;
    let seed = seed.derive("sra");
    let gens = p.generations(nx.max(ny));
    let lat = p.lacunarity;
    // Generation 0: lattice spacing λ^G cells; enough points to cover the grid.
    let spacing = |g: u32| lat.powi((gens - g) as i32);
    let dims = |g: u32| {
        let s = spacing(g);
        (
            ((nx - 1) as f64 / s).floor() as usize + 2,
            ((ny - 1) as f64 / s).floor() as usize + 2,
        )
    };
    let (w0, h0) = dims(0);
    let mut prev = Grid2::from_fn(w0, h0, |i, j| {
        seed.gaussian(&[0, i as i64, j as i64]) * p.sigma_m
    })?;
    for g in 1..=gens {
        let (w, h) = if g == gens { (nx, ny) } else { dims(g) };
        let sd = p.sigma_m * lat.powf(-p.h * f64::from(g));
        let mut next = Grid2::new(w, h, 0.0f64)?;
        let pr = &prev;
        bands::map_bands(w, h, [next.as_mut_slice()], |y0, _, [out]| {
            for (r, row) in out.chunks_mut(w).enumerate() {
                let j = y0 + r;
                let fy = j as f64 / lat;
                for (i, v) in row.iter_mut().enumerate() {
                    let fx = i as f64 / lat;
                    *v = bilinear(pr, fx, fy)
                        + seed.gaussian(&[i64::from(g), i as i64, j as i64]) * sd;
                }
            }
        });
        prev = next;
    }
    if gens == 0 {
        prev = Grid2::from_fn(nx, ny, |i, j| prev[(i, j)])?;
    }
    let heights = Grid2::from_fn(nx, ny, |i, j| prev[(i, j)] as f32)?;
    Ok(HeightField::new(heights, cell_size)?)
}

/// Bilinear interpolation in lattice units, clamped to the lattice.
fn bilinear(g: &Grid2<f64>, x: f64, y: f64) -> f64 {
    let (w, h) = g.dims();
    let x0 = (x.floor() as usize).min(w - 1);
    let y0 = (y.floor() as usize).min(h - 1);
    let x1 = (x0 + 1).min(w - 1);
    let y1 = (y0 + 1).min(h - 1);
    let (tx, ty) = (x - x0 as f64, y - y0 as f64);
    let a = g[(x0, y0)] + (g[(x1, y0)] - g[(x0, y0)]) * tx;
    let b = g[(x0, y1)] + (g[(x1, y1)] - g[(x0, y1)]) * tx;
    a + (b - a) * ty
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn any_size_and_deterministic() {
        let p = SraParams {
            lacunarity: 1.7,
            ..Default::default()
        };
        let a = successive_random_additions(45, 31, 2.0, &p, Seed(2)).unwrap();
        assert_eq!((a.nx(), a.ny()), (45, 31));
        assert_eq!(
            a,
            successive_random_additions(45, 31, 2.0, &p, Seed(2)).unwrap()
        );
        assert!(
            SraParams {
                lacunarity: 1.0,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
        assert!(
            SraParams {
                h: 1.5,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
    }
}
