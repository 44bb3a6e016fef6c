//! The octave constants of the layer-cloud sky's fast mode against the
//! reference path tracer on cloudscapes of other seeds than the one the
//! comparison reports, and where the fast mode's error lies (slow: run with
//! `cargo test --release -p natura-volume --test it -- cloudscape_fit:: --ignored
//! --nocapture`).
//!
//! Training: the default cloudscape with cloud seeds 3 and 5 (the comparison
//! in `cloudscape.rs` uses seed 11), the rays through the centres of every
//! 20th pixel of the 1920 × 1080 frame, the reference at 512 paths per
//! pixel (two seeds of 256). The loss is the one the comparison reports,
//! over 3 × 3 blocks of rays, in squares:
//! `Σ_blocks (L_fast − L_ref)² / Σ_blocks L_ref²` (the reference's noise
//! adds a constant and does not move the minimum).
//!
//! Measured (with the near-sun shadow rays of the cloudscape's fast
//! settings): the default constants `(8, 0.4, 0.4, 0.85)` give a loss of
//! 0.082 (L1 over blocks 0.136 and 0.144 on the two seeds, against
//! references whose own noise is of that order); the best of the grid below,
//! `(16, 0.3, 0.5, 0.95)`, 0.078 (0.102 and 0.129). Re-fitting the constants
//! on cloudscapes gains about 5 % in the loss, so the defaults stay.
//! [`where_the_error_lies`] shows what is left: within 3° of the sun
//! through cloud the fast mode is within a quarter of the references
//! (before the near-sun shadow rays it was 0.4–0.5 of them, the largest
//! single share of the error), 5–15° from the sun in thick cloud it is
//! 10–50 % too bright, and a few blocks are the 256-path references' own
//! fireflies (one reference four times the other).

use natura_volume::scene::{Cloudscape, CloudscapeParams};
use natura_volume::transport::{FastRenderer, LookAtCamera, ScatterOctaves};
use rayon::prelude::*;

use crate::common;

use common::{centre_ray, frame_rays, lum, reference_lum};

/// Sums of `v` (row-major, `w` wide) over `b × b` blocks.
fn blocks(v: &[f64], w: usize, b: usize) -> Vec<f64> {
    let h = v.len() / w;
    let mut out = Vec::new();
    for by in 0..h / b {
        for bx in 0..w / b {
            let mut s = 0.0;
            for y in by * b..(by + 1) * b {
                for x in bx * b..(bx + 1) * b {
                    s += v[y * w + x];
                }
            }
            out.push(s);
        }
    }
    out
}

struct Training {
    cs: Cloudscape,
    cam: LookAtCamera,
    rays: Vec<(usize, usize)>,
    w: usize,
    reference: Vec<f64>,
}

fn training(seed: u64, spp: u32) -> Training {
    training_with(seed, spp, 7)
}

fn training_with(seed: u64, spp: u32, ref_seed: u64) -> Training {
    let cs = Cloudscape::new(&CloudscapeParams::default(), seed).unwrap();
    let cam = cs.camera();
    let (rays, w) = frame_rays(&cam, 20);
    let reference = reference_lum(&cs.scene(), &cam, &rays, spp, ref_seed);
    Training {
        cs,
        cam,
        rays,
        w,
        reference,
    }
}

/// (L2 loss, L1 error over 3 × 3 blocks, mean ratio) of the fast mode with `oc`.
fn score(t: &Training, oc: ScatterOctaves) -> (f64, f64, f64) {
    let scene = t.cs.scene();
    let f = FastRenderer::new(
        &scene,
        natura_volume::transport::FastSettings {
            scattering: natura_volume::transport::Scattering::Octaves(oc),
            ..t.cs.fast_settings()
        },
    )
    .unwrap();
    let a: Vec<f64> = t
        .rays
        .par_iter()
        .map(|&(x, y)| lum(f.radiance(t.cam.eye(), centre_ray(&t.cam, x, y))))
        .collect();
    let (ba, br) = (blocks(&a, t.w, 3), blocks(&t.reference, t.w, 3));
    let (mut d2, mut r2, mut d1, mut r1) = (0.0, 0.0, 0.0, 0.0);
    for (x, r) in ba.iter().zip(&br) {
        d2 += (x - r) * (x - r);
        r2 += r * r;
        d1 += (x - r).abs();
        r1 += r;
    }
    (d2 / r2, d1 / r1, ba.iter().sum::<f64>() / r1)
}

#[test]
#[ignore = "slow: minutes"]
fn fit_cloudscape_octaves() {
    // Two references per scene, averaged: 512 paths per pixel.
    let data: Vec<Training> = [3u64, 5]
        .iter()
        .map(|&s| {
            let (a, b) = (training_with(s, 256, 7), training_with(s, 256, 8));
            Training {
                reference: a
                    .reference
                    .iter()
                    .zip(&b.reference)
                    .map(|(x, y)| 0.5 * (x + y))
                    .collect(),
                ..a
            }
        })
        .collect();
    let base = ScatterOctaves::default();
    for t in &data {
        eprintln!("default constants: {:?}", score(t, base));
    }
    let mut best = (f64::INFINITY, base);
    for count in [16u32] {
        for a in [0.1f32, 0.15, 0.2, 0.25, 0.3] {
            for b in [0.15f32, 0.2, 0.25, 0.3, 0.4, 0.5] {
                if a > b {
                    continue;
                }
                for c in [0.9f32, 0.95, 0.98, 1.0] {
                    let oc = ScatterOctaves { count, a, b, c };
                    let l: f64 = data.iter().map(|t| score(t, oc).0).sum();
                    if l < best.0 {
                        best = (l, oc);
                        eprintln!("{l:.4} {oc:?}");
                    }
                }
            }
        }
    }
    let default_loss: f64 = data.iter().map(|t| score(t, base).0).sum();
    for t in &data {
        eprintln!("best {:?}: {:?}", best.1, score(t, best.1));
    }
    eprintln!("loss: default {default_loss:.4}, best {:.4}", best.0);
    // Refitting on cloudscapes gains under 10 %: the defaults stay.
    assert!(default_loss < 1.10 * best.0, "{default_loss} vs {}", best.0);
}

/// The blocks of seed 5 with the largest share of the fast mode's error,
/// with a second reference beside the first (to tell the fast mode's error
/// from the reference's noise), their angle to the sun and transmittance.
#[test]
#[ignore = "slow: minutes"]
fn where_the_error_lies() {
    let t = training(5, 256);
    let t2 = training_with(5, 256, 8);
    let scene = t.cs.scene();
    let f = FastRenderer::new(&scene, t.cs.fast_settings()).unwrap();
    let sun = scene.sun.unwrap().direction;
    let a: Vec<f64> = t
        .rays
        .iter()
        .map(|&(x, y)| lum(f.radiance(t.cam.eye(), centre_ray(&t.cam, x, y))))
        .collect();
    let (ba, br, bn) = (
        blocks(&a, t.w, 3),
        blocks(&t.reference, t.w, 3),
        blocks(&t2.reference, t.w, 3),
    );
    let bw = t.w / 3;
    let mut rows: Vec<(f64, usize)> = ba
        .iter()
        .zip(&br)
        .enumerate()
        .map(|(k, (x, r))| ((x - r).abs(), k))
        .collect();
    rows.sort_by(|p, q| q.0.partial_cmp(&p.0).unwrap());
    let total: f64 = br.iter().sum();
    let err: f64 = rows.iter().map(|r| r.0).sum();
    let noise: f64 = bn.iter().zip(&br).map(|(x, r)| (x - r).abs()).sum();
    eprintln!(
        "total L1 {:.3}, noise floor {:.3}",
        err / total,
        noise / total
    );
    for &(d, k) in rows.iter().take(25) {
        let (bx, by) = (k % bw, k / bw);
        let (x, y) = t.rays[(by * 3 + 1) * t.w + bx * 3 + 1];
        let dir = centre_ray(&t.cam, x, y);
        let ang = dir.dot(sun).clamp(-1.0, 1.0).acos().to_degrees();
        let tr = f.transmittance(t.cam.eye(), dir, f32::INFINITY);
        eprintln!(
            "block ({bx:2},{by:2}) share {:.3} fast {:.3} ref {:.3} ref2 {:.3} angle to sun {ang:5.1} T {tr:.3}",
            d / err,
            ba[k],
            br[k],
            bn[k],
        );
    }
    // Sums by angle from the sun: within 3° (through cloud, the aureole)
    // and 5–15° in thick cloud, against the mean of the two references.
    let (mut near, mut ring) = ([0.0f64; 2], [0.0f64; 2]);
    for k in 0..ba.len() {
        let (bx, by) = (k % bw, k / bw);
        let (x, y) = t.rays[(by * 3 + 1) * t.w + bx * 3 + 1];
        let dir = centre_ray(&t.cam, x, y);
        let ang = dir.dot(sun).clamp(-1.0, 1.0).acos().to_degrees();
        let tr = f.transmittance(t.cam.eye(), dir, f32::INFINITY);
        let r = 0.5 * (br[k] + bn[k]);
        if ang < 3.0 && tr < 0.5 {
            near[0] += ba[k];
            near[1] += r;
        } else if (5.0..15.0).contains(&ang) && tr < 0.1 {
            ring[0] += ba[k];
            ring[1] += r;
        }
    }
    let (near, ring) = (near[0] / near[1], ring[0] / ring[1]);
    eprintln!(
        "fast over reference: within 3° of the sun {near:.3}, 5–15° in thick cloud {ring:.3}"
    );
    assert!((0.75..1.25).contains(&near), "near the sun {near}");
    assert!((1.05..1.5).contains(&ring), "5–15° from the sun {ring}");
}
