//! The fast mode's multiple scattering against the reference path tracer
//! over a matrix of scenes: a homogeneous ball, a homogeneous slab and a
//! voxel blob, under every phase family the crate provides (Henyey–Greenstein
//! `g = 0, 0.3, 0.6, 0.8, −0.3` and the cloud phase at 5 and 20 µm), each lit
//! by a sun behind the viewer, beside it and ahead of it (backlit), with the
//! single-scattering albedo (0.8 … 0.999) and the optical thickness
//! (0.3 … 50) spread across the scenes. Every scene is rendered twice:
//! under a black sky (the sun's light alone, single and multiple
//! scattering) and under the sun and a uniform blue sky, whose light the
//! volume scatters too.
//!
//! For each scene: the fast mode's and the reference's luminance summed over
//! the image (the total error), and over blocks of 4 × 4 pixels (the block
//! error: the blocks' absolute errors summed over the blocks that see the
//! volume, over their reference light). Under the sky, the light measured
//! is what the volume sends the eye: each pixel's luminance less the sky
//! it lets through (the sky's luminance times the pixel's transmittance,
//! the same for both renderers), so the sky seen around and through a
//! thin volume does not dilute the errors. The reference is rendered twice
//! with independent seeds; their mean is the oracle, and half their
//! difference estimates its noise, which is subtracted in quadrature from
//! each error (`√max(e² − σ², 0)`), so the figures are the model's error,
//! not the oracle's.
//!
//! The fast mode renders with its default multiple scattering, the cache
//! of [`natura_volume::transport::ScatterCache`].
//!
//! `cargo test --release -p natura-volume --test it -- scatter_matrix::` runs a
//! reduced matrix (six scenes, one under the sky, 32 × 32 pixels, 48 paths
//! per pixel and seed) and asserts the errors stay within today's; the
//! whole matrix (126 scenes, 48 × 48 pixels, 96 paths per pixel and seed, or 384
//! where the 96-path references' noise exceeds 1 % of the total, the references
//! cached under the target's temporary directory), with the targets (totals
//! within ±5 %, block error ≤ 10 %), is
//! `cargo test --release -p natura-volume --test it -- scatter_matrix:: --ignored --nocapture`
//! (`MATRIX_SKY=black` or `blue` runs one sky's half).

use natura_volume::transport::{FastRenderer, FastSettings, ScatterOctaves, Scattering, Shadows};

#[path = "scatter_matrix/scenes.rs"]
mod scenes;
use scenes::*;

fn run(cases: &[Case], px: u32, spp: u32) -> Vec<(Case, Errors)> {
    cases
        .iter()
        .map(|c| {
            let e = errors(&render_case(c, px, spp));
            println!(
                "{}  total {:+6.1} %  (noise {:4.1} %)  block {:5.1} %",
                describe(c),
                100.0 * e.total,
                100.0 * e.noise,
                100.0 * e.block
            );
            (*c, e)
        })
        .collect()
}

/// Min / median / max of the total and block errors per sky and phase
/// family.
fn summary(res: &[(Case, Errors)]) {
    let stats = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        (v[0], v[v.len() / 2], v[v.len() - 1])
    };
    for sky in [Sky::Black, Sky::Blue] {
        for p in PHASES {
            let sel: Vec<&Errors> = res
                .iter()
                .filter(|(c, _)| c.phase == p && c.sky == sky)
                .map(|(_, e)| e)
                .collect();
            if sel.is_empty() {
                continue;
            }
            let t = stats(sel.iter().map(|e| 100.0 * e.total).collect());
            let b = stats(sel.iter().map(|e| 100.0 * e.block).collect());
            println!(
                "{:<5} {:<13} total min/median/max {:+6.1} {:+6.1} {:+6.1} %   block {:5.1} {:5.1} {:5.1} %",
                format!("{sky:?}"),
                phase_name(&p),
                t.0,
                t.1,
                t.2,
                b.0,
                b.1,
                b.2
            );
        }
    }
}

/// The reduced matrix's errors `(|total|, block)` per scene with the
/// octaves of Wrenninge et al. 2013 as fitted for clouds (`a = b = 0.4`,
/// `c = 0.85`) applied unchanged, before their medium's form
/// ([`natura_volume::transport::MediumOctaves`]): mean block error 0.42.
const REDUCED_BEFORE: [(f64, f64); 5] = [
    (0.122, 0.160),
    (0.036, 0.104),
    (0.506, 0.474),
    (0.904, 0.886),
    (0.482, 0.479),
];

/// The bound on the reduced matrix's mean block error: the octaves applied
/// unchanged measured 0.42 (`REDUCED_BEFORE`), their medium's form 0.25,
/// the multiple-scattering cache 0.073 (its worst scene, the cloud phase
/// seen from the side, 0.26).
const REDUCED_MEAN_BLOCK_BOUND: f64 = 0.10;

#[test]
fn reduced_matrix_within_bounds() {
    let res = run(&reduced_matrix(), 32, 48);
    summary(&res);
    let worst_before = REDUCED_BEFORE
        .iter()
        .map(|&(t, b)| t.max(b))
        .fold(0.0, f64::max);
    for (c, e) in &res {
        assert!(
            e.total.abs() <= worst_before && e.block <= worst_before,
            "{}: {e:?}",
            describe(c)
        );
    }
    let mean = res.iter().map(|(_, e)| e.block).sum::<f64>() / res.len() as f64;
    assert!(mean <= REDUCED_MEAN_BLOCK_BOUND, "mean block error {mean}");
    // Under the sky the targets themselves hold (with the sky as the
    // march's ambient term instead of a source of the cache, this scene
    // was outside both).
    for (c, e) in res.iter().filter(|(c, _)| c.sky == Sky::Blue) {
        assert!(
            e.total.abs() <= 0.05 && e.block <= 0.10,
            "{}: {e:?}",
            describe(c)
        );
    }
}

#[test]
#[ignore = "slow: the whole matrix (minutes)"]
fn full_matrix_meets_targets() {
    let cases = full_matrix();
    assert!(cases.len() >= 24);
    // `MATRIX_ONLY=<text>|<text>…` keeps the scenes whose description
    // contains one of them (to study a few; the assertion then covers
    // those alone).
    // `MATRIX_SKY=black` or `blue` keeps one sky's half.
    let only = std::env::var("MATRIX_ONLY").unwrap_or_default();
    let sky = std::env::var("MATRIX_SKY").unwrap_or_default();
    let cases: Vec<Case> = cases
        .into_iter()
        .filter(|c| only.split('|').any(|o| describe(c).contains(o)))
        .filter(|c| sky.is_empty() || format!("{:?}", c.sky).eq_ignore_ascii_case(&sky))
        .collect();
    // The references take 96 paths a pixel and seed, and 384 where the
    // 96-path pair's own noise on the total exceeds 1 % of it: such scenes
    // (nearly all of the cloud phase, lit through its narrow peak) have
    // heavy-tailed path weights, whose few large samples a short run
    // usually misses, so its mean falls short and the fast mode reads too
    // bright; the noise estimate, subtracted in quadrature, does not cover
    // that bias. `MATRIX_SPP=<n>` takes n paths for every scene,
    // `MATRIX_DEPTH=<n>` lets the references' paths run to n scatterings.
    let fixed = std::env::var("MATRIX_SPP")
        .ok()
        .and_then(|v| v.parse::<u32>().ok());
    let px = 48;
    let res: Vec<(Case, Errors)> = cases
        .iter()
        .map(|c| {
            let fast = fast_lums(c, px, Scattering::default());
            let sky = background(c, px);
            let measure = |spp| {
                let (ref_a, ref_b) = cached_reference(c, px, spp);
                errors(&Measured {
                    fast: fast.clone(),
                    ref_a,
                    ref_b,
                    sky: sky.clone(),
                    px: px as usize,
                })
            };
            let (spp, e) = match fixed {
                Some(n) => (n, measure(n)),
                None => {
                    let e = measure(96);
                    if e.noise > NOISY_REFERENCE {
                        (384, measure(384))
                    } else {
                        (96, e)
                    }
                }
            };
            println!(
                "{}  total {:+6.1} %  (noise {:4.1} %, {spp:3} paths)  block {:5.1} %",
                describe(c),
                100.0 * e.total,
                100.0 * e.noise,
                100.0 * e.block
            );
            (*c, e)
        })
        .collect();
    summary(&res);
    let failing: Vec<_> = res
        .iter()
        .filter(|(_, e)| e.total.abs() > 0.05 || e.block > 0.10)
        .collect();
    for (c, e) in &failing {
        println!("outside the target: {} {e:?}", describe(c));
    }
    assert!(
        failing.is_empty(),
        "{} of {} scenes outside the target",
        failing.len(),
        res.len()
    );
}

/// A thick, nearly conservative ball lit from the side (optical diameter
/// 50, albedo 0.999), where the light the viewer sees has scattered up to
/// hundreds of times. Under a Russian roulette that let a path's weight
/// grow past 1 (survival 0.95 at each collision), the reference drew too
/// few of those long paths and came out some 4 % dark: the fast mode read
/// +6.3 % against it in the full matrix. With the weight kept at most 1 the
/// two agree within the targets (+2 %).
#[test]
fn thick_conservative_ball_within_the_targets() {
    let case = Case {
        shape: Shape::Ball,
        phase: PHASES[0],
        sun: SunAt::Beside,
        sky: Sky::Black,
        albedo: 0.999,
        tau: 50.0,
    };
    let res = run(&[case], 32, 48);
    let e = &res[0].1;
    assert!(e.total.abs() <= 0.05 && e.block <= 0.10, "{e:?}");
}

/// The references' relative noise on a scene's total above which the full
/// matrix takes four times the paths.
const NOISY_REFERENCE: f64 = 0.01;

/// The reference luminances of a case, cached under the target's temporary
/// directory (they take most of the time).
fn cached_reference(c: &Case, px: u32, spp: u32) -> (Vec<f64>, Vec<f64>) {
    let key = format!("{}_{px}_{spp}_{}", describe(c), reference_depth())
        .chars()
        .map(|ch| {
            if ch.is_ascii_alphanumeric() || ch == '.' || ch == '-' {
                ch
            } else {
                '_'
            }
        })
        .collect::<String>();
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("matrix_{key}.txt"));
    if let Ok(s) = std::fs::read_to_string(&path) {
        let v: Vec<f64> = s.split_whitespace().map(|x| x.parse().unwrap()).collect();
        let n = v.len() / 2;
        return (v[..n].to_vec(), v[n..].to_vec());
    }
    let m = render_case(c, px, spp);
    let s: Vec<String> = m
        .ref_a
        .iter()
        .chain(&m.ref_b)
        .map(|x| format!("{x:e}"))
        .collect();
    std::fs::write(&path, s.join(" ")).unwrap();
    (m.ref_a, m.ref_b)
}

/// The fast mode's luminance for a case with the given octaves.
fn fast_lums(c: &Case, px: u32, scattering: Scattering) -> Vec<f64> {
    let d = density(c.shape);
    let scene = scene(c, d.as_ref());
    // `MATRIX_CELLS`, `MATRIX_ORDER`, `MATRIX_ZONAL` and `MATRIX_SEED` override the
    // cache's grid, band, zonal tail and photons' seed (a study's knobs).
    let knob = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<u32>().ok());
    let scattering = match scattering {
        Scattering::Cache(c) => Scattering::Cache(natura_volume::transport::CacheParams {
            cells: knob("MATRIX_CELLS").unwrap_or(c.cells),
            order: knob("MATRIX_ORDER").unwrap_or(c.order),
            zonal: knob("MATRIX_ZONAL").unwrap_or(c.zonal),
            seed: knob("MATRIX_SEED").map_or(c.seed, u64::from),
            ..c
        }),
        s => s,
    };
    let scattering = if std::env::var("MATRIX_SINGLE").is_ok() {
        Scattering::Single
    } else {
        scattering
    };
    let mut settings = FastSettings {
        scattering,
        ..fast_settings(&d.bounds())
    };
    if let Some(n) = knob("MATRIX_TABLE") {
        settings.shadows = Shadows::Table(n as usize);
    }
    // `MATRIX_RAYS=<metres>`: direct shadow rays instead of the table.
    if let Some(h) = std::env::var("MATRIX_RAYS")
        .ok()
        .and_then(|v| v.parse::<f32>().ok())
    {
        settings.shadows = Shadows::Rays(h);
    }
    if std::env::var("MATRIX_NOTRUNC").is_ok() {
        settings.truncate_forward_peak = false;
    }
    // `MATRIX_POWDER=<strength>`: Schneider's powder term on, to measure
    // the error it adds against the reference.
    if let Some(s) = std::env::var("MATRIX_POWDER")
        .ok()
        .and_then(|v| v.parse::<f32>().ok())
    {
        settings.powder = s;
    }
    lums(
        &FastRenderer::new(&scene, settings)
            .unwrap()
            .render(&camera(c.shape, px))
            .unwrap(),
    )
}

/// Per scene, the octave constants `(a, b)` (with `c = 0.85`) that minimise
/// the block error, to see what they depend on.
#[test]
#[ignore = "slow: a study, not a check"]
fn octaves_per_scene() {
    let (px, spp) = (48, 96);
    for c in full_matrix() {
        let (ref_a, ref_b) = cached_reference(&c, px, spp);
        let sky = background(&c, px);
        let measure = |o| {
            errors(&Measured {
                fast: fast_lums(&c, px, Scattering::Octaves(o)),
                ref_a: ref_a.clone(),
                ref_b: ref_b.clone(),
                sky: sky.clone(),
                px: px as usize,
            })
        };
        let base = measure(natura_volume::transport::ScatterOctaves::default());
        let mut best = (f64::INFINITY, 0.0, 0.0, base);
        for a in [0.1f32, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9] {
            for b in [0.05f32, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9] {
                if a > b {
                    continue;
                }
                let e = measure(natura_volume::transport::ScatterOctaves {
                    a,
                    b,
                    ..natura_volume::transport::ScatterOctaves::default()
                });
                if e.block < best.0 {
                    best = (e.block, a, b, e);
                }
            }
        }
        println!(
            "{}  now total {:+6.1} % block {:5.1} %   best a {:.2} b {:.2}: total {:+6.1} % block {:5.1} %",
            describe(&c),
            100.0 * base.total,
            100.0 * base.block,
            best.1,
            best.2,
            100.0 * best.3.total,
            100.0 * best.3.block
        );
    }
}

/// The median block error of `cases` with `octaves`.
fn median_block(cases: &[Case], px: u32, spp: u32, octaves: ScatterOctaves) -> f64 {
    let mut v: Vec<f64> = cases
        .iter()
        .map(|c| {
            let (ref_a, ref_b) = cached_reference(c, px, spp);
            errors(&Measured {
                fast: fast_lums(c, px, Scattering::Octaves(octaves)),
                ref_a,
                ref_b,
                sky: background(c, px),
                px: px as usize,
            })
            .block
        })
        .collect();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The octave constants refitted in the medium's form
/// ([`natura_volume::transport::MediumOctaves`]) on the even scenes of the
/// matrix (the median block error), and tested on the odd ones.
#[test]
#[ignore = "slow: a fit, not a check"]
fn refit_octaves_held_out() {
    let (px, spp) = (48, 96);
    let all = full_matrix();
    let train: Vec<Case> = all.iter().step_by(2).copied().collect();
    let test: Vec<Case> = all.iter().skip(1).step_by(2).copied().collect();
    let mut best = (f64::INFINITY, ScatterOctaves::default());
    for (a, b) in [(0.4, 0.4), (0.5, 0.5), (0.6, 0.6), (0.7, 0.7), (0.5, 0.7)] {
        let o = ScatterOctaves {
            a,
            b,
            ..ScatterOctaves::default()
        };
        let m = median_block(&train, px, spp, o);
        println!(
            "a {a} b {b}: training median block error {:.1} %",
            100.0 * m
        );
        if m < best.0 {
            best = (m, o);
        }
    }
    println!(
        "best {:?}: held-out median block error {:.1} % (default {:.1} %)",
        best.1,
        100.0 * median_block(&test, px, spp, best.1),
        100.0 * median_block(&test, px, spp, ScatterOctaves::default())
    );
}
