//! Poisson faulting (Mandelbrot's fractional Poisson field with step faults):
//! Gaussian random displacements applied across random straight lines
//! (Fournier et al. 1982, §3.2.2, Musgrave et al. 1989, §2.1, Musgrave 1993, §2.2.2.1). The net result is a Brownian surface (H = ½).
//!
//! The sources quote O(N³) for N × N (N faults × N² cells). Each fault is a
//! straight line, so along a row it changes sign exactly once: we add it as a
//! step in a per-row difference array, O(N·F + N²) in total, with exactly the
//! same result as the cell-by-cell sum (up to the order of f64 additions,
//! which is fixed). Fault lines are uniform in direction `θ ∈ [0, π)` and in
//! signed offset over the domain's projected extent; amplitudes are Gaussian.
//! The sources give no kernel for H ≠ ½, so only steps are offered.

use natura_core::{Grid2, HeightField, Seed};
use rand_core::Rng;

use crate::bands;
use crate::error::{Result, invalid, min_size, non_negative};

/// Parameters of [`poisson_faults`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct FaultParams {
    /// Number of faults. The sources give no count; 1000 is enough for a
    /// Brownian look on a few hundred cells per side.
    pub faults: usize,
    /// Standard deviation of each fault's throw (total step height), metres.
    pub amplitude_m: f64,
}

impl Default for FaultParams {
    fn default() -> Self {
        Self {
            faults: 1000,
            amplitude_m: 10.0,
        }
    }
}

impl FaultParams {
    /// `faults ≥ 1` and at most 10⁸; `amplitude_m` finite and ≥ 0.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        if self.faults == 0 || self.faults > 100_000_000 {
            return Err(invalid(
                "FaultParams::faults",
                self.faults,
                "must lie in [1, 1e8]",
            ));
        }
        non_negative("FaultParams::amplitude_m", self.amplitude_m)
    }
}

/// Standard normal from two uniforms of a stream (Box–Muller).
pub(crate) fn stream_gauss(rng: &mut impl Rng) -> f64 {
    let u1 = ((rng.next_u64() >> 11) + 1) as f64 * (1.0 / (1u64 << 53) as f64);
    let u2 = natura_core::unit_f64(rng.next_u64());
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// An `nx × ny` field made by `p.faults` random step faults. Deterministic per
/// seed; rows in parallel.
///
/// # Errors
///
/// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`](crate::TerrainError::BadSize)
/// for a size the method cannot make, and [`TerrainError::Core`](crate::TerrainError::Core) if the field
/// cannot be allocated.
pub fn poisson_faults(
    nx: usize,
    ny: usize,
    cell_size: f32,
    p: &FaultParams,
    seed: Seed,
) -> Result<HeightField> {
    p.validate()?;
    min_size("poisson_faults", nx, ny, 1, 1)?;
    natura_core::check::positive("cell_size", f64::from(cell_size))?;
    let mut rng = seed.derive("poisson-faults").rng();
    let (cx, cy) = ((nx - 1) as f64 / 2.0, (ny - 1) as f64 / 2.0);
    let radius = (cx * cx + cy * cy).sqrt().max(0.5);
    // (cos θ, sin θ, offset, amplitude) in cell units.
    let faults: Vec<[f64; 4]> = (0..p.faults)
        .map(|_| {
            let theta = std::f64::consts::PI * natura_core::unit_f64(rng.next_u64());
            let d = radius * (2.0 * natura_core::unit_f64(rng.next_u64()) - 1.0);
            let a = stream_gauss(&mut rng) * p.amplitude_m;
            [theta.cos(), theta.sin(), d, a]
        })
        .collect();
    let mut heights = Grid2::new(nx, ny, 0.0f32)?;
    bands::map_bands(nx, ny, [heights.as_mut_slice()], |y0, _y1, [out]| {
        let mut diff = vec![0.0f64; nx + 1];
        for (r, row) in out.chunks_mut(nx).enumerate() {
            let y = (y0 + r) as f64 - cy;
            diff.iter_mut().for_each(|v| *v = 0.0);
            let mut base = 0.0f64;
            for &[c, s, d, a] in &faults {
                // Side of cell x: c·(x − cx) + s·y − d > 0 → +a/2, else −a/2.
                let rest = s * y - d;
                if c > 0.0 {
                    // Positive for x > cx − rest / c.
                    let xs = cx - rest / c;
                    let i0 = first_index_above(xs, nx);
                    base -= a / 2.0;
                    diff[i0] += a;
                } else if c < 0.0 {
                    let xs = cx - rest / c; // positive for x < xs
                    let i1 = first_index_at_or_above(xs, nx);
                    base += a / 2.0;
                    diff[i1] -= a;
                } else {
                    base += if rest > 0.0 { a / 2.0 } else { -a / 2.0 };
                }
            }
            let mut acc = base;
            for (x, v) in row.iter_mut().enumerate() {
                acc += diff[x];
                *v = acc as f32;
            }
        }
    });
    Ok(HeightField::new(heights, cell_size)?)
}

/// Smallest integer `i ∈ [0, n]` with `i > x`.
fn first_index_above(x: f64, n: usize) -> usize {
    if x < 0.0 {
        0
    } else if x >= n as f64 {
        n
    } else {
        x.floor() as usize + 1
    }
}

/// Smallest integer `i ∈ [0, n]` with `i ≥ x`.
fn first_index_at_or_above(x: f64, n: usize) -> usize {
    if x <= 0.0 {
        0
    } else if x > n as f64 {
        n
    } else {
        x.ceil() as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The difference-array fast path equals the brute-force sum over faults.
    #[test]
    fn fast_path_matches_brute_force() {
        let p = FaultParams {
            faults: 300,
            amplitude_m: 2.0,
        };
        let (nx, ny) = (37, 23);
        let hf = poisson_faults(nx, ny, 1.0, &p, Seed(5)).unwrap();
        let mut rng = Seed(5).derive("poisson-faults").rng();
        let (cx, cy) = ((nx - 1) as f64 / 2.0, (ny - 1) as f64 / 2.0);
        let radius = (cx * cx + cy * cy).sqrt();
        let faults: Vec<[f64; 4]> = (0..p.faults)
            .map(|_| {
                let theta = std::f64::consts::PI * natura_core::unit_f64(rng.next_u64());
                let d = radius * (2.0 * natura_core::unit_f64(rng.next_u64()) - 1.0);
                let a = stream_gauss(&mut rng) * p.amplitude_m;
                [theta.cos(), theta.sin(), d, a]
            })
            .collect();
        for j in 0..ny {
            for i in 0..nx {
                let mut z = 0.0;
                for &[c, s, d, a] in &faults {
                    let side = c * (i as f64 - cx) + s * (j as f64 - cy) - d;
                    z += if side > 0.0 { a / 2.0 } else { -a / 2.0 };
                }
                let got = f64::from(hf.heights()[(i, j)]);
                assert!(
                    (got - z).abs() < 1e-4 * (1.0 + z.abs()),
                    "({i},{j}) {got} vs {z}"
                );
            }
        }
    }

    #[test]
    fn zero_mean_and_deterministic() {
        let p = FaultParams::default();
        let a = poisson_faults(64, 64, 1.0, &p, Seed(1)).unwrap();
        let b = poisson_faults(64, 64, 1.0, &p, Seed(1)).unwrap();
        assert_eq!(a, b);
        // Mean is a sum of 1000 zero-mean terms of σ ≈ 5 m·(imbalance): loose bound.
        let m = a.heights().mean();
        assert!(m.abs() < 60.0, "{m}");
        assert!(
            FaultParams {
                faults: 0,
                amplitude_m: 1.0
            }
            .validate()
            .is_err()
        );
        assert!(
            FaultParams {
                faults: 1,
                amplitude_m: -1.0
            }
            .validate()
            .is_err()
        );
    }
}
