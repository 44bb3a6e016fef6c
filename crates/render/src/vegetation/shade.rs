//! Light leaving a tree's surface: Lambertian bark, and leaves that reflect
//! on the lit side and transmit diffusely to the shaded side.
//!
//! A thin leaf scatters the sunlight it intercepts both ways: reflected with
//! albedo ρ into the hemisphere of the lit face and transmitted with τ into
//! the other, each as a Lambertian lobe (the bi-Lambertian leaf of canopy
//! radiative-transfer models; our values: transmitted light is yellower).
//! A viewer on the lit side sees ρ/π·E·cos θ; on the far side τ/π·E·|cos θ|.
//! Skylight reaches a crown's surface from above through gaps: the upper
//! half of the sky for the face looking up, scaled by a constant openness.

use glam::Vec3;

use natura_plant::eco::catalogue::Look;

/// Fraction of the sky a point on a crown's surface sees (the rest is the
/// crown itself and its neighbours): an own value.
pub const CROWN_OPENNESS: f32 = 0.6;

/// The light arriving at a tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Unit direction toward the sun.
    pub sun: Vec3,
    /// Sun irradiance on a surface facing it, linear RGB.
    pub sun_irradiance: Vec3,
    /// Sky irradiance on a horizontal surface, linear RGB.
    pub sky_irradiance: Vec3,
}

/// Radiance toward `-d` from a tree surface of unit geometric normal `n`
/// (either side), leaf or bark, with the sun visible or not; `transmission`
/// scales the leaf's transmitted colour.
#[must_use]
pub fn radiance(
    look: &Look,
    leaf: bool,
    n: Vec3,
    d: Vec3,
    light: &Light,
    sun_visible: bool,
    transmission: f32,
) -> Vec3 {
    // The face the viewer sees.
    let nf = if n.dot(d) < 0.0 { n } else { -n };
    let cos = nf.dot(light.sun);
    let up = 0.5 * (1.0 + nf.z);
    let inv_pi = std::f32::consts::FRAC_1_PI;
    if leaf {
        let rho = look.leaf;
        let tau = look.leaf_transmit * transmission;
        let mut l = (rho * up + tau * (1.0 - up)) * inv_pi * light.sky_irradiance * CROWN_OPENNESS;
        if sun_visible {
            let lobe = if cos >= 0.0 { rho } else { tau };
            l += lobe * inv_pi * light.sun_irradiance * cos.abs();
        }
        l
    } else {
        let rho = look.bark;
        let mut l = rho * inv_pi * light.sky_irradiance * up * CROWN_OPENNESS;
        if sun_visible && cos > 0.0 {
            l += rho * inv_pi * light.sun_irradiance * cos;
        }
        l
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn look() -> Look {
        Look {
            layer: natura_plant::eco::catalogue::Layer::Conifer,
            height_factor: 1.0,
            leaf: Vec3::splat(0.1),
            leaf_spring: Vec3::splat(0.1),
            leaf_autumn: Vec3::splat(0.1),
            leaf_transmit: Vec3::splat(0.5),
            bark: Vec3::splat(0.2),
        }
    }

    fn light() -> Light {
        Light {
            sun: Vec3::Z,
            sun_irradiance: Vec3::splat(std::f32::consts::PI),
            sky_irradiance: Vec3::ZERO,
        }
    }

    #[test]
    fn a_leaf_lit_from_behind_transmits() {
        // Viewer below a horizontal leaf, sun above: τ·E·|cos|/π = 0.5·0.4.
        let l = radiance(&look(), true, Vec3::Z, Vec3::Z, &light(), true, 0.4);
        approx::assert_relative_eq!(l.x, 0.2, epsilon = 1e-6);
        // Viewer above: the reflected ρ·E/π = 0.1, whichever way the normal points.
        let l = radiance(&look(), true, -Vec3::Z, -Vec3::Z, &light(), true, 0.4);
        approx::assert_relative_eq!(l.x, 0.1, epsilon = 1e-6);
        // Bark lit from behind is dark.
        let l = radiance(&look(), false, Vec3::Z, Vec3::Z, &light(), true, 0.4);
        assert_eq!(l, Vec3::ZERO);
    }

    #[test]
    fn shadow_removes_the_sun() {
        let l = radiance(&look(), true, Vec3::Z, -Vec3::Z, &light(), false, 0.4);
        assert_eq!(l, Vec3::ZERO);
    }
}
