//! The brute-force oracle: every triangle of the field, no traversal, no culls.

use natura_core::HeightField;

use crate::error::Result;
use crate::field::FieldView;
use crate::grid_ray::GridRay;
use crate::ray::{Hit, Ray};
use crate::ray_cell::{CellHit, intersect_cell};

/// Returns the closest hit of `ray` with the surface in `[t_min, t_max]`,
/// found by testing all `2·(nx − 1)·(ny − 1)` triangles.
///
/// This is the reference the fast tracers are tested against: it uses the same diagonal and the exact,
/// inclusive watertight test, with no traversal and no culling, so it is
/// correct by construction and slow (O(N) per ray). Equal `t` keeps the
/// first triangle in row-major cell order, lower before upper.
///
/// # Errors
///
/// Fails like [`crate::MipmapTracer::new`] on a field that cannot be traced.
pub fn brute_force(hf: &HeightField, ray: &Ray, t_min: f32, t_max: f32) -> Result<Option<Hit>> {
    let f = FieldView::new(hf)?;
    let Some(r) = GridRay::new(&f, ray, t_min, t_max) else {
        return Ok(None);
    };
    let mut best: Option<CellHit> = None;
    for j in 0..f.ncy {
        for i in 0..f.ncx {
            if let Some(h) = intersect_cell::<false>(&r, i, j, f.corners(i, j)) {
                if best.is_none_or(|b| h.t < b.t) {
                    best = Some(h);
                }
            }
        }
    }
    Ok(best.map(|h| crate::ray_cell::make_hit(&f, ray, h)))
}
