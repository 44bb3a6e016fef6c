//! The straightforward evaluation: one complex 2-D inverse FFT per field.
//!
//! For each of the eight fields of a [`Frame`](crate::Frame) it builds the
//! full N × M spectrum (h̃(k,t) with `f32` `sin_cos`, times the field's
//! factor of k), runs row FFTs, a plain transpose, column FFTs and a
//! transpose back, and keeps the real part. It is what the fast path is
//! tested against (same fields to round-off, and the imaginary parts it
//! throws away are measured by [`Reference::imaginary_residue`]) and the
//! baseline the benchmarks measure it against. Single-threaded.

use std::sync::Arc;

use natura_core::Grid2;
use natura_core::fft::{self, Complex, Fft, FftDirection};

use crate::error::Result;
use crate::frame::FrameField;
use crate::patch::{Ocean, signed};

type C32 = Complex<f32>;

/// Buffers and plans for the straightforward evaluation of one patch size.
pub struct Reference {
    nx: usize,
    ny: usize,
    h0: Vec<C32>,
    h0_neg_conj: Vec<C32>,
    omega: Vec<f32>,
    kx: Vec<f32>,
    ky: Vec<f32>,
    spectrum: Vec<C32>,
    buf: Vec<C32>,
    tmp: Vec<C32>,
    scratch: Vec<C32>,
    fft_x: Arc<dyn Fft<f32>>,
    fft_y: Arc<dyn Fft<f32>>,
    fields: [Grid2<f32>; 8],
    residue: [f32; 8],
    choppiness: f32,
}

impl std::fmt::Debug for Reference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Reference")
            .field("nx", &self.nx)
            .field("ny", &self.ny)
            .finish_non_exhaustive()
    }
}

impl Reference {
    /// Prepares the straightforward evaluation of `ocean`.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::Core`](crate::OceanError::Core) if the fields' grids exceed natura-core's
    /// memory cap.
    pub fn new(ocean: &Ocean) -> Result<Self> {
        let p = ocean.params();
        let (nx, ny) = (p.nx, p.ny);
        let h0 = ocean.h0();
        let fft_x = fft::plan_f32(nx, FftDirection::Inverse);
        let fft_y = fft::plan_f32(ny, FftDirection::Inverse);
        let scratch = fft_x
            .get_inplace_scratch_len()
            .max(fft_y.get_inplace_scratch_len());
        let zero = C32::new(0.0, 0.0);
        let grid = Grid2::new(nx, ny, 0.0f32)?;
        Ok(Self {
            nx,
            ny,
            h0: h0
                .iter()
                .map(|c| C32::new(c.re as f32, c.im as f32))
                .collect(),
            h0_neg_conj: (0..nx * ny)
                .map(|i| {
                    let (n, m) = (i % nx, i / nx);
                    let c = h0[((ny - m) % ny) * nx + (nx - n) % nx].conj();
                    C32::new(c.re as f32, c.im as f32)
                })
                .collect(),
            omega: ocean.omega().iter().map(|&w| w as f32).collect(),
            kx: (0..nx)
                .map(|n| (signed(n, nx) as f64 * std::f64::consts::TAU / p.lx) as f32)
                .collect(),
            ky: (0..ny)
                .map(|m| (signed(m, ny) as f64 * std::f64::consts::TAU / p.ly) as f32)
                .collect(),
            spectrum: vec![zero; nx * ny],
            buf: vec![zero; nx * ny],
            tmp: vec![zero; nx * ny],
            scratch: vec![zero; scratch],
            fft_x,
            fft_y,
            fields: std::array::from_fn(|_| grid.clone()),
            residue: [0.0; 8],
            choppiness: p.choppiness as f32,
        })
    }

    /// Evaluates all eight fields at time `t`, one complex 2-D FFT each.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`](crate::OceanError::InvalidParameter) if `t` is not finite.
    pub fn evaluate(&mut self, t: f64) -> Result<()> {
        crate::error::finite("t", t)?;
        let (nx, ny) = (self.nx, self.ny);
        let tf = t as f32;
        for (i, s) in self.spectrum.iter_mut().enumerate() {
            let (sn, cs) = (self.omega[i] * tf).sin_cos();
            let e = C32::new(cs, -sn);
            *s = self.h0[i] * e + self.h0_neg_conj[i] * e.conj();
        }
        let lam = self.choppiness;
        let im = C32::new(0.0, 1.0);
        for f in FrameField::ALL {
            for m in 0..ny {
                let ky = self.ky[m];
                for n in 0..nx {
                    let kx = self.kx[n];
                    let k = (kx * kx + ky * ky).sqrt();
                    let inv = if k > 0.0 { 1.0 / k } else { 0.0 };
                    let h = self.spectrum[m * nx + n];
                    self.buf[m * nx + n] = match f {
                        FrameField::Height => h,
                        FrameField::SlopeX => im * kx * h,
                        FrameField::SlopeY => im * ky * h,
                        FrameField::DispX => im * (lam * kx * inv) * h,
                        FrameField::DispY => im * (lam * ky * inv) * h,
                        FrameField::Jxx => h * (-lam * kx * kx * inv),
                        FrameField::Jyy => h * (-lam * ky * ky * inv),
                        FrameField::Jxy => h * (-lam * kx * ky * inv),
                    };
                }
            }
            self.fft_x
                .process_with_scratch(&mut self.buf, &mut self.scratch);
            transpose(&self.buf, &mut self.tmp, nx, ny);
            self.fft_y
                .process_with_scratch(&mut self.tmp, &mut self.scratch);
            transpose(&self.tmp, &mut self.buf, ny, nx);
            let offset = if matches!(f, FrameField::Jxx | FrameField::Jyy) {
                1.0
            } else {
                0.0
            };
            let mut max_im = 0.0f32;
            let mut sum2 = 0.0f64;
            for (o, c) in self.fields[f as usize]
                .as_mut_slice()
                .iter_mut()
                .zip(&self.buf)
            {
                *o = c.re + offset;
                max_im = max_im.max(c.im.abs());
                sum2 += f64::from(c.re) * f64::from(c.re);
            }
            let rms = (sum2 / (nx * ny) as f64).sqrt() as f32;
            self.residue[f as usize] = if rms > 0.0 { max_im / rms } else { max_im };
        }
        Ok(())
    }

    /// Returns field `f` from the last [`Reference::evaluate`].
    #[must_use]
    pub fn field(&self, f: FrameField) -> &Grid2<f32> {
        &self.fields[f as usize]
    }

    /// Returns max |Im| / RMS(Re) of field `f`'s inverse FFT in the last
    /// evaluation: how far the output is from real (0 for an exactly
    /// Hermitian spectrum, round-off in practice).
    #[must_use]
    pub fn imaginary_residue(&self, f: FrameField) -> f32 {
        self.residue[f as usize]
    }
}

/// Plain out-of-place transpose of a `rows × cols` row-major matrix.
fn transpose(src: &[C32], dst: &mut [C32], cols: usize, rows: usize) {
    for r in 0..rows {
        for c in 0..cols {
            dst[c * rows + r] = src[r * cols + c];
        }
    }
}
