//! Normals for bump and displacement maps: finite-difference gradients of a
//! height function and the perturbed normal they give.

use glam::DVec3;

/// The gradient of `f` at `p` by central differences with step `h`.
#[must_use]
pub fn gradient_fd(f: impl Fn(DVec3) -> f64, p: DVec3, h: f64) -> DVec3 {
    let d = |e: DVec3| (f(p + e * h) - f(p - e * h)) / (2.0 * h);
    DVec3::new(d(DVec3::X), d(DVec3::Y), d(DVec3::Z))
}

/// The normal of a surface with unit normal `n` displaced along `n` by a
/// height field whose gradient is `grad`: `normalize(n − (grad − (grad·n)·n))`
/// (only the tangential part of the gradient tilts the normal). Returns `n`
/// if the result would not normalise.
#[must_use]
pub fn bump(n: DVec3, grad: DVec3) -> DVec3 {
    let tangential = grad - n * grad.dot(n);
    (n - tangential).try_normalize().unwrap_or(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_of_a_plane_and_a_tilted_normal() {
        let g = gradient_fd(|p| 2.0 * p.x - 3.0 * p.z, DVec3::new(0.3, 1.0, 2.0), 1e-3);
        assert!((g - DVec3::new(2.0, 0.0, -3.0)).length() < 1e-9);
        // A ramp h = x on the plane z = 0 tilts the normal by 45°.
        let n = bump(DVec3::Z, DVec3::X);
        assert!((n - DVec3::new(-1.0, 0.0, 1.0).normalize()).length() < 1e-12);
        // The normal component of the gradient does not tilt it.
        assert_eq!(bump(DVec3::Z, DVec3::Z * 5.0), DVec3::Z);
    }
}
