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
//! Through the same gaps the lit ground around the tree lights it from
//! below ([`Light::bounced`]), the face looking down most. Under a low sun
//! this is as much light as the sky gives a crown's shaded side: without
//! it the shade is crushed to black, and every lit needle tip in it shows
//! as a lone bright speck.

use glam::Vec3;

use natura_plant::eco::catalogue::Look;

/// Fraction of the sky a point on a crown's surface sees (the rest is the
/// crown itself and its neighbours): an own value.
pub const CROWN_OPENNESS: f32 = 0.6;

/// Albedo of the ground around a surface, which lights it from below
/// (grass, soil and rock in sun and shade): an own value.
pub const SURROUNDINGS_ALBEDO: f32 = 0.25;

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

impl Light {
    /// Irradiance a surface facing straight down receives from the lit
    /// ground around it: [`SURROUNDINGS_ALBEDO`] times the sun's and the
    /// sky's irradiance on the horizontal, the ground seen as a
    /// Lambertian plane. A face of unit normal `n` receives `(1 − n_z)/2`
    /// of it, as it sees `(1 + n_z)/2` of the sky's.
    #[must_use]
    pub fn bounced(&self) -> Vec3 {
        SURROUNDINGS_ALBEDO * (self.sun_irradiance * self.sun.z.max(0.0) + self.sky_irradiance)
    }
}

/// Radiance toward `-d` from a tree surface of unit geometric normal `n`
/// (either side), leaf or bark, with the share `sun_visible` of the sun's
/// light reaching it (0 in shadow, 1 in full sun); `transmission` scales
/// the leaf's transmitted colour.
#[must_use]
pub fn radiance(
    look: &Look,
    leaf: bool,
    n: Vec3,
    d: Vec3,
    light: &Light,
    sun_visible: f32,
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
        // Sky from above and the ground's light from below, each on the
        // face it reaches and through the leaf to the other.
        let sky = light.sky_irradiance * CROWN_OPENNESS;
        let ground = light.bounced() * CROWN_OPENNESS;
        let mut l =
            ((rho * up + tau * (1.0 - up)) * sky + (rho * (1.0 - up) + tau * up) * ground) * inv_pi;
        if sun_visible > 0.0 {
            let lobe = if cos >= 0.0 { rho } else { tau };
            l += lobe * inv_pi * light.sun_irradiance * (cos.abs() * sun_visible);
        }
        l
    } else {
        let rho = look.bark;
        let mut l = rho
            * inv_pi
            * (light.sky_irradiance * up + light.bounced() * (1.0 - up))
            * CROWN_OPENNESS;
        if sun_visible > 0.0 && cos > 0.0 {
            l += rho * inv_pi * light.sun_irradiance * (cos * sun_visible);
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
        // The ground's light from below, through the crown's openness, in
        // units of E/π: 0.25·0.6.
        let b = SURROUNDINGS_ALBEDO * CROWN_OPENNESS;
        // Viewer below a horizontal leaf, sun above: τ·E·|cos|/π = 0.5·0.4,
        // and the ground's light reflected by the face looking down, ρ·b.
        let l = radiance(&look(), true, Vec3::Z, Vec3::Z, &light(), 1.0, 0.4);
        approx::assert_relative_eq!(l.x, 0.2 + 0.1 * b, epsilon = 1e-6);
        // Viewer above: the reflected ρ·E/π = 0.1, whichever way the normal
        // points, and the ground's light passed through the leaf, τ·b.
        let l = radiance(&look(), true, -Vec3::Z, -Vec3::Z, &light(), 1.0, 0.4);
        approx::assert_relative_eq!(l.x, 0.1 + 0.2 * b, epsilon = 1e-6);
        // Bark lit from behind has only the ground's light.
        let l = radiance(&look(), false, Vec3::Z, Vec3::Z, &light(), 1.0, 0.4);
        approx::assert_relative_eq!(l.x, 0.2 * b, epsilon = 1e-6);
    }

    #[test]
    fn shadow_removes_the_sun() {
        // The sun straight up, no sky: a leaf looking up gets no bounce
        // either (the ground's light reaches the face looking down, which
        // transmits with τ = 0 here).
        let mut lk = look();
        lk.leaf_transmit = Vec3::ZERO;
        let l = radiance(&lk, true, Vec3::Z, -Vec3::Z, &light(), 0.0, 0.4);
        assert_eq!(l, Vec3::ZERO);
    }

    #[test]
    fn the_ground_lights_the_shade_from_below() {
        // Sun straight up (E = π), no sky: the ground's albedo returns
        // 0.25·π from below; through the crown's openness 0.6 of it.
        let e = SURROUNDINGS_ALBEDO * std::f32::consts::PI * CROWN_OPENNESS;
        approx::assert_relative_eq!(
            light().bounced().x,
            SURROUNDINGS_ALBEDO * std::f32::consts::PI
        );
        // A shaded leaf looking down, seen from below: ρ·E/π.
        let l = radiance(&look(), true, Vec3::Z, Vec3::Z, &light(), 0.0, 1.0);
        approx::assert_relative_eq!(l.x, 0.1 * e / std::f32::consts::PI, epsilon = 1e-6);
        // The same leaf seen from above: the light it passes, τ·E/π.
        let l = radiance(&look(), true, Vec3::Z, -Vec3::Z, &light(), 0.0, 1.0);
        approx::assert_relative_eq!(l.x, 0.5 * e / std::f32::consts::PI, epsilon = 1e-6);
        // Vertical bark in shade: half of it, ρ·E/(2π).
        let l = radiance(&look(), false, Vec3::X, -Vec3::X, &light(), 0.0, 1.0);
        approx::assert_relative_eq!(l.x, 0.2 * e / (2.0 * std::f32::consts::PI), epsilon = 1e-6);
    }
}
