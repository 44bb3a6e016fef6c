//! `Dir3`: a unit direction that can only be built from a vector that
//! normalises, so no model ever silently uses a zero, NaN or unnormalised
//! direction.

use glam::{DVec3, Vec3};

use crate::error::{AtmosError, Result};

/// A unit vector in the world frame (z up), stored in `f64`.
///
/// Built with [`Dir3::new`], which normalises any finite non-zero vector and
/// refuses the rest with [`AtmosError::BadDirection`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Dir3(DVec3);

impl Dir3 {
    /// Straight up (+z).
    pub const UP: Dir3 = Dir3(DVec3::Z);
    /// Straight down (−z).
    pub const DOWN: Dir3 = Dir3(DVec3::NEG_Z);
    /// +x.
    pub const X: Dir3 = Dir3(DVec3::X);
    /// +y.
    pub const Y: Dir3 = Dir3(DVec3::Y);

    /// Returns `v / |v|`, or [`AtmosError::BadDirection`] if `v` is zero, NaN or infinite.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::BadDirection`] if `v` is zero, NaN or infinite.
    pub fn new(v: DVec3) -> Result<Self> {
        Self::named("direction", v)
    }

    /// Like [`Dir3::new`], naming the argument `name` in the error.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::BadDirection`] naming `name` if `v` is zero, NaN or infinite.
    pub fn named(name: &'static str, v: DVec3) -> Result<Self> {
        // Scale by the largest component first so tiny and huge vectors neither
        // underflow nor overflow when squared.
        let m = v.abs().max_element();
        if v.is_finite() && m > 0.0 {
            let w = v / m;
            let u = w / w.length();
            if u.is_finite() {
                return Ok(Dir3(u));
            }
        }
        Err(AtmosError::BadDirection {
            name,
            value: format!("{v}"),
        })
    }

    /// Returns the normalised `f32` vector `v` as a direction (see [`Dir3::new`]).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::BadDirection`] if `v` is zero, NaN or infinite.
    pub fn from_f32(v: Vec3) -> Result<Self> {
        Self::new(v.as_dvec3())
    }

    /// The direction with elevation `elevation` above the x–y plane and azimuth
    /// `azimuth` counter-clockwise from +x (radians).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`] naming `elevation` or `azimuth`
    /// if it is NaN or infinite.
    pub fn from_angles(elevation: f64, azimuth: f64) -> Result<Self> {
        crate::error::finite("elevation", elevation)?;
        crate::error::finite("azimuth", azimuth)?;
        let (se, ce) = elevation.sin_cos();
        let (sa, ca) = azimuth.sin_cos();
        // Exactly unit up to rounding; renormalise so |d| = 1 to the last bit.
        let v = DVec3::new(ce * ca, ce * sa, se);
        Ok(Dir3(v / v.length()))
    }

    /// The unit vector.
    #[inline]
    #[must_use]
    pub fn get(self) -> DVec3 {
        self.0
    }

    /// The unit vector in `f32`.
    #[inline]
    #[must_use]
    pub fn as_vec3(self) -> Vec3 {
        self.0.as_vec3()
    }

    /// The opposite direction.
    #[inline]
    #[must_use]
    pub fn reversed(self) -> Self {
        Dir3(-self.0)
    }

    /// The cosine of the angle to `other`.
    #[inline]
    #[must_use]
    pub fn dot(self, other: Dir3) -> f64 {
        self.0.dot(other.0).clamp(-1.0, 1.0)
    }

    /// Elevation above the x–y plane, radians in `[−π/2, π/2]`.
    #[inline]
    #[must_use]
    pub fn elevation(self) -> f64 {
        self.0.z.clamp(-1.0, 1.0).asin()
    }
}

impl From<Dir3> for DVec3 {
    fn from(d: Dir3) -> DVec3 {
        d.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalises_and_refuses() {
        let d = Dir3::new(DVec3::new(3.0, 0.0, 4.0)).unwrap();
        assert!((d.get().length() - 1.0).abs() < 1e-15);
        assert_eq!(d.get(), DVec3::new(0.6, 0.0, 0.8));
        for bad in [
            DVec3::ZERO,
            DVec3::new(f64::NAN, 0.0, 1.0),
            DVec3::new(f64::INFINITY, 0.0, 0.0),
        ] {
            assert!(matches!(
                Dir3::new(bad),
                Err(AtmosError::BadDirection { .. })
            ));
        }
        // Tiny but non-zero vectors still normalise.
        let t = Dir3::new(DVec3::new(1e-300, 0.0, 0.0)).unwrap();
        assert_eq!(t.get(), DVec3::X);
        let a = Dir3::from_angles(0.3, 1.2).unwrap();
        assert!((a.elevation() - 0.3).abs() < 1e-14);
        // Non-finite angles are refused by name instead of giving a NaN direction.
        for (el, az, name) in [
            (f64::NAN, 0.0, "elevation"),
            (0.0, f64::INFINITY, "azimuth"),
        ] {
            let e = Dir3::from_angles(el, az).unwrap_err().to_string();
            assert!(e.contains(name), "{e}");
        }
    }
}
