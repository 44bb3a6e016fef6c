//! Opaque solids in a volume scene: spheres (a fluid simulation's obstacle)
//! and upright cylinders (a cup under its steam), each lit as a Lambertian
//! surface, seen, and shadowing the volume, the ground and each other.

use glam::Vec3;

/// The shape of a [`Solid`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum SolidShape {
    /// A sphere of the solid's radius about its centre.
    #[default]
    Sphere,
    /// An upright cylinder (its axis along z) of the solid's radius, closed
    /// at both ends, reaching `half_height` (m, `> 0`) below and above the
    /// solid's centre.
    Cylinder {
        /// Half its height (m).
        half_height: f32,
    },
}

/// An opaque Lambertian solid (for example a fluid simulation's obstacle):
/// seen, lit by the sun through the volume, shadowing the volume, the ground
/// and other solids from the sun; like the ground it does not reflect light
/// back into the volume.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solid {
    /// Centre (m).
    pub centre: Vec3,
    /// Radius (m, `> 0`): the sphere's, or the cylinder's across its axis.
    pub radius: f32,
    /// Albedo (linear RGB, each in `[0, 1]`).
    pub albedo: Vec3,
    /// Ambient irradiance on its surface (linear RGB).
    pub sky_irradiance: Vec3,
    /// Its shape (a sphere unless said otherwise).
    pub shape: SolidShape,
}

impl Solid {
    /// Whether `p` lies inside the solid.
    #[inline]
    #[must_use]
    pub fn contains(&self, p: Vec3) -> bool {
        let q = p - self.centre;
        let r2 = self.radius * self.radius;
        match self.shape {
            SolidShape::Sphere => q.length_squared() < r2,
            SolidShape::Cylinder { half_height } => {
                q.x * q.x + q.y * q.y < r2 && q.z.abs() < half_height
            }
        }
    }

    /// Distance along unit `d` from `o` to the solid's surface (from
    /// outside; 0 from inside), if the ray meets it.
    #[inline]
    #[must_use]
    pub fn hit(&self, o: Vec3, d: Vec3) -> Option<f32> {
        let q = o - self.centre;
        let r2 = self.radius * self.radius;
        let (t0, t1) = match self.shape {
            SolidShape::Sphere => {
                let b = q.dot(d);
                let c = q.length_squared() - r2;
                let disc = b * b - c;
                if disc < 0.0 {
                    return None;
                }
                let s = disc.sqrt();
                (-b - s, -b + s)
            }
            SolidShape::Cylinder { half_height: h } => {
                // The slab between the caps, then the infinite side.
                let (mut t0, mut t1) = if d.z != 0.0 {
                    let (a, b) = ((-h - q.z) / d.z, (h - q.z) / d.z);
                    (a.min(b), a.max(b))
                } else if q.z.abs() < h {
                    (f32::NEG_INFINITY, f32::INFINITY)
                } else {
                    return None;
                };
                let a = d.x * d.x + d.y * d.y;
                let c = q.x * q.x + q.y * q.y - r2;
                if a > 0.0 {
                    let b = q.x * d.x + q.y * d.y;
                    let disc = b * b - a * c;
                    if disc < 0.0 {
                        return None;
                    }
                    let s = disc.sqrt();
                    t0 = t0.max((-b - s) / a);
                    t1 = t1.min((-b + s) / a);
                } else if c >= 0.0 {
                    return None;
                }
                if t0 > t1 {
                    return None;
                }
                (t0, t1)
            }
        };
        if t0 > 0.0 {
            Some(t0)
        } else if t1 > 0.0 {
            Some(0.0)
        } else {
            None
        }
    }

    /// The outward unit normal at `p` on (or just off) the surface.
    #[inline]
    #[must_use]
    pub fn normal(&self, p: Vec3) -> Vec3 {
        let q = p - self.centre;
        match self.shape {
            SolidShape::Sphere => q.normalize_or(Vec3::Z),
            SolidShape::Cylinder { half_height } => {
                let rho = (q.x * q.x + q.y * q.y).sqrt();
                // The nearer of the caps and the side.
                if half_height - q.z.abs() < self.radius - rho {
                    Vec3::Z * q.z.signum()
                } else {
                    Vec3::new(q.x, q.y, 0.0).normalize_or(Vec3::X)
                }
            }
        }
    }

    /// A point just outside the surface near `p`, where the light arriving
    /// at the surface is looked up.
    #[inline]
    #[must_use]
    pub fn lift(&self, p: Vec3) -> Vec3 {
        let eps = 1e-3 * self.size() + 1e-4;
        match self.shape {
            SolidShape::Sphere => {
                self.centre + (p - self.centre).normalize_or(Vec3::Z) * (self.radius + eps)
            }
            SolidShape::Cylinder { .. } => p + self.normal(p) * eps,
        }
    }

    /// Its largest half-extent (m).
    fn size(&self) -> f32 {
        match self.shape {
            SolidShape::Sphere => self.radius,
            SolidShape::Cylinder { half_height } => self.radius.max(half_height),
        }
    }

    /// Its surface area (m²).
    #[must_use]
    pub fn area(&self) -> f32 {
        let r = self.radius;
        match self.shape {
            SolidShape::Sphere => 4.0 * std::f32::consts::PI * r * r,
            SolidShape::Cylinder { half_height } => {
                2.0 * std::f32::consts::PI * r * (2.0 * half_height + r)
            }
        }
    }

    /// A point of the surface uniform by area, and its outward normal,
    /// from uniform numbers in `[0, 1)` drawn by `unit`.
    pub(crate) fn sample(&self, unit: &mut impl FnMut() -> f32) -> (Vec3, Vec3) {
        let r = self.radius;
        let tau = 2.0 * std::f32::consts::PI;
        match self.shape {
            SolidShape::Sphere => {
                let n = uniform_direction(unit);
                (self.centre + n * r, n)
            }
            SolidShape::Cylinder { half_height: h } => {
                let side = 2.0 * h / (2.0 * h + r);
                let (u, phi) = (unit(), tau * unit());
                let (c, s) = (phi.cos(), phi.sin());
                if u < side {
                    let z = h * (2.0 * unit() - 1.0);
                    let n = Vec3::new(c, s, 0.0);
                    (self.centre + Vec3::new(r * c, r * s, z), n)
                } else {
                    let top = (u - side) / (1.0 - side) < 0.5;
                    let rho = r * unit().sqrt();
                    let z = if top { h } else { -h };
                    (
                        self.centre + Vec3::new(rho * c, rho * s, z),
                        Vec3::Z * z.signum(),
                    )
                }
            }
        }
    }
}

/// A direction uniform over the sphere, from uniform numbers in `[0, 1)`
/// drawn by `unit` (its height first, then its azimuth).
pub(crate) fn uniform_direction(unit: &mut impl FnMut() -> f32) -> Vec3 {
    let z = 1.0 - 2.0 * unit();
    let s = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * unit();
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::Rng;

    fn solids() -> [Solid; 2] {
        let base = Solid {
            centre: Vec3::new(0.3, -0.2, 0.5),
            radius: 0.7,
            albedo: Vec3::splat(0.5),
            sky_irradiance: Vec3::ZERO,
            shape: SolidShape::Sphere,
        };
        [
            base,
            Solid {
                shape: SolidShape::Cylinder { half_height: 0.4 },
                ..base
            },
        ]
    }

    fn uniform(rng: &mut impl Rng) -> f32 {
        (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32
    }

    #[test]
    fn hits_agree_with_a_brute_force_march() {
        // From points round the solid, in random directions: the first
        // point of a fine march inside the solid lies at the hit.
        let mut rng = natura_core::Seed(5).rng();
        for s in solids() {
            let (mut hits, mut inside) = (0, 0);
            for _ in 0..2000 {
                let o = s.centre
                    + Vec3::new(
                        4.0 * uniform(&mut rng) - 2.0,
                        4.0 * uniform(&mut rng) - 2.0,
                        4.0 * uniform(&mut rng) - 2.0,
                    );
                let d = Vec3::new(
                    2.0 * uniform(&mut rng) - 1.0,
                    2.0 * uniform(&mut rng) - 1.0,
                    2.0 * uniform(&mut rng) - 1.0,
                )
                .normalize();
                let h = 1e-3;
                let first = (0..6000)
                    .map(|k| k as f32 * h)
                    .find(|&t| s.contains(o + d * t));
                match (s.hit(o, d), first) {
                    (Some(t), Some(f)) => {
                        assert!((t - f).abs() <= 1.5 * h, "{s:?} {o} {d}: {t} {f}");
                        hits += 1;
                        if s.contains(o) {
                            assert_eq!(t, 0.0);
                            inside += 1;
                        }
                    }
                    (None, None) => {}
                    // A ray that only grazes the surface may fall between
                    // the march's points.
                    (Some(t), None) => {
                        let p = o + d * t;
                        assert!(
                            s.contains(p + s.normal(p) * -2e-3) || t > 5.9,
                            "{o} {d} {t}"
                        );
                    }
                    (None, Some(f)) => panic!("{s:?} {o} {d}: missed, marched to {f}"),
                }
            }
            assert!(hits > 100 && inside > 10, "{hits} {inside}");
        }
    }

    #[test]
    fn normals_face_the_ray_and_lifted_points_lie_outside() {
        let mut rng = natura_core::Seed(9).rng();
        for s in solids() {
            for _ in 0..2000 {
                let o = s.centre + Vec3::new(3.0, 0.0, 0.0);
                let d = (s.centre
                    + Vec3::new(
                        1.6 * uniform(&mut rng) - 0.8,
                        1.6 * uniform(&mut rng) - 0.8,
                        1.6 * uniform(&mut rng) - 0.8,
                    )
                    - o)
                    .normalize();
                if let Some(t) = s.hit(o, d) {
                    let p = o + d * t;
                    let n = s.normal(p);
                    assert!((n.length() - 1.0).abs() < 1e-5);
                    assert!(n.dot(d) <= 1e-4, "{s:?} {p} {n} {d}");
                    assert!(!s.contains(s.lift(p)));
                }
            }
        }
    }

    #[test]
    fn samples_cover_the_surface_uniformly_by_area() {
        let mut rng = natura_core::Seed(11).rng();
        for s in solids() {
            let n = 40_000;
            let (mut caps, mut upper) = (0usize, 0usize);
            for _ in 0..n {
                let (p, nrm) = s.sample(&mut || uniform(&mut rng));
                // On the surface: just inside along the normal is inside,
                // just outside is not.
                assert!(s.contains(p - nrm * 1e-3), "{s:?} {p} {nrm}");
                assert!(!s.contains(p + nrm * 1e-3), "{s:?} {p} {nrm}");
                assert!((s.normal(p) - nrm).length() < 1e-4 || nrm.z.abs() > 0.5);
                caps += usize::from(nrm.z.abs() > 0.999);
                upper += usize::from(p.z > s.centre.z);
            }
            let share = |k: usize| k as f64 / f64::from(n);
            // Half the area lies above the centre for both shapes.
            assert!((share(upper) - 0.5).abs() < 0.01, "{}", share(upper));
            if let SolidShape::Cylinder { half_height: h } = s.shape {
                // The caps' share of the area: 2πr² of 2πr(2h + r).
                let r = f64::from(s.radius);
                let want = r / (2.0 * f64::from(h) + r);
                assert!((share(caps) - want).abs() < 0.01, "{} {want}", share(caps));
                let total = 2.0 * std::f64::consts::PI * r * (2.0 * f64::from(h) + r);
                assert!((f64::from(s.area()) - total).abs() < 1e-5);
            }
        }
    }
}
