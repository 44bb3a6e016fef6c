//! Musgrave's planar mirage: one horizontal index discontinuity, with
//! Fresnel reflection, refraction and total internal reflection.

use glam::DVec3;

use super::air::StratifiedAir;
use crate::Dir3;
use crate::error::{Result, finite, positive};
use crate::optics::{fresnel, reflect, refract};

/// What happens when a ray meets Musgrave's mirage plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interaction {
    /// Where the ray meets the plane.
    pub point: DVec3,
    /// The reflected direction.
    pub reflected: Dir3,
    /// The refracted direction, `None` on total internal reflection.
    pub refracted: Option<Dir3>,
    /// Unpolarised Fresnel reflectance (1 on TIR).
    pub reflectance: f64,
}

/// Musgrave's mirage: a horizontal plane at `height_m` separating air of index
/// `n_above` from hotter, optically thinner air `n_below` (Musgrave 1993, §1.2.4.4, §4.3.2).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PlanarMirage {
    height_m: f64,
    n_above: f64,
    n_below: f64,
}

impl PlanarMirage {
    /// A mirage plane; refuses NaN heights and non-positive indices.
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) for a NaN height or a non-positive or NaN index.
    pub fn new(height_m: f64, n_above: f64, n_below: f64) -> Result<Self> {
        finite("height_m", height_m)?;
        crate::optics::check_ior("n_above", n_above)?;
        crate::optics::check_ior("n_below", n_below)?;
        Ok(Self {
            height_m,
            n_above,
            n_below,
        })
    }

    /// The plane from air temperatures above and below (Gladstone–Dale at `pressure_pa`).
    ///
    /// # Errors
    ///
    /// Returns [`AtmosError::InvalidParameter`](crate::AtmosError::InvalidParameter) if a temperature or the pressure is not finite and
    /// positive.
    pub fn from_temperatures(
        height_m: f64,
        above_k: f64,
        below_k: f64,
        pressure_pa: f64,
    ) -> Result<Self> {
        positive("above_k", above_k)?;
        positive("below_k", below_k)?;
        positive("pressure_pa", pressure_pa)?;
        Self::new(
            height_m,
            StratifiedAir::index_of(above_k, pressure_pa),
            StratifiedAir::index_of(below_k, pressure_pa),
        )
    }

    /// The critical *grazing* angle (from the plane) below which rays from
    /// above are totally reflected: `arccos(n_below/n_above)`, or `None` if
    /// the lower layer is not thinner.
    #[must_use]
    pub fn critical_grazing_angle(&self) -> Option<f64> {
        (self.n_below < self.n_above).then(|| (self.n_below / self.n_above).acos())
    }

    /// Intersects the ray with the plane and splits it there. `bump`, if given,
    /// is the perturbed (e.g. fBm-bumped) unit normal at the hit point; it is
    /// oriented to face the incoming ray. `None` if the ray never meets the plane.
    #[must_use]
    pub fn interact(&self, origin: DVec3, dir: Dir3, bump: Option<Dir3>) -> Option<Interaction> {
        let d = dir.get();
        if d.z == 0.0 {
            return None;
        }
        let t = (self.height_m - origin.z) / d.z;
        if t.is_nan() || t <= 0.0 {
            return None;
        }
        let point = origin + d * t;
        let from_above = d.z < 0.0;
        let (n1, n2) = if from_above {
            (self.n_above, self.n_below)
        } else {
            (self.n_below, self.n_above)
        };
        let mut normal = bump.unwrap_or(Dir3::UP);
        if normal.get().dot(d) > 0.0 {
            normal = normal.reversed();
        }
        let cos_i = -normal.get().dot(d);
        let f = fresnel(n1, n2, cos_i);
        Some(Interaction {
            point,
            reflected: reflect(dir, normal),
            refracted: refract(dir, normal, n1 / n2),
            reflectance: f.unpolarized(),
        })
    }
}
