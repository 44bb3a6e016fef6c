//! The kilometre-scale cloudscape's fast mode against the reference (slow:
//! run with `cargo test --release -p natura-volume --test it -- cloudscape:: --ignored --nocapture`).
//!
//! The metric is the relative luminance error `Σ|L_fast − L_ref| / Σ L_ref`
//! over pixels (also over blocks of pixels, to average the reference's
//! noise), and the relative error of the mean luminance
//! `|mean L_fast − mean L_ref| / mean L_ref`.

use glam::Vec3;
use natura_core::Image;
use natura_volume::scene::{Cloudscape, CloudscapeParams};
use natura_volume::transport::{FastRenderer, ReferenceRenderer, ReferenceSettings};
use rayon::prelude::*;

use crate::common;

use common::{cached_reference_lum, centre_ray, frame_rays, lum};

/// Relative luminance error per pixel, over `b × b` blocks (to average the
/// reference's noise), and of the mean.
fn errors_image(a: &Image, r: &Image, b: usize) -> (f64, f64) {
    let (w, h) = (a.width(), a.height());
    let (mut d, mut s, mut ma, mut mr) = (0.0, 0.0, 0.0, 0.0);
    for by in 0..h / b {
        for bx in 0..w / b {
            let (mut la, mut lr) = (0.0, 0.0);
            for y in by * b..(by + 1) * b {
                for x in bx * b..(bx + 1) * b {
                    la += lum(a.get(x, y).unwrap_or(Vec3::ZERO));
                    lr += lum(r.get(x, y).unwrap_or(Vec3::ZERO));
                }
            }
            d += (la - lr).abs();
            s += lr;
            ma += la;
            mr += lr;
        }
    }
    (d / s, (ma - mr).abs() / mr)
}

#[test]
#[ignore = "slow: minutes"]
fn cloudscape_fast_mode_against_the_reference() {
    let p = CloudscapeParams {
        width: 96,
        height: 54,
        ..CloudscapeParams::default()
    };
    let cs = Cloudscape::new(&p, 11).unwrap();
    let scene = cs.scene();
    let fast = FastRenderer::new(&scene, cs.fast_settings())
        .unwrap()
        .render(&cs.camera())
        .unwrap();
    let t = std::time::Instant::now();
    let reference = ReferenceRenderer::new(
        &scene,
        ReferenceSettings {
            samples_per_pixel: 256,
            ..ReferenceSettings::default()
        },
    )
    .unwrap()
    .render(&cs.camera())
    .unwrap();
    let secs = t.elapsed().as_secs_f64();
    // Where the difference lies: ground, clear sky, cloud.
    let f = FastRenderer::new(&scene, cs.fast_settings()).unwrap();
    let cam = cs.camera();
    let mut sums = [[0.0f64; 3]; 4];
    let res = cam.resolution();
    for y in 0..res.y as usize {
        for x in 0..res.x as usize {
            let d = centre_ray(&cam, x, y);
            let tr = f.transmittance(cam.eye(), d, f32::INFINITY);
            let k = if d.z < 0.0 {
                0
            } else if tr > 0.99 {
                1
            } else if tr > 0.3 {
                2
            } else {
                3
            };
            sums[k][0] += lum(fast.get(x, y).unwrap());
            sums[k][1] += lum(reference.get(x, y).unwrap());
            sums[k][2] += 1.0;
        }
    }
    for (k, name) in ["ground", "clear sky", "thin cloud", "thick cloud"]
        .iter()
        .enumerate()
    {
        let [a, r, n] = sums[k];
        eprintln!(
            "{name}: {n} pixels, mean luminance fast {:.4}, reference {:.4}",
            a / n,
            r / n
        );
    }
    for b in [1, 2, 3, 6] {
        let (e, m) = errors_image(&fast, &reference, b);
        eprintln!("blocks of {b}×{b}: relative luminance error {e:.3}; of the mean {m:.3}");
    }
    eprintln!("reference: 96×54 at 256 paths per pixel in {secs:.1} s");
    // The reference here has 256 paths per pixel, whose own noise over 3×3
    // blocks is of the order of the goal; the full-frame comparison below
    // holds the goal against 4096 paths. The bounds here are looser: the
    // mean was 0.050 here (2026-12-01, the cache's cells carried by their
    // fluence gradients) while the full frame's was 0.046.
    let (e, m) = errors_image(&fast, &reference, 3);
    assert!(e <= 0.18 && m <= 0.055, "{e} {m}");
}

/// Relative luminance error of `a` against `r` (row-major `w × h`), over
/// `b × b` blocks, and of the mean.
fn errors(a: &[f64], r: &[f64], w: usize, b: usize) -> (f64, f64) {
    let h = a.len() / w;
    let (mut d, mut s) = (0.0, 0.0);
    for by in 0..h / b {
        for bx in 0..w / b {
            let (mut la, mut lr) = (0.0, 0.0);
            for y in by * b..(by + 1) * b {
                for x in bx * b..(bx + 1) * b {
                    la += a[y * w + x];
                    lr += r[y * w + x];
                }
            }
            d += (la - lr).abs();
            s += lr;
        }
    }
    let (ma, mr) = (a.iter().sum::<f64>(), r.iter().sum::<f64>());
    (d / s, (ma - mr).abs() / mr)
}

/// The comparison at the example's full 1920 × 1080 frame: the fast mode's
/// value at a pixel depends only on that pixel's ray, so both renderers
/// evaluate the same rays, the centres of every 20th pixel across and down
/// (96 × 54 rays), and the fast mode's values there are exactly those of its
/// full-frame image. The reference is itself noisy (a cloud's phase function
/// has a diffraction peak a fraction of a degree wide toward a low sun; the
/// reference lights it by two strategies, which bounds the brightest paths
/// but does not remove the noise), so it is four seeds of 1024 paths averaged (4096
/// paths per pixel), and its own noise is printed beside, from the
/// difference of its two 2048-path halves.
#[test]
#[ignore = "slow: minutes"]
fn cloudscape_full_frame_against_the_reference_and_its_noise_floor() {
    let p = CloudscapeParams::default();
    assert_eq!((p.width, p.height), (1920, 1080));
    let cs = Cloudscape::new(&p, 11).unwrap();
    let scene = cs.scene();
    let cam = cs.camera();
    let (rays, w) = frame_rays(&cam, 20);
    let spp = 1024;
    let fast = FastRenderer::new(&scene, cs.fast_settings()).unwrap();
    let reference =
        |seed: u64| cached_reference_lum("cloudscape_full", &scene, &cam, &rays, spp, seed);
    let a: Vec<f64> = rays
        .par_iter()
        .map(|&(x, y)| lum(fast.radiance(cam.eye(), centre_ray(&cam, x, y))))
        .collect();
    let t = std::time::Instant::now();
    let r: Vec<Vec<f64>> = (1..=4).map(reference).collect();
    let secs = t.elapsed().as_secs_f64() / 4.0;
    let mean = |k: &[usize]| -> Vec<f64> {
        (0..a.len())
            .map(|i| k.iter().map(|&j| r[j][i]).sum::<f64>() / k.len() as f64)
            .collect()
    };
    // The reference: four seeds averaged, 4096 paths per pixel. Its own
    // noise: half the difference of two 2048-path halves (the mean of two
    // independent halves has 1/√2 of a half's noise, and their difference √2).
    let r1 = mean(&[0, 1, 2, 3]);
    let (h1, h2) = (mean(&[0, 1]), mean(&[2, 3]));
    // Where the difference lies: ground, clear sky, cloud.
    let mut sums = [[0.0f64; 3]; 3];
    for (k, &(x, y)) in rays.iter().enumerate() {
        let d = centre_ray(&cam, x, y);
        let c = if d.z < 0.0 {
            0
        } else if fast.transmittance(cam.eye(), d, f32::INFINITY) > 0.99 {
            1
        } else {
            2
        };
        sums[c][0] += a[k];
        sums[c][1] += r1[k];
        sums[c][2] += 1.0;
    }
    for (k, name) in ["ground", "clear sky", "cloud"].iter().enumerate() {
        let [fa, fr, n] = sums[k];
        eprintln!(
            "{name}: {n} pixels, mean luminance fast {:.4}, reference {:.4}",
            fa / n,
            fr / n
        );
    }
    for b in [1, 3, 6] {
        let (e, m) = errors(&a, &r1, w, b);
        let (e1, m1) = errors(&a, &r[0], w, b);
        let (en, mn) = errors(&h2, &h1, w, b);
        eprintln!(
            "blocks of {b}×{b}: relative luminance error {e:.3}, of the mean {m:.3} \
             (against one 1024-path reference {e1:.3}, {m1:.3}); the reference's own noise \
             about {:.3}, of the mean {:.3} (two 2048-path halves differ by {en:.3}, {mn:.3})",
            en / 2.0,
            mn / 2.0
        );
    }
    eprintln!(
        "reference: {} rays of the 1920×1080 frame at 1024 paths per pixel in {secs:.1} s, four times",
        rays.len()
    );
    // The goal: the mean within 5 % and the blocks within 10 %. Measured
    // 2026-11-29 against the 4096-path reference (which samples the cloud
    // phase exactly and lights its forward peak by two strategies): with the
    // cache's bands up to 3 alone, 0.083 of the mean, the fast mode 13 %
    // short of the sun's light on this low, backlit sun (the cut series
    // spread the light's forward peak sideways) and 2.6 % of the sky's;
    // with the zonal tail to band 23, the figures printed above (see
    // docs/performance.md).
    let (e, m) = errors(&a, &r1, w, 3);
    assert!(e <= 0.10 && m <= 0.05, "{e} {m}");
}
