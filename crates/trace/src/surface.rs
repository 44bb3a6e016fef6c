//! The triangulated surface the tracers intersect, evaluated directly.

use natura_core::HeightField;

/// Returns the height at world `(x, y)` of the piecewise-planar surface the
/// tracers intersect (two triangles per cell split along `u + v = 1`, see
/// [`crate::Triangle`]), or `None` outside the field or for NaN.
///
/// This differs from [`HeightField::height_at`], which interpolates
/// bilinearly; both agree at the samples and along cell edges.
#[must_use]
pub fn surface_height(hf: &HeightField, x: f32, y: f32) -> Option<f32> {
    let e = hf.extent();
    if !(x >= 0.0 && y >= 0.0 && x <= e.x && y <= e.y) || hf.nx() < 2 || hf.ny() < 2 {
        return None;
    }
    let (i, j, u, v) = cell_at(hf, x, y);
    let h = hf.heights();
    let c = [h[(i, j)], h[(i + 1, j)], h[(i, j + 1)], h[(i + 1, j + 1)]];
    Some(cell_plane_height(&c, u, v))
}

/// The cell `(i, j)` holding world `(x, y)` (inside the field, of at least
/// 2 × 2 samples) and the point's place `(u, v)` in it, as
/// [`surface_height`] finds them.
#[inline(always)]
pub(crate) fn cell_at(hf: &HeightField, x: f32, y: f32) -> (usize, usize, f32, f32) {
    let (gx, gy) = (x / hf.cell_size(), y / hf.cell_size());
    // `x, y ≥ 0`: truncation is the floor.
    let i = (gx as usize).min(hf.nx() - 2);
    let j = (gy as usize).min(hf.ny() - 2);
    (i, j, gx - i as f32, gy - j as f32)
}

/// The height at `(u, v) ∈ [0, 1]²` in a cell of corner heights
/// `[h00, h10, h01, h11]`: the lower triangle's plane where `u + v ≤ 1`,
/// else the upper's (the split [`surface_height`] and the tracers use).
#[inline(always)]
pub(crate) fn cell_plane_height(c: &[f32; 4], u: f32, v: f32) -> f32 {
    let [h00, h10, h01, h11] = *c;
    if u + v <= 1.0 {
        h00 + (h10 - h00) * u + (h01 - h00) * v
    } else {
        h11 + (h11 - h01) * (u - 1.0) + (h11 - h10) * (v - 1.0)
    }
}
