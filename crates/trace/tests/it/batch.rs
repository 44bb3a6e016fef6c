//! Oracle tests of the batch paths: `MipmapTracer::trace_many` /
//! `occluded_many` (lock-step lanes to each ray's first cell, then the
//! single-ray walk) and `trace_image` return exactly what one call per ray
//! returns, and the brute-force first hit.

use crate::common;

use common::*;
use glam::{Vec2, Vec3};
use natura_core::{Boundary, Grid2, HeightField, NoProgress, Seed};
use natura_trace::{
    Camera, GridTracer, Hit, MipmapTracer, PinholeCamera, Ray, RenderOptions, Tracer, brute_force,
    render_camera, trace_image,
};
use proptest::prelude::*;

/// The same hit, bit for bit.
fn key(h: &Option<Hit>) -> Option<(u32, glam::UVec2, u32, [u32; 3])> {
    h.map(|h| {
        (
            h.t.to_bits(),
            h.cell,
            h.triangle.index(),
            h.point.to_array().map(f32::to_bits),
        )
    })
}

/// Brute-force agreement as in the oracle tests: `t` within 1e-4 relative,
/// the same triangle or (on a shared edge) the same point.
fn near_oracle(got: &Option<Hit>, want: &Option<Hit>, scale: f32) -> Result<(), String> {
    match (got, want) {
        (None, None) => Ok(()),
        (Some(a), Some(b)) => {
            if (a.t - b.t).abs() > 1e-4 * b.t.abs().max(1.0) {
                return Err(format!("t {} vs oracle {}", a.t, b.t));
            }
            if (a.cell, a.triangle) != (b.cell, b.triangle)
                && (a.point - b.point).length() > 1e-3 * scale
            {
                return Err(format!("triangle {:?} vs oracle {:?}", a, b));
            }
            Ok(())
        }
        (a, b) => Err(format!("hit {a:?} but oracle {b:?}")),
    }
}

fn scene() -> impl Strategy<Value = (HeightField, Vec<Ray>, (f32, f32))> {
    any_field().prop_flat_map(|hf| {
        let rays = proptest::collection::vec(ray_for(&hf), 1..40);
        (Just(hf), rays, t_range())
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 800, ..ProptestConfig::default() })]

    /// Batches of rays of every awkward sort (axis-parallel, vertical,
    /// grazing, from below, through corners) on random fields: each batch
    /// result is the single-ray result bit for bit, and the brute-force hit.
    #[test]
    fn batches_match_single_rays_and_brute_force((hf, rays, (t0, t1)) in scene()) {
        batch_matches_single_rays(&hf, &rays, t0, t1, 1)?;
    }
}

/// `trace_many` / `occluded_many` over `rays` equal one `trace` /
/// `occluded` per ray bit for bit, and every `brute_every`-th ray's hit is
/// the brute-force hit (and its occlusion the brute-force answer).
fn batch_matches_single_rays(
    hf: &HeightField,
    rays: &[Ray],
    t0: f32,
    t1: f32,
    brute_every: usize,
) -> Result<(), TestCaseError> {
    let mip = MipmapTracer::new(hf).unwrap();
    let (lo, hi) = hf.min_max();
    let scale = (hi - lo).max(hf.extent().max_element()).max(1.0);
    let many = mip.trace_many(rays, t0, t1);
    let occ = mip.occluded_many(rays, t0, t1);
    prop_assert_eq!(many.len(), rays.len());
    prop_assert_eq!(occ.len(), rays.len());
    for (k, r) in rays.iter().enumerate() {
        let one = mip.trace(r, t0, t1);
        prop_assert_eq!(key(&many[k]), key(&one), "ray {} {:?}", k, r);
        prop_assert_eq!(many[k], one);
        prop_assert_eq!(occ[k], mip.occluded(r, t0, t1));
        if k % brute_every == 0 {
            let want = brute_force(hf, r, t0, t1).unwrap();
            near_oracle(&many[k], &want, scale).map_err(TestCaseError::fail)?;
            prop_assert_eq!(occ[k], want.is_some());
        }
    }
    Ok(())
}

/// A heterogeneous multifractal-like field like the benchmark's, `n × n`.
fn terrain(n: usize, cell: f32, seed: u64) -> HeightField {
    let s = Seed(seed);
    let mut octaves = Vec::new();
    let mut lattice = 4usize;
    while lattice <= n / 2 {
        let so = s.derive_index(lattice as u64);
        octaves.push(
            Grid2::from_fn(lattice + 1, lattice + 1, |i, j| {
                so.gaussian2(i as i64, j as i64) as f32
            })
            .unwrap(),
        );
        lattice *= 2;
    }
    HeightField::from_fn(n, n, cell, |i, j| {
        let (mut h, mut amp) = (0.0f32, 1.0f32);
        for (k, g) in octaves.iter().enumerate() {
            let f = (g.width() - 1) as f32 / (n - 1) as f32;
            let v = g.sample_bilinear(i as f32 * f, j as f32 * f, Boundary::Clamp);
            let w = if k == 0 {
                1.0
            } else {
                (0.6 + 0.5 * h).clamp(0.05, 1.5)
            };
            h += amp * w * v;
            amp *= 0.5;
        }
        1200.0 * h.max(-0.8) + 1000.0
    })
    .unwrap()
}

/// The benchmark's grazing view (30 m above the ground near a corner,
/// looking to the horizon) and its top-down view, at reduced size.
fn views(hf: &HeightField, w: u32, h: u32) -> [PinholeCamera; 2] {
    let e = hf.extent();
    let (x, y) = (0.08 * e.x, 0.08 * e.y);
    let ground = hf.height_at(x, y).unwrap();
    let eye = Vec3::new(x, y, ground + 30.0);
    let target = Vec3::new(0.9 * e.x, 0.75 * e.y, ground - 0.02 * e.x);
    let grazing = PinholeCamera::look_at(eye, target, Vec3::Z, 40f32.to_radians(), w, h).unwrap();
    let c = Vec3::new(0.5 * e.x, 0.5 * e.y, 0.0);
    let topdown =
        PinholeCamera::look_at(c + Vec3::new(0.0, 0.0, 1.3 * e.x), c, Vec3::Y, 0.7, w, h).unwrap();
    [grazing, topdown]
}

fn camera_rays(cam: &PinholeCamera) -> Vec<Ray> {
    let r = cam.resolution();
    (0..r.y)
        .flat_map(|y| (0..r.x).map(move |x| (x, y)))
        .map(|(x, y)| cam.ray(x, y, Vec2::splat(0.5)))
        .collect()
}

/// The benchmark's views on a 129² field: every pixel's batch hit is the
/// single-ray hit, and a subset matches brute force over all triangles.
#[test]
fn bench_views_match_brute_force() {
    let hf = terrain(129, 10.0, 3);
    let mip = MipmapTracer::new(&hf).unwrap();
    let (lo, hi) = hf.min_max();
    let scale = (hi - lo).max(hf.extent().max_element());
    for cam in views(&hf, 64, 36) {
        let rays = camera_rays(&cam);
        let many = mip.trace_many(&rays, 0.0, f32::INFINITY);
        let mut hits = 0;
        for (k, r) in rays.iter().enumerate() {
            assert_eq!(many[k], mip.trace(r, 0.0, f32::INFINITY), "pixel {k}");
            hits += usize::from(many[k].is_some());
            if k % 7 == 0 {
                let want = brute_force(&hf, r, 0.0, f32::INFINITY).unwrap();
                near_oracle(&many[k], &want, scale).unwrap();
            }
        }
        assert!(hits > rays.len() / 3, "{hits} of {}", rays.len());
    }
}

/// On a 1025² field (ten pyramid levels, rays skimming hundreds of cells)
/// the batch paths equal the single-ray paths for primary rays of both
/// views and for shadow rays toward a low sun from their hits; the plain
/// grid tracer (the reference) agrees on a subset.
#[test]
fn large_field_batches_equal_single_rays() {
    let hf = terrain(1025, 10.0, 4);
    let mip = MipmapTracer::new(&hf).unwrap();
    let grid = GridTracer::new(&hf).unwrap();
    let sun = Vec3::new(-0.6, 0.75, 10f32.to_radians().tan()).normalize();
    for cam in views(&hf, 192, 108) {
        let rays = camera_rays(&cam);
        let many = mip.trace_many(&rays, 0.0, f32::INFINITY);
        for (k, r) in rays.iter().enumerate() {
            assert_eq!(many[k], mip.trace(r, 0.0, f32::INFINITY), "pixel {k}");
            if k % 31 == 0 {
                assert_eq!(
                    key(&many[k]),
                    key(&grid.trace(r, 0.0, f32::INFINITY)),
                    "grid tracer, pixel {k}"
                );
            }
        }
        let shadows: Vec<Ray> = many
            .iter()
            .flatten()
            .map(|h| Ray::new(h.point + 0.01 * h.geometric_normal, sun))
            .collect();
        assert!(shadows.len() > 1000);
        let occ = mip.occluded_many(&shadows, 0.0, f32::INFINITY);
        let lit = occ.iter().filter(|&&o| !o).count();
        assert!(lit > 0 && lit < shadows.len(), "{lit} lit");
        for (k, r) in shadows.iter().enumerate() {
            assert_eq!(
                occ[k],
                mip.occluded(r, 0.0, f32::INFINITY),
                "shadow ray {k}"
            );
        }
    }
}

/// `trace_image` equals `render_camera` with a shade that traces each ray
/// itself, bit for bit, with jittered samples, on 1 and 2 threads and any
/// tile size.
#[test]
fn trace_image_equals_per_pixel_rendering_on_any_thread_count() {
    let hf = terrain(257, 10.0, 5);
    let mip = MipmapTracer::new(&hf).unwrap();
    let [cam, _] = views(&hf, 70, 41);
    let shade = |r: &Ray, h: Option<&Hit>| match h {
        Some(h) => Vec3::new(h.t, h.smooth_normal.z, h.cell.x as f32),
        None => Vec3::new(-1.0, r.dir.z, 0.0),
    };
    let options = RenderOptions {
        tile: 16,
        samples_per_pixel: 3,
        seed: Seed(11),
    };
    let want = render_camera(&cam, &options, &NoProgress, |r| {
        shade(r, mip.trace(r, 0.0, f32::INFINITY).as_ref())
    })
    .unwrap();
    let bits = |img: &natura_core::Image| -> Vec<u32> {
        img.pixels()
            .as_slice()
            .iter()
            .flat_map(|p| p.to_array())
            .map(f32::to_bits)
            .collect()
    };
    for (threads, tile) in [(1, 16), (2, 16), (2, 7)] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let o = RenderOptions { tile, ..options };
        let got = pool
            .install(|| trace_image(&mip, &cam, &o, &NoProgress, shade))
            .unwrap();
        assert_eq!(bits(&got), bits(&want), "{threads} threads, tile {tile}");
    }
    // The default (one ray per call) batch of another tracer gives the same image.
    let grid = GridTracer::new(&hf).unwrap();
    let via_grid = trace_image(&grid, &cam, &options, &NoProgress, shade).unwrap();
    assert_eq!(via_grid.width(), want.width());
}

/// Bad input: invalid options are refused; empty batches and invalid rays
/// (NaN, zero direction, empty range) give no hit and never panic.
#[test]
fn bad_input() {
    let hf = terrain(33, 1.0, 6);
    let mip = MipmapTracer::new(&hf).unwrap();
    let [cam, _] = views(&hf, 8, 8);
    let zero = RenderOptions {
        tile: 0,
        ..RenderOptions::default()
    };
    assert!(trace_image(&mip, &cam, &zero, &NoProgress, |_, _| Vec3::ZERO).is_err());
    assert!(mip.trace_many(&[], 0.0, 1.0).is_empty());
    let bad = [
        Ray::new(Vec3::new(1.0, 1.0, 5000.0), Vec3::new(f32::NAN, 0.0, -1.0)),
        Ray::new(Vec3::new(1.0, 1.0, 5000.0), Vec3::ZERO),
        Ray::new(Vec3::splat(f32::INFINITY), Vec3::NEG_Z),
        Ray::new(Vec3::new(10.0, 10.0, 5000.0), Vec3::NEG_Z),
    ];
    let many = mip.trace_many(&bad, 0.0, f32::INFINITY);
    assert_eq!(many[..3], [None, None, None]);
    assert!(many[3].is_some());
    assert_eq!(mip.trace_many(&bad, 2.0, 1.0), vec![None; 4]);
    assert_eq!(mip.occluded_many(&bad, f32::NAN, 1.0), vec![false; 4]);
}

/// Packets of rays from one origin (what the packet skip bounds as a
/// whole): a random origin in or around the box (also below the surface
/// and on lattice points), a random base direction (axis-parallel,
/// vertical, grazing, diagonal …) and directions spread around it from
/// not at all to fully divergent, some made exactly axis-parallel or
/// vertical, over random ranges.
fn packet_scene() -> impl Strategy<Value = (HeightField, Vec<Ray>, (f32, f32))> {
    any_field().prop_flat_map(|hf| {
        (
            ray_for(&hf),
            ray_for(&hf),
            prop_oneof![Just(0.0f32), 0.0f32..0.05, 0.0f32..2.0],
            1usize..160,
            any::<u64>(),
            t_range(),
            Just(hf),
        )
            .prop_map(|(o, base, spread, n, seed, range, hf)| {
                let s = Seed(seed);
                let cell = hf.cell_size();
                let rays = (0..n as i64)
                    .map(|k| {
                        let j = Vec3::new(
                            s.uniform2(k, 0) as f32 - 0.5,
                            s.uniform2(k, 1) as f32 - 0.5,
                            s.uniform2(k, 2) as f32 - 0.5,
                        );
                        let mut d = base.dir + spread * 2.0 * j * Vec3::new(cell, cell, 1.0);
                        match s.uniform2(k, 3) {
                            u if u < 0.05 => d.y = 0.0,
                            u if u < 0.10 => d.x = 0.0,
                            u if u < 0.13 => d = Vec3::new(0.0, 0.0, d.z),
                            _ => {}
                        }
                        Ray::new(o.origin, d)
                    })
                    .collect::<Vec<_>>();
                (hf, rays, range)
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// One-origin packets (the packet skip's case), converging or
    /// diverging: each batch result is the single-ray result bit for bit,
    /// and the brute-force hit.
    #[test]
    fn one_origin_packets_match_single_rays_and_brute_force((hf, rays, (t0, t1)) in packet_scene()) {
        batch_matches_single_rays(&hf, &rays, t0, t1, 3)?;
    }
}

/// Camera tiles through the batch path (one origin per tile, traced in tile
/// order as `trace_image` does) on a 513² terrain equal one `trace` per ray
/// bit for bit: the grazing and top-down views, a camera looking exactly
/// along +x and along −y (axis-parallel rays in the middle row and column),
/// one inside the box below the highest peaks, one below the surface, and a
/// 170° field of view (strongly diverging packets).
#[test]
fn camera_tiles_equal_single_rays() {
    let hf = terrain(513, 10.0, 8);
    let mip = MipmapTracer::new(&hf).unwrap();
    let e = hf.extent();
    let (lo, hi) = hf.min_max();
    let at = |x: f32, y: f32| hf.height_at(x, y).unwrap();
    let [grazing, topdown] = views(&hf, 96, 64);
    let (x0, y0) = (0.1 * e.x, 0.5 * e.y);
    let along_x = PinholeCamera::look_at(
        Vec3::new(x0, y0, at(x0, y0) + 5.0),
        Vec3::new(e.x, y0, at(x0, y0) - 20.0),
        Vec3::Z,
        0.5,
        65,
        33,
    )
    .unwrap();
    let (x1, y1) = (0.6 * e.x, 0.9 * e.y);
    let along_y = PinholeCamera::look_at(
        Vec3::new(x1, y1, 0.5 * (lo + hi)),
        Vec3::new(x1, 0.0, lo),
        Vec3::Z,
        0.8,
        33,
        65,
    )
    .unwrap();
    let (x2, y2) = (0.3 * e.x, 0.7 * e.y);
    let below = PinholeCamera::look_at(
        Vec3::new(x2, y2, at(x2, y2) - 3.0),
        Vec3::new(0.9 * e.x, 0.1 * e.y, hi),
        Vec3::Z,
        1.0,
        48,
        48,
    )
    .unwrap();
    let wide = PinholeCamera::look_at(
        Vec3::new(0.5 * e.x, 0.5 * e.y, hi + 50.0),
        Vec3::new(0.9 * e.x, 0.6 * e.y, lo),
        Vec3::Z,
        170f32.to_radians(),
        80,
        48,
    )
    .unwrap();
    let options = RenderOptions::default();
    for (name, cam) in [
        ("grazing", grazing),
        ("topdown", topdown),
        ("along x", along_x),
        ("along y", along_y),
        ("below", below),
        ("wide", wide),
    ] {
        let res = cam.resolution();
        let mut hits = 0;
        for tile in [32, 13] {
            for by in (0..res.y).step_by(tile as usize) {
                for bx in (0..res.x).step_by(tile as usize) {
                    let (w, h) = (tile.min(res.x - bx), tile.min(res.y - by));
                    let mut rays = Vec::new();
                    cam.rays_into(bx, by, w, h, &options, &mut rays);
                    let many = mip.trace_many(&rays, 0.0, f32::INFINITY);
                    for (k, r) in rays.iter().enumerate() {
                        let one = mip.trace(r, 0.0, f32::INFINITY);
                        assert_eq!(
                            key(&many[k]),
                            key(&one),
                            "{name}: tile ({bx}, {by}) ray {k}"
                        );
                        assert_eq!(many[k], one, "{name}");
                        hits += usize::from(one.is_some());
                    }
                }
            }
        }
        assert!(hits > 0, "{name}: no hits");
    }
}
