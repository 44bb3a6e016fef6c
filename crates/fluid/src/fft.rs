//! The periodic-domain solver of Stable Fluids (Stam 1999, §2.3): in
//! Fourier space diffusion is the filter `1/(1 + ν dt k²)` and projection is
//! `P̂ ŵ(k) = ŵ(k) − (k·ŵ(k)) k / k²`.
//!
//! Not in the source: the `k = 0` mode (mean flow) is left
//! unchanged and the pressure gauge is zero mean; derivative symbols at the
//! Nyquist wavenumber of an even axis are zero, since `i k` there is not
//! Hermitian-consistent for real data. [`FftVariant::ModifiedWavenumber`]
//! uses the symbols of the finite-difference operators instead (compact
//! Laplacian `4 sin²(kh/2)/h²`, central first derivative `sin(kh)/h`), which
//! makes the FFT solution equal the iterative solvers' to their tolerance.

use std::sync::Arc;

use natura_core::Grid3;
use natura_core::fft::{self, Complex, Fft, FftDirection};

use crate::chunks;
use crate::error::{FluidError, Result};
use crate::grid::Dims;

/// A double-precision complex value.
type Complex64 = Complex<f64>;

/// Which wavenumbers the Fourier operators use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum FftVariant {
    /// The paper's exact spectral symbols `k²`, `i k` (Stam 1999, §2.3).
    #[default]
    Spectral,
    /// Symbols of the grid's finite-difference operators (compact Laplacian,
    /// central differences): agrees with iterative solvers to their tolerance.
    ModifiedWavenumber,
}

/// The diffusion filter applied per Fourier mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum DiffusionFilter {
    /// `1 / (1 + ν dt k²)`: implicit Euler, the paper's formula (Stam 1999, §2.3).
    #[default]
    Rational,
    /// `exp(−ν dt k²)`: the exact decay, as in Stam's later FFT code (JGT 2001).
    Exponential,
}

/// A planned 3-D complex FFT over `dims` (flat axes are skipped).
#[derive(Clone)]
pub(crate) struct Fft3 {
    dims: Dims,
    fwd: [Option<Arc<dyn Fft<f64>>>; 3],
    inv: [Option<Arc<dyn Fft<f64>>>; 3],
}

impl std::fmt::Debug for Fft3 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Fft3({})", self.dims)
    }
}

impl Fft3 {
    pub fn new(dims: Dims) -> Self {
        let n = dims.n();
        Self {
            dims,
            fwd: std::array::from_fn(|a| {
                (n[a] > 1).then(|| fft::plan_f64(n[a], FftDirection::Forward))
            }),
            inv: std::array::from_fn(|a| {
                (n[a] > 1).then(|| fft::plan_f64(n[a], FftDirection::Inverse))
            }),
        }
    }

    fn run(&self, data: &mut [Complex64], inverse: bool) {
        let n = self.dims.n();
        let st = [1, n[0], n[0] * n[1]];
        for a in 0..3 {
            let plan = if inverse { &self.inv[a] } else { &self.fwd[a] };
            let Some(plan) = plan else { continue };
            if a == 0 {
                chunks::for_chunks(data, n[0], |_, row| {
                    let mut scratch = vec![Complex64::default(); plan.get_inplace_scratch_len()];
                    plan.process_with_scratch(row, &mut scratch);
                });
                continue;
            }
            // Lines along axis a: gather, transform, scatter.
            let lines = data.len() / n[a];
            let base_of = |l: usize| -> usize {
                if a == 1 {
                    let (i, k) = (l % n[0], l / n[0]);
                    i + k * st[2]
                } else {
                    l
                }
            };
            let src: &[Complex64] = data;
            let out: Vec<Vec<Complex64>> = chunks::map_collect(lines, |l| {
                let b = base_of(l);
                let mut v: Vec<Complex64> = (0..n[a]).map(|t| src[b + t * st[a]]).collect();
                plan.process(&mut v);
                v
            });
            for (l, v) in out.into_iter().enumerate() {
                let b = base_of(l);
                for (t, c) in v.into_iter().enumerate() {
                    data[b + t * st[a]] = c;
                }
            }
        }
        if inverse {
            let s = 1.0 / self.dims.cells() as f64;
            data.iter_mut().for_each(|c| *c *= s);
        }
    }

    pub fn forward(&self, data: &mut [Complex64]) {
        self.run(data, false);
    }

    pub fn inverse(&self, data: &mut [Complex64]) {
        self.run(data, true);
    }
}

/// Per-axis wavenumber tables: `(k², derivative symbol)` for index `m`.
pub(crate) fn symbols(dims: Dims, h: f32, variant: FftVariant) -> [Vec<(f64, f64)>; 3] {
    let h = f64::from(h);
    std::array::from_fn(|a| {
        let n = dims.n()[a];
        (0..n)
            .map(|m| {
                if n == 1 {
                    return (0.0, 0.0);
                }
                let signed = if m <= n / 2 {
                    m as f64
                } else {
                    m as f64 - n as f64
                };
                let k = 2.0 * std::f64::consts::PI * signed / (n as f64 * h);
                let nyquist = n.is_multiple_of(2) && m == n / 2;
                match variant {
                    FftVariant::Spectral => (k * k, if nyquist { 0.0 } else { k }),
                    FftVariant::ModifiedWavenumber => {
                        let s = (0.5 * k * h).sin();
                        (4.0 * s * s / (h * h), (k * h).sin() / h)
                    }
                }
            })
            .collect()
    })
}

fn to_complex(g: &Grid3<f32>) -> Vec<Complex64> {
    g.as_slice()
        .iter()
        .map(|&v| Complex64::new(f64::from(v), 0.0))
        .collect()
}

/// Solves `∇² p = f` on a periodic grid by FFT (zero-mean `p`; the mean of
/// `f` is ignored, as it must be zero for a solution to exist).
///
/// # Errors
///
/// Returns [`FluidError::InvalidParameter`] for a non-positive or non-finite cell
/// size, [`FluidError::InvalidSize`] for an oversized grid, and
/// [`FluidError::NonFinite`] naming the first NaN or infinite sample of `f`.
pub fn solve_poisson_periodic(f: &Grid3<f32>, h: f32, variant: FftVariant) -> Result<Grid3<f64>> {
    crate::error::positive("h", f64::from(h))?;
    let (nx, ny, nz) = f.dims();
    let dims = Dims::new(nx, ny, nz)?;
    if let Some(i) = f.as_slice().iter().position(|v| !v.is_finite()) {
        return Err(FluidError::NonFinite {
            field: "poisson right-hand side",
            index: dims.ijk(i),
            value: f.as_slice()[i],
            stage: "fft solve",
        });
    }
    let fft = Fft3::new(dims);
    let sym = symbols(dims, h, variant);
    let mut data = to_complex(f);
    fft.forward(&mut data);
    for (c, v) in data.iter_mut().enumerate() {
        let [i, j, k] = dims.ijk(c);
        let k2 = sym[0][i].0 + sym[1][j].0 + sym[2][k].0;
        *v = if k2 > 0.0 {
            -*v / k2
        } else {
            Complex64::default()
        };
    }
    fft.inverse(&mut data);
    Ok(Grid3::from_vec(
        nx,
        ny,
        nz,
        data.iter().map(|c| c.re).collect(),
    )?)
}

/// Diffuses and projects a collocated periodic velocity in place (the
/// transform/diffuse/project/transform lines of Stable Fluids' FourierStep,
/// Stam 1999, §2.3). `nu_dt = ν·dt`. Flat components stay zero.
pub(crate) fn diffuse_project(
    fft: &Fft3,
    comps: &mut [Grid3<f32>; 3],
    h: f32,
    nu_dt: f64,
    filter: DiffusionFilter,
    variant: FftVariant,
    project: bool,
) {
    let dims = fft.dims;
    let sym = symbols(dims, h, variant);
    let act: Vec<usize> = (0..3).filter(|&a| dims.active(a)).collect();
    let mut spec: Vec<Vec<Complex64>> = act
        .iter()
        .map(|&a| {
            let mut d = to_complex(&comps[a]);
            fft.forward(&mut d);
            d
        })
        .collect();
    for c in 0..dims.cells() {
        let [i, j, k] = dims.ijk(c);
        let k2 = sym[0][i].0 + sym[1][j].0 + sym[2][k].0;
        let damp = match filter {
            DiffusionFilter::Rational => 1.0 / (1.0 + nu_dt * k2),
            DiffusionFilter::Exponential => (-nu_dt * k2).exp(),
        };
        let kv = [sym[0][i].1, sym[1][j].1, sym[2][k].1];
        let kk: f64 = act.iter().map(|&a| kv[a] * kv[a]).sum();
        let mut w: Vec<Complex64> = spec.iter().map(|s| s[c] * damp).collect();
        if project && kk > 0.0 {
            let dot: Complex64 = act.iter().zip(&w).map(|(&a, v)| v * kv[a]).sum();
            for (q, &a) in act.iter().enumerate() {
                w[q] -= dot * (kv[a] / kk);
            }
        }
        for (q, v) in w.into_iter().enumerate() {
            spec[q][c] = v;
        }
    }
    for (q, &a) in act.iter().enumerate() {
        fft.inverse(&mut spec[q]);
        for (o, v) in comps[a].as_mut_slice().iter_mut().zip(&spec[q]) {
            *o = v.re as f32;
        }
    }
}

/// Diffuses a periodic scalar by `1/(1 + κ dt k²)` (or the exponential filter).
pub(crate) fn diffuse_scalar(
    fft: &Fft3,
    g: &mut Grid3<f32>,
    h: f32,
    kappa_dt: f64,
    filter: DiffusionFilter,
    variant: FftVariant,
) {
    if kappa_dt == 0.0 {
        return;
    }
    let dims = fft.dims;
    let sym = symbols(dims, h, variant);
    let mut d = to_complex(g);
    fft.forward(&mut d);
    for (c, v) in d.iter_mut().enumerate() {
        let [i, j, k] = dims.ijk(c);
        let k2 = sym[0][i].0 + sym[1][j].0 + sym[2][k].0;
        *v *= match filter {
            DiffusionFilter::Rational => 1.0 / (1.0 + kappa_dt * k2),
            DiffusionFilter::Exponential => (-kappa_dt * k2).exp(),
        };
    }
    fft.inverse(&mut d);
    for (o, v) in g.as_mut_slice().iter_mut().zip(&d) {
        *o = v.re as f32;
    }
}
