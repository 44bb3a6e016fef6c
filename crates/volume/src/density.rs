//! The [`Density`] trait: a scalar density field in world space with a
//! support box and conservative bounds for empty-space skipping, plus the
//! small box helpers every renderer uses.

use glam::Vec3;
use natura_core::Aabb;

use crate::error::{Result, VolumeError};

/// A density field: `f32` density (dimensionless, usually in `[0, 1]`) at a
/// world-space point (metres, z up).
///
/// Contract, relied on by every renderer in this crate:
/// * [`density`](Density::density) is finite and `≥ 0` everywhere, and `0`
///   outside [`bounds`](Density::bounds);
/// * [`bound_in`](Density::bound_in) is `≥` the density at every point of the
///   given box (a majorant: delta tracking is unbiased only if it holds);
/// * evaluation is a pure function of the point (no interior mutability), so
///   results do not depend on evaluation order or thread count.
pub trait Density: Send + Sync {
    /// The density at `p`.
    fn density(&self, p: Vec3) -> f32;

    /// A box outside which the density is zero.
    fn bounds(&self) -> Aabb;

    /// An upper bound of the density inside `region` (the default: the
    /// global bound [`max_density`](Density::max_density)).
    fn bound_in(&self, region: &Aabb) -> f32 {
        let _ = region;
        self.max_density()
    }

    /// An upper bound of the density in the box `centre ± radius` (every
    /// axis), such as the box round a march's step of length `2·radius`
    /// centred at `centre`. The default is [`bound_in`](Density::bound_in)
    /// of that box; fields with a quicker bound for short steps override it.
    fn bound_near(&self, centre: Vec3, radius: f32) -> f32 {
        self.bound_in(&Aabb {
            min: centre - Vec3::splat(radius),
            max: centre + Vec3::splat(radius),
        })
    }

    /// Along the ray from `o` along unit `d`, from distance `t` to
    /// `t_max`: `Some((a, b))` when the density is zero on `[t, a)` and may
    /// be positive on `[a, b)` (`t ≤ a ≤ b ≤ t_max`; `a = b = t_max` when it is
    /// zero all the way), or `None` when the field cannot tell more cheaply
    /// than [`bound_in`](Density::bound_in) over boxes (the default). A
    /// march skips `[t, a)` and samples `[a, b)` without bounding its steps.
    fn clear_along(&self, o: Vec3, d: Vec3, t: f32, t_max: f32) -> Option<(f32, f32)> {
        let _ = (o, d, t, t_max);
        None
    }

    /// An upper bound of the density over all space.
    fn max_density(&self) -> f32;

    /// The densities at many points at once, struct of arrays:
    /// `out[i]` is the density at `(x[i], y[i], z[i])`.
    ///
    /// The default evaluates point by point (exactly
    /// [`density`](Density::density)); fields with a vectorised path
    /// override it and state how closely it agrees with the point path.
    ///
    /// # Errors
    ///
    /// [`VolumeError::SizeMismatch`] if the four slices differ in length.
    fn density_batch(&self, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) -> Result<()> {
        check_batch(x, y, z, out)?;
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.density(Vec3::new(x[i], y[i], z[i]));
        }
        Ok(())
    }

    /// [`density_batch`](Density::density_batch) for samples `spacing`
    /// metres apart, such as the steps of a march toward a light or the
    /// nodes of a shadow table: a density with detail finer than the
    /// spacing (noise octaves) may leave that detail out and keep its mean,
    /// since samples that far apart cannot resolve it and would only alias
    /// it. The default ignores `spacing` and is
    /// [`density_batch`](Density::density_batch) bit for bit.
    ///
    /// # Errors
    ///
    /// [`VolumeError::SizeMismatch`] if the four slices differ in length.
    fn density_batch_spaced(
        &self,
        x: &[f32],
        y: &[f32],
        z: &[f32],
        spacing: f32,
        out: &mut [f32],
    ) -> Result<()> {
        let _ = spacing;
        self.density_batch(x, y, z, out)
    }
}

/// The densities of `density` at `(x[i], y[i], z[i])` into `out`: one
/// batch, or point by point should the batch refuse the slices (it does
/// only when their lengths differ; callers pass equal lengths).
pub(crate) fn fill_densities(
    density: &dyn Density,
    x: &[f32],
    y: &[f32],
    z: &[f32],
    out: &mut [f32],
) {
    if density.density_batch(x, y, z, out).is_err() {
        for (i, o) in out.iter_mut().enumerate() {
            *o = density.density(Vec3::new(x[i], y[i], z[i]));
        }
    }
}

/// [`fill_densities`] for samples `spacing` metres apart
/// ([`Density::density_batch_spaced`]).
pub(crate) fn fill_densities_spaced(
    density: &dyn Density,
    x: &[f32],
    y: &[f32],
    z: &[f32],
    spacing: f32,
    out: &mut [f32],
) {
    if density.density_batch_spaced(x, y, z, spacing, out).is_err() {
        for (i, o) in out.iter_mut().enumerate() {
            *o = density.density(Vec3::new(x[i], y[i], z[i]));
        }
    }
}

/// Checks that the coordinate slices of a batch evaluation are as long as its output.
///
/// # Errors
///
/// [`VolumeError::SizeMismatch`] otherwise.
pub fn check_batch(x: &[f32], y: &[f32], z: &[f32], out: &[f32]) -> Result<()> {
    for len in [x.len(), y.len(), z.len()] {
        if len != out.len() {
            return Err(VolumeError::SizeMismatch {
                name: "batch points",
                expected: out.len().to_string(),
                actual: len.to_string(),
            });
        }
    }
    Ok(())
}

impl<D: Density + ?Sized> Density for &D {
    fn density(&self, p: Vec3) -> f32 {
        (**self).density(p)
    }
    fn bounds(&self) -> Aabb {
        (**self).bounds()
    }
    fn bound_in(&self, region: &Aabb) -> f32 {
        (**self).bound_in(region)
    }
    fn bound_near(&self, centre: Vec3, radius: f32) -> f32 {
        (**self).bound_near(centre, radius)
    }
    fn clear_along(&self, o: Vec3, d: Vec3, t: f32, t_max: f32) -> Option<(f32, f32)> {
        (**self).clear_along(o, d, t, t_max)
    }
    fn max_density(&self) -> f32 {
        (**self).max_density()
    }
    fn density_batch(&self, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) -> Result<()> {
        (**self).density_batch(x, y, z, out)
    }
}

impl<D: Density + ?Sized> Density for Box<D> {
    fn density(&self, p: Vec3) -> f32 {
        (**self).density(p)
    }
    fn bounds(&self) -> Aabb {
        (**self).bounds()
    }
    fn bound_in(&self, region: &Aabb) -> f32 {
        (**self).bound_in(region)
    }
    fn bound_near(&self, centre: Vec3, radius: f32) -> f32 {
        (**self).bound_near(centre, radius)
    }
    fn clear_along(&self, o: Vec3, d: Vec3, t: f32, t_max: f32) -> Option<(f32, f32)> {
        (**self).clear_along(o, d, t, t_max)
    }
    fn max_density(&self) -> f32 {
        (**self).max_density()
    }
    fn density_batch(&self, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) -> Result<()> {
        (**self).density_batch(x, y, z, out)
    }
}

/// A constant density inside a box, zero outside: the homogeneous slab of the
/// closed-form tests (`T = exp(−σ·ρ·ℓ)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Homogeneous {
    region: Aabb,
    value: f32,
}

impl Homogeneous {
    /// Density `value` inside `region`.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidBounds`] for an empty, inverted or non-finite box;
    /// [`VolumeError::InvalidParameter`] for a negative or non-finite `value`.
    pub fn new(region: Aabb, value: f32) -> Result<Self> {
        check_bounds("region", &region)?;
        crate::error::non_negative("value", value)?;
        Ok(Self { region, value })
    }
}

impl Density for Homogeneous {
    fn density(&self, p: Vec3) -> f32 {
        if self.region.contains(p) {
            self.value
        } else {
            0.0
        }
    }
    fn bounds(&self) -> Aabb {
        self.region
    }
    fn bound_in(&self, region: &Aabb) -> f32 {
        if overlaps(region, &self.region) {
            self.value
        } else {
            0.0
        }
    }
    fn max_density(&self) -> f32 {
        self.value
    }
}

/// A constant density inside a ball, zero outside (the sphere of the
/// closed-form transmittance tests).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    centre: Vec3,
    radius: f32,
    value: f32,
}

impl Ball {
    /// Density `value` inside the ball of `radius` about `centre`.
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] for a non-finite centre, a radius
    /// that is not finite and positive, or a negative or non-finite `value`.
    pub fn new(centre: Vec3, radius: f32, value: f32) -> Result<Self> {
        crate::error::finite3("centre", centre)?;
        crate::error::positive("radius", radius)?;
        crate::error::non_negative("value", value)?;
        Ok(Self {
            centre,
            radius,
            value,
        })
    }
}

impl Density for Ball {
    fn density(&self, p: Vec3) -> f32 {
        if (p - self.centre).length_squared() <= self.radius * self.radius {
            self.value
        } else {
            0.0
        }
    }
    fn bounds(&self) -> Aabb {
        Aabb {
            min: self.centre - Vec3::splat(self.radius),
            max: self.centre + Vec3::splat(self.radius),
        }
    }
    fn max_density(&self) -> f32 {
        self.value
    }
}

/// Checks that `b` is finite and non-empty on every axis.
///
/// # Errors
///
/// [`VolumeError::InvalidBounds`] naming `name` otherwise.
pub fn check_bounds(name: &'static str, b: &Aabb) -> Result<()> {
    if b.min.is_finite() && b.max.is_finite() && b.min.cmplt(b.max).all() {
        Ok(())
    } else {
        Err(VolumeError::InvalidBounds {
            name,
            min: b.min.to_array(),
            max: b.max.to_array(),
        })
    }
}

/// Points per axis of [`probe_density`]'s lattice.
pub const PROBE_POINTS: usize = 16;

/// Checks a density before any rendering work: at a lattice of
/// [`PROBE_POINTS`]³ points through its bounds (cell centres, shifted by a
/// fixed irrational fraction so that the lattice does not sit on the planes
/// of symmetry of a procedural field), every value must be finite, at
/// least 0 and at most [`Density::max_density`] (the majorant the
/// reference's delta tracking and the march's empty-space skipping rely on).
/// A probe, not a proof: a field that goes wrong only between the points
/// passes.
///
/// # Errors
///
/// [`VolumeError::InvalidParameter`] naming `density` for a NaN, infinite
/// or negative value, or `max_density` for a value above the bound, with
/// the point where it was found.
pub fn probe_density(density: &dyn Density) -> Result<()> {
    let b = density.bounds();
    let n = PROBE_POINTS;
    let shift = Vec3::new(0.618_034, 0.414_213_56, 0.732_050_8) - Vec3::splat(0.5);
    let size = b.max - b.min;
    let mut xs = Vec::with_capacity(n * n * n);
    let (mut ys, mut zs) = (Vec::with_capacity(n * n * n), Vec::with_capacity(n * n * n));
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let u = (Vec3::new(i as f32, j as f32, k as f32) + Vec3::splat(0.5) + shift * 0.5)
                    / n as f32;
                let p = b.min + size * u;
                xs.push(p.x);
                ys.push(p.y);
                zs.push(p.z);
            }
        }
    }
    let mut out = vec![0.0f32; xs.len()];
    density.density_batch(&xs, &ys, &zs, &mut out)?;
    let bound = density.max_density();
    for (i, &v) in out.iter().enumerate() {
        let at = || format!("{v} at ({}, {}, {})", xs[i], ys[i], zs[i]);
        if !(v.is_finite() && v >= 0.0) {
            return Err(VolumeError::InvalidParameter {
                name: "density",
                value: at(),
                expected: "a finite density ≥ 0 everywhere",
            });
        }
        if v > bound * (1.0 + 1e-5) + 1e-30 {
            return Err(VolumeError::InvalidParameter {
                name: "max_density",
                value: format!("{bound} below the density {}", at()),
                expected: "a bound at least the density everywhere",
            });
        }
    }
    Ok(())
}

/// Whether two boxes overlap (touching counts).
#[inline]
#[must_use]
pub fn overlaps(a: &Aabb, b: &Aabb) -> bool {
    a.min.cmple(b.max).all() && b.min.cmple(a.max).all()
}

/// `b` grown by `d` on every side.
#[inline]
#[must_use]
pub fn expand(b: &Aabb, d: Vec3) -> Aabb {
    Aabb {
        min: b.min - d,
        max: b.max + d,
    }
}

/// The smallest box holding both.
#[inline]
#[must_use]
pub fn union(a: &Aabb, b: &Aabb) -> Aabb {
    Aabb {
        min: a.min.min(b.min),
        max: a.max.max(b.max),
    }
}

/// The parameter interval `[t0, t1]` (clipped to `t ≥ 0`) over which the ray
/// `o + t·inv_d⁻¹` lies in `b`, given the component-wise inverse direction;
/// `None` if it misses. Axis-parallel rays (infinite `inv_d`) are handled by
/// IEEE arithmetic, with the NaN of `0·∞` on a slab face treated as inside.
#[inline]
#[must_use]
pub fn ray_box(o: Vec3, inv_d: Vec3, b: &Aabb) -> Option<(f32, f32)> {
    let t_a = (b.min - o) * inv_d;
    let t_b = (b.max - o) * inv_d;
    let lo = t_a.min(t_b);
    let hi = t_a.max(t_b);
    // NaN-ignoring max/min of the components.
    let t0 = lo.x.max(lo.y).max(lo.z).max(0.0);
    let t1 = hi.x.min(hi.y).min(hi.z);
    if t1 >= t0 { Some((t0, t1)) } else { None }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_box_axis_parallel_and_miss() {
        let b = Aabb {
            min: Vec3::ZERO,
            max: Vec3::ONE,
        };
        let d = Vec3::X;
        let r = ray_box(Vec3::new(-1.0, 0.5, 0.5), d.recip(), &b).unwrap();
        assert!((r.0 - 1.0).abs() < 1e-6 && (r.1 - 2.0).abs() < 1e-6);
        assert!(ray_box(Vec3::new(-1.0, 2.0, 0.5), d.recip(), &b).is_none());
        // Starting inside clips at 0.
        let r = ray_box(Vec3::splat(0.5), Vec3::Z.recip(), &b).unwrap();
        assert_eq!(r.0, 0.0);
    }

    #[test]
    fn bad_boxes_are_refused() {
        let inverted = Aabb {
            min: Vec3::ONE,
            max: Vec3::ZERO,
        };
        assert!(check_bounds("b", &inverted).is_err());
        let nan = Aabb {
            min: Vec3::splat(f32::NAN),
            max: Vec3::ONE,
        };
        assert!(check_bounds("b", &nan).is_err());
        assert!(Homogeneous::new(inverted, 1.0).is_err());
        let ok = Aabb {
            min: Vec3::ZERO,
            max: Vec3::ONE,
        };
        assert!(Homogeneous::new(ok, f32::NAN).is_err());
        assert!(Ball::new(Vec3::ZERO, 0.0, 1.0).is_err());
    }
}
