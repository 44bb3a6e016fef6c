//! The lanes against the single-ray walk, stage by stage, at every
//! instruction set.

use super::kernels::{descend_with, hits_with, setup_with};
use super::node::{event_mask, event_mask_avx2};
use super::walk::walk_lanes_with;
use super::*;
use crate::Hit;
use crate::Ray;
use crate::max_mipmap::MipmapTracer;
use crate::ray::TraceStats;
use crate::ray_cell::{CellHit, HIT_LANES, HitLanes};
use glam::Vec3;
use natura_core::simd::Simd;
use natura_core::{HeightField, Seed};

/// The single-ray walk from the scalar pre-descent's cursor ends exactly
/// as the walk from the start (closest and any hit), on fields with
/// plateaus and flats (altitudes on node bounds) and rays from inside
/// the box, from above, along axes and vertical; and the pre-descent
/// does descend for rays starting among the terrain.
#[test]
fn pre_descent_leaves_the_walk_unchanged() {
    let s = Seed(31);
    let mut descended = 0;
    for (case, plateau) in [(0i64, false), (1, true), (2, true), (3, false)] {
        let hf = HeightField::from_fn(150 + case as usize * 40, 97, 1.5, |i, j| {
            let v = 30.0 * s.uniform2(i as i64 / 5 + case * 1000, j as i64 / 4) as f32;
            if plateau {
                (v / 7.5).floor() * 7.5
            } else {
                v + s.uniform2(i as i64, j as i64) as f32
            }
        })
        .unwrap();
        let tr = MipmapTracer::new(&hf).unwrap();
        for k in 0..1500i64 {
            let u = |c: i64| s.uniform2(case * 100_000 + k, c) as f32;
            let o = Vec3::new(300.0 * u(0) - 30.0, 170.0 * u(1) - 15.0, 40.0 * u(2) - 5.0);
            let o = if k % 4 == 0 { o.round() } else { o };
            let d = match k % 5 {
                0 => Vec3::new(u(3) - 0.5, 0.0, 0.1 * (u(5) - 0.5)),
                1 => Vec3::new(0.0, 0.0, -1.0),
                _ => Vec3::new(u(3) - 0.5, u(4) - 0.5, 0.3 * (u(5) - 0.6)),
            };
            let Some(r) = tr.setup(&Ray::new(o, d), 0.0, f32::INFINITY) else {
                continue;
            };
            let c = tr.start(&r);
            let mut st = TraceStats::default();
            let c2 = tr.descend(&r, c, &mut st);
            descended += usize::from(c2.level < c.level);
            let key = |h: Option<CellHit>| h.map(|h| (h.t.to_bits(), h.cell, h.triangle.index()));
            assert_eq!(
                key(tr.walk::<false>(&r, c2, &mut st)),
                key(tr.walk::<false>(&r, c, &mut st)),
                "case {case}, ray {k}"
            );
            assert_eq!(
                tr.walk::<true>(&r, c2, &mut st).is_some(),
                tr.walk::<true>(&r, c, &mut st).is_some()
            );
        }
    }
    assert!(descended > 1000, "{descended}");
}

/// The step's event masks (parked lanes in the low half, departed lanes
/// in the high half) are the same from the portable loop and the AVX2
/// compares, and say exactly which lanes report which event.
#[test]
fn event_masks_agree_at_every_instruction_set() {
    let s = Seed(5);
    for k in 0..4000i64 {
        let mut events = [GOING; LANES];
        for (l, e) in events.iter_mut().enumerate() {
            *e = match (s.uniform2(k, l as i64) * 3.0) as u32 {
                0 => GOING,
                1 => AT_CELL,
                _ => LEFT,
            };
        }
        if k % 7 == 0 {
            events = [[GOING, AT_CELL, LEFT][(k / 7 % 3) as usize]; LANES];
        }
        let m = event_mask(&events);
        for (l, &e) in events.iter().enumerate() {
            assert_eq!((m >> l) & 1 == 1, e == AT_CELL);
            assert_eq!((m >> (l + LANES)) & 1 == 1, e == LEFT);
        }
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            #[allow(unsafe_code)]
            // SAFETY: the CPU reported AVX2.
            let v = unsafe { event_mask_avx2(&events) };
            assert_eq!(v, m, "{events:?}");
        }
    }
}

/// The instruction sets this CPU supports, portable code first.
fn levels() -> Vec<Simd> {
    Simd::supported().collect()
}

/// The set-up in lanes equals `setup` (`GridRay::new` and the box test),
/// `start` and `descend` bit for bit, at every instruction set: rays with zero,
/// tiny, huge, infinite and NaN components, zero directions, axis-parallel
/// and vertical rays, rays through grid points, inside and outside the
/// box, over several ranges.
#[test]
fn lane_set_up_equals_the_single_ray_set_up() {
    let s = Seed(41);
    let hf = HeightField::from_fn(77, 45, 2.5, |i, j| {
        30.0 * s.uniform2(i as i64, j as i64) as f32 - 4.0
    })
    .unwrap();
    let tr = MipmapTracer::new(&hf).unwrap();
    let f = &tr.f;
    let pick = |k: i64, c: i64, scale: f32, off: f32| {
        let u = s.uniform2(1000 + k, c) as f32;
        match (k + c) % 23 {
            0 => 0.0,
            1 => f32::NAN,
            2 => f32::INFINITY,
            3 => -1e30,
            4 => 1e-30,
            5 => (scale * u + off).round(),
            _ => scale * u + off,
        }
    };
    let mut rays = Vec::new();
    for k in 0..4000i64 {
        let o = Vec3::new(
            pick(k, 0, 260.0, -30.0),
            pick(k, 1, 160.0, -20.0),
            pick(k, 2, 60.0, -10.0),
        );
        let mut d = Vec3::new(
            pick(k, 3, 2.0, -1.0),
            pick(k, 4, 2.0, -1.0),
            pick(k, 5, 2.0, -1.0),
        );
        match k % 6 {
            0 => d.x = 0.0,
            1 => d.y = 0.0,
            2 => d = Vec3::new(0.0, 0.0, d.z),
            3 => d = Vec3::ZERO,
            _ => {}
        }
        rays.push(Ray::new(o, d));
    }
    let bits3 = |v: Vec3| v.to_array().map(f32::to_bits);
    let mut met = 0;
    let mut descents = 0;
    for (t_min, t_max) in [
        (0.0, f32::INFINITY),
        (f32::NEG_INFINITY, f32::INFINITY),
        (-3.0, 70.0),
        (2.0, 2.0),
    ] {
        for &level in &levels() {
            let mut lanes = SetupLanes::new();
            let mut offset = [0u32; 32];
            for (o, &m) in offset.iter_mut().zip(&tr.mip.offset) {
                *o = m as u32;
            }
            let mut dl = [0u32; SETUP_LANES];
            for group in rays.chunks_exact(SETUP_LANES) {
                let g: &[Ray; SETUP_LANES] = group.try_into().unwrap();
                setup_with(level, f, g, t_min, t_max, tr.mip.top, &mut lanes);
                descend_with(level, &tr, &offset, &mut lanes, &mut dl);
                for (l, ray) in group.iter().enumerate() {
                    let want = tr.setup(ray, t_min, t_max);
                    assert_eq!(lanes.ok[l], want.is_some(), "{level:?} {ray:?}");
                    let Some(w) = want else { continue };
                    met += 1;
                    let g = lanes.ray(l, t_min, t_max);
                    let key = |r: &GridRay| {
                        (
                            bits3(r.o),
                            bits3(r.d),
                            [r.inv.x, r.inv.y, r.t_min, r.t_max, r.t0, r.t1].map(f32::to_bits),
                            [r.zeps, r.xyeps, r.ttol, r.zm].map(f32::to_bits),
                            [bits3(r.shear.px), bits3(r.shear.py), bits3(r.shear.pz)],
                        )
                    };
                    assert_eq!(key(&g), key(&w), "{level:?} {ray:?}");
                    let c = tr.start(&w);
                    assert_eq!(
                        (lanes.ci[l], lanes.cj[l], lanes.level[l]),
                        (c.ci, c.cj, c.level),
                        "{level:?} {ray:?}"
                    );
                    let dc = tr.descend(&w, c, &mut TraceStats::default());
                    assert_eq!(dl[l], dc.level, "descent: {level:?} {ray:?}");
                    descents += usize::from(dc.level < c.level);
                }
            }
        }
    }
    assert!(met > 5000, "{met} rays meet the box");
    assert!(descents > 1000, "{descents} rays descend at the start");
}

/// The hit records filled in lanes equal `make_hit`'s bit for bit, at
/// every instruction set: fields too small for interior cells, border and
/// interior cells, both triangles, barycentrics on corners and edges, flat
/// (zero-gradient) and steep fields, partial groups.
#[test]
fn hit_lanes_equal_make_hit() {
    use crate::ray::Triangle;
    use crate::ray_cell::make_hit;
    let s = Seed(43);
    let mut checked = 0;
    for (case, (nx, ny, cell)) in [
        (2, 2, 1.0),
        (3, 5, 0.5),
        (4, 4, 2.0),
        (37, 23, 3.7),
        (64, 65, 10.0),
    ]
    .into_iter()
    .enumerate()
    {
        for kind in 0..3 {
            let hf = HeightField::from_fn(nx, ny, cell, |i, j| {
                let v = s.uniform2(case as i64 * 100 + i as i64, j as i64) as f32;
                match kind {
                    0 => 5.0,
                    1 => 300.0 * v - 50.0,
                    _ => (3.0 * v).floor() * 1e-3 + 1e4,
                }
            })
            .unwrap();
            let tr = MipmapTracer::new(&hf).unwrap();
            let f = &tr.f;
            let mut lanes = HitLanes::new();
            let mut rays = Vec::new();
            for k in 0..200i64 {
                let u = |c: i64| s.uniform2(k + 7919 * case as i64, c + 10 * kind) as f32;
                let (i, j) = ((u(0) * f.ncx as f32) as u32, (u(1) * f.ncy as f32) as u32);
                let (i, j) = (i.min(f.ncx - 1), j.min(f.ncy - 1));
                let bary = match k % 5 {
                    0 => Vec3::new(1.0, 0.0, 0.0),
                    1 => Vec3::new(0.5, 0.5, 0.0),
                    _ => {
                        let (a, b) = (u(2), u(3) * (1.0 - u(2)));
                        Vec3::new(a, b, 1.0 - a - b)
                    }
                };
                let triangle = if k % 2 == 0 {
                    Triangle::Lower
                } else {
                    Triangle::Upper
                };
                let hit = CellHit {
                    t: u(4) * 100.0,
                    cell: (i, j),
                    triangle,
                    bary,
                };
                let ray = Ray::new(Vec3::ZERO, Vec3::new(u(5) - 0.5, u(6) - 0.5, u(7) - 0.7));
                rays.push((hit, ray));
            }
            for &level in &levels() {
                for group in rays.chunks(HIT_LANES) {
                    for (l, (h, r)) in group.iter().enumerate() {
                        lanes.hit[l] = *h;
                        lanes.dir[l] = r.dir;
                    }
                    let mut out = vec![None; group.len()];
                    let slot: [usize; HIT_LANES] = std::array::from_fn(|l| l);
                    hits_with(level, f, &lanes, group.len(), &mut out, &slot);
                    for ((h, r), got) in group.iter().zip(&out) {
                        let want = make_hit(f, r, *h);
                        let got = got.expect("every lane is filled in");
                        let key = |h: &Hit| {
                            (
                                h.t.to_bits(),
                                [h.point, h.geometric_normal, h.smooth_normal, h.barycentric]
                                    .map(|v| v.to_array().map(f32::to_bits)),
                                h.cell,
                                h.triangle,
                                h.from_above,
                            )
                        };
                        assert_eq!(key(&got), key(&want), "{level:?}, {nx} × {ny}, {h:?}");
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 5000, "{checked}");
}

/// The lane step's shift form of a level's width equals the pyramid's.
#[test]
fn level_widths_by_shift() {
    for nx in [2usize, 3, 5, 17, 64, 65, 100, 1025] {
        let hf = HeightField::flat(nx, 3, 1.0, 0.0).unwrap();
        let tr = MipmapTracer::new(&hf).unwrap();
        let m = tr.mipmap();
        let ncx = (nx - 1) as u32;
        for k in 1..=m.top_level() {
            assert_eq!(
                ((ncx - 1) >> k) + 1,
                m.level_dims(k).unwrap().0,
                "{nx}, level {k}"
            );
        }
    }
}

/// Every instruction set this CPU supports ends every walk the same way
/// as the portable code, bit for bit.
#[test]
fn every_level_gives_the_same_outcomes() {
    let s = Seed(7);
    let hf = HeightField::from_fn(300, 213, 2.0, |i, j| {
        40.0 * s.uniform2(i as i64 / 9, j as i64 / 7) as f32
            + 3.0 * s.uniform2(i as i64, j as i64) as f32
    })
    .unwrap();
    let tr = MipmapTracer::new(&hf).unwrap();
    let mut rays = Vec::new();
    for k in 0..3000i64 {
        let u = |c: i64| s.uniform2(k, c) as f32;
        let o = Vec3::new(600.0 * u(0) - 20.0, 430.0 * u(1) - 20.0, 60.0 * u(2) - 5.0);
        let d = Vec3::new(u(3) - 0.5, u(4) - 0.5, 0.2 * (u(5) - 0.6));
        rays.push(Ray::new(o, d));
    }
    let grid: Vec<GridRay> = rays
        .iter()
        .map(|r| {
            tr.setup(r, 0.0, f32::INFINITY)
                .unwrap_or_else(GridRay::idle)
        })
        .collect();
    let start: Vec<Option<Cursor>> = rays
        .iter()
        .map(|r| tr.setup(r, 0.0, f32::INFINITY).map(|g| tr.start(&g)))
        .collect();
    let key = |o: &Outcome| match *o {
        Outcome::Miss => (0, 0, 0, 0, 0),
        Outcome::Hit(h) => (1, h.t.to_bits(), h.cell.0, h.cell.1, h.triangle.index()),
        Outcome::Walk(c) => (2, c.t.to_bits(), c.ci, c.cj, c.level),
    };
    let levels: Vec<Simd> = Simd::supported().skip(1).collect();
    for any in [false, true] {
        let run = |level: Simd| {
            let mut out = Vec::new();
            if any {
                walk_lanes_with::<true, [GridRay]>(
                    level,
                    0,
                    &tr,
                    grid.as_slice(),
                    &start,
                    None,
                    &mut out,
                );
            } else {
                walk_lanes_with::<false, [GridRay]>(
                    level,
                    0,
                    &tr,
                    grid.as_slice(),
                    &start,
                    None,
                    &mut out,
                );
            }
            out
        };
        let want = run(Simd::baseline());
        let hits = want.iter().filter(|o| matches!(o, Outcome::Hit(_))).count();
        assert!(hits > 1000, "{hits}");
        for &level in &levels {
            let got = run(level);
            for (g, w) in got.iter().zip(&want) {
                assert_eq!(key(g), key(w), "{level:?}");
            }
        }
        // The batch path's rays, set up in lanes (and walked from the
        // lane pre-descent), end the same way at every instruction set.
        for level in levels.iter().copied().chain([Simd::baseline()]) {
            let mut groups = vec![SetupLanes::new(); rays.len().div_ceil(SETUP_LANES)];
            let mut dl = vec![0u32; groups.len() * SETUP_LANES];
            let mut offset = [0u32; 32];
            for (o, &m) in offset.iter_mut().zip(&tr.mip.offset) {
                *o = m as u32;
            }
            for (g, (chunk, d)) in groups
                .iter_mut()
                .zip(rays.chunks(SETUP_LANES).zip(dl.chunks_mut(SETUP_LANES)))
            {
                let mut a = [chunk[0]; SETUP_LANES];
                a[..chunk.len()].copy_from_slice(chunk);
                setup_with(level, &tr.f, &a, 0.0, f32::INFINITY, tr.mip.top, g);
                descend_with(level, &tr, &offset, g, d.try_into().unwrap());
            }
            let soa = SoaRays {
                groups: &groups,
                t_min: 0.0,
                t_max: f32::INFINITY,
            };
            let mut got = Vec::new();
            if any {
                walk_lanes_with::<true, _>(level, 0, &tr, &soa, &start, Some(&dl), &mut got);
            } else {
                walk_lanes_with::<false, _>(level, 0, &tr, &soa, &start, Some(&dl), &mut got);
            }
            let mut stats = TraceStats::default();
            for (k, (g, w)) in got.iter().zip(&want).enumerate() {
                // Hand-overs to the single-ray walk may start from a
                // different cursor (the lanes walked from the descent):
                // compare where the walks end.
                let mut end = |o: &Outcome| match *o {
                    Outcome::Walk(c) => match if any {
                        tr.walk::<true>(&grid[k], c, &mut stats)
                    } else {
                        tr.walk::<false>(&grid[k], c, &mut stats)
                    } {
                        Some(h) => Outcome::Hit(h),
                        None => Outcome::Miss,
                    },
                    o => o,
                };
                assert_eq!(
                    key(&end(g)),
                    key(&end(w)),
                    "lane set-up, {level:?}, ray {k}"
                );
            }
        }
    }
}

/// Every ray walked in the lanes from its start (whatever its level)
/// ends with the single-ray walk's hit, bit for bit: small fields of
/// every kind (flat, spiky, plateaus, tilted) and rays of every awkward
/// sort (axis-parallel, vertical, grazing, through corners, from below,
/// from inside), closest and any hit.
#[test]
fn lanes_equal_the_single_ray_walk_on_awkward_rays() {
    let s = Seed(23);
    let mut checked = 0;
    for case in 0..60i64 {
        let u = |a: i64, b: i64| s.uniform2(case * 1000 + a, b) as f32;
        let (nx, ny) = (2 + (u(0, 0) * 40.0) as usize, 2 + (u(0, 1) * 40.0) as usize);
        let cell = [1.0, 0.5, 2.0, 3.7][case as usize % 4];
        let kind = case % 5;
        let hf = HeightField::from_fn(nx, ny, cell, |i, j| {
            let v = s.uniform2(case * 7919 + i as i64, j as i64) as f32;
            match kind {
                0 => 10.0 * v,
                1 => 3.0,
                2 => {
                    if v > 0.85 {
                        20.0 * v
                    } else {
                        0.0
                    }
                }
                3 => (4.0 * v).floor() * 2.5,
                _ => 0.7 * i as f32 - 0.4 * j as f32 + 2.0,
            }
        })
        .unwrap();
        let tr = MipmapTracer::new(&hf).unwrap();
        let (lo, hi) = hf.min_max();
        let mut rays = Vec::new();
        for k in 0..64i64 {
            let r = |c: i64| u(k + 1, c);
            let o = Vec3::new(
                (1.6 * r(0) - 0.3) * nx as f32 * cell,
                (1.6 * r(1) - 0.3) * ny as f32 * cell,
                lo + (1.6 * r(2) - 0.3) * (hi - lo + 1.0),
            );
            let o = if k % 5 == 0 {
                (o / cell).round() * cell
            } else {
                o
            };
            let d = match k % 6 {
                0 => Vec3::new(r(3) - 0.5, r(4) - 0.5, r(5) - 0.5),
                1 => Vec3::new(if r(3) > 0.5 { 1.0 } else { -1.0 }, 0.0, r(5) - 0.5),
                2 => Vec3::new(0.0, if r(3) > 0.5 { 1.0 } else { -1.0 }, r(5) - 0.5),
                3 => Vec3::new(0.0, 0.0, if r(3) > 0.5 { 1.0 } else { -1.0 }),
                4 => Vec3::new(r(3) - 0.5, r(4) - 0.5, 0.02 * (r(5) - 0.5)),
                _ => Vec3::new(1.0, if r(3) > 0.5 { 1.0 } else { -1.0 }, 0.3 * (r(5) - 0.5)),
            };
            rays.push(Ray::new(o, d * Vec3::new(cell, cell, 1.0)));
        }
        let grid: Vec<GridRay> = rays
            .iter()
            .map(|r| {
                tr.setup(r, 0.0, f32::INFINITY)
                    .unwrap_or_else(GridRay::idle)
            })
            .collect();
        let start: Vec<Option<Cursor>> = rays
            .iter()
            .map(|r| tr.setup(r, 0.0, f32::INFINITY).map(|g| tr.start(&g)))
            .collect();
        let key = |h: Option<CellHit>| h.map(|h| (h.t.to_bits(), h.cell, h.triangle.index()));
        let mut stats = TraceStats::default();
        let mut out = Vec::new();
        walk_lanes_with::<false, [GridRay]>(
            Simd::best(),
            0,
            &tr,
            grid.as_slice(),
            &start,
            None,
            &mut out,
        );
        for (k, (r, o)) in grid.iter().zip(&out).enumerate() {
            let got = match *o {
                Outcome::Miss => None,
                Outcome::Hit(h) => Some(h),
                Outcome::Walk(c) => tr.walk::<false>(r, c, &mut stats),
            };
            let want = start[k].and_then(|c| tr.walk::<false>(r, c, &mut stats));
            assert_eq!(key(got), key(want), "case {case}, ray {k}: {:?}", rays[k]);
            checked += usize::from(want.is_some());
        }
        walk_lanes_with::<true, [GridRay]>(
            Simd::best(),
            0,
            &tr,
            grid.as_slice(),
            &start,
            None,
            &mut out,
        );
        for (k, (r, o)) in grid.iter().zip(&out).enumerate() {
            let got = match *o {
                Outcome::Miss => false,
                Outcome::Hit(_) => true,
                Outcome::Walk(c) => tr.walk::<true>(r, c, &mut stats).is_some(),
            };
            let want = start[k].is_some_and(|c| tr.walk::<true>(r, c, &mut stats).is_some());
            assert_eq!(got, want, "any hit: case {case}, ray {k}");
        }
    }
    assert!(checked > 500, "{checked} hits");
}
