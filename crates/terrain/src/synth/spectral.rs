//! Fourier (spectral) synthesis (Fournier et al. 1982, §3.2.2, Musgrave et al. 1989, §2.1, Musgrave 1993, §2.2.2.4): Gaussian
//! white noise is Fourier-transformed, multiplied by a `1/f^(H+1)` amplitude
//! filter and transformed back. The 2-D power spectrum is then
//! `∝ |f|^(−(2H+2))` and every 1-D transect follows `f^(−β)` with
//! `β = 2H + 1` (Musgrave et al. 1989, §3.1, Musgrave 1993, §2.2.1.4). Filtering real white noise keeps
//! the spectrum Hermitian, so the output is real; DC is zero, so the mean is 0.
//!
//! The output is a periodic tile of any size (`rustfft` handles every length):
//! it wraps seamlessly, which is both the method's strength and its known
//! drawback (periodicity, Musgrave et al. 1989, §2.1).

use natura_core::{Grid2, HeightField, Seed};

use crate::error::{Result, invalid, min_size, non_negative};
use crate::fft;

/// Parameters of [`spectral_synthesis`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct SpectralParams {
    /// Hurst exponent `H ∈ (0, 1]`; spectral exponent `β = 2H + 1`.
    pub h: f64,
    /// Expected standard deviation of the heights, metres (the filter is
    /// normalised analytically, so each seed varies around it).
    pub sigma_m: f64,
    /// Frequencies below this many cycles per tile are removed (≥ 0; 0 keeps all
    /// but DC). Raising it sets an upper crossover scale (Musgrave et al. 1989, §3.1).
    pub low_cut: f64,
    /// Frequencies above this many cycles per tile are removed (`None` keeps
    /// all up to Nyquist). Lowering it sets a lower crossover: a smooth surface.
    pub high_cut: Option<f64>,
}

impl Default for SpectralParams {
    fn default() -> Self {
        Self {
            h: 0.8,
            sigma_m: 100.0,
            low_cut: 0.0,
            high_cut: None,
        }
    }
}

impl SpectralParams {
    /// `h ∈ (0, 1]`, `sigma_m ≥ 0`, `low_cut ≥ 0`, `high_cut > low_cut`.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        if !(self.h > 0.0 && self.h <= 1.0) {
            return Err(invalid(
                "SpectralParams::h",
                self.h,
                "Hurst exponent must lie in (0, 1]",
            ));
        }
        non_negative("SpectralParams::sigma_m", self.sigma_m)?;
        non_negative("SpectralParams::low_cut", self.low_cut)?;
        if let Some(hc) = self.high_cut
            && !(hc.is_finite() && hc > self.low_cut)
        {
            return Err(invalid(
                "SpectralParams::high_cut",
                hc,
                "must be finite and > low_cut",
            ));
        }
        Ok(())
    }
}

/// A periodic `nx × ny` fBm-like tile by spectral synthesis. Needs at least 2 × 2 samples.
///
/// # Errors
///
/// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`](crate::TerrainError::BadSize)
/// for a size the method cannot make, and [`TerrainError::Core`](crate::TerrainError::Core) if the field
/// cannot be allocated.
pub fn spectral_synthesis(
    nx: usize,
    ny: usize,
    cell_size: f32,
    p: &SpectralParams,
    seed: Seed,
) -> Result<HeightField> {
    Ok(spectral_with_residue(nx, ny, cell_size, p, seed)?.0)
}

/// [`spectral_synthesis`] plus the largest imaginary residue dropped by the
/// inverse transform (relative to the largest height), for testing realness.
pub(crate) fn spectral_with_residue(
    nx: usize,
    ny: usize,
    cell_size: f32,
    p: &SpectralParams,
    seed: Seed,
) -> Result<(HeightField, f64)> {
    p.validate()?;
    min_size("spectral_synthesis", nx, ny, 2, 2)?;
    natura_core::check::positive("cell_size", f64::from(cell_size))?;
    natura_core::checked_len::<f64>(&[nx, ny, 4])?;
    let seed = seed.derive("spectral");
    let mut noise = vec![0.0f64; nx * ny];
    crate::bands::map_bands(nx, ny, [noise.as_mut_slice()], |y0, _, [out]| {
        for (r, row) in out.chunks_mut(nx).enumerate() {
            for (x, v) in row.iter_mut().enumerate() {
                *v = seed.gaussian2(x as i64, (y0 + r) as i64);
            }
        }
    });
    let mut spec = fft::forward_real_2d(&noise, nx, ny);
    drop(noise);
    // Frequencies in cycles per tile along the longer side, so the filter is
    // isotropic in world space on non-square tiles.
    let l = nx.max(ny) as f64;
    let filter = |kx: f64, ky: f64| -> f64 {
        let f = ((kx * l / nx as f64).powi(2) + (ky * l / ny as f64).powi(2)).sqrt();
        if f == 0.0 || f < p.low_cut || p.high_cut.is_some_and(|hc| f > hc) {
            0.0
        } else {
            f.powf(-(p.h + 1.0))
        }
    };
    // Var(z) = (1/N) Σ_k |F(k)|² over the full spectrum for unit white noise.
    let mut power = 0.0;
    for ky in 0..ny {
        for kx in 0..nx {
            let a = filter(fft::signed_freq(kx, nx), fft::signed_freq(ky, ny));
            power += a * a;
        }
    }
    let norm = if power > 0.0 {
        p.sigma_m / (power / (nx * ny) as f64).sqrt()
    } else {
        0.0
    };
    let hx = fft::half(nx);
    for ky in 0..ny {
        let fy = fft::signed_freq(ky, ny);
        for kx in 0..hx {
            spec[ky * hx + kx] *= filter(kx as f64, fy) * norm;
        }
    }
    let (data, residue) = fft::inverse_real_2d(spec, nx, ny);
    let max = data
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    let heights = Grid2::from_vec(nx, ny, data.iter().map(|&v| v as f32).collect())?;
    Ok((HeightField::new(heights, cell_size)?, residue / max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn real_zero_mean_any_size() {
        for (nx, ny) in [(64, 64), (45, 30)] {
            let (hf, residue) =
                spectral_with_residue(nx, ny, 1.0, &SpectralParams::default(), Seed(4)).unwrap();
            assert!(residue < 1e-10, "imaginary residue {residue}");
            let mean = hf.heights().mean();
            assert!(mean.abs() < 1e-3, "mean {mean}");
            let sd = (hf
                .heights()
                .as_slice()
                .iter()
                .map(|&v| f64::from(v).powi(2))
                .sum::<f64>()
                / (nx * ny) as f64)
                .sqrt();
            assert!(sd > 20.0 && sd < 400.0, "sd {sd}");
        }
        assert!(spectral_synthesis(1, 8, 1.0, &SpectralParams::default(), Seed(1)).is_err());
    }
}
