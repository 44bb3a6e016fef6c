//! Every camera's `ray_at` and `project` invert each other.

use std::f32::consts::{PI, TAU};

use natura_core::camera::{
    Eye, OrthographicCamera, PanoramicCamera, PinholeCamera, Projection, Ray, Stereo,
};
use natura_core::glam::{UVec2, Vec2, Vec3};
use proptest::prelude::*;

/// The cameras under test, behind one interface.
enum Cam {
    Pinhole(PinholeCamera),
    Ortho(OrthographicCamera),
    Pano(PanoramicCamera, f32),
}

impl Cam {
    fn resolution(&self) -> UVec2 {
        match self {
            Cam::Pinhole(c) => c.resolution(),
            Cam::Ortho(c) => c.resolution(),
            Cam::Pano(c, ..) => c.resolution(),
        }
    }
    fn ray_at(&self, p: Vec2) -> Ray {
        match self {
            Cam::Pinhole(c) => c.ray_at(p.x, p.y),
            Cam::Ortho(c) => c.ray_at(p.x, p.y),
            Cam::Pano(c, ..) => c.ray_at(p.x, p.y),
        }
    }
    fn project(&self, q: Vec3) -> Option<Vec2> {
        match self {
            Cam::Pinhole(c) => c.project(q),
            Cam::Ortho(c) => c.project(q),
            Cam::Pano(c, ..) => c.project(q),
        }
    }
    /// Columns after which a panorama repeats (`f32::INFINITY` if it does not).
    fn period(&self) -> f32 {
        match self {
            Cam::Pano(c, hfov) if *hfov > TAU => c.resolution().x as f32 * TAU / hfov,
            _ => f32::INFINITY,
        }
    }
    /// Whether the ray through `p` is well conditioned for inversion (a
    /// panorama's azimuth is undefined at the poles).
    fn well_conditioned(&self, p: Vec2) -> bool {
        match self {
            Cam::Pano(c, ..) => c.elevation(p.y).abs() < 1.4,
            _ => true,
        }
    }
}

#[derive(Clone, Debug)]
struct Setup {
    eye: Vec3,
    yaw: f32,
    pitch: f32,
    tilt: Vec2,
    size: (u32, u32),
    fov: f32,
    aspect: Option<f32>,
    view_height: f32,
    hfov: f32,
    stereo: Option<(bool, f32)>,
}

fn setup() -> impl Strategy<Value = Setup> {
    (
        (
            prop::array::uniform3(-100.0f32..100.0),
            -PI..PI,
            -1.2f32..1.2,
            prop::array::uniform2(-0.3f32..0.3),
            (1u32..=1024, 1u32..=1024),
        ),
        (
            0.2f32..2.8,
            prop::option::of(0.3f32..3.0),
            10.0f32..500.0,
            0.3f32..8.0,
            prop::option::of((any::<bool>(), 0.0f32..2.0)),
        ),
    )
        .prop_map(
            |((eye, yaw, pitch, tilt, size), (fov, aspect, view_height, hfov, stereo))| Setup {
                eye: Vec3::from(eye),
                yaw,
                pitch,
                tilt: Vec2::from(tilt),
                size,
                fov,
                aspect,
                view_height,
                hfov,
                stereo,
            },
        )
}

fn cameras(s: &Setup) -> Vec<Cam> {
    let look = Vec3::new(
        s.pitch.cos() * s.yaw.cos(),
        s.pitch.cos() * s.yaw.sin(),
        s.pitch.sin(),
    );
    let up = Vec3::new(s.tilt.x, s.tilt.y, 1.0);
    let target = s.eye + 50.0 * look;
    let (w, h) = s.size;
    let mut pin = PinholeCamera::look_at(s.eye, target, up, s.fov, w, h).unwrap();
    if let Some(a) = s.aspect {
        pin = pin.with_aspect(a).unwrap();
    }
    let ortho = OrthographicCamera::look_at(s.eye, target, up, s.view_height, w, h).unwrap();
    let mut out = vec![Cam::Pinhole(pin), Cam::Ortho(ortho)];
    for projection in [Projection::Cylindrical, Projection::Spherical] {
        let vfov = match projection {
            Projection::Cylindrical => s.fov,
            Projection::Spherical => s.fov * 1.1,
        };
        let mut pano =
            PanoramicCamera::new(s.eye, look, Vec3::Z, s.hfov, vfov, projection, w, h).unwrap();
        if let Some((left, separation)) = s.stereo {
            let eye = if left { Eye::Left } else { Eye::Right };
            pano = pano.with_stereo(Stereo { eye, separation }).unwrap();
        }
        out.push(Cam::Pano(pano, s.hfov));
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Pixel → ray → a point along it → `project` gives the pixel back; and a
    /// point in view → `project` → the ray there passes through the point:
    /// for the pinhole (square and explicit aspect), orthographic, and
    /// cylindrical and spherical panoramic cameras, mono and stereo.
    #[test]
    fn rays_and_projections_invert_each_other(
        s in setup(),
        pixel in prop::array::uniform2(0.0f32..1.0),
        t in 0.0f32..1.0,
        offset in prop::array::uniform3(-300.0f32..300.0),
    ) {
        for cam in cameras(&s) {
            let res = cam.resolution().as_vec2();
            let p = Vec2::from(pixel) * res;
            let ray = cam.ray_at(p);
            prop_assert!((ray.dir.length() - 1.0).abs() < 1e-5);
            if cam.well_conditioned(p) {
                let far = 20.0 + 1000.0 * t;
                let back = cam.project(ray.at(far));
                prop_assert!(back.is_some(), "{p} lost");
                let back = back.unwrap();
                let mut dx = (back.x - p.x).abs();
                let period = cam.period();
                if period.is_finite() {
                    dx = dx.rem_euclid(period);
                    dx = dx.min(period - dx);
                }
                let tol = 0.02;
                prop_assert!(
                    dx < tol && (back.y - p.y).abs() < tol,
                    "pixel {p} → {back} ({res})"
                );
            }
            let point = s.eye + Vec3::from(offset);
            let in_view = cam.project(point).filter(|q| {
                q.x > 0.0 && q.y > 0.0 && q.x < res.x && q.y < res.y && cam.well_conditioned(*q)
            });
            if let Some(q) = in_view {
                let r = cam.ray_at(q);
                let v = point - r.origin;
                let along = v.dot(r.dir);
                prop_assert!(along > -1e-3, "{point} behind the ray at {q}");
                let miss = (v - along * r.dir).length();
                prop_assert!(
                    miss < 1e-4 * v.length() + 1e-3,
                    "ray at {q} misses {point} by {miss}"
                );
            }
        }
    }
}
