//! The traced view of a height field: validated dimensions and height range.

use natura_core::HeightField;

use crate::error::{Result, TraceError};

/// Largest samples per axis: cell corners are exact integers in `f32` grid
/// space up to 2²⁴, which the watertight test relies on.
pub const MAX_SAMPLES_PER_AXIS: usize = 1 << 24;

/// A height field checked for tracing, with the numbers every tracer needs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FieldView<'a> {
    pub hf: &'a HeightField,
    pub h: &'a [f32],
    /// Samples along x (row length).
    pub nx: usize,
    /// Cells along x and y.
    pub ncx: u32,
    pub ncy: u32,
    pub cell: f32,
    pub zmin: f32,
    pub zmax: f32,
    /// `max(|zmin|, |zmax|)`.
    pub zabs: f32,
    /// `ncx + ncy` as `f32`.
    pub nxy: f32,
    /// Largest height span `max − min` of any cell's four corners: how far the
    /// surface can move per cell of horizontal distance.
    pub smax: f32,
}

impl<'a> FieldView<'a> {
    /// Validates `hf` for tracing: at least 2 × 2 samples, at most
    /// [`MAX_SAMPLES_PER_AXIS`] per axis, every height finite.
    ///
    /// # Errors
    ///
    /// Returns [`TraceError::Field`] if `hf` has fewer than 2 × 2 samples, more
    /// than [`MAX_SAMPLES_PER_AXIS`] along an axis, or a NaN or infinite height.
    pub fn new(hf: &'a HeightField) -> Result<Self> {
        let (nx, ny) = (hf.nx(), hf.ny());
        let bad = |reason: String| TraceError::Field { nx, ny, reason };
        if nx < 2 || ny < 2 {
            return Err(bad(
                "at least 2 × 2 samples are needed to form a cell".into()
            ));
        }
        if nx > MAX_SAMPLES_PER_AXIS || ny > MAX_SAMPLES_PER_AXIS {
            return Err(bad(format!(
                "at most {MAX_SAMPLES_PER_AXIS} samples per axis are supported"
            )));
        }
        if let Some((x, y, v)) = hf.heights().find(|v| !v.is_finite()) {
            return Err(bad(format!("non-finite height {v} at sample ({x}, {y})")));
        }
        let cell = hf.cell_size();
        if !(cell.is_finite() && cell > 0.0) {
            return Err(bad(format!("cell size {cell} must be finite and > 0")));
        }
        let (zmin, zmax) = hf.min_max();
        let h = hf.heights().as_slice();
        let mut smax = 0.0f32;
        for (r0, r1) in h.chunks_exact(nx).zip(h.chunks_exact(nx).skip(1)) {
            for k in 0..nx - 1 {
                let c = [r0[k], r0[k + 1], r1[k], r1[k + 1]];
                let span = c[0].max(c[1]).max(c[2].max(c[3])) - c[0].min(c[1]).min(c[2].min(c[3]));
                smax = smax.max(span);
            }
        }
        Ok(Self {
            hf,
            h: hf.heights().as_slice(),
            nx,
            ncx: (nx - 1) as u32,
            ncy: (ny - 1) as u32,
            cell,
            zmin,
            zmax,
            zabs: zmin.abs().max(zmax.abs()),
            nxy: ((nx - 1) as u32 + (ny - 1) as u32) as f32,
            smax,
        })
    }

    /// The four corner heights of cell `(i, j)`: `[h00, h10, h01, h11]`.
    #[inline(always)]
    pub fn corners(&self, i: u32, j: u32) -> [f32; 4] {
        let k = j as usize * self.nx + i as usize;
        let lo = &self.h[k..k + 2];
        let hi = &self.h[k + self.nx..k + self.nx + 2];
        [lo[0], lo[1], hi[0], hi[1]]
    }
}
