//! 2-D real FFTs (rows real-to-complex, columns complex), parallel over
//! rows and columns. Spectra are stored row-major by `ky`: element
//! `ky·(nx/2 + 1) + kx` holds frequency `(kx, ky)`, `kx ∈ [0, nx/2]`.

use natura_core::fft::{self, Complex, FftDirection};

use crate::bands;

/// Number of complex columns of the half spectrum of a row of `nx` reals.
#[inline]
pub(crate) fn half(nx: usize) -> usize {
    nx / 2 + 1
}

/// Forward 2-D FFT of `nx × ny` reals (row-major), unnormalised.
pub(crate) fn forward_real_2d(data: &[f64], nx: usize, ny: usize) -> Vec<Complex<f64>> {
    let hx = half(nx);
    let r2c = fft::plan_real_forward_f64(nx);
    let rows: Vec<usize> = (0..ny).collect();
    let spec_rows: Vec<Vec<Complex<f64>>> = bands::run(chunk_list(rows), |rows| {
        let mut input = r2c.make_input_vec();
        let mut scratch = r2c.make_scratch_vec();
        let mut out = Vec::with_capacity(rows.len() * hx);
        for y in rows {
            input.copy_from_slice(&data[y * nx..(y + 1) * nx]);
            let mut o = r2c.make_output_vec();
            // Lengths come from the plan itself, so this cannot fail.
            let _ = r2c.process_with_scratch(&mut input, &mut o, &mut scratch);
            out.extend_from_slice(&o);
        }
        out
    });
    let mut spec: Vec<Complex<f64>> = spec_rows.into_iter().flatten().collect();
    columns(&mut spec, hx, ny, false);
    spec
}

/// Inverse 2-D FFT of a half spectrum back to `nx × ny` reals, normalised by
/// `1/(nx·ny)`. The imaginary parts of the `kx = 0` and `kx = nx/2` (even `nx`)
/// columns after the column pass are round-off for a Hermitian spectrum; they
/// are dropped, and the largest such residue is returned alongside the data.
pub(crate) fn inverse_real_2d(
    mut spec: Vec<Complex<f64>>,
    nx: usize,
    ny: usize,
) -> (Vec<f64>, f64) {
    let hx = half(nx);
    columns(&mut spec, hx, ny, true);
    let c2r = fft::plan_real_inverse_f64(nx);
    let norm = 1.0 / (nx as f64 * ny as f64);
    let rows: Vec<usize> = (0..ny).collect();
    let spec = &spec;
    let parts: Vec<(Vec<f64>, f64)> = bands::run(chunk_list(rows), |rows| {
        let mut input = c2r.make_input_vec();
        let mut scratch = c2r.make_scratch_vec();
        let mut output = c2r.make_output_vec();
        let mut out = Vec::with_capacity(rows.len() * nx);
        let mut residue = 0.0f64;
        for y in rows {
            input.copy_from_slice(&spec[y * hx..(y + 1) * hx]);
            residue = residue.max(input[0].im.abs());
            input[0].im = 0.0;
            if nx.is_multiple_of(2) {
                residue = residue.max(input[hx - 1].im.abs());
                input[hx - 1].im = 0.0;
            }
            let _ = c2r.process_with_scratch(&mut input, &mut output, &mut scratch);
            out.extend(output.iter().map(|v| v * norm));
        }
        (out, residue * norm)
    });
    let mut data = Vec::with_capacity(nx * ny);
    let mut residue = 0.0f64;
    for (d, r) in parts {
        data.extend(d);
        residue = residue.max(r);
    }
    (data, residue)
}

/// Complex FFT of every column of a `w × h` row-major array, in place.
fn columns(spec: &mut [Complex<f64>], w: usize, h: usize, inverse: bool) {
    let direction = if inverse {
        FftDirection::Inverse
    } else {
        FftDirection::Forward
    };
    let fft = fft::plan_f64(h, direction);
    // Transpose into column-major, transform contiguous columns, transpose back.
    let mut t = vec![Complex::new(0.0, 0.0); w * h];
    for y in 0..h {
        for x in 0..w {
            t[x * h + y] = spec[y * w + x];
        }
    }
    let chunk = h * 8;
    let jobs: Vec<&mut [Complex<f64>]> = t.chunks_mut(chunk).collect();
    bands::run(jobs, |cols| {
        let mut scratch = vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()];
        for c in cols.chunks_mut(h) {
            fft.process_with_scratch(c, &mut scratch);
        }
    });
    for y in 0..h {
        for x in 0..w {
            spec[y * w + x] = t[x * h + y];
        }
    }
}

/// Splits a list of rows into jobs of a fixed size (independent of thread count).
fn chunk_list(rows: Vec<usize>) -> Vec<Vec<usize>> {
    rows.chunks(16).map(<[usize]>::to_vec).collect()
}

/// Signed integer frequency of index `k` in a transform of length `n`.
#[inline]
pub(crate) fn signed_freq(k: usize, n: usize) -> f64 {
    if k <= n / 2 {
        k as f64
    } else {
        k as f64 - n as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        for (nx, ny) in [(8, 6), (7, 5), (16, 9)] {
            let data: Vec<f64> = (0..nx * ny).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
            let spec = forward_real_2d(&data, nx, ny);
            let (back, res) = inverse_real_2d(spec, nx, ny);
            assert!(res < 1e-12, "{res}");
            for (a, b) in data.iter().zip(&back) {
                assert!((a - b).abs() < 1e-10);
            }
        }
    }
}
