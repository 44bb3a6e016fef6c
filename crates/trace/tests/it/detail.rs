//! The detail tracer against a brute-force fine march of the same surface.

use crate::common;

use common::{Kind, field};
use glam::Vec3;
use natura_core::{Grid2, Seed};
use natura_trace::{
    Detail, DetailParams, DetailSurface, DetailTracer, MipmapTracer, Ray, RayCone, Tracer,
    detail_brute_force,
};

fn params(amplitude_m: f32) -> DetailParams {
    DetailParams {
        amplitude_m,
        h: 0.8,
        lacunarity: 2.0,
        octaves: 6,
        wavelength_m: 10.0,
        seed: 11,
    }
}

/// Random rays from above a 330 m field, down at 2°–60°.
fn rays(seed: u64, n: usize) -> Vec<Ray> {
    let s = Seed(seed);
    (0..n as i64)
        .map(|k| {
            let u = |c: i64| s.uniform2(k, c) as f32;
            let o = Vec3::new(
                -20.0 + 370.0 * u(0),
                -20.0 + 370.0 * u(1),
                14.0 + 20.0 * u(2),
            );
            let az = std::f32::consts::TAU * u(3);
            let el = (2.0 + 58.0 * u(4)).to_radians();
            Ray::new(
                o,
                Vec3::new(az.cos() * el.cos(), az.sin() * el.cos(), -el.sin()),
            )
        })
        .collect()
}

/// Length of the stretch of `ray` on the far side of the surface from `t` on
/// (metres; below it for a ray from above), by fine steps (`f64::INFINITY`
/// past 2 m).
fn submerged(s: &DetailSurface<'_>, ray: &Ray, t: f64, fp: RayCone) -> f64 {
    let p0 = ray.origin.as_dvec3();
    let above = s
        .height(p0.x as f32, p0.y as f32, fp.at(0.0))
        .is_none_or(|h| p0.z >= h);
    let d = ray.dir.as_dvec3();
    for k in 1..=4000 {
        let tt = t + k as f64 * 5e-4;
        let p = ray.origin.as_dvec3() + tt * d;
        match s.height(p.x as f32, p.y as f32, fp.at(tt)) {
            Some(h) if (p.z > h) == above => return tt - t,
            None => return tt - t,
            _ => {}
        }
    }
    f64::INFINITY
}

/// The detail tracer's hits on `surface` against a fine brute-force march
/// of 300 random rays: they agree within a hundredth of a metre and a
/// fraction of the footprint, except where the tracer stepped over a
/// sliver thinner than a quarter of the footprint (at most 3 %).
fn agree_with_brute_force(surface: &DetailSurface<'_>, fp: RayCone, what: &str) {
    agree_on(surface, fp, what, &rays(5, 300));
}

/// [`agree_with_brute_force`] on the rays `all`.
fn agree_on(surface: &DetailSurface<'_>, fp: RayCone, what: &str, all: &[Ray]) {
    let tracer = DetailTracer::new(surface.clone(), fp).unwrap();
    let (mut agree, mut thin) = (0, 0);
    for ray in all {
        let fast = tracer.trace_footprint(ray, 0.0, f32::INFINITY, fp);
        let brute = detail_brute_force(surface, ray, 0.0, 1e4, fp, 0.004);
        let tol = |t: f64| 0.01 + 2e-3 * fp.at(t);
        match (fast, brute) {
            (None, None) => agree += 1,
            (Some(f), Some(b)) if (f64::from(f.t) - b).abs() <= tol(b) => agree += 1,
            (f, b) => {
                // The only allowed disagreement: the fast path stepped over a
                // sliver thinner than a quarter of the footprint, and then
                // found the next crossing (or none).
                let b = b.expect("the fast path reports no hit the fine march misses");
                let len = submerged(surface, ray, b, fp);
                let w = fp.at(b).max(surface.detail().finest_footprint());
                assert!(
                    len <= 0.25 * w + 2e-3,
                    "{what}: fast {f:?} vs brute {b}: stretch of {len} m below the surface"
                );
                if let Some(f) = f {
                    assert!(f64::from(f.t) > b, "{what}: fast hit before the brute one");
                }
                thin += 1;
            }
        }
    }
    eprintln!("{what}: {agree} of {} agree, {thin} slivers", all.len());
    assert!(
        agree >= all.len() * 97 / 100,
        "{what}: {agree} agree, {thin} slivers"
    );
}

#[test]
fn hits_agree_with_a_fine_brute_force_march() {
    for (kind, fp) in [
        (Kind::Smooth, RayCone::cone(2e-3)),
        (Kind::Uniform, RayCone::cone(5e-3)),
        (
            Kind::Spiky,
            RayCone {
                at_origin_m: 0.05,
                per_metre: 0.0,
            },
        ),
    ] {
        let hf = field(kind, 34, 34, 10.0, 3);
        let surface = DetailSurface::new(&hf, Detail::new(&params(1.5)).unwrap(), None).unwrap();
        agree_with_brute_force(&surface, fp, &format!("{kind:?}"));
    }
}

#[test]
fn rays_from_below_and_skimming_agree_with_a_fine_brute_force_march() {
    // Rays that start under the surface and rise (the march's gap is then
    // read from below), and rays that skim it at under 3°: where the
    // over-relaxed steps and their backward check do most of the work.
    let hf = field(Kind::Uniform, 34, 34, 10.0, 3);
    let surface = DetailSurface::new(&hf, Detail::new(&params(1.5)).unwrap(), None).unwrap();
    let s = Seed(8);
    let all: Vec<Ray> = (0..300i64)
        .map(|k| {
            let u = |c: i64| s.uniform2(k, c) as f32;
            let (x, y) = (20.0 + 290.0 * u(0), 20.0 + 290.0 * u(1));
            let ground = surface.height(x, y, 0.0).unwrap() as f32;
            let az = std::f32::consts::TAU * u(3);
            let (z, el) = if k % 2 == 0 {
                (ground - 0.3 - 3.0 * u(2), (1.0 + 19.0 * u(4)).to_radians())
            } else {
                (ground + 2.0 + 6.0 * u(2), -(0.5 + 2.5 * u(4)).to_radians())
            };
            Ray::new(
                Vec3::new(x, y, z),
                Vec3::new(az.cos() * el.cos(), az.sin() * el.cos(), el.sin()),
            )
        })
        .collect();
    agree_on(&surface, RayCone::cone(2e-3), "below and skimming", &all);
}

#[test]
fn masked_hits_agree_with_a_fine_brute_force_march() {
    // A mask of bare patches (0, where the tracer solves the triangles
    // exactly and its pyramid drops the detail's shell), full detail (1),
    // partial detail, and ramps between them: the bounds scaled by the
    // mask's greatest value in a cell or node must still never step over
    // the surface.
    let mask = Grid2::from_fn(34, 34, |i, j| match (i / 6 + j / 6) % 4 {
        0 => 0.0f32,
        1 => 1.0,
        2 => 0.4,
        _ => ((i % 6) as f32 / 5.0).min(1.0),
    })
    .unwrap();
    for (kind, fp) in [
        (Kind::Smooth, RayCone::cone(2e-3)),
        (Kind::Uniform, RayCone::cone(5e-3)),
    ] {
        let hf = field(kind, 34, 34, 10.0, 3);
        let surface =
            DetailSurface::new(&hf, Detail::new(&params(1.5)).unwrap(), Some(mask.clone()))
                .unwrap();
        agree_with_brute_force(&surface, fp, &format!("{kind:?} masked"));
    }
}

#[test]
fn hit_points_lie_on_the_surface_with_finite_normals() {
    let hf = field(Kind::Smooth, 34, 34, 10.0, 9);
    let surface = DetailSurface::new(&hf, Detail::new(&params(2.0)).unwrap(), None).unwrap();
    let fp = RayCone::cone(3e-3);
    let tracer = DetailTracer::new(surface.clone(), fp).unwrap();
    let mut hits = 0;
    for ray in rays(21, 400) {
        if let Some(h) = tracer.trace(&ray, 0.0, f32::INFINITY) {
            hits += 1;
            let s = surface
                .height(h.point.x, h.point.y, fp.at(f64::from(h.t)))
                .unwrap();
            assert!(
                (f64::from(h.point.z) - s).abs() < 0.02,
                "{} vs {s}",
                h.point.z
            );
            for n in [h.geometric_normal, h.smooth_normal] {
                assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-4 && n.z > 0.0);
            }
            assert!(h.from_above);
            // The same ray again: bit-identical.
            assert_eq!(tracer.trace(&ray, 0.0, f32::INFINITY), Some(h));
        }
    }
    assert!(hits > 200, "{hits}");
    // Degenerate rays hit nothing and do not panic.
    for r in [
        Ray::new(Vec3::splat(f32::NAN), Vec3::Z),
        Ray::new(Vec3::new(5.0, 5.0, 50.0), Vec3::ZERO),
        Ray::new(
            Vec3::new(5.0, 5.0, 50.0),
            Vec3::new(0.0, 0.0, f32::INFINITY),
        ),
    ] {
        assert_eq!(tracer.trace(&r, 0.0, f32::INFINITY), None);
    }
    // A vertical ray works.
    let h = tracer
        .trace(
            &Ray::new(Vec3::new(101.0, 57.0, 60.0), -Vec3::Z),
            0.0,
            f32::INFINITY,
        )
        .unwrap();
    assert!(h.t > 0.0);
}

#[test]
fn without_detail_or_beyond_the_far_footprint_the_plain_tracer_answers() {
    let hf = field(Kind::Uniform, 34, 34, 10.0, 4);
    let plain = MipmapTracer::new(&hf).unwrap();
    let zero = DetailSurface::new(&hf, Detail::new(&params(0.0)).unwrap(), None).unwrap();
    let none = DetailTracer::new(zero, RayCone::cone(1e-3)).unwrap();
    // RayCone already past the first octave's Nyquist limit: no detail anywhere.
    let coarse = RayCone {
        at_origin_m: 6.0,
        per_metre: 0.0,
    };
    let full = DetailSurface::new(&hf, Detail::new(&params(2.0)).unwrap(), None).unwrap();
    let far = DetailTracer::new(full, coarse).unwrap();
    for ray in rays(8, 300) {
        let p = plain.trace(&ray, 0.0, f32::INFINITY);
        assert_eq!(none.trace(&ray, 0.0, f32::INFINITY), p);
        assert_eq!(far.trace(&ray, 0.0, f32::INFINITY), p);
        assert_eq!(
            none.occluded(&ray, 0.0, 50.0),
            plain.occluded(&ray, 0.0, 50.0)
        );
    }
}

#[test]
fn a_zero_mask_keeps_the_field_bare() {
    let hf = field(Kind::Smooth, 34, 34, 10.0, 2);
    let mask = Grid2::from_fn(34, 34, |i, _| if i < 17 { 0.0f32 } else { 1.0 }).unwrap();
    let s = DetailSurface::new(&hf, Detail::new(&params(2.0)).unwrap(), Some(mask)).unwrap();
    let b = natura_trace::surface_height(&hf, 50.0, 100.0).unwrap();
    assert_eq!(s.height(50.0, 100.0, 0.1), Some(f64::from(b)));
    assert_ne!(
        s.height(250.0, 100.0, 0.1),
        natura_trace::surface_height(&hf, 250.0, 100.0).map(f64::from)
    );
    let bad = Grid2::new(33, 34, 1.0f32).unwrap();
    assert!(DetailSurface::new(&hf, Detail::new(&params(2.0)).unwrap(), Some(bad)).is_err());
    let nan = Grid2::new(34, 34, f32::NAN).unwrap();
    assert!(DetailSurface::new(&hf, Detail::new(&params(2.0)).unwrap(), Some(nan)).is_err());
}

#[test]
fn shadow_rays_agree_with_the_closest_hit() {
    let hf = field(Kind::Uniform, 34, 34, 10.0, 3);
    let surface = DetailSurface::new(&hf, Detail::new(&params(1.5)).unwrap(), None).unwrap();
    let fp = RayCone {
        at_origin_m: 0.02,
        per_metre: 3e-3,
    };
    let tracer = DetailTracer::new(surface, fp).unwrap();
    let (mut hits, mut misses) = (0, 0);
    for ray in rays(9, 300) {
        for t_max in [5.0, 40.0, f32::INFINITY] {
            let hit = tracer.trace_footprint(&ray, 0.0, t_max, fp).is_some();
            assert_eq!(tracer.occluded_footprint(&ray, 0.0, t_max, fp), hit);
            if hit { hits += 1 } else { misses += 1 }
        }
    }
    assert!(hits > 50 && misses > 50, "{hits} hits, {misses} misses");
}
