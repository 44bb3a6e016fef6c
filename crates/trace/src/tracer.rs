//! The [`Tracer`] trait: the seam where the grid tracer, the mipmap tracer
//! (and any future accelerator) plug into cameras and image drivers.

use natura_core::HeightField;

use crate::ray::{Hit, Ray, TraceStats};

/// The [`Tracer`] queries of a cell walk, written once for the walks that
/// share their shape (the grid DDA and the mipmap walk): each has a field `f`
/// (the surface) and a method `run::<OCCLUSION>(ray, t_min, t_max, stats)`
/// returning the first cell hit, which [`crate::ray_cell::make_hit`] turns
/// into a [`Hit`]. Expanded inside the walk's `impl Tracer`.
macro_rules! walk_queries {
    () => {
        fn trace(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
            self.run::<false>(ray, t_min, t_max, &mut TraceStats::default())
                .map(|h| crate::ray_cell::make_hit(&self.f, ray, h))
        }

        fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
            self.run::<true>(ray, t_min, t_max, &mut TraceStats::default())
                .is_some()
        }

        fn trace_with_stats(&self, ray: &Ray, t_min: f32, t_max: f32) -> (Option<Hit>, TraceStats) {
            let mut s = TraceStats::default();
            let h = self
                .run::<false>(ray, t_min, t_max, &mut s)
                .map(|h| crate::ray_cell::make_hit(&self.f, ray, h));
            (h, s)
        }

        fn height_field(&self) -> &HeightField {
            self.f.hf
        }
    };
}
pub(crate) use walk_queries;

/// A ray tracer over one height field.
///
/// Both queries take a parameter range `[t_min, t_max]` (inclusive; use
/// `f32::INFINITY` for no far limit) and never panic: a ray with a NaN,
/// infinite or zero direction, or an empty or NaN range, hits nothing.
pub trait Tracer: Sync {
    /// Returns the closest hit of `ray` with the surface with `t` in `[t_min, t_max]`.
    fn trace(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit>;

    /// Returns whether anything lies on `ray` with `t` in `[t_min, t_max]`
    /// (a shadow ray); stops at the first hit found.
    fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool;

    /// [`Tracer::trace`] together with the work it took.
    fn trace_with_stats(&self, ray: &Ray, t_min: f32, t_max: f32) -> (Option<Hit>, TraceStats);

    /// The height field being traced.
    fn height_field(&self) -> &HeightField;

    /// [`Tracer::trace`] of every ray of `rays`, in order. Tracers override
    /// this where batches run faster ([`crate::MipmapTracer`] does); the
    /// results are the same as one call per ray.
    fn trace_many(&self, rays: &[Ray], t_min: f32, t_max: f32) -> Vec<Option<Hit>> {
        rays.iter().map(|r| self.trace(r, t_min, t_max)).collect()
    }

    /// [`Tracer::occluded`] of every ray of `rays`, in order (overridden
    /// where batches run faster, with the same results).
    fn occluded_many(&self, rays: &[Ray], t_min: f32, t_max: f32) -> Vec<bool> {
        rays.iter()
            .map(|r| self.occluded(r, t_min, t_max))
            .collect()
    }
}
