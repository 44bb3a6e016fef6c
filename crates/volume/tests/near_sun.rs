//! Direct shadow rays near the sun: the aureole through cloud against the
//! reference, nothing changed away from the sun, and bad settings refused.

use glam::Vec3;
use natura_core::camera::PinholeCamera;
use natura_volume::scene::{Cloudscape, CloudscapeParams};
use natura_volume::transport::{
    FastRenderer, FastSettings, NearSunRays, ReferenceRenderer, ReferenceSettings,
};
use rayon::prelude::*;

/// The unit direction through the centre of pixel `(x, y)` of `cam`.
fn centre_ray(cam: &PinholeCamera, x: usize, y: usize) -> Vec3 {
    cam.ray_at(x as f32 + 0.5, y as f32 + 0.5).dir
}

fn lum(c: Vec3) -> f64 {
    f64::from(natura_core::colour::luminance(c))
}

/// The cloudscape of cloud seed 5 at a quarter of the frame's size (the
/// same view), and a 3 × 3 patch of its pixels where the eye looks through
/// cloud within about 2° of the low sun.
fn scene() -> (Cloudscape, Vec<(usize, usize)>) {
    let p = CloudscapeParams {
        width: 480,
        height: 270,
        ..CloudscapeParams::default()
    };
    let cs = Cloudscape::new(&p, 5).unwrap();
    // Every fifth pixel from (242, 152): the rays of the full frame's
    // pixels (970 + 20i, 610 + 20j).
    let patch = (0..3)
        .flat_map(|j| (0..3).map(move |i| (242 + 5 * i, 152 + 5 * j)))
        .collect();
    (cs, patch)
}

#[test]
fn near_the_sun_direct_shadow_rays_match_the_reference_where_the_table_is_too_dark() {
    let (cs, patch) = scene();
    let scene = cs.scene();
    let cam = cs.camera();
    let sun = scene.sun.unwrap().direction;
    for &(x, y) in &patch {
        let a = centre_ray(&cam, x, y)
            .dot(sun)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        assert!(a < 3.6, "pixel ({x}, {y}) is {a}° from the sun");
    }
    let table = FastSettings {
        near_sun: None,
        ..cs.fast_settings()
    };
    let near = cs.fast_settings();
    assert!(near.near_sun.is_some());
    let sum = |s: FastSettings| -> f64 {
        let f = FastRenderer::new(&scene, s).unwrap();
        patch
            .iter()
            .map(|&(x, y)| lum(f.radiance(cam.eye(), centre_ray(&cam, x, y))))
            .sum()
    };
    let r = ReferenceRenderer::new(
        &scene,
        ReferenceSettings {
            samples_per_pixel: 2048,
            seed: 3,
            ..ReferenceSettings::default()
        },
    )
    .unwrap();
    let reference: f64 = patch
        .par_iter()
        .map(|&(x, y)| lum(r.pixel(cam.eye(), centre_ray(&cam, x, y), x, y)))
        .sum();
    let (t, n) = (sum(table) / reference, sum(near) / reference);
    eprintln!("near the sun: the table alone {t:.3}, with near-sun rays {n:.3} of the reference");
    assert!(t < 0.7, "the table alone: {t} of the reference");
    assert!(
        (0.8..1.25).contains(&n),
        "with near-sun rays: {n} of the reference"
    );
}

#[test]
fn away_from_the_sun_the_image_is_the_tables_bit_for_bit() {
    let (cs, _) = scene();
    let scene = cs.scene();
    let cam = cs.camera();
    let sun = scene.sun.unwrap().direction;
    let near = cs.fast_settings();
    let within = near.near_sun.unwrap().within_deg;
    let table = FastSettings {
        near_sun: None,
        ..near
    };
    let (a, b) = (
        FastRenderer::new(&scene, near).unwrap(),
        FastRenderer::new(&scene, table).unwrap(),
    );
    let (mut far, mut changed) = (0, 0);
    let res = cam.resolution();
    for y in (0..res.y as usize).step_by(7) {
        for x in (0..res.x as usize).step_by(7) {
            let d = centre_ray(&cam, x, y);
            let angle = d.dot(sun).clamp(-1.0, 1.0).acos().to_degrees();
            let (ra, rb) = (a.radiance(cam.eye(), d), b.radiance(cam.eye(), d));
            if angle > 1.5 * within {
                assert_eq!(ra, rb, "pixel ({x}, {y}), {angle}° from the sun");
                far += 1;
            } else if ra != rb {
                changed += 1;
            }
        }
    }
    assert!(
        far > 2000 && changed > 0,
        "{far} far, {changed} near and changed"
    );
}

#[test]
fn bad_near_sun_settings_are_refused() {
    let (cs, _) = scene();
    let scene = cs.scene();
    for (name, n) in [
        (
            "near_sun.within_deg",
            NearSunRays {
                within_deg: 0.0,
                step: 20.0,
            },
        ),
        (
            "near_sun.within_deg",
            NearSunRays {
                within_deg: f32::NAN,
                step: 20.0,
            },
        ),
        (
            "near_sun.within_deg",
            NearSunRays {
                within_deg: 75.0,
                step: 20.0,
            },
        ),
        (
            "near_sun.step",
            NearSunRays {
                within_deg: 3.0,
                step: 0.0,
            },
        ),
        (
            "near_sun.step",
            NearSunRays {
                within_deg: 3.0,
                step: f32::INFINITY,
            },
        ),
    ] {
        let s = FastSettings {
            near_sun: Some(n),
            ..cs.fast_settings()
        };
        let e = FastRenderer::new(&scene, s).err().unwrap().to_string();
        assert!(e.contains(name), "{name}: {e}");
    }
}
