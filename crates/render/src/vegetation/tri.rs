//! Ray–triangle intersection: the one equation both the BVH path and the
//! brute-force path call.
//!
//! Möller & Trumbore 1997, §2 (the solution by Cramer's rule): with edges `e1 = v1 − v0`,
//! `e2 = v2 − v0`, `p = d × e2`, `s = o − v0`, `q = s × e1` and
//! `det = e1 · p`, the barycentric coordinates are `u = (s · p) / det`,
//! `v = (d · q) / det` and the distance `t = (e2 · q) / det`. Both faces
//! count (leaves are seen from both sides).

use glam::Vec3;

/// The ray parameter `t ∈ (t_min, t_max)` where the ray `o + t·d` crosses
/// the triangle `v`, or `None` (also for rays in its plane).
#[inline]
#[must_use]
pub fn intersect(o: Vec3, d: Vec3, v: &[Vec3; 3], t_min: f32, t_max: f32) -> Option<f32> {
    let e1 = v[1] - v[0];
    let e2 = v[2] - v[0];
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - v[0];
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let w = d.dot(q) * inv;
    if w < 0.0 || u + w > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > t_min && t < t_max).then_some(t)
}

/// Barycentric weights `(w0, w1, w2)` of the point `p` (in the plane of
/// triangle `v`, as a hit is): the solution of `p = w0·v0 + w1·v1 + w2·v2`,
/// `w0 + w1 + w2 = 1`, by the normal equations of the two edges; clamped to
/// the triangle and renormalised against rounding. A degenerate triangle
/// gives its first corner.
#[must_use]
pub fn barycentric(p: Vec3, v: &[Vec3; 3]) -> [f32; 3] {
    let (e1, e2, w) = (v[1] - v[0], v[2] - v[0], p - v[0]);
    let (d00, d01, d11) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d20, d21) = (w.dot(e1), w.dot(e2));
    let den = d00 * d11 - d01 * d01;
    if den <= 0.0 || !den.is_finite() {
        return [1.0, 0.0, 0.0];
    }
    let b1 = ((d11 * d20 - d01 * d21) / den).clamp(0.0, 1.0);
    let b2 = ((d00 * d21 - d01 * d20) / den).clamp(0.0, 1.0);
    let s = (b1 + b2).max(1.0);
    let (b1, b2) = (b1 / s, b2 / s);
    [1.0 - b1 - b2, b1, b2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn barycentric_weights_rebuild_the_point() {
        let v = [
            Vec3::new(1.0, 0.0, 2.0),
            Vec3::new(4.0, 1.0, 2.0),
            Vec3::new(2.0, 5.0, 3.0),
        ];
        let w = [0.2, 0.5, 0.3];
        let p = v[0] * w[0] + v[1] * w[1] + v[2] * w[2];
        let b = barycentric(p, &v);
        for k in 0..3 {
            approx::assert_relative_eq!(b[k], w[k], epsilon = 1e-5);
        }
        // At a corner, that corner alone.
        assert_eq!(barycentric(v[1], &v), [0.0, 1.0, 0.0]);
    }

    const T: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

    #[test]
    fn hits_inside_from_both_sides() {
        let t = intersect(Vec3::new(0.2, 0.2, 2.0), -Vec3::Z, &T, 0.0, 10.0).unwrap();
        approx::assert_relative_eq!(t, 2.0);
        let t = intersect(Vec3::new(0.2, 0.2, -3.0), Vec3::Z, &T, 0.0, 10.0).unwrap();
        approx::assert_relative_eq!(t, 3.0);
    }

    #[test]
    fn misses_outside_behind_and_beyond() {
        assert!(intersect(Vec3::new(0.8, 0.8, 2.0), -Vec3::Z, &T, 0.0, 10.0).is_none());
        assert!(intersect(Vec3::new(0.2, 0.2, 2.0), Vec3::Z, &T, 0.0, 10.0).is_none());
        assert!(intersect(Vec3::new(0.2, 0.2, 2.0), -Vec3::Z, &T, 0.0, 1.5).is_none());
        // In the triangle's plane.
        assert!(intersect(Vec3::new(-1.0, 0.2, 0.0), Vec3::X, &T, 0.0, 10.0).is_none());
    }

    #[test]
    fn a_scaled_direction_scales_t() {
        let t = intersect(Vec3::new(0.2, 0.2, 2.0), -Vec3::Z * 4.0, &T, 0.0, 10.0).unwrap();
        approx::assert_relative_eq!(t, 0.5);
    }
}
