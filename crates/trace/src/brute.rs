//! The brute-force oracle: every triangle of the field, no traversal, no culls.

use natura_core::HeightField;

use crate::detail::{DetailSurface, RayCone};
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
            if let Some(h) = intersect_cell::<false>(&r, i, j, f.corners(i, j))
                && best.is_none_or(|b| h.t < b.t)
            {
                best = Some(h);
            }
        }
    }
    Ok(best.map(|h| crate::ray_cell::make_hit(&f, ray, h)))
}

/// The first crossing of `ray` with a detailed surface over `[t_min, t_max]`
/// (footprint `fp` along the ray), found by evaluating the surface's own
/// height function every `step_m` metres of the ray and bisecting the first
/// interval whose ends lie on opposite sides: the oracle
/// [`crate::DetailTracer`] is tested against. No bounds, no hierarchy; a
/// crossing and re-crossing within one step is missed, so choose `step_m`
/// well below the features of interest. Only the part of the ray over the
/// field counts; the side the ray starts on is the side of its first point
/// there. Returns the ray parameter of the crossing (to 1e-7 relative), or
/// `None`, also for an invalid ray or range or a `step_m` that is not
/// finite and positive.
#[must_use]
pub fn detail_brute_force(
    surface: &DetailSurface<'_>,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
    fp: RayCone,
    step_m: f32,
) -> Option<f64> {
    let range_ok = t_min <= t_max && step_m.is_finite() && step_m > 0.0;
    if !(ray.is_valid() && range_ok) {
        return None;
    }
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
    let len = d.length();
    let e = surface.height_field().extent().as_dvec2();
    // The stretch of the ray over the field.
    let (mut a, mut b) = (f64::from(t_min), f64::from(t_max));
    for (oo, dd, hi) in [(o.x, d.x, e.x), (o.y, d.y, e.y)] {
        if dd == 0.0 {
            if oo < 0.0 || oo > hi {
                return None;
            }
        } else {
            let (p, q) = ((0.0 - oo) / dd, (hi - oo) / dd);
            a = a.max(p.min(q));
            b = b.min(p.max(q));
        }
    }
    if a.partial_cmp(&b) == Some(std::cmp::Ordering::Greater) || !(a.is_finite() && b.is_finite()) {
        return None;
    }
    let gap = |t: f64| {
        let p = o + t * d;
        let (x, y) = (
            (p.x as f32).clamp(0.0, e.x as f32),
            (p.y as f32).clamp(0.0, e.y as f32),
        );
        surface
            .height(x, y, fp.at(t * len))
            .map_or(f64::NAN, |s| p.z - s)
    };
    let g0 = gap(a);
    let side = if g0 >= 0.0 { 1.0 } else { -1.0 };
    if side * g0 <= 0.0 {
        return Some(a);
    }
    let dt = f64::from(step_m) / len;
    let n = ((b - a) / dt).ceil() as u64;
    let mut lo = a;
    for k in 1..=n {
        let hi = (a + k as f64 * dt).min(b);
        if side * gap(hi) <= 0.0 {
            let mut hi = hi;
            while hi - lo > 1e-7 * hi.abs().max(1.0) {
                let mid = 0.5 * (lo + hi);
                if side * gap(mid) > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return Some(hi);
        }
        lo = hi;
    }
    None
}
