//! `FastRenderer::render_supersampled`: s × s rays a pixel resolved by the
//! camera's pixel filter antialias a solid's silhouette (the disc of a
//! black sphere against a bright background covers the area its
//! projection does, where one ray a pixel counts whole pixels), keep flat
//! regions exactly, and refuse a bad ray count by name.

use glam::Vec3;
use natura_core::NoProgress;
use natura_volume::VolumeError;
use natura_volume::density::Ball;
use natura_volume::transport::{
    FastRenderer, FastSettings, LookAtCamera, MediumParams, Scene, Solid, SolidShape,
};

const W: u32 = 48;
const H: u32 = 40;
const FOV: f32 = 0.5;
const EYE_DISTANCE: f32 = 4.0;
const RADIUS: f32 = 0.37;
const BACKGROUND: f32 = 0.6;

fn scene(ball: &Ball) -> Scene<'_> {
    Scene {
        sun: None,
        solids: vec![Solid {
            centre: Vec3::ZERO,
            radius: RADIUS,
            albedo: Vec3::ZERO,
            sky_irradiance: Vec3::ZERO,
            shape: SolidShape::Sphere,
        }],
        ..Scene::new(ball, MediumParams::default(), Vec3::splat(BACKGROUND))
    }
}

fn camera() -> LookAtCamera {
    LookAtCamera::look_at(
        Vec3::new(0.0, -EYE_DISTANCE, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        FOV,
        W,
        H,
    )
    .unwrap()
}

/// The black disc's area in pixels, from the picture: each pixel's share
/// of the background it misses.
fn covered(img: &natura_core::Image) -> f64 {
    img.pixels()
        .as_slice()
        .iter()
        .map(|c| 1.0 - f64::from(c.y) / f64::from(BACKGROUND))
        .sum()
}

#[test]
fn supersampling_antialiases_a_silhouette() {
    // The medium: an empty ball far behind the eye.
    let ball = Ball::new(Vec3::new(0.0, -50.0, 0.0), 0.1, 0.0).unwrap();
    let scene = scene(&ball);
    let fast = FastRenderer::new(&scene, FastSettings::default()).unwrap();
    // The sphere's projection is a disc of radius f·tan(asin(R/D)) pixels.
    let f = f64::from(H) / 2.0 / (f64::from(FOV) / 2.0).tan();
    let r = f * (f64::from(RADIUS) / f64::from(EYE_DISTANCE)).asin().tan();
    let area = std::f64::consts::PI * r * r;
    let plain = fast.render(&camera()).unwrap();
    let fine = fast.render_supersampled(&camera(), 4, &NoProgress).unwrap();
    assert_eq!((fine.width(), fine.height()), (W as usize, H as usize));
    let (a1, a4) = (covered(&plain), covered(&fine));
    assert!(((a4 - area) / area).abs() < 0.01, "{a4} against {area}");
    // One ray a pixel: every pixel is all disc or all background; four by
    // four: the silhouette's pixels take their share.
    let grey = |img: &natura_core::Image| {
        img.pixels()
            .as_slice()
            .iter()
            .filter(|c| c.y > 0.01 && c.y < BACKGROUND - 0.01)
            .count()
    };
    assert_eq!(grey(&plain), 0, "{a1}");
    assert!(
        grey(&fine) as f64 > 2.0 * std::f64::consts::PI * r,
        "{}",
        grey(&fine)
    );
    // Far from the disc, the background exactly.
    assert_eq!(fine.get(0, 0), Some(Vec3::splat(BACKGROUND)));
}

#[test]
fn supersampling_is_the_same_on_any_thread_count_and_refuses_bad_counts() {
    let ball = Ball::new(Vec3::new(0.0, 0.0, 0.5), 0.3, 2.0).unwrap();
    let scene = scene(&ball);
    let fast = FastRenderer::new(&scene, FastSettings::default()).unwrap();
    let render = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| fast.render_supersampled(&camera(), 3, &NoProgress).unwrap())
    };
    assert_eq!(render(1), render(3));
    for s in [0, 9] {
        match fast.render_supersampled(&camera(), s, &NoProgress) {
            Err(VolumeError::InvalidParameter {
                name: "supersample",
                ..
            }) => {}
            other => panic!("{s}: {other:?}"),
        }
    }
}
