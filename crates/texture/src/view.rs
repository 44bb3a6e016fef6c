//! Views and ray geometry in `f64` world space: a pinhole view whose eye
//! stays exact at planetary distances, and ray–sphere and ray–plane tests.

use glam::{DVec3, Vec3};
use natura_core::camera::PinholeCamera;

use crate::error::{Result, direction, invalid};

/// A pinhole view: eye position in `f64` (a planet-scale coordinate stays
/// exact) with the ray directions of natura-core's [`PinholeCamera`] set
/// up at the origin, so only directions pass through `f32`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    eye: DVec3,
    camera: PinholeCamera,
    pixel_angle: f64,
}

impl View {
    /// A view from `eye` towards `target` with up hint `up`, vertical field
    /// of view `vfov` (radians, in `(0, π)`) and a `width × height` image.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) for a non-finite eye or target,
    /// `eye == target`, an `up` parallel to the view, a bad field of view or
    /// resolution (natura-core's camera checks).
    pub fn look_at(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        vfov: f64,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        if !eye.is_finite() || !target.is_finite() {
            return Err(invalid("eye", eye, "eye and target must be finite"));
        }
        let forward = direction("target − eye", target - eye)?.normalize();
        let up = direction("up", up)?.normalize();
        let camera = PinholeCamera::look_at(
            Vec3::ZERO,
            forward.as_vec3(),
            up.as_vec3(),
            vfov as f32,
            width,
            height,
        )?;
        Ok(Self {
            eye,
            camera,
            pixel_angle: vfov / f64::from(height),
        })
    }

    /// The eye.
    #[must_use]
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// Image width, pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.camera.resolution().x
    }

    /// Image height, pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.camera.resolution().y
    }

    /// The angle one pixel subtends at the image centre, radians: a ray's
    /// footprint at distance `t` is `t·pixel_angle`.
    #[must_use]
    pub fn pixel_angle(&self) -> f64 {
        self.pixel_angle
    }

    /// The unit direction through continuous pixel coordinates `(px, py)`
    /// (`(0, 0)` the top-left corner).
    #[must_use]
    pub fn direction(&self, px: f64, py: f64) -> DVec3 {
        self.camera
            .ray_at(px as f32, py as f32)
            .dir
            .as_dvec3()
            .normalize()
    }

    /// The unit direction through the centre of pixel `(x, y)`.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> DVec3 {
        self.direction(f64::from(x) + 0.5, f64::from(y) + 0.5)
    }
}

/// The parameters `t0 ≤ t1` where the line `o + t·d` (unit `d`) meets the
/// sphere of radius `r` about the origin, computed without cancellation.
#[must_use]
pub fn sphere_hits(o: DVec3, d: DVec3, r: f64) -> Option<(f64, f64)> {
    let b = o.dot(d);
    // |o|² − r² as (|o| − r)(|o| + r), exact-ish at planetary radii.
    let ol = o.length();
    let c = (ol - r) * (ol + r);
    // Discriminant from the perpendicular distance, stable for distant eyes.
    let perp2 = (o - d * b).length_squared();
    let disc = r * r - perp2;
    if disc < 0.0 || !disc.is_finite() {
        return None;
    }
    let s = disc.sqrt();
    // Stable roots of t² + 2bt + c = 0.
    let q = -b - b.signum() * s;
    let (t0, t1) = if q == 0.0 {
        (-s, s)
    } else {
        let a = q;
        let b2 = c / q;
        (a.min(b2), a.max(b2))
    };
    Some((t0, t1))
}

/// The parameter where the line `o + t·d` crosses the plane `z = 0`, if it
/// is not parallel to it.
#[must_use]
pub fn equator_plane_hit(o: DVec3, d: DVec3) -> Option<f64> {
    (d.z != 0.0).then(|| -o.z / d.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_hits_from_far_away_are_accurate() {
        let r = 6.371e6;
        let o = DVec3::new(0.0, 0.0, 3.0 * r);
        let d = -DVec3::Z;
        let (t0, t1) = sphere_hits(o, d, r).unwrap();
        assert!((t0 - 2.0 * r).abs() < 1e-6 && (t1 - 4.0 * r).abs() < 1e-6);
        let inside = DVec3::new(0.0, r - 1.0, 0.0);
        let (a, b) = sphere_hits(inside, DVec3::Y, r).unwrap();
        assert!(a < 0.0 && (b - 1.0).abs() < 1e-6);
        assert!(sphere_hits(o, DVec3::X, r).is_none());
        assert_eq!(
            equator_plane_hit(DVec3::new(1.0, 2.0, 4.0), DVec3::new(0.0, 0.0, -2.0)),
            Some(2.0)
        );
        assert_eq!(equator_plane_hit(DVec3::ONE, DVec3::X), None);
    }

    #[test]
    fn view_directions_are_unit_and_centred() {
        let v = View::look_at(
            DVec3::new(0.0, -3.0, 0.0),
            DVec3::ZERO,
            DVec3::Z,
            0.5,
            64,
            32,
        )
        .unwrap();
        let c = v.direction(32.0, 16.0);
        assert!((c - DVec3::Y).length() < 1e-6);
        assert!((v.pixel(0, 0).length() - 1.0).abs() < 1e-12);
        assert!((v.pixel_angle() - 0.5 / 32.0).abs() < 1e-15);
        assert!(View::look_at(DVec3::ZERO, DVec3::ZERO, DVec3::Z, 0.5, 8, 8).is_err());
        assert!(View::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 0.5, 0, 8).is_err());
        assert!(View::look_at(DVec3::NAN, DVec3::X, DVec3::Z, 0.5, 8, 8).is_err());
    }
}
