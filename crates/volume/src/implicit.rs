//! Ebert's implicit macrostructure: skeletal primitives (points, segments,
//! ellipsoids) summed with the Wyvill soft-object blending function.
//!
//! Ebert 2001, "Volumetric Procedural Implicit Functions": the implicit
//! density is `Σ_i w_i · F(|p − q_i|)` with `q_i` the closest point of
//! skeleton `i` to `p` (a point gives a sphere, a segment a cylinder), and
//!
//! `F(r) = −(4/9)·r⁶/R⁶ + (17/9)·r⁴/R⁴ − (22/9)·r²/R² + 1`
//!
//! for radius of influence `R`. Erratum: the source gives the polynomial
//! without a domain, but it rises again beyond `R` (to ≈ 0.129 at
//! `r ≈ 1.35·R`) and turns negative past `1.5·R`; here `F = 0` for `r ≥ R`, so
//! each primitive's support is its ball (or capsule) of influence.

use glam::{Quat, Vec3};
use natura_core::Aabb;

use crate::density::{check_bounds, expand, overlaps};
use crate::error::{Result, VolumeError, finite3, positive};

/// The Wyvill soft-object blending function `F(r)` for radius of influence
/// `R`, written as `(1 − t)²(9 − 4t)/9` with `t = r²/R²` (the same
/// polynomial), and `0` for `r ≥ R`: `F(0) = 1`, `F(R/2) = ½`, `F(R) = 0`,
/// strictly decreasing on `[0, R]` with zero slope at both ends.
#[inline]
#[must_use]
pub fn wyvill(r: f32, radius: f32) -> f32 {
    wyvill_sq(r * r, radius * radius)
}

/// [`wyvill`] from squared distance and squared radius (no square root).
#[inline]
#[must_use]
pub fn wyvill_sq(r2: f32, radius2: f32) -> f32 {
    let t = r2 / radius2;
    if t >= 1.0 {
        return 0.0;
    }
    let u = 1.0 - t;
    u * u * (9.0 - 4.0 * t) * (1.0 / 9.0)
}

/// The skeleton of one implicit primitive.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Skeleton {
    /// A point: a sphere of influence.
    Point(Vec3),
    /// A segment from `a` to `b`: a cylinder with round caps.
    Segment {
        /// One end.
        a: Vec3,
        /// The other end.
        b: Vec3,
    },
    /// A point with a non-uniform metric: an ellipsoid with semi-axes
    /// `radius·scale` along the axes of `rotation`.
    Ellipsoid {
        /// Centre.
        centre: Vec3,
        /// Relative semi-axes (each `> 0`; the largest is usually 1).
        scale: Vec3,
        /// Orientation of the axes.
        rotation: Quat,
    },
}

/// One implicit primitive: a skeleton, its radius of influence `R` (m) and
/// its weight `w`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct ImplicitPrimitive {
    /// The skeleton.
    pub skeleton: Skeleton,
    /// Radius of influence `R` (m, `> 0`).
    pub radius: f32,
    /// Weight `w` (finite; negative weights carve; 1 when a file leaves it out).
    #[cfg_attr(feature = "serde", serde(default = "unit_weight"))]
    pub weight: f32,
}

/// The weight of a primitive that does not give one.
#[cfg(feature = "serde")]
fn unit_weight() -> f32 {
    1.0
}

impl ImplicitPrimitive {
    /// A sphere of influence `radius` about `centre` with weight 1.
    #[must_use]
    pub fn sphere(centre: Vec3, radius: f32) -> Self {
        Self {
            skeleton: Skeleton::Point(centre),
            radius,
            weight: 1.0,
        }
    }

    /// A capsule (cylinder with round caps) of influence `radius` about the segment `a`–`b`.
    #[must_use]
    pub fn cylinder(a: Vec3, b: Vec3, radius: f32) -> Self {
        Self {
            skeleton: Skeleton::Segment { a, b },
            radius,
            weight: 1.0,
        }
    }

    /// An axis-aligned ellipsoid with semi-axes `semi` (m) about `centre`.
    #[must_use]
    pub fn ellipsoid(centre: Vec3, semi: Vec3) -> Self {
        let r = semi.max_element();
        Self {
            skeleton: Skeleton::Ellipsoid {
                centre,
                scale: semi / r,
                rotation: Quat::IDENTITY,
            },
            radius: r,
            weight: 1.0,
        }
    }

    /// This primitive with weight `w`.
    #[must_use]
    pub fn with_weight(mut self, w: f32) -> Self {
        self.weight = w;
        self
    }

    /// Checks radius, weight and skeleton are finite (radius and scales `> 0`).
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] naming the bad field.
    pub fn validate(&self) -> Result<()> {
        positive("radius", self.radius)?;
        if !self.weight.is_finite() {
            return Err(VolumeError::InvalidParameter {
                name: "weight",
                value: self.weight.to_string(),
                expected: "must be finite",
            });
        }
        match self.skeleton {
            Skeleton::Point(c) => {
                finite3("centre", c)?;
            }
            Skeleton::Segment { a, b } => {
                finite3("a", a)?;
                finite3("b", b)?;
            }
            Skeleton::Ellipsoid {
                centre,
                scale,
                rotation,
            } => {
                finite3("centre", centre)?;
                if !(scale.is_finite() && scale.min_element() > 0.0) {
                    return Err(VolumeError::InvalidParameter {
                        name: "scale",
                        value: format!("{scale:?}"),
                        expected: "every component must be finite and > 0",
                    });
                }
                if !rotation.is_finite() || !rotation.is_normalized() {
                    return Err(VolumeError::InvalidParameter {
                        name: "rotation",
                        value: format!("{rotation:?}"),
                        expected: "must be a unit quaternion",
                    });
                }
            }
        }
        Ok(())
    }

    /// Squared skeleton distance `|p − q|²` (in the ellipsoid's metric for an ellipsoid).
    #[inline]
    #[must_use]
    pub fn distance_sq(&self, p: Vec3) -> f32 {
        match self.skeleton {
            Skeleton::Point(c) => (p - c).length_squared(),
            Skeleton::Segment { a, b } => {
                let ab = b - a;
                let len2 = ab.length_squared();
                let t = if len2 > 0.0 {
                    ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (p - (a + t * ab)).length_squared()
            }
            Skeleton::Ellipsoid {
                centre,
                scale,
                rotation,
            } => ((rotation.inverse() * (p - centre)) / scale).length_squared(),
        }
    }

    /// The primitive's weighted field `w·F(r)`.
    #[inline]
    #[must_use]
    pub fn field(&self, p: Vec3) -> f32 {
        self.weight * wyvill_sq(self.distance_sq(p), self.radius * self.radius)
    }

    /// The box outside which the field is zero.
    #[must_use]
    pub fn support(&self) -> Aabb {
        let r = Vec3::splat(self.radius);
        match self.skeleton {
            Skeleton::Point(c) => Aabb {
                min: c - r,
                max: c + r,
            },
            Skeleton::Segment { a, b } => Aabb {
                min: a.min(b) - r,
                max: a.max(b) + r,
            },
            Skeleton::Ellipsoid {
                centre,
                scale,
                rotation,
            } => {
                // Half extent of a rotated box of semi-axes radius·scale.
                let m = glam::Mat3::from_quat(rotation);
                let s = scale * self.radius;
                let h = m.x_axis.abs() * s.x + m.y_axis.abs() * s.y + m.z_axis.abs() * s.z;
                Aabb {
                    min: centre - h,
                    max: centre + h,
                }
            }
        }
    }
}

/// The weighted sum of primitives: Ebert's implicit density
/// `Σ_i w_i·F_i(p)` (not clamped: overlapping primitives sum past 1; the
/// cloud models clamp before shaping).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Implicit {
    primitives: Vec<ImplicitPrimitive>,
    supports: Vec<Aabb>,
    bounds: Aabb,
}

impl Implicit {
    /// The sum of `primitives` (at least one, each valid).
    ///
    /// # Errors
    ///
    /// [`VolumeError::InvalidParameter`] for an empty list or an invalid primitive.
    pub fn new(primitives: Vec<ImplicitPrimitive>) -> Result<Self> {
        if primitives.is_empty() {
            return Err(VolumeError::InvalidParameter {
                name: "primitives",
                value: "0".into(),
                expected: "at least one primitive",
            });
        }
        if primitives.len() > 1_000_000 {
            return Err(VolumeError::InvalidParameter {
                name: "primitives",
                value: primitives.len().to_string(),
                expected: "at most 1 000 000 primitives",
            });
        }
        for p in &primitives {
            p.validate()?;
        }
        let supports: Vec<Aabb> = primitives.iter().map(ImplicitPrimitive::support).collect();
        let bounds = supports
            .iter()
            .skip(1)
            .fold(supports[0], |a, b| crate::density::union(&a, b));
        check_bounds("primitives", &bounds)?;
        Ok(Self {
            primitives,
            supports,
            bounds,
        })
    }

    /// The primitives.
    #[must_use]
    pub fn primitives(&self) -> &[ImplicitPrimitive] {
        &self.primitives
    }

    /// The union of the primitives' supports.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The implicit density `Σ w_i F_i(p)` at `p`.
    #[inline]
    #[must_use]
    pub fn eval(&self, p: Vec3) -> f32 {
        let mut s = 0.0;
        for (prim, b) in self.primitives.iter().zip(&self.supports) {
            if b.contains(p) {
                s += prim.field(p);
            }
        }
        s
    }

    /// An upper bound of [`Implicit::eval`] over points within `margin` of
    /// `region`: the sum of the positive weights whose support reaches it.
    #[must_use]
    pub fn bound_in(&self, region: &Aabb, margin: Vec3) -> f32 {
        let r = expand(region, margin);
        self.primitives
            .iter()
            .zip(&self.supports)
            .filter(|(_, b)| overlaps(b, &r))
            .map(|(p, _)| p.weight.max(0.0))
            .sum()
    }

    /// The sum of the positive weights (the global bound).
    #[must_use]
    pub fn max_value(&self) -> f32 {
        self.primitives.iter().map(|p| p.weight.max(0.0)).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wyvill_matches_the_source_polynomial_inside() {
        for i in 0..=100 {
            let r = i as f32 / 100.0 * 2.0;
            let rr = r / 2.0;
            let poly = -(4.0 / 9.0) * rr.powi(6) + (17.0 / 9.0) * rr.powi(4)
                - (22.0 / 9.0) * rr.powi(2)
                + 1.0;
            assert!((wyvill(r, 2.0) - poly).abs() < 1e-6, "r = {r}");
        }
        // Outside R the source polynomial is nonzero; ours is clamped.
        assert_eq!(wyvill(2.7, 2.0), 0.0);
    }

    #[test]
    fn segment_and_ellipsoid_distances() {
        let c = ImplicitPrimitive::cylinder(Vec3::ZERO, Vec3::X * 4.0, 1.0);
        assert!((c.distance_sq(Vec3::new(2.0, 0.5, 0.0)) - 0.25).abs() < 1e-6);
        assert!((c.distance_sq(Vec3::new(5.0, 0.0, 0.0)) - 1.0).abs() < 1e-6);
        let e = ImplicitPrimitive::ellipsoid(Vec3::ZERO, Vec3::new(4.0, 2.0, 1.0));
        // On the surface of the ellipsoid the metric distance equals R = 4.
        assert!((e.distance_sq(Vec3::new(0.0, 2.0, 0.0)) - 16.0).abs() < 1e-4);
        assert_eq!(e.field(Vec3::new(0.0, 0.0, 1.01)), 0.0);
        let s = e.support();
        assert!((s.max - Vec3::new(4.0, 2.0, 1.0)).abs().max_element() < 1e-5);
    }

    #[test]
    fn invalid_primitives_are_refused() {
        assert!(Implicit::new(vec![]).is_err());
        assert!(Implicit::new(vec![ImplicitPrimitive::sphere(Vec3::ZERO, f32::NAN)]).is_err());
        assert!(
            Implicit::new(vec![
                ImplicitPrimitive::sphere(Vec3::ZERO, 1.0).with_weight(f32::INFINITY)
            ])
            .is_err()
        );
    }
}
