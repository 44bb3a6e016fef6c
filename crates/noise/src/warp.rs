//! Domain distortion: warps of the evaluation point, and fields evaluated at
//! warped points (Musgrave 2001, "Domain Distortion"; Musgrave 1998,
//! "Distortion for Cirrus Clouds and Global Circulation"; Musgrave 1993, §5.2).

use glam::{DVec2, DVec3};

use crate::error::{NoiseError, Result};
use crate::field::Field;
use crate::vector::{DNoise, Smooth, VecNoise, VectorField};

/// A map of the domain `R³ → R³` (and `R² → R²`).
pub trait Warp: Send + Sync {
    /// The warped 3-D point.
    fn warp3(&self, p: DVec3) -> DVec3;
    /// The warped 2-D point.
    fn warp2(&self, p: DVec2) -> DVec2;
    /// A Lipschitz constant of the map (infinite if it has none).
    fn lipschitz(&self) -> f64;
}

/// Displacement by a vector field: `p ↦ a·p + s·V(p + shift)`.
///
/// With `a = 1` this is the general distortion `F(p + s·V(p))` of Musgrave
/// 2001, "Domain Distortion"; `shift` misregisters the lattices (the `+0.5` of
/// Musgrave 1993, §5.2, and Musgrave 1998, "A Variety of fBm"); `a ≠ 1` is the
/// dissertation C code's `scale`, which multiplies the point. (The
/// dissertation's pseudo-code for `VLNoise` adds `0.5` and has no scale, its C
/// code has the scale and no `0.5`; both forms are expressible here.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Displace<V> {
    /// The displacing vector field.
    pub field: V,
    /// `s`: displacement magnitude ("distortion").
    pub distortion: f64,
    /// `a`: scales the point before displacement.
    pub point_scale: f64,
    /// Added to the point where `V` is sampled.
    pub shift: DVec3,
}

impl<V: VectorField> Displace<V> {
    /// `p ↦ p + distortion·V(p)`.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] if `distortion` is NaN or infinite.
    pub fn new(field: V, distortion: f64) -> Result<Self> {
        if !distortion.is_finite() {
            return Err(NoiseError::InvalidParam {
                name: "distortion",
                value: distortion,
                expected: "must be finite",
            });
        }
        Ok(Self {
            field,
            distortion,
            point_scale: 1.0,
            shift: DVec3::ZERO,
        })
    }
}

impl<V: VectorField> Warp for Displace<V> {
    fn warp3(&self, p: DVec3) -> DVec3 {
        p * self.point_scale + self.field.eval3(p + self.shift) * self.distortion
    }
    fn warp2(&self, p: DVec2) -> DVec2 {
        p * self.point_scale + self.field.eval2(p + self.shift.truncate()) * self.distortion
    }
    fn lipschitz(&self) -> f64 {
        self.point_scale.abs() + self.distortion.abs() * self.field.lipschitz()
    }
}

/// How a [`Twist`] turns the point about the z axis.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum TwistLaw {
    /// Coriolis twist `θ = 2π·twist·r²` (Venus, Musgrave 1993, §5.4; Musgrave
    /// 1998, "The Coriolis Effect").
    Quadratic {
        /// Turns per unit r².
        twist: f64,
    },
    /// Cyclone: inside `r < R`, `θ = π + 2π·twist·(R − (R − r)^power)/R` (power
    /// 2 in Musgrave 1993, §5.3; power 3 in the `cyclone` listing of Musgrave
    /// 1998, "Distortion for Cirrus Clouds and Global Circulation"); identity
    /// outside. The warp is continuous at `r = R` only for `twist = ½` modulo 1
    /// (our derivation: the rim angle `θ(R) = π + 2π·twist` must be a multiple
    /// of 2π).
    Cyclone {
        /// `R`, the storm radius.
        max_radius: f64,
        /// Turns across the storm (½ in the sources).
        twist: f64,
        /// 2 (dissertation) or 3 (Texturing & Modeling).
        power: f64,
    },
}

/// Rotation of the point about the z axis by an angle depending on `r = |xy|`;
/// preserves `z` and `r`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Twist {
    law: TwistLaw,
}

impl Twist {
    /// A twist; refuses non-finite parameters, `R ≤ 0` and `power < 1`.
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] if the twist is NaN or infinite, or a maximum radius is not finite and positive.
    pub fn new(law: TwistLaw) -> Result<Self> {
        match law {
            TwistLaw::Quadratic { twist } => crate::error::finite("twist", twist)?,
            TwistLaw::Cyclone {
                max_radius,
                twist,
                power,
            } => {
                crate::error::finite("twist", twist)?;
                if !(max_radius.is_finite() && max_radius > 0.0) {
                    return Err(NoiseError::InvalidParam {
                        name: "max_radius",
                        value: max_radius,
                        expected: "must be finite and > 0",
                    });
                }
                crate::error::in_range("power", power, 1.0, 16.0, "must be in [1, 16]")?;
            }
        }
        Ok(Self { law })
    }

    /// The rotation angle at radius `r`.
    #[must_use]
    pub fn angle(&self, r: f64) -> f64 {
        use core::f64::consts::{PI, TAU};
        match self.law {
            TwistLaw::Quadratic { twist } => TAU * twist * r * r,
            TwistLaw::Cyclone {
                max_radius,
                twist,
                power,
            } => {
                if r < max_radius {
                    PI + TAU * twist * (max_radius - libm::pow(max_radius - r, power)) / max_radius
                } else {
                    0.0
                }
            }
        }
    }

    fn rotate(&self, x: f64, y: f64) -> (f64, f64) {
        let a = self.angle(libm::sqrt(x * x + y * y));
        let (s, c) = (libm::sin(a), libm::cos(a));
        (c * x - s * y, s * x + c * y)
    }
}

impl Warp for Twist {
    fn warp3(&self, p: DVec3) -> DVec3 {
        let (x, y) = self.rotate(p.x, p.y);
        DVec3::new(x, y, p.z)
    }
    fn warp2(&self, p: DVec2) -> DVec2 {
        let (x, y) = self.rotate(p.x, p.y);
        DVec2::new(x, y)
    }
    /// `1 + r·|θ′(r)|` where bounded; infinite for the unbounded quadratic law
    /// and for a cyclone that is discontinuous at its rim (twist ≠ ½).
    fn lipschitz(&self) -> f64 {
        use core::f64::consts::TAU;
        match self.law {
            TwistLaw::Quadratic { twist } => {
                if twist == 0.0 {
                    1.0
                } else {
                    f64::INFINITY
                }
            }
            TwistLaw::Cyclone {
                max_radius,
                twist,
                power,
            } => {
                let closes = libm::fmod(twist - 0.5, 1.0) == 0.0;
                if closes {
                    1.0 + TAU * twist.abs() * power * libm::pow(max_radius, power - 1.0)
                } else {
                    f64::INFINITY
                }
            }
        }
    }
}

/// A field evaluated at warped points: `F(W(p))`. Bound of `F`; Lipschitz
/// `L_F·L_W`; gradient by central differences (the warps have no analytic Jacobian).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Warped<F, W> {
    /// The field.
    pub field: F,
    /// The warp applied to its argument.
    pub warp: W,
}

impl<F: Field, W: Warp> Field for Warped<F, W> {
    fn eval2(&self, p: DVec2) -> f64 {
        self.field.eval2(self.warp.warp2(p))
    }
    fn eval3(&self, p: DVec3) -> f64 {
        self.field.eval3(self.warp.warp3(p))
    }
    fn bound(&self) -> f64 {
        self.field.bound()
    }
    fn lipschitz2(&self) -> f64 {
        self.field.lipschitz2() * self.warp.lipschitz()
    }
    fn lipschitz3(&self) -> f64 {
        self.field.lipschitz3() * self.warp.lipschitz()
    }
}

/// Musgrave's `DistNoise(p, d) = N(p + d·VecNoise(p + ½))` (Musgrave 1998, "A
/// Variety of fBm"): "variable lacunarity" noise with stringy, wispy features;
/// four evaluations of `N` in 3-D (three of them for `VecNoise`), three in
/// 2-D. The chapter's RenderMan version offsets the point by the scalar
/// `snoise` (the same offset on all three axes, a diagonal shift rather than
/// a distortion); that slip is not reproduced: the vector `VecNoise` is used,
/// as in the C version.
pub type DistNoise<B> = Warped<B, Displace<VecNoise<B>>>;

/// The dissertation's C `VLNoise(p, scale) = N(scale·p + DNoise(p))` (Musgrave
/// 1993, §5.2). This follows the C code, not the section's pseudo-code, which
/// adds a `+0.5` misregistration and no scale: `scale` multiplies the point.
pub type VlNoise<B> = Warped<B, Displace<DNoise<B>>>;

impl<B: Field + Clone> DistNoise<B> {
    /// `DistNoise` of `basis` with distortion `d` (`d = 0` is `basis` itself).
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] if `d` is NaN or infinite.
    pub fn dist_noise(basis: B, d: f64) -> Result<Self> {
        let mut warp = Displace::new(VecNoise::new(basis.clone()), d)?;
        warp.shift = DVec3::splat(0.5);
        Ok(Warped { field: basis, warp })
    }
}

impl<B: Smooth + Clone> VlNoise<B> {
    /// The C `VLNoise` of `basis` with point scale `scale` (1.0 in `VLfBm`, 1.5 in `MVfBm`).
    ///
    /// # Errors
    /// [`NoiseError::InvalidParam`] if `scale` is NaN or infinite.
    pub fn vl_noise(basis: B, scale: f64) -> Result<Self> {
        crate::error::finite("scale", scale)?;
        let mut warp = Displace::new(DNoise(basis.clone()), 1.0)?;
        warp.point_scale = scale;
        Ok(Warped { field: basis, warp })
    }
}
