//! The pixel filter's tests: the Gaussian's shape and reach, the means of
//! unevenly sampled pixels, and the regular frames' resolve against the
//! per-pixel mean it stands for.

use super::*;
use crate::grid2::Grid2;

/// A pixel that took four times its neighbours' samples, all at the
/// same places in their pixels, counts as much as when it took as few:
/// the value is that of the even sampling.
#[test]
fn a_pixel_with_more_samples_does_not_weigh_more() {
    let f = PixelFilter::gaussian(0.5);
    let spots = [
        Vec2::new(0.25, 0.25),
        Vec2::new(0.75, 0.25),
        Vec2::new(0.25, 0.75),
        Vec2::new(0.75, 0.75),
    ];
    // The pixel right of (1, 1) is bright; it took 16 or 4 samples.
    let value = |copies: usize| {
        f.mean(1, 1, (3, 3), |nx, ny, g| {
            let l = if (nx, ny) == (2, 1) {
                Vec3::ONE
            } else {
                Vec3::ZERO
            };
            let k = if (nx, ny) == (2, 1) { copies } else { 1 };
            for _ in 0..k {
                for &p in &spots {
                    g(p, l);
                }
            }
        })
    };
    let (even, refined) = (value(1), value(4));
    assert!(even.x > 0.01 && even.x < 0.3, "{even}");
    approx::assert_relative_eq!(even.x, refined.x, max_relative = 1e-6);
    // The plain weighted mean over all samples would weigh it 4 times.
    let all = |copies: f32| {
        let w = |p: Vec2, dx: f32| f.weight(Vec2::new(dx - 0.5, -0.5) + p);
        let bright: f32 = spots.iter().map(|&p| w(p, 1.0)).sum::<f32>() * copies;
        let dark: f32 = (-1..=1)
            .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
            .filter(|&d| d != (1, 0))
            .map(|(dx, dy)| {
                spots
                    .iter()
                    .map(|&p| f.weight(Vec2::new(dx as f32 - 0.5, dy as f32 - 0.5) + p))
                    .sum::<f32>()
            })
            .sum();
        bright / (bright + dark)
    };
    approx::assert_relative_eq!(all(1.0), even.x, max_relative = 1e-5);
    assert!(all(4.0) > 2.0 * even.x);
}

#[test]
fn the_box_counts_its_own_square() {
    let f = PixelFilter::gaussian(0.0);
    assert!(f.is_box());
    assert_eq!(f.reach(), 0);
    assert_eq!(f.weight(Vec2::new(0.4, -0.3)), 1.0);
    assert_eq!(f.weight(Vec2::new(0.6, 0.0)), 0.0);
    assert!(PixelFilter::gaussian(f32::NAN).is_box());
}

#[test]
fn the_gaussian_is_smooth_symmetric_and_truncated() {
    let f = PixelFilter::gaussian(0.5);
    assert_eq!(f.reach(), 1);
    assert_eq!(PixelFilter::gaussian(0.2).reach(), 1);
    assert_eq!(PixelFilter::gaussian(1.0).reach(), 3);
    // Zero at and beyond 3σ, continuous there, and decreasing before.
    assert_eq!(f.weight(Vec2::new(1.5, 0.0)), 0.0);
    assert_eq!(f.weight(Vec2::new(0.0, 2.0)), 0.0);
    assert!(f.weight(Vec2::new(1.49, 0.0)) < 1e-3);
    let mut last = f32::INFINITY;
    for i in 0..150 {
        let x = i as f32 * 0.01;
        let w = f.weight(Vec2::new(x, 0.0));
        assert!(w < last || (w == 0.0 && last == 0.0), "at {x}");
        assert_eq!(w, f.weight(Vec2::new(-x, 0.0)));
        // Separable: w(x, y)·w(0, 0) = w(x, 0)·w(0, y).
        approx::assert_relative_eq!(
            w * f.weight(Vec2::new(0.0, 0.3)),
            f.weight(Vec2::new(x, 0.3)) * f.weight(Vec2::ZERO),
            max_relative = 1e-6
        );
        last = w;
    }
    // The shifted Gaussian's values: 1 − e^{−4.5} at the centre,
    // e^{−2} − e^{−4.5} one pixel away.
    let floor = (-4.5f32).exp();
    approx::assert_relative_eq!(f.weight(Vec2::ZERO), (1.0 - floor) * (1.0 - floor));
    approx::assert_relative_eq!(
        f.weight(Vec2::new(1.0, 0.0)),
        ((-2.0f32).exp() - floor) * (1.0 - floor)
    );
}

#[test]
fn a_sample_counts_only_within_the_reach() {
    // A sample anywhere in its pixel weighs nothing on the pixels
    // beyond `reach`, for every σ the scene allows.
    for sigma in [0.1f32, 0.3, 0.5, 0.7, 1.0] {
        let f = PixelFilter::gaussian(sigma);
        let r = f.reach() as f32;
        for i in 0..=20 {
            let u = i as f32 / 20.0;
            // Distance from a point u of the pixel [0, 1) to the centre
            // of the pixel r + 1 away.
            let beyond = (r + 1.0 + 0.5) - u;
            assert_eq!(f.weight(Vec2::new(beyond, 0.0)), 0.0, "σ {sigma}, u {u}");
        }
    }
}

/// A frame of `s × s` samples a pixel from a closure of sample indices.
fn frame(w: usize, h: usize, s: usize, f: impl Fn(usize, usize) -> Vec3) -> Grid2<Vec3> {
    let mut g = Grid2::new(w * s, h * s, Vec3::ZERO).unwrap();
    for j in 0..h * s {
        for i in 0..w * s {
            g[(i, j)] = f(i, j);
        }
    }
    g
}

#[test]
fn the_resolve_of_a_regular_frame_is_the_mean_of_its_pixels() {
    // An irregular pattern, resolved by the fast path and by `mean` visiting
    // each pixel's samples at their places.
    let (w, h, s) = (7usize, 5usize, 3usize);
    let g = frame(w, h, s, |i, j| {
        Vec3::new(
            ((i * 7 + j * 13) % 11) as f32,
            (i % 4) as f32,
            (j % 3) as f32,
        )
    });
    for f in [
        PixelFilter::camera(),
        PixelFilter::gaussian(0.8),
        PixelFilter::BOX,
    ] {
        let img = f.resolve(&g, s).unwrap();
        for y in 0..h as u32 {
            for x in 0..w as u32 {
                let m = f.mean(x, y, (w as u32, h as u32), |nx, ny, visit| {
                    for j in 0..s {
                        for i in 0..s {
                            let p =
                                Vec2::new((i as f32 + 0.5) / s as f32, (j as f32 + 0.5) / s as f32);
                            visit(p, g[(nx as usize * s + i, ny as usize * s + j)]);
                        }
                    }
                });
                let v = img.get(x as usize, y as usize).unwrap();
                approx::assert_relative_eq!(v.x, m.x, max_relative = 1e-5);
                approx::assert_relative_eq!(v.y, m.y, max_relative = 1e-5, epsilon = 1e-6);
                approx::assert_relative_eq!(v.z, m.z, max_relative = 1e-5, epsilon = 1e-6);
            }
        }
    }
}

#[test]
fn a_flat_frame_stays_flat_and_a_point_is_shared() {
    let g = frame(6, 4, 2, |_, _| Vec3::splat(0.3));
    let img = PixelFilter::camera().resolve(&g, 2).unwrap();
    assert!(
        img.pixels()
            .as_slice()
            .iter()
            .all(|&c| c == Vec3::splat(0.3))
    );
    // One lit sample: the box keeps it in its pixel, the Gaussian lends
    // its neighbours enough that none of them is 4 times darker than it
    // would be with the point at its own centre.
    let g = frame(5, 5, 1, |i, j| {
        if (i, j) == (2, 2) {
            Vec3::ONE
        } else {
            Vec3::ZERO
        }
    });
    let boxed = PixelFilter::BOX.resolve(&g, 1).unwrap();
    assert_eq!(boxed.get(2, 2), Some(Vec3::ONE));
    assert_eq!(boxed.get(1, 2), Some(Vec3::ZERO));
    let soft = PixelFilter::camera().resolve(&g, 1).unwrap();
    let (c, side) = (soft.get(2, 2).unwrap().x, soft.get(1, 2).unwrap().x);
    assert!(c > 0.5 && c < 0.7, "{c}");
    assert!(side > 0.07 && side < c / 4.0 * 1.5, "{side}");
}

#[test]
fn the_box_resolve_is_the_plain_mean() {
    let g = frame(3, 2, 4, |i, j| Vec3::splat((i * 5 + j) as f32 * 0.01));
    let img = PixelFilter::BOX.resolve(&g, 4).unwrap();
    let mut acc = Vec3::ZERO;
    for j in 0..4 {
        for i in 0..4 {
            acc += g[(4 + i, 4 + j)];
        }
    }
    assert_eq!(img.get(1, 1), Some(acc * (1.0 / 16.0)));
}

#[test]
fn a_frame_that_does_not_divide_is_refused() {
    let g = Grid2::new(7, 6, Vec3::ZERO).unwrap();
    assert!(matches!(
        PixelFilter::camera().resolve(&g, 2),
        Err(crate::CoreError::InvalidParameter { .. })
    ));
    assert!(PixelFilter::BOX.resolve(&g, 0).is_err());
}
