//! Hypsometry and fractal statistics: the radially averaged power spectrum
//! and its log-log slope (`−(2H + 2)` for an fBm surface, Musgrave et al. 1989, §3.1) and the
//! variogram `γ(r) = E[(z(x + r) − z(x))²] ∝ r^(2H)`.

use natura_core::HeightField;

use crate::error::{Result, invalid, min_size};
use crate::fft;

/// The hypsometric curve: `bins + 1` points `(relative height, fraction of area
/// at or above it)`, relative height 0 at the lowest sample and 1 at the highest.
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated.
pub fn hypsometric_curve(hf: &HeightField, bins: usize) -> Result<Vec<(f64, f64)>> {
    if bins == 0 || bins > 1_000_000 {
        return Err(invalid("bins", bins, "must lie in [1, 1e6]"));
    }
    hf.check_finite()?;
    let (lo, hi) = hf.min_max();
    let (lo, span) = (f64::from(lo), f64::from(hi - lo).max(f64::MIN_POSITIVE));
    let mut counts = vec![0u64; bins + 1];
    for &v in hf.heights().as_slice() {
        let t = (f64::from(v) - lo) / span;
        counts[((t * bins as f64).floor() as usize).min(bins)] += 1;
    }
    let n = hf.heights().len() as f64;
    let mut above = n;
    let mut out = Vec::with_capacity(bins + 1);
    for (k, c) in counts.iter().enumerate() {
        out.push((k as f64 / bins as f64, above / n));
        above -= *c as f64;
    }
    Ok(out)
}

/// The hypsometric integral `(mean − min) / (max − min)` (Strahler 1952): high for
/// young uplands, low for old eroded terrain. 0 for a flat field.
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated.
pub fn hypsometric_integral(hf: &HeightField) -> Result<f64> {
    hf.check_finite()?;
    let (lo, hi) = hf.min_max();
    if hi <= lo {
        return Ok(0.0);
    }
    Ok((hf.heights().mean() - f64::from(lo)) / f64::from(hi - lo))
}

/// A radially averaged power spectrum: mean periodogram power in rings of unit
/// width in `|k|` (cycles per tile along the longer side).
#[derive(Clone, Debug, PartialEq)]
pub struct RadialSpectrum {
    /// Ring centres `|k|`, cycles per tile.
    pub frequency: Vec<f64>,
    /// Mean power in each ring.
    pub power: Vec<f64>,
}

impl RadialSpectrum {
    /// Least-squares slope of `log P` against `log |k|` over rings with
    /// `lo ≤ |k| ≤ hi`. Needs at least two rings in the band.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
    /// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated.
    pub fn slope(&self, lo: f64, hi: f64) -> Result<f64> {
        let pts: Vec<(f64, f64)> = self
            .frequency
            .iter()
            .zip(&self.power)
            .filter(|(f, p)| **f >= lo && **f <= hi && **p > 0.0)
            .map(|(f, p)| (f.ln(), p.ln()))
            .collect();
        fit_slope(&pts).ok_or_else(|| {
            invalid(
                "band",
                format!("[{lo}, {hi}]"),
                "contains fewer than two rings",
            )
        })
    }
}

/// Least-squares slope of `y` on `x`.
pub(crate) fn fit_slope(pts: &[(f64, f64)]) -> Option<f64> {
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (x, y) in pts {
        sxy += (x - mx) * (y - my);
        sxx += (x - mx) * (x - mx);
    }
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The radially averaged periodogram of `hf` (mean removed). With `window`, a
/// separable Hann window is applied first, for non-periodic fields (it
/// suppresses the edge discontinuity's `f^(−2)` leakage). Needs ≥ 4 × 4 samples.
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated.
pub fn radial_power_spectrum(hf: &HeightField, window: bool) -> Result<RadialSpectrum> {
    min_size("radial_power_spectrum", hf.nx(), hf.ny(), 4, 4)?;
    hf.check_finite()?;
    let (nx, ny) = (hf.nx(), hf.ny());
    let mean = hf.heights().mean();
    let hann = |i: usize, n: usize| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / n as f64).cos();
    let data: Vec<f64> = hf
        .heights()
        .as_slice()
        .iter()
        .enumerate()
        .map(|(k, &v)| {
            let w = if window {
                hann(k % nx, nx) * hann(k / nx, ny)
            } else {
                1.0
            };
            (f64::from(v) - mean) * w
        })
        .collect();
    let spec = fft::forward_real_2d(&data, nx, ny);
    let hx = fft::half(nx);
    let l = nx.max(ny) as f64;
    let rings = (l / 2.0).floor() as usize + 1;
    let mut sum = vec![0.0f64; rings];
    let mut count = vec![0u64; rings];
    for ky in 0..ny {
        let fy = fft::signed_freq(ky, ny) * l / ny as f64;
        for kx in 0..hx {
            let fx = kx as f64 * l / nx as f64;
            let f = (fx * fx + fy * fy).sqrt();
            let ring = f.round() as usize;
            if ring == 0 || ring >= rings {
                continue;
            }
            // Columns 1..nx/2 stand for two conjugate frequencies; same mean power.
            sum[ring] += spec[ky * hx + kx].norm_sqr();
            count[ring] += 1;
        }
    }
    let (mut frequency, mut power) = (Vec::new(), Vec::new());
    for r in 1..rings {
        if count[r] > 0 {
            frequency.push(r as f64);
            power.push(sum[r] / count[r] as f64);
        }
    }
    Ok(RadialSpectrum { frequency, power })
}

/// Estimates `H` from the radially averaged spectrum slope over `[lo, hi]`
/// cycles per tile: slope `= −(2H + 2)`, so `H = −slope/2 − 1`.
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated.
/// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) if the fitting range is empty or
/// holds too few points for a slope.
pub fn spectral_h(hf: &HeightField, window: bool, lo: f64, hi: f64) -> Result<f64> {
    let s = radial_power_spectrum(hf, window)?.slope(lo, hi)?;
    Ok(-s / 2.0 - 1.0)
}

/// The variogram along the grid axes: `(lag in metres, γ)` for lags `1..=max_lag`
/// cells, averaging x and y increments.
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated.
pub fn variogram(hf: &HeightField, max_lag: usize) -> Result<Vec<(f64, f64)>> {
    hf.check_finite()?;
    let (nx, ny) = (hf.nx(), hf.ny());
    if max_lag == 0 || max_lag >= nx.min(ny) {
        return Err(invalid(
            "max_lag",
            max_lag,
            format!("must lie in [1, {})", nx.min(ny)),
        ));
    }
    let h = hf.heights();
    let c = f64::from(hf.cell_size());
    let lags: Vec<usize> = (1..=max_lag).collect();
    let out = crate::bands::run(lags, |r| {
        let (mut s, mut n) = (0.0f64, 0u64);
        for y in 0..ny {
            let row = h.row(y);
            for x in 0..nx - r {
                let d = f64::from(row[x + r] - row[x]);
                s += d * d;
                n += 1;
            }
        }
        for y in 0..ny - r {
            let (a, b) = (h.row(y), h.row(y + r));
            for x in 0..nx {
                let d = f64::from(b[x] - a[x]);
                s += d * d;
                n += 1;
            }
        }
        (r as f64 * c, s / n as f64)
    });
    Ok(out)
}

/// Estimates `H` as half the log-log slope of the variogram between lags
/// `lo..=hi` cells.
///
/// # Errors
///
/// Returns [`TerrainError::BadSize`](crate::TerrainError::BadSize) if `hf` is too small for the method, and
/// [`TerrainError::Core`](crate::TerrainError::Core) if a result grid cannot be allocated.
/// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter) if the lag range is empty or
/// holds too few points for a slope.
pub fn variogram_h(hf: &HeightField, lo: usize, hi: usize) -> Result<f64> {
    if lo == 0 || hi <= lo {
        return Err(invalid("lags", format!("{lo}..={hi}"), "need 1 ≤ lo < hi"));
    }
    let v = variogram(hf, hi)?;
    let pts: Vec<(f64, f64)> = v[lo - 1..]
        .iter()
        .filter(|(_, g)| *g > 0.0)
        .map(|(r, g)| (r.ln(), g.ln()))
        .collect();
    let s = fit_slope(&pts)
        .ok_or_else(|| invalid("lags", format!("{lo}..={hi}"), "variogram is zero"))?;
    Ok(s / 2.0)
}

/// Estimates `H` of a 1-D sample path (equally spaced `values`, e.g. a
/// profile or [`midpoint_1d`](crate::synth::midpoint_1d)) as half the
/// log-log slope of its variogram `E[(z(t + r) − z(t))²] ∝ r^(2H)` between
/// lags `lo..=hi` samples. The graph of such a path has fractal dimension
/// `D = 2 − H` (Fournier et al. 1982, §3.1, after Mandelbrot; a surface's is
/// `3 − H`, Musgrave et al. 1989, §3.1).
///
/// ```
/// use natura_terrain::analysis::path_h;
/// // A straight line has H = 1 (dimension 1).
/// let line: Vec<f64> = (0..100).map(|i| 0.3 * i as f64).collect();
/// assert!((path_h(&line, 1, 10)? - 1.0).abs() < 1e-12);
/// # Ok::<(), natura_terrain::TerrainError>(())
/// ```
///
/// # Errors
///
/// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
/// if the lag range is empty or reaches past the path, if a value is not
/// finite, or if the path is constant over the lags.
pub fn path_h(values: &[f64], lo: usize, hi: usize) -> Result<f64> {
    if lo == 0 || hi <= lo || hi >= values.len() {
        return Err(invalid(
            "lags",
            format!("{lo}..={hi}"),
            format!("need 1 ≤ lo < hi < {} (the path's length)", values.len()),
        ));
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(invalid(
            "values",
            format!("value {i} = {}", values[i]),
            "must be finite",
        ));
    }
    let pts: Vec<(f64, f64)> = (lo..=hi)
        .filter_map(|r| {
            let n = values.len() - r;
            let g = (0..n)
                .map(|i| (values[i + r] - values[i]).powi(2))
                .sum::<f64>()
                / n as f64;
            (g > 0.0).then(|| ((r as f64).ln(), g.ln()))
        })
        .collect();
    let s = fit_slope(&pts).ok_or_else(|| {
        invalid(
            "values",
            format!("lags {lo}..={hi}"),
            "the path is constant",
        )
    })?;
    Ok(s / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_h_of_midpoint_paths_gives_d_two_minus_h() {
        use crate::synth::{EndpointMode, MidpointParams, midpoint_1d};
        use natura_core::Seed;
        // Fournier et al. 1982, Figs. 1-3: H = 0.5, 0.3, 0.7; the graph's
        // dimension D = 2 − H. Averaged over 8 paths of 4097 points, the
        // variogram over lags 1..16 recovers H within 0.06 (midpoint
        // displacement is not exactly fBm: its increments are not stationary).
        for h in [0.3, 0.5, 0.7] {
            let p = MidpointParams {
                h,
                scale: 1.0,
                endpoints: EndpointMode::Fixed(0.0, 0.0),
                variance_correction: true,
                ..MidpointParams::default()
            };
            let est: f64 = (0..8)
                .map(|s| path_h(&midpoint_1d(&p, 12, Seed(s)).unwrap(), 1, 16).unwrap())
                .sum::<f64>()
                / 8.0;
            let d = 2.0 - est;
            assert!((d - (2.0 - h)).abs() < 0.06, "H {h}: D measured {d}");
        }
        assert!(path_h(&[1.0, 2.0, 3.0], 1, 3).is_err());
        assert!(path_h(&[1.0; 10], 1, 3).is_err());
        assert!(path_h(&[1.0, f64::NAN, 0.0, 2.0], 1, 2).is_err());
    }

    #[test]
    fn hypsometry_of_a_ramp() {
        let hf = HeightField::from_fn(101, 3, 1.0, |i, _| i as f32).unwrap();
        assert!((hypsometric_integral(&hf).unwrap() - 0.5).abs() < 1e-9);
        let c = hypsometric_curve(&hf, 10).unwrap();
        assert_eq!(c[0], (0.0, 1.0));
        assert!((c[5].1 - 0.505).abs() < 0.02);
    }

    #[test]
    fn variogram_of_a_plane_is_quadratic() {
        let hf = HeightField::from_fn(32, 32, 1.0, |i, _| i as f32).unwrap();
        // γ(r) = r²/2 (x increments r², y increments 0): slope 2, H = 1.
        let h = variogram_h(&hf, 1, 8).unwrap();
        assert!((h - 1.0).abs() < 1e-9, "{h}");
    }
}
