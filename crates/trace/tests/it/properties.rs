//! Geometric properties of the tracers: hits on the
//! surface and on the ray, rising rays miss, reversibility, analytic cases,
//! symmetries, normals, the traversal order, and refusals of bad input.

use crate::common;

use approx::assert_relative_eq;
use common::*;
use glam::{UVec2, Vec3};
use natura_core::{Grid2, HeightField};
use natura_trace::{
    GridTracer, MaxMipmap, MipmapTracer, Ray, TraceError, Tracer, Triangle, brute_force,
    surface_height,
};
use proptest::prelude::*;

fn scale(hf: &HeightField) -> f32 {
    let (lo, hi) = hf.min_max();
    (hi - lo).max(hf.extent().max_element()).max(1.0)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    /// Properties 2–4, 13: a hit lies on the ray, on the surface, in its cell
    /// and triangle; its normals are unit, upward, and the geometric one is
    /// perpendicular to the triangle.
    #[test]
    fn hits_lie_on_the_surface_and_the_ray(
        (hf, ray, (t0, t1)) in any_field().prop_flat_map(|hf| { let r = ray_for(&hf); (Just(hf), r, t_range()) })
    ) {
        let mip = MipmapTracer::new(&hf).unwrap();
        if let Some(h) = mip.trace(&ray, t0, t1) {
            let s = scale(&hf);
            prop_assert!(h.t >= t0 && h.t <= t1);
            prop_assert!((h.point - ray.at(h.t)).length() <= 1e-4 * s * ray.dir.length().max(1.0));
            // A ray along the field's border may round a hair past it.
            let e = hf.extent();
            let (qx, qy) = (h.point.x.clamp(0.0, e.x), h.point.y.clamp(0.0, e.y));
            prop_assert!((qx - h.point.x).abs() <= 1e-4 * s && (qy - h.point.y).abs() <= 1e-4 * s);
            let z = surface_height(&hf, qx, qy).unwrap();
            prop_assert!((z - h.point.z).abs() <= 1e-4 * s, "surface {} vs hit {}", z, h.point.z);
            let c = hf.cell_size();
            let (u, v) = (h.point.x / c - h.cell.x as f32, h.point.y / c - h.cell.y as f32);
            let e = 1e-4;
            prop_assert!(u >= -e && v >= -e && u <= 1.0 + e && v <= 1.0 + e);
            match h.triangle {
                Triangle::Lower => prop_assert!(u + v <= 1.0 + e),
                Triangle::Upper => prop_assert!(u + v >= 1.0 - e),
            }
            prop_assert!((h.barycentric.element_sum() - 1.0).abs() < 1e-4);
            for n in [h.geometric_normal, h.smooth_normal] {
                prop_assert!((n.length() - 1.0).abs() < 1e-5 && n.z > 0.0);
            }
            let k = h.triangle.corners().map(|(di, dj)| hf.point((h.cell.x + di) as usize, (h.cell.y + dj) as usize));
            for (a, b) in [(k[0], k[1]), (k[0], k[2])] {
                prop_assert!(h.geometric_normal.dot((b - a).normalize()).abs() < 1e-4);
            }
            prop_assert_eq!(h.from_above, ray.dir.dot(h.geometric_normal) < 0.0);
            // Property 6: the segment up to just before the hit is unobstructed.
            let before = h.t - 1e-3 * (h.t - t0.max(-1e30)).abs().max(1e-3);
            if before > t0 {
                let first = mip.trace(&ray, t0, before);
                prop_assert!(first.is_none(), "a hit before the closest: {:?}", first);
            }
        }
    }

    /// Property 9: a ray above the highest point going up (or level) never hits.
    #[test]
    fn rising_rays_above_the_field_miss(
        hf in any_field(),
        (x, y, dz) in (-0.5f32..1.5, -0.5f32..1.5, 0.0f32..1.0),
        (dx, dy) in (-1.0f32..1.0, -1.0f32..1.0),
        above in 1e-3f32..50.0,
    ) {
        let e = hf.extent();
        let (_, hi) = hf.min_max();
        let ray = Ray::new(Vec3::new(x * e.x, y * e.y, hi + above), Vec3::new(dx, dy, dz));
        prop_assert!(MipmapTracer::new(&hf).unwrap().trace(&ray, 0.0, f32::INFINITY).is_none());
        prop_assert!(GridTracer::new(&hf).unwrap().trace(&ray, 0.0, f32::INFINITY).is_none());
    }

    /// A segment crosses the surface if and only if its reverse does.
    #[test]
    fn a_ray_and_its_reverse_agree(
        hf in any_field(),
        a in (-0.2f32..1.2, -0.2f32..1.2, -0.2f32..1.2),
        b in (-0.2f32..1.2, -0.2f32..1.2, -0.2f32..1.2),
    ) {
        let e = hf.extent();
        let (lo, hi) = hf.min_max();
        let p = |(x, y, z): (f32, f32, f32)| Vec3::new(x * e.x, y * e.y, lo + z * (hi - lo + 1.0));
        let (pa, pb) = (p(a), p(b));
        // Keep clear of the surface so the endpoints are unambiguous.
        for q in [pa, pb] {
            if let Some(z) = surface_height(&hf, q.x, q.y) {
                prop_assume!((q.z - z).abs() > 1e-3 * scale(&hf));
            }
        }
        prop_assume!((pb - pa).length() > 1e-3);
        let mip = MipmapTracer::new(&hf).unwrap();
        let fwd = mip.occluded(&Ray::new(pa, pb - pa), 0.0, 1.0);
        let back = mip.occluded(&Ray::new(pb, pa - pb), 0.0, 1.0);
        prop_assert_eq!(fwd, back);
        // And the forward closest hit is the backward farthest: tracing back from
        // just past the forward hit toward `pa` finds it again.
        if let Some(h) = mip.trace(&Ray::new(pa, pb - pa), 0.0, 1.0) {
            let from = h.point + (pb - pa) * 1e-3;
            let r = Ray::new(from, pa - from);
            let back_hit = mip.trace(&r, 0.0, 1.0);
            prop_assert!(back_hit.is_some());
        }
    }

    /// Property 14: a vertical ray from above lands on the surface under it.
    #[test]
    fn vertical_rays_land_on_the_surface(hf in any_field(), (x, y) in (0.0f32..1.0, 0.0f32..1.0)) {
        let e = hf.extent();
        let (_, hi) = hf.min_max();
        let (x, y) = (x * e.x, y * e.y);
        let ray = Ray::new(Vec3::new(x, y, hi + 10.0), Vec3::NEG_Z);
        let h = MipmapTracer::new(&hf).unwrap().trace(&ray, 0.0, f32::INFINITY).unwrap();
        let z = surface_height(&hf, x, y).unwrap();
        prop_assert!((h.point.z - z).abs() <= 1e-4 * scale(&hf));
        prop_assert!((h.t - (hi + 10.0 - z)).abs() <= 1e-4 * scale(&hf));
    }

    /// Property 11: transposing the field and the ray transposes the hit;
    /// rotating both by 180° rotates it (both keep the anti-diagonal split).
    #[test]
    fn symmetries_of_the_split(
        (hf, ray) in any_field().prop_flat_map(|hf| { let r = ray_for(&hf); (Just(hf), r) })
    ) {
        let (nx, ny) = (hf.nx(), hf.ny());
        let c = hf.cell_size();
        let e = hf.extent();
        let h = hf.heights();
        let tr = HeightField::from_fn(ny, nx, c, |i, j| h[(j, i)]).unwrap();
        let rot = HeightField::from_fn(nx, ny, c, |i, j| h[(nx - 1 - i, ny - 1 - j)]).unwrap();
        let swap = |v: Vec3| Vec3::new(v.y, v.x, v.z);
        let ray_t = Ray::new(swap(ray.origin), swap(ray.dir));
        let ray_r = Ray::new(
            Vec3::new(e.x - ray.origin.x, e.y - ray.origin.y, ray.origin.z),
            Vec3::new(-ray.dir.x, -ray.dir.y, ray.dir.z),
        );
        let base = MipmapTracer::new(&hf).unwrap().trace(&ray, 0.0, f32::INFINITY);
        let t = MipmapTracer::new(&tr).unwrap().trace(&ray_t, 0.0, f32::INFINITY);
        let r = MipmapTracer::new(&rot).unwrap().trace(&ray_r, 0.0, f32::INFINITY);
        let tol = |a: f32| 1e-4 * a.abs().max(1.0);
        match (base, t, r) {
            (None, None, None) => {}
            (Some(b), Some(t), Some(r)) => {
                // Mirroring rounds the ray's origin by an ulp of the field's
                // size, which moves the hit along a ray that grazes the
                // triangle by that over the cosine between them (a ray
                // 0.2° off a near-vertical face moved it by 2.6e-4 in 2.5).
                let cos = b.geometric_normal.dot(ray.dir.normalize()).abs().max(1e-6);
                let tol = |a: f32| tol(a) + 4.0 * f32::EPSILON * scale(&hf) / cos;
                prop_assert!(
                    (b.t - t.t).abs() <= tol(b.t) && (b.t - r.t).abs() <= tol(b.t),
                    "{ray:?}: {b:?}, transposed {t:?}, rotated {r:?}"
                );
                prop_assert!((swap(b.point) - t.point).length() <= 1e-3 * scale(&hf));
            }
            (b, t, r) => {
                // Mirroring the ray rounds its origin: a hit exactly on the
                // field's outer border may fall just outside in another frame.
                let on_border = |p: Vec3| {
                    let m = 1e-4 * scale(&hf);
                    p.x <= m || p.y <= m || p.x >= e.x - m || p.y >= e.y - m
                };
                for h in [b, t, r].into_iter().flatten() {
                    let p = h.point;
                    prop_assert!(
                        on_border(p) || on_border(swap(p)) || on_border(Vec3::new(e.x - p.x, e.y - p.y, p.z))
                            || on_border(Vec3::new(e.y - p.x, e.x - p.y, p.z)),
                        "hit in some frames only, away from the border: {:?}", (b, t, r)
                    );
                }
            }
        }
    }

    /// Property 12: raising the field and the ray together leaves `t` unchanged.
    #[test]
    fn height_offsets_leave_t_unchanged(
        (hf, ray) in any_field().prop_flat_map(|hf| { let r = ray_for(&hf); (Just(hf), r) }),
        dz in -50.0f32..50.0,
    ) {
        let up = HeightField::new(hf.heights().map(|&v| v + dz), hf.cell_size()).unwrap();
        let moved = Ray::new(ray.origin + Vec3::Z * dz, ray.dir);
        let a = brute_force(&hf, &ray, 0.0, f32::INFINITY).unwrap();
        let b = MipmapTracer::new(&up).unwrap().trace(&moved, 0.0, f32::INFINITY);
        // Offsetting rounds the heights, so only compare clear hits and misses.
        if let (Some(a), Some(b)) = (a, b) {
            prop_assert!((a.t - b.t).abs() <= 1e-3 * a.t.abs().max(1.0) * scale(&hf));
        }
    }
}

#[test]
fn flat_and_planar_fields_match_closed_forms() {
    let flat = HeightField::flat(9, 7, 2.0, 3.0).unwrap();
    let mip = MipmapTracer::new(&flat).unwrap();
    let ray = Ray::new(Vec3::new(1.0, 2.0, 10.0), Vec3::new(0.3, 0.2, -1.0));
    let h = mip.trace(&ray, 0.0, f32::INFINITY).unwrap();
    assert_relative_eq!(h.t, (3.0 - 10.0) / -1.0, epsilon = 1e-5);
    assert_relative_eq!(h.geometric_normal, Vec3::Z, epsilon = 1e-6);
    // z = 0.5x − 0.25y + 1 over world coordinates (cell 2): exact ray–plane solution.
    let plane = HeightField::from_fn(17, 17, 2.0, |i, j| {
        0.5 * (2 * i) as f32 - 0.25 * (2 * j) as f32 + 1.0
    })
    .unwrap();
    let mip = MipmapTracer::new(&plane).unwrap();
    let o = Vec3::new(3.0, 5.0, 40.0);
    let d = Vec3::new(0.4, 0.7, -1.0);
    let n = Vec3::new(-0.5, 0.25, 1.0);
    let t = (1.0 - o.dot(n)) / d.dot(n);
    let h = mip.trace(&Ray::new(o, d), 0.0, f32::INFINITY).unwrap();
    assert_relative_eq!(h.t, t, max_relative = 1e-5);
    assert_relative_eq!(h.geometric_normal, n.normalize(), epsilon = 1e-5);
    assert_relative_eq!(h.smooth_normal, n.normalize(), epsilon = 1e-5);
}

#[test]
fn single_spike_shows_the_diagonal() {
    // A 10 m spike at sample (2, 2) of a flat 5 × 5 field, unit cells.
    let hf =
        HeightField::from_fn(5, 5, 1.0, |i, j| if (i, j) == (2, 2) { 10.0 } else { 0.0 }).unwrap();
    let mip = MipmapTracer::new(&hf).unwrap();
    let down = |x: f32, y: f32| {
        mip.trace(
            &Ray::new(Vec3::new(x, y, 20.0), Vec3::NEG_Z),
            0.0,
            f32::INFINITY,
        )
        .unwrap()
    };
    // On the apex.
    assert_relative_eq!(down(2.0, 2.0).point.z, 10.0, epsilon = 1e-5);
    // Cell (1, 1) holds the spike at its upper corner: the upper triangle
    // (u + v ≥ 1) rises to it, the lower one stays flat.
    let h = down(1.75, 1.75);
    assert_eq!((h.cell, h.triangle), (UVec2::new(1, 1), Triangle::Upper));
    assert_relative_eq!(h.point.z, 5.0, epsilon = 1e-5);
    let h = down(1.4, 1.4);
    assert_eq!(h.triangle, Triangle::Lower);
    assert_relative_eq!(h.point.z, 0.0, epsilon = 1e-6);
    // Cell (2, 2) holds it at its lower corner: z = 10·(1 − u − v) there.
    let h = down(2.25, 2.25);
    assert_eq!((h.cell, h.triangle), (UVec2::new(2, 2), Triangle::Lower));
    assert_relative_eq!(h.point.z, 5.0, epsilon = 1e-5);
    // A horizontal ray at 4 m through the spike's ridge line hits its flank.
    let h = mip
        .trace(
            &Ray::new(Vec3::new(0.0, 2.0, 4.0), Vec3::X),
            0.0,
            f32::INFINITY,
        )
        .unwrap();
    assert_relative_eq!(h.t, 1.4, epsilon = 1e-5);
}

#[test]
fn rays_from_below_and_inside_are_handled() {
    let hf = HeightField::from_fn(33, 33, 1.0, |i, j| {
        ((i as f32 * 0.3).sin() + (j as f32 * 0.2).cos()) * 4.0
    })
    .unwrap();
    let mip = MipmapTracer::new(&hf).unwrap();
    let grid = GridTracer::new(&hf).unwrap();
    // Straight up from below the lowest point hits the underside.
    let up = Ray::new(Vec3::new(10.3, 20.7, -100.0), Vec3::Z);
    let h = mip.trace(&up, 0.0, f32::INFINITY).unwrap();
    assert!(!h.from_above);
    assert_relative_eq!(
        h.point.z,
        surface_height(&hf, 10.3, 20.7).unwrap(),
        epsilon = 1e-4
    );
    // A shadow ray starting on the surface with t_min > 0 does not hit itself
    // when it leaves upward.
    let p = Vec3::new(16.2, 8.9, surface_height(&hf, 16.2, 8.9).unwrap());
    assert!(!mip.occluded(&Ray::new(p, Vec3::new(0.0, 0.0, 1.0)), 1e-3, f32::INFINITY));
    assert!(!grid.occluded(&Ray::new(p, Vec3::new(0.0, 0.0, 1.0)), 1e-3, f32::INFINITY));
    // A horizontal ray starting inside a hill (below its surface) leaves it.
    let inside = Ray::new(Vec3::new(16.0, 16.0, -20.0), Vec3::X);
    assert!(
        mip.trace(&inside, 0.0, f32::INFINITY).is_none(),
        "entirely below the field"
    );
}

#[test]
fn traversal_visits_every_crossed_cell_in_order() {
    // Property 8 against crossings computed in f64.
    let hf = HeightField::flat(41, 29, 1.5, 0.0).unwrap();
    let grid = GridTracer::new(&hf).unwrap();
    let seed = natura_core::Seed(5);
    let mut k = 0i64;
    let mut u = move || {
        k += 1;
        seed.uniform1(k)
    };
    for _ in 0..2000 {
        let o = Vec3::new((u() * 80.0 - 10.0) as f32, (u() * 60.0 - 10.0) as f32, 0.0);
        let d = Vec3::new((u() * 2.0 - 1.0) as f32, (u() * 2.0 - 1.0) as f32, 0.0);
        let visits: Vec<_> = grid.cells(&Ray::new(o, d), 0.0, f32::INFINITY).collect();
        let Some((first, last)) = visits.first().zip(visits.last()) else {
            continue;
        };
        let (t0, t1) = (f64::from(first.t_in), f64::from(last.t_out));
        let (ox, oy, dx, dy) = (
            f64::from(o.x) / 1.5,
            f64::from(o.y) / 1.5,
            f64::from(d.x) / 1.5,
            f64::from(d.y) / 1.5,
        );
        let mut ts = vec![];
        for k in 0..=40 {
            ts.push((k as f64 - ox) / dx);
        }
        for k in 0..=28 {
            ts.push((k as f64 - oy) / dy);
        }
        ts.retain(|t| *t > t0 && *t < t1);
        ts.extend([t0, t1]);
        ts.sort_by(f64::total_cmp);
        let mut want: Vec<UVec2> = Vec::new();
        for w in ts.windows(2).filter(|w| w[1] - w[0] > 2e-4) {
            let m = 0.5 * (w[0] + w[1]);
            let (cx, cy) = ((ox + m * dx).floor(), (oy + m * dy).floor());
            // The walk's clip is padded by a rounding margin; ignore slivers outside.
            if !(0.0..40.0).contains(&cx) || !(0.0..28.0).contains(&cy) {
                continue;
            }
            let c = UVec2::new(cx as u32, cy as u32);
            if want.last() != Some(&c) {
                want.push(c);
            }
        }
        let got: Vec<UVec2> = visits
            .iter()
            .filter(|v| f64::from(v.t_out - v.t_in) > 2e-4)
            .map(|v| v.cell)
            .collect();
        assert_eq!(got, want, "ray {o} {d}");
        for w in visits.windows(2) {
            assert!(w[1].t_in >= w[0].t_in && w[0].t_out <= w[1].t_out);
            let step = (w[1].cell.as_ivec2() - w[0].cell.as_ivec2()).abs();
            assert_eq!(step.x + step.y, 1, "consecutive cells share an edge");
        }
    }
}

#[test]
fn mipmap_bounds_are_conservative_and_compact() {
    let hf = field(Kind::Uniform, 67, 45, 1.0, 9);
    let mip = MaxMipmap::new(&hf).unwrap();
    let h = hf.heights();
    let (lo, hi) = hf.min_max();
    let quantum = (hi - lo) / 65000.0 * 1.01;
    for k in 1..=mip.top_level() {
        let (w, hgt) = mip.level_dims(k).unwrap();
        for b in 0..hgt {
            for a in 0..w {
                let (mn, mx) = mip.node_range(k, a, b).unwrap();
                let (mut tmn, mut tmx) = (f32::INFINITY, f32::NEG_INFINITY);
                let s = 1usize << k;
                for j in (b as usize * s)..=((b as usize + 1) * s).min(hf.ny() - 1) {
                    for i in (a as usize * s)..=((a as usize + 1) * s).min(hf.nx() - 1) {
                        tmn = tmn.min(h[(i, j)]);
                        tmx = tmx.max(h[(i, j)]);
                    }
                }
                assert!(mn <= tmn && mx >= tmx, "level {k} node ({a},{b})");
                assert!(tmn - mn <= quantum && mx - tmx <= quantum);
            }
        }
    }
    assert_eq!(mip.level_dims(mip.top_level()), Some((1, 1)));
    let field_bytes = hf.nx() * hf.ny() * 4;
    assert!(mip.memory_bytes() as f64 <= 0.45 * field_bytes as f64);
}

#[test]
fn bad_input_is_refused_or_misses() {
    let mut hf = HeightField::flat(8, 8, 1.0, 0.0).unwrap();
    let tiny = HeightField::flat(1, 8, 1.0, 0.0).unwrap();
    for r in [
        GridTracer::new(&tiny).err(),
        MipmapTracer::new(&tiny).err().map(|_| TraceError::Field {
            nx: 1,
            ny: 8,
            reason: String::new(),
        }),
    ] {
        assert!(matches!(r, Some(TraceError::Field { nx: 1, ny: 8, .. })));
    }
    hf.heights_mut()[(3, 5)] = f32::NAN;
    let err = MipmapTracer::new(&hf).unwrap_err();
    assert!(err.to_string().contains("(3, 5)"), "{err}");
    assert!(GridTracer::new(&hf).is_err());
    assert!(brute_force(&hf, &Ray::new(Vec3::ZERO, Vec3::Z), 0.0, 1.0).is_err());
    assert!(
        Grid2::new(0, 4, 0.0f32).is_err(),
        "zero-size fields cannot even be built"
    );

    let hf = field(Kind::Uniform, 16, 16, 1.0, 3);
    let mip = MipmapTracer::new(&hf).unwrap();
    let grid = GridTracer::new(&hf).unwrap();
    let o = Vec3::new(5.0, 5.0, 50.0);
    let bad = [
        (Ray::new(o, Vec3::ZERO), 0.0, f32::INFINITY),
        (
            Ray::new(o, Vec3::new(f32::NAN, 0.0, -1.0)),
            0.0,
            f32::INFINITY,
        ),
        (
            Ray::new(o, Vec3::new(0.0, f32::INFINITY, -1.0)),
            0.0,
            f32::INFINITY,
        ),
        (
            Ray::new(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::NEG_Z),
            0.0,
            f32::INFINITY,
        ),
        (Ray::new(o, Vec3::NEG_Z), f32::NAN, f32::INFINITY),
        (Ray::new(o, Vec3::NEG_Z), 0.0, f32::NAN),
        (Ray::new(o, Vec3::NEG_Z), 10.0, 1.0),
    ];
    for (r, a, b) in bad {
        assert!(mip.trace(&r, a, b).is_none() && !mip.occluded(&r, a, b));
        assert!(grid.trace(&r, a, b).is_none() && !grid.occluded(&r, a, b));
        assert_eq!(grid.cells(&r, a, b).count(), 0);
    }
    // Huge but finite values do not panic.
    let r = Ray::new(Vec3::splat(1e30), Vec3::new(-1e30, -1e30, -1e30));
    let _ = mip.trace(&r, 0.0, f32::INFINITY);
}
