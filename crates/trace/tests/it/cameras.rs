//! Camera mappings.

use approx::assert_relative_eq;
use glam::{Vec2, Vec3};
use natura_core::Seed;
use natura_trace::{
    Camera, Eye, OrthographicCamera, PanoramicCamera, PinholeCamera, Projection, Ray,
    RenderOptions, Stereo,
};
use std::f32::consts::{FRAC_PI_2, PI, TAU};

fn angle(a: Vec3, b: Vec3) -> f32 {
    a.normalize().dot(b.normalize()).clamp(-1.0, 1.0).acos()
}

#[test]
fn pinhole_centre_symmetry_and_field_of_view() {
    let eye = Vec3::new(10.0, -5.0, 30.0);
    let target = Vec3::new(200.0, 150.0, 0.0);
    let vfov = 50f32.to_radians();
    let cam = PinholeCamera::look_at(eye, target, Vec3::Z, vfov, 640, 360).unwrap();
    let view = (target - eye).normalize();
    // The centre of the image looks along the view direction.
    let c = cam.ray_at(320.0, 180.0);
    assert_eq!(c.origin, eye);
    assert_relative_eq!(c.dir, view, epsilon = 1e-6);
    // Pixels symmetric about the centre are symmetric about the view direction.
    for (x, y) in [(0u32, 0u32), (100, 40), (639, 17), (5, 359)] {
        let a = cam.ray(x, y, Vec2::splat(0.5)).dir;
        let b = cam.ray(639 - x, 359 - y, Vec2::splat(0.5)).dir;
        assert_relative_eq!(angle(a, view), angle(b, view), epsilon = 1e-5);
        assert_relative_eq!((a + b).normalize(), view, epsilon = 1e-5);
        assert_relative_eq!(a.length(), 1.0, epsilon = 1e-6);
    }
    // Edge to edge through the centre spans the fields of view.
    assert_relative_eq!(
        angle(cam.ray_at(320.0, 0.0).dir, cam.ray_at(320.0, 360.0).dir),
        vfov,
        epsilon = 1e-5
    );
    let hfov = 2.0 * ((0.5 * vfov).tan() * 640.0 / 360.0).atan();
    assert_relative_eq!(
        angle(cam.ray_at(0.0, 180.0).dir, cam.ray_at(640.0, 180.0).dir),
        hfov,
        epsilon = 1e-5
    );
    assert_relative_eq!(cam.hfov(), hfov, epsilon = 1e-6);
    // Row 0 is the top: its rays point higher than the bottom row's.
    assert!(cam.ray_at(320.0, 0.0).dir.z > cam.ray_at(320.0, 360.0).dir.z);
    // Column 0 is on the left: (view × up) points right.
    let right = view.cross(Vec3::Z);
    assert!(cam.ray_at(0.0, 180.0).dir.dot(right) < 0.0);
    // An explicit aspect changes the horizontal field only.
    let wide = cam.with_aspect(3.0).unwrap();
    assert_relative_eq!(
        wide.hfov(),
        2.0 * ((0.5 * vfov).tan() * 3.0).atan(),
        epsilon = 1e-6
    );
}

#[test]
fn orthographic_rays_are_parallel_and_evenly_spaced() {
    let cam = OrthographicCamera::look_at(
        Vec3::new(50.0, 50.0, 100.0),
        Vec3::new(50.0, 50.0, 0.0),
        Vec3::Y,
        20.0,
        40,
        20,
    )
    .unwrap();
    let a = cam.ray_at(0.0, 0.0);
    let b = cam.ray_at(40.0, 20.0);
    assert_eq!(a.dir, Vec3::NEG_Z);
    assert_eq!(b.dir, Vec3::NEG_Z);
    // 20 m tall, 40 m wide; top-left is (−x, +y) looking down with y up.
    assert_relative_eq!(a.origin, Vec3::new(30.0, 60.0, 100.0), epsilon = 1e-4);
    assert_relative_eq!(b.origin, Vec3::new(70.0, 40.0, 100.0), epsilon = 1e-4);
}

#[test]
fn panoramic_azimuth_is_linear_and_elevation_follows_the_mapping() {
    let pos = Vec3::new(1.0, 2.0, 3.0);
    let look = Vec3::new(1.0, 1.0, 0.3); // not level: the camera levels it
    let (w, h) = (720u32, 300u32);
    let hfov = TAU;
    let vfov = 150f32.to_radians();
    for projection in [Projection::Spherical, Projection::Cylindrical] {
        let cam = PanoramicCamera::new(pos, look, Vec3::Z, hfov, vfov, projection, w, h).unwrap();
        let forward = Vec3::new(1.0, 1.0, 0.0).normalize();
        let left = Vec3::Z.cross(forward);
        for py in [0.0f32, 10.5, 150.0, 222.25, 300.0] {
            let want_el = match projection {
                Projection::Spherical => vfov * (0.5 - py / h as f32),
                Projection::Cylindrical => {
                    ((0.5 * vfov).tan() * (1.0 - 2.0 * py / h as f32)).atan()
                }
            };
            assert_relative_eq!(cam.elevation(py), want_el, epsilon = 1e-6);
            for px in [0.0f32, 1.0, 99.5, 360.0, 500.0, 719.0] {
                let r = cam.ray_at(px, py);
                assert_eq!(r.origin, pos);
                assert_relative_eq!(r.dir.length(), 1.0, epsilon = 1e-6);
                let el = r.dir.z.clamp(-1.0, 1.0).asin();
                assert_relative_eq!(el, want_el, epsilon = 1e-5);
                if want_el.abs() < 1.5 {
                    let az = r.dir.dot(left).atan2(r.dir.dot(forward));
                    let want_az = hfov * (0.5 - px / w as f32);
                    let diff = (az - want_az).rem_euclid(TAU);
                    assert!(
                        !(1e-4..=TAU - 1e-4).contains(&diff),
                        "azimuth {az} vs {want_az}"
                    );
                }
            }
        }
        // 360°: the first and the past-the-end columns coincide.
        assert_relative_eq!(
            cam.ray_at(0.0, 100.0).dir,
            cam.ray_at(w as f32, 100.0).dir,
            epsilon = 1e-5
        );
        // The image's centre looks along the levelled view direction.
        assert_relative_eq!(cam.ray_at(360.0, 150.0).dir, forward, epsilon = 1e-5);
    }
}

#[test]
fn spherical_screen_reaches_the_poles_and_repeats_beyond_them() {
    let cam = PanoramicCamera::new(
        Vec3::ZERO,
        Vec3::X,
        Vec3::Z,
        TAU,
        PI,
        Projection::Spherical,
        64,
        32,
    )
    .unwrap();
    assert_relative_eq!(cam.ray_at(10.0, 0.0).dir, Vec3::Z, epsilon = 1e-5);
    assert_relative_eq!(cam.ray_at(10.0, 32.0).dir, Vec3::NEG_Z, epsilon = 1e-5);
    // Beyond 180° the source's tan table repeats with period 180°, right side up.
    let tall = PanoramicCamera::new(
        Vec3::ZERO,
        Vec3::X,
        Vec3::Z,
        TAU,
        2.0 * PI,
        Projection::Spherical,
        64,
        64,
    )
    .unwrap();
    for py in [3.0f32, 10.0, 13.5] {
        // Rows 16 apart differ by 90°·2 = 180° of elevation.
        assert_relative_eq!(
            tall.ray_at(7.0, py).dir,
            tall.ray_at(7.0, py + 32.0).dir,
            epsilon = 1e-5
        );
    }
    let e = tall.ray_at(7.0, 40.0).dir.z.asin();
    assert!(e.abs() <= FRAC_PI_2 + 1e-6);
}

#[test]
fn stereo_eyes_circle_the_centre_perpendicular_to_the_view() {
    let pos = Vec3::new(5.0, 5.0, 100.0);
    let sep = 0.065;
    let base = PanoramicCamera::new(
        pos,
        Vec3::Y,
        Vec3::Z,
        TAU,
        1.0,
        Projection::Spherical,
        90,
        20,
    )
    .unwrap();
    let l = base
        .with_stereo(Stereo {
            eye: Eye::Left,
            separation: sep,
        })
        .unwrap();
    let r = base
        .with_stereo(Stereo {
            eye: Eye::Right,
            separation: sep,
        })
        .unwrap();
    for px in [0.0f32, 13.0, 45.0, 77.7] {
        let (a, b) = (l.ray_at(px, 10.0), r.ray_at(px, 10.0));
        assert_relative_eq!((a.origin - b.origin).length(), sep, epsilon = 1e-5);
        assert_relative_eq!((a.origin - pos).length(), 0.5 * sep, epsilon = 1e-5);
        assert!((a.origin - b.origin).dot(a.dir).abs() < 1e-6);
        assert_eq!(a.dir, b.dir);
        // The left eye is on the left: (up × view) points left.
        assert!((a.origin - pos).dot(Vec3::Z.cross(a.dir)) > 0.0);
    }
    assert!(
        base.with_stereo(Stereo {
            eye: Eye::Left,
            separation: f32::NAN
        })
        .is_err()
    );
}

#[test]
fn bad_camera_parameters_are_refused() {
    let o = Vec3::ZERO;
    let x = Vec3::X;
    assert!(
        PinholeCamera::look_at(o, o, Vec3::Z, 1.0, 10, 10).is_err(),
        "eye = target"
    );
    assert!(
        PinholeCamera::look_at(o, Vec3::Z, Vec3::Z, 1.0, 10, 10).is_err(),
        "up ∥ view"
    );
    assert!(PinholeCamera::look_at(o, x, Vec3::ZERO, 1.0, 10, 10).is_err());
    assert!(PinholeCamera::look_at(o, x, Vec3::Z, 0.0, 10, 10).is_err());
    assert!(PinholeCamera::look_at(o, x, Vec3::Z, PI, 10, 10).is_err());
    assert!(PinholeCamera::look_at(o, x, Vec3::Z, f32::NAN, 10, 10).is_err());
    assert!(PinholeCamera::look_at(o, x, Vec3::Z, 1.0, 0, 10).is_err());
    assert!(PinholeCamera::look_at(o, x, Vec3::Z, 1.0, 10, 1 << 20).is_err());
    assert!(PinholeCamera::look_at(Vec3::NAN, x, Vec3::Z, 1.0, 10, 10).is_err());
    assert!(
        PinholeCamera::look_at(o, x, Vec3::Z, 1.0, 10, 10)
            .unwrap()
            .with_aspect(-1.0)
            .is_err()
    );
    assert!(OrthographicCamera::look_at(o, x, Vec3::Z, 0.0, 10, 10).is_err());
    let pano =
        |look: Vec3, h: f32, v: f32, p| PanoramicCamera::new(o, look, Vec3::Z, h, v, p, 10, 10);
    assert!(
        pano(Vec3::Z, 1.0, 1.0, Projection::Spherical).is_err(),
        "look ∥ up"
    );
    assert!(pano(x, 0.0, 1.0, Projection::Spherical).is_err());
    assert!(pano(x, f32::INFINITY, 1.0, Projection::Spherical).is_err());
    assert!(pano(x, 1.0, PI, Projection::Cylindrical).is_err());
    assert!(
        pano(x, 7.0, 4.0, Projection::Spherical).is_ok(),
        "wider than the sphere is allowed"
    );
    let msg = PinholeCamera::look_at(o, x, Vec3::Z, 4.0, 10, 10)
        .unwrap_err()
        .to_string();
    assert!(msg.contains("vfov"), "{msg}");
}

/// `Camera::rays_into` (the lane generation of the pinhole and orthographic
/// cameras, the per-pixel default of the panoramic one) returns exactly the
/// rays `Camera::ray(x, y, options.jitter(x, y, s))`, bit for bit and in
/// order: blocks of every shape (narrower and wider than the 16 lanes, not a
/// multiple of them, single pixels, image edges), one and several samples
/// per pixel, square and non-square pixels, views from every side.
#[test]
fn block_rays_equal_per_pixel_rays_bit_for_bit() {
    let bits = |r: &Ray| {
        let (o, d) = (r.origin, r.dir);
        [o.x, o.y, o.z, d.x, d.y, d.z].map(f32::to_bits)
    };
    let (w, h) = (203u32, 117u32);
    let mut cams: Vec<Box<dyn Camera>> = Vec::new();
    for (k, (eye, target, up)) in [
        (
            Vec3::new(10.0, -5.0, 30.0),
            Vec3::new(200.0, 150.0, 0.0),
            Vec3::Z,
        ),
        (
            Vec3::new(-3.5, 7.25, 1e4),
            Vec3::new(-3.0, 7.0, 0.0),
            Vec3::Y,
        ),
        (
            Vec3::new(4e4, 3e4, 12.0),
            Vec3::new(0.0, 0.0, 900.0),
            Vec3::Z,
        ),
        (
            Vec3::new(0.1, 0.2, 0.3),
            Vec3::new(0.1, -50.0, -0.3),
            Vec3::new(0.3, 0.0, 1.0),
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let vfov = (20.0 + 37.0 * k as f32).to_radians();
        let p = PinholeCamera::look_at(eye, target, up, vfov, w, h).unwrap();
        cams.push(Box::new(p));
        cams.push(Box::new(p.with_aspect(0.37 + k as f32).unwrap()));
        cams.push(Box::new(
            OrthographicCamera::look_at(eye, target, up, 3.0 + 400.0 * k as f32, w, h).unwrap(),
        ));
    }
    cams.push(Box::new(
        PanoramicCamera::new(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::X,
            Vec3::Z,
            2.0,
            1.0,
            Projection::Cylindrical,
            w,
            h,
        )
        .unwrap(),
    ));
    let big = PinholeCamera::look_at(Vec3::ZERO, Vec3::X, Vec3::Z, 0.7, 1920, 1080).unwrap();
    let blocks = [
        (0u32, 0u32, w, h),
        (0, 0, 1, 1),
        (w - 1, h - 1, 1, 1),
        (5, 9, 15, 3),
        (17, 2, 16, 5),
        (w - 11, 40, 11, 17),
        (64, h - 7, 33, 7),
        (31, 31, 1, 40),
    ];
    let mut n_rays = 0;
    for samples in [1u32, 3] {
        let options = RenderOptions {
            samples_per_pixel: samples,
            seed: Seed(7),
            ..RenderOptions::default()
        };
        let mut check = |cam: &dyn Camera, (x0, y0, bw, bh): (u32, u32, u32, u32)| {
            let mut got = vec![Ray::new(Vec3::NAN, Vec3::NAN)];
            cam.rays_into(x0, y0, bw, bh, &options, &mut got);
            let mut want = vec![Ray::new(Vec3::NAN, Vec3::NAN)];
            for y in y0..y0 + bh {
                for x in x0..x0 + bw {
                    for s in 0..samples {
                        want.push(cam.ray(x, y, options.jitter(x, y, s)));
                    }
                }
            }
            assert_eq!(got.len(), want.len(), "{x0} {y0} {bw} {bh}");
            // (Appends: the first element is kept.)
            assert!(got[0].origin.x.is_nan());
            for (a, b) in got.iter().zip(&want).skip(1) {
                assert_eq!(
                    bits(a),
                    bits(b),
                    "{a:?} vs {b:?} in block {x0} {y0} {bw} {bh}"
                );
            }
            n_rays += want.len() - 1;
        };
        for cam in &cams {
            for &b in &blocks {
                check(cam.as_ref(), b);
            }
        }
        for b in [(0, 0, 32, 32), (1888, 1056, 32, 24), (960, 540, 1, 1)] {
            check(&big, b);
        }
    }
    assert!(n_rays > 500_000, "{n_rays}");
    // An empty block appends nothing.
    let mut v = Vec::new();
    big.rays_into(3, 3, 0, 5, &RenderOptions::default(), &mut v);
    big.rays_into(3, 3, 5, 0, &RenderOptions::default(), &mut v);
    assert!(v.is_empty());
}

/// The tile driver puts every pixel in its place: `render` equals the
/// per-pixel grid for tiles of one pixel, ragged edges, one tile larger than
/// the image and square tiles, on 1 and 2 threads, reports every pixel once,
/// and refuses a zero tile or resolution.
#[test]
fn render_places_every_pixel_for_any_tile_and_thread_count() {
    use natura_core::{CountingProgress, Grid2, NoProgress};
    use natura_trace::render;
    let f = |x: u32, y: u32| (u64::from(y) << 32 | u64::from(x)).wrapping_mul(0x9E37_79B9);
    for (w, h) in [(1u32, 1u32), (37, 23), (64, 64), (130, 3)] {
        let want = Grid2::from_fn(w as usize, h as usize, |x, y| f(x as u32, y as u32)).unwrap();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            for tile in [1u32, 5, 16, 32, 200] {
                let p = CountingProgress::new();
                let got = pool.install(|| render(w, h, tile, &p, f)).unwrap();
                assert_eq!(got.dims(), want.dims());
                assert_eq!(
                    got.as_slice(),
                    want.as_slice(),
                    "{w}×{h}, tile {tile}, {threads} threads"
                );
                assert_eq!(p.advanced(), u64::from(w * h));
                assert_eq!(p.finished(), 1);
            }
        }
    }
    assert!(render(8, 8, 0, &NoProgress, f).is_err());
    assert!(render(0, 8, 4, &NoProgress, f).is_err());
    assert!(render(8, 0, 4, &NoProgress, f).is_err());
}
