//! Every camera's `ray_at` and `project` invert each other.

use std::f32::consts::{PI, TAU};

use natura_core::camera::{
    Eye, FisheyeCamera, OrthographicCamera, PanoramicCamera, PinholeCamera, Projection, Ray, Stereo,
};
use natura_core::glam::{UVec2, Vec2, Vec3};
use proptest::prelude::*;

/// The cameras under test, behind one interface.
enum Cam {
    Pinhole(PinholeCamera),
    Ortho(OrthographicCamera),
    Pano(PanoramicCamera, f32),
    Fish(FisheyeCamera),
}

impl Cam {
    fn resolution(&self) -> UVec2 {
        match self {
            Cam::Pinhole(c) => c.resolution(),
            Cam::Ortho(c) => c.resolution(),
            Cam::Pano(c, ..) => c.resolution(),
            Cam::Fish(c) => c.resolution(),
        }
    }
    fn ray_at(&self, p: Vec2) -> Ray {
        match self {
            Cam::Pinhole(c) => c.ray_at(p.x, p.y),
            Cam::Ortho(c) => c.ray_at(p.x, p.y),
            Cam::Pano(c, ..) => c.ray_at(p.x, p.y),
            Cam::Fish(c) => c.ray_at(p.x, p.y),
        }
    }
    fn project(&self, q: Vec3) -> Option<Vec2> {
        match self {
            Cam::Pinhole(c) => c.project(q),
            Cam::Ortho(c) => c.project(q),
            Cam::Pano(c, ..) => c.project(q),
            Cam::Fish(c) => c.project(q),
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
    /// panorama's azimuth is undefined at the poles; a fisheye sees nothing
    /// outside its circle, and its direction of view is ill defined where
    /// its field meets the point straight behind).
    fn kind(&self) -> &'static str {
        match self {
            Cam::Pinhole(..) => "pinhole",
            Cam::Ortho(..) => "orthographic",
            Cam::Pano(..) => "panoramic",
            Cam::Fish(..) => "fisheye",
        }
    }
    fn well_conditioned(&self, p: Vec2) -> bool {
        match self {
            // Within 85° of the axis. A screen wider than that (a horizontal
            // field of view near 180°, from a tall vertical one on a wide
            // image) divides by the point's depth along the axis, a few
            // thousandths of its distance at the edge, and the point's own
            // f32 rounding moves the projection by hundredths of a pixel.
            Cam::Pinhole(c) => c.ray_at(p.x, p.y).dir.dot(c.direction()) > 85f32.to_radians().cos(),
            Cam::Pano(c, ..) => c.elevation(p.y).abs() < 1.4,
            Cam::Fish(c) => {
                let ray = c.ray_at(p.x, p.y);
                ray.is_valid() && ray.dir.dot(c.direction()) > -0.95
            }
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
    centre: f32,
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
            -0.8f32..0.8,
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
            |((eye, yaw, pitch, tilt, size, centre), (fov, aspect, view_height, hfov, stereo))| {
                Setup {
                    eye: Vec3::from(eye),
                    yaw,
                    pitch,
                    tilt: Vec2::from(tilt),
                    centre,
                    size,
                    fov,
                    aspect,
                    view_height,
                    hfov,
                    stereo,
                }
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
        let mut pano = PanoramicCamera::new(s.eye, look, Vec3::Z, s.hfov, vfov, projection, w, h)
            .unwrap()
            .with_elevation_centre(s.centre)
            .unwrap();
        if let Some((left, separation)) = s.stereo {
            let eye = if left { Eye::Left } else { Eye::Right };
            pano = pano.with_stereo(Stereo { eye, separation }).unwrap();
        }
        out.push(Cam::Pano(pano, s.hfov));
    }
    let fish = FisheyeCamera::new(s.eye, look, up, 1.2 * s.fov + 0.2 * s.hfov, w, h).unwrap();
    out.push(Cam::Fish(fish));
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Pixel → ray → a point along it → `project` gives the pixel back; and a
    /// point in view → `project` → the ray there passes through the point:
    /// for the pinhole (square and explicit aspect), orthographic,
    /// cylindrical and spherical panoramic cameras (mono and stereo, the
    /// screen shifted up or down) and the fisheye.
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
            let outside_circle = matches!(cam, Cam::Fish(_)) && !ray.is_valid();
            prop_assert!(outside_circle || (ray.dir.length() - 1.0).abs() < 1e-5);
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
                    "{}: pixel {p} → {back} ({res})",
                    cam.kind()
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
                prop_assert!(
                    along > -1e-3,
                    "{}: {point} behind the ray at {q}",
                    cam.kind()
                );
                let miss = (v - along * r.dir).length();
                // Plus the f32 rounding of the positions involved, the
                // screen's among them: an orthographic screen 224 km wide
                // (527 × 1 pixels of 425 m) places its rays' origins to
                // millimetres, a ten-thousandth of a pixel.
                let mut scale = (r.origin - s.eye).length() + (point - s.eye).length();
                if matches!(cam, Cam::Ortho(_)) {
                    scale += s.view_height * res.x / res.y;
                }
                prop_assert!(
                    miss < 1e-4 * v.length() + 1e-3 + 8.0 * f32::EPSILON * scale,
                    "{}: ray at {q} misses {point} by {miss} (from {}, along {})",
                    cam.kind(),
                    r.origin,
                    r.dir
                );
            }
        }
    }
}

/// The fisheye's centre looks along the view direction, the inscribed
/// circle at half the field from it, linearly in between (equidistant), and
/// the corners see nothing.
#[test]
fn fisheye_is_equidistant_and_circular() {
    let (w, h) = (300u32, 200u32);
    let cam = FisheyeCamera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, PI, w, h).unwrap();
    let centre = cam.ray_at(150.0, 100.0);
    assert!((centre.dir - Vec3::Z).length() < 1e-6);
    for k in 0..=10 {
        let r = k as f32 / 10.0;
        // Straight up in the picture: towards the up vector (+y).
        let ray = cam.ray_at(150.0, 100.0 - 100.0 * r);
        let theta = ray.dir.dot(Vec3::Z).clamp(-1.0, 1.0).acos();
        assert!((theta - r * PI / 2.0).abs() < 1e-5, "r {r}: θ {theta}");
        assert!(ray.dir.x.abs() < 1e-6 && ray.dir.y >= 0.0);
    }
    // Right in the picture is the camera's right: looking up with north (+y)
    // up, that is west (−x).
    let right = cam.ray_at(250.0, 100.0);
    assert!((right.dir - Vec3::NEG_X).length() < 1e-5, "{}", right.dir);
    assert!(!cam.ray_at(1.0, 1.0).is_valid());
    assert!(cam.project(Vec3::NEG_Z).is_none());
}

/// A panorama shifted by `with_elevation_centre` spans `centre ± vfov/2` on
/// the spherical screen, and slides its cylinder by `tan(centre)`.
#[test]
fn elevation_centre_shifts_the_screen() {
    let (lo, hi) = (-0.3f32, 1.2f32);
    let sph = PanoramicCamera::new(
        Vec3::ZERO,
        Vec3::X,
        Vec3::Z,
        TAU,
        hi - lo,
        Projection::Spherical,
        64,
        32,
    )
    .unwrap()
    .with_elevation_centre(0.5 * (lo + hi))
    .unwrap();
    assert!((sph.elevation(0.0) - hi).abs() < 1e-6);
    assert!((sph.elevation(32.0) - lo).abs() < 1e-6);
    let el = sph.ray_at(32.0, 0.0).dir.z.asin();
    assert!((el - hi).abs() < 1e-5);
    let cyl = PanoramicCamera::new(
        Vec3::ZERO,
        Vec3::X,
        Vec3::Z,
        TAU,
        1.0,
        Projection::Cylindrical,
        64,
        32,
    )
    .unwrap()
    .with_elevation_centre(0.4)
    .unwrap();
    assert!((cyl.elevation(16.0) - 0.4).abs() < 1e-6);
    let top = 0.4f32.tan() + 0.5f32.tan();
    assert!((cyl.elevation(0.0) - top.atan()).abs() < 1e-6);
    for bad in [f32::NAN, 1.6, -1.6] {
        assert!(cyl.with_elevation_centre(bad).is_err(), "{bad}");
    }
    assert!(sph.with_elevation_centre(f32::INFINITY).is_err());
    assert!(sph.with_elevation_centre(2.0).is_ok());
}

/// Bad fisheye parameters are refused, naming the parameter.
#[test]
fn fisheye_refuses_bad_input() {
    let ok = |fov: f32, w: u32| FisheyeCamera::new(Vec3::ZERO, Vec3::Z, Vec3::Y, fov, w, 8);
    for (fov, w, name) in [
        (0.0, 8, "fov"),
        (7.0, 8, "fov"),
        (f32::NAN, 8, "fov"),
        (1.0, 0, "width"),
    ] {
        let e = ok(fov, w).unwrap_err().to_string();
        assert!(e.contains(name), "{e}");
    }
    assert!(FisheyeCamera::new(Vec3::ZERO, Vec3::Z, Vec3::Z, 1.0, 8, 8).is_err());
    assert!(ok(TAU, 8).is_ok());
}
