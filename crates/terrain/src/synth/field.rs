//! Noise synthesis: fill a height field from any point-evaluated scalar field
//! (fBm, multifractals, …) in parallel rows, with the height scale in metres.
//!
//! Point evaluation is what makes noise synthesis local and level-of-detail
//! friendly (Musgrave et al. 1989, §2.1, Musgrave 1993, §2): each sample needs no neighbours and no
//! global state. [`fill_field`] takes any `Fn(f64, f64) -> f64 + Sync` (f64
//! points, one call per sample); [`fill_rows`] takes a batch row filler (one
//! call per row, f32 output); [`fill_noise`] fills from any natura-noise
//! [`Field`] (fBm, hetero terrain, hybrid and ridged multifractals,
//! statistics-by-altitude, Musgrave's large-scale terrain, …) through its
//! SIMD row path, rows in parallel.

use glam::DVec2;
use natura_core::{Grid2, HeightField};
use natura_noise::{Field, Simd};

use crate::bands;
use crate::error::{Result, TerrainError, invalid, min_size};

/// Where and how a field is sampled onto the grid.
///
/// Sample `(i, j)` evaluates the field at
/// `(origin + (i, j)·cell_size) · frequency` and stores
/// `offset_m + height_m · value`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldMapping {
    /// World position of sample (0, 0), metres.
    pub origin: DVec2,
    /// Field units per metre (e.g. `1/2000` for features ~2 km across).
    pub frequency: f64,
    /// Metres per unit of field value.
    pub height_m: f64,
    /// Height added after scaling, metres.
    pub offset_m: f64,
}

impl Default for FieldMapping {
    fn default() -> Self {
        Self {
            origin: DVec2::ZERO,
            frequency: 1.0 / 1000.0,
            height_m: 500.0,
            offset_m: 0.0,
        }
    }
}

impl FieldMapping {
    /// Every value must be finite; `frequency` and `height_m` non-zero.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`] naming the first parameter that is
    /// NaN, infinite or outside its documented range.
    pub fn validate(&self) -> Result<()> {
        if !self.origin.is_finite() {
            return Err(invalid(
                "FieldMapping::origin",
                self.origin,
                "must be finite",
            ));
        }
        if !(self.frequency.is_finite() && self.frequency != 0.0) {
            return Err(invalid(
                "FieldMapping::frequency",
                self.frequency,
                "must be finite and non-zero",
            ));
        }
        if !self.height_m.is_finite() {
            return Err(invalid(
                "FieldMapping::height_m",
                self.height_m,
                "must be finite",
            ));
        }
        if !self.offset_m.is_finite() {
            return Err(invalid(
                "FieldMapping::offset_m",
                self.offset_m,
                "must be finite",
            ));
        }
        Ok(())
    }

    /// Field-space point of sample `(i, j)`.
    #[inline]
    #[must_use]
    pub fn point(&self, i: usize, j: usize, cell_size: f32) -> DVec2 {
        (self.origin + DVec2::new(i as f64, j as f64) * f64::from(cell_size)) * self.frequency
    }
}

/// Fills an `nx × ny` field from `field(x, y)` at f64 points, rows in parallel.
///
/// A non-finite field value is an error naming the first such cell.
///
/// # Errors
///
/// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`]
/// for a size the method cannot make, and [`TerrainError::Core`] if the field
/// cannot be allocated.
/// Returns [`TerrainError::Noise`] if the noise cannot be evaluated.
pub fn fill_field<F>(
    nx: usize,
    ny: usize,
    cell_size: f32,
    map: &FieldMapping,
    field: &F,
) -> Result<HeightField>
where
    F: Fn(f64, f64) -> f64 + Sync + ?Sized,
{
    map.validate()?;
    min_size("fill_field", nx, ny, 1, 1)?;
    natura_core::check::positive("cell_size", f64::from(cell_size))?;
    let mut g = Grid2::new(nx, ny, 0.0f32)?;
    bands::map_bands(nx, ny, [g.as_mut_slice()], |y0, _, [out]| {
        for (r, row) in out.chunks_mut(nx).enumerate() {
            for (i, v) in row.iter_mut().enumerate() {
                let p = map.point(i, y0 + r, cell_size);
                *v = (map.offset_m + map.height_m * field(p.x, p.y)) as f32;
            }
        }
    });
    finish(g, cell_size)
}

/// Fills an `nx × ny` field one row at a time: `row(x0, y, dx, out)` must write
/// the field at `(x0 + k·dx, y)` into `out[k]` (field units). Values are then
/// mapped to metres. This is the batch path for SIMD noise implementations.
///
/// # Errors
///
/// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`]
/// for a size the method cannot make, and [`TerrainError::Core`] if the field
/// cannot be allocated.
pub fn fill_rows<F>(
    nx: usize,
    ny: usize,
    cell_size: f32,
    map: &FieldMapping,
    row: &F,
) -> Result<HeightField>
where
    F: Fn(f64, f64, f64, &mut [f32]) + Sync + ?Sized,
{
    fill_blocks(
        nx,
        ny,
        cell_size,
        map,
        &|x0, ys: &[f64], dx, out: &mut [f32]| {
            for (line, &y) in out.chunks_mut(nx).zip(ys) {
                row(x0, y, dx, line);
            }
        },
    )
}

/// Rows [`fill_blocks`] hands its writer at a time.
const BLOCK_ROWS: usize = 8;

/// [`fill_rows`] with a writer of [`BLOCK_ROWS`] rows at a time:
/// `rows(x0, ys, dx, out)` writes row `r` of `out` (`nx` points each) at
/// `(x0 + k·dx, ys[r])`. Bands of rows in parallel.
fn fill_blocks<F>(
    nx: usize,
    ny: usize,
    cell_size: f32,
    map: &FieldMapping,
    rows: &F,
) -> Result<HeightField>
where
    F: Fn(f64, &[f64], f64, &mut [f32]) + Sync + ?Sized,
{
    map.validate()?;
    min_size("fill_rows", nx, ny, 1, 1)?;
    natura_core::check::positive("cell_size", f64::from(cell_size))?;
    let mut g = Grid2::new(nx, ny, 0.0f32)?;
    let dx = f64::from(cell_size) * map.frequency;
    bands::map_bands(nx, ny, [g.as_mut_slice()], |y0, _, [out]| {
        for (b, block) in out.chunks_mut(BLOCK_ROWS * nx).enumerate() {
            let first = y0 + b * BLOCK_ROWS;
            let m = block.len() / nx;
            let ys: [f64; BLOCK_ROWS] =
                core::array::from_fn(|r| map.point(0, first + r.min(m - 1), cell_size).y);
            rows(map.point(0, first, cell_size).x, &ys[..m], dx, block);
            for v in block.iter_mut() {
                *v = (map.offset_m + map.height_m * f64::from(*v)) as f32;
            }
        }
    });
    finish(g, cell_size)
}

/// Fills an `nx × ny` field from a natura-noise [`Field`] (2-D evaluation) with
/// its batch fill of rows (SIMD, run-time dispatch), bands of rows in
/// parallel, blocks of rows at a time; heights in
/// metres through `map`. Equals [`fill_field`] with `field.eval2` to f32 rounding.
///
/// # Errors
///
/// Returns the errors of the parameters' `validate`, [`TerrainError::BadSize`]
/// for a size the method cannot make, and [`TerrainError::Core`] if the field
/// cannot be allocated.
/// Returns [`TerrainError::Noise`] if the noise cannot be evaluated.
pub fn fill_noise<F: Field + ?Sized>(
    nx: usize,
    ny: usize,
    cell_size: f32,
    map: &FieldMapping,
    field: &F,
) -> Result<HeightField> {
    // Blocks of rows, which the noise fills sharing its work along x (the
    // same values as row by row).
    let simd = Simd::best();
    fill_blocks(
        nx,
        ny,
        cell_size,
        map,
        &|x0, ys: &[f64], dx, out: &mut [f32]| {
            field.fill_rows2_with(simd, x0, ys, dx, out);
        },
    )
}

fn finish(g: Grid2<f32>, cell_size: f32) -> Result<HeightField> {
    if let Some((x, y, &value)) = g.find(|v| !v.is_finite()) {
        return Err(TerrainError::NonFinite {
            what: "field value",
            x,
            y,
            value,
        });
    }
    Ok(HeightField::new(g, cell_size)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_and_row_paths_agree() {
        let f = |x: f64, y: f64| (x * 1.3).sin() * (y * 0.7).cos();
        let map = FieldMapping {
            origin: DVec2::new(10.0, -5.0),
            frequency: 0.01,
            height_m: 100.0,
            offset_m: 20.0,
        };
        let a = fill_field(33, 17, 3.0, &map, &f).unwrap();
        let b = fill_rows(
            33,
            17,
            3.0,
            &map,
            &|x0: f64, y: f64, dx: f64, out: &mut [f32]| {
                for (k, v) in out.iter_mut().enumerate() {
                    *v = f(x0 + k as f64 * dx, y) as f32;
                }
            },
        )
        .unwrap();
        for (p, q) in a.heights().as_slice().iter().zip(b.heights().as_slice()) {
            assert!((p - q).abs() < 1e-4);
        }
        assert_eq!(a.heights()[(0, 0)], (20.0 + 100.0 * f(0.1, -0.05)) as f32);
        // A natura-noise field through the SIMD row path matches point evaluation.
        let fbm = natura_noise::Fbm::new(
            natura_noise::Perlin::new(3),
            natura_noise::Spectral::default().with_h(0.8),
        )
        .unwrap();
        let a = fill_noise(40, 9, 3.0, &map, &fbm).unwrap();
        let b = fill_field(40, 9, 3.0, &map, &|x: f64, y: f64| {
            fbm.eval2(DVec2::new(x, y))
        })
        .unwrap();
        for (p, q) in a.heights().as_slice().iter().zip(b.heights().as_slice()) {
            assert!((p - q).abs() < 1e-3, "{p} vs {q}");
        }
        let err = fill_field(4, 4, 1.0, &map, &|x: f64, _| {
            if x > 0.11 { f64::NAN } else { 0.0 }
        })
        .unwrap_err();
        // Cell (1, 0) sits at exactly x = 0.11, so the first bad cell is (2, 0).
        assert!(err.to_string().contains("(2, 0)"), "{err}");
    }

    #[test]
    fn noise_blocks_of_rows_equal_the_row_fill_bit_for_bit() {
        // 29 rows (bands and blocks of 8 with a ragged end), at steps of
        // the window kernel: the blocks' shared x work changes no value.
        let map = FieldMapping {
            origin: DVec2::new(-37.0, 12.5),
            frequency: 0.05,
            height_m: 300.0,
            offset_m: -4.0,
        };
        let fbm = natura_noise::Fbm::new(
            natura_noise::Perlin::new(9),
            natura_noise::Spectral::default().with_h(0.7),
        )
        .unwrap();
        let ridged =
            natura_noise::RidgedMultifractal::new(natura_noise::Perlin::new(9), Default::default())
                .unwrap();
        for field in [&fbm as &dyn Field, &ridged] {
            let a = fill_noise(301, 29, 2.5, &map, field).unwrap();
            let b = fill_rows(
                301,
                29,
                2.5,
                &map,
                &|x0: f64, y: f64, dx, out: &mut [f32]| {
                    field.fill_row2(DVec2::new(x0, y), dx, out);
                },
            )
            .unwrap();
            let bits = |h: &HeightField| -> Vec<u32> {
                h.heights().as_slice().iter().map(|v| v.to_bits()).collect()
            };
            assert_eq!(bits(&a), bits(&b));
        }
    }
}
