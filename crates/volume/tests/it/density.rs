//! Property tests of the density models: the blending function, the implicit
//! field's support, the two blend forms, ranges, determinism, the swirl
//! period, exponent monotonicity, warps and easing, and grids against brute
//! force.

use glam::Vec3;
use natura_core::{Aabb, Grid3};
use natura_volume::animate::{
    ImplicitParticles, ParticleParams, cloud_is_born, ease, eased_amount, keyed_implicit,
};
use natura_volume::cloud::{
    BlendForm, Cloud, CloudParams, FrameConstants, SWIRL_PERIOD, cloud, nine_sphere_cumulus, warp,
};
use natura_volume::gas::{DensityShaping, Fog, Steam, SteamParams};
use natura_volume::grid::GridDensity;
use natura_volume::implicit::{Implicit, ImplicitPrimitive, wyvill};
use natura_volume::layer::{LayerClouds, LayerParams};
use natura_volume::{Density, VolumeError};
use proptest::prelude::*;

fn pts(n: usize, b: Aabb, seed: u64) -> Vec<Vec3> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut u = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..n)
        .map(|_| b.min + (b.max - b.min) * Vec3::new(u(), u(), u()))
        .collect()
}

// A13.1: the blending function.
#[test]
fn wyvill_blending_function_properties() {
    let r = 3.0;
    assert_eq!(wyvill(0.0, r), 1.0);
    assert!((wyvill(r / 2.0, r) - 0.5).abs() < 1e-6);
    assert_eq!(wyvill(r, r), 0.0);
    let mut prev = 1.0;
    for i in 0..=1000 {
        let x = r * i as f32 / 1000.0;
        let f = wyvill(x, r);
        assert!(f <= prev + 1e-7, "not monotone at {x}");
        prev = f;
        let d = x / 2.0;
        let s = wyvill(r / 2.0 - d, r) + wyvill(r / 2.0 + d, r);
        // The exact minimum of the sum is 0.997942… (at d ≈ 0.26 R): "symmetric about 0.5" is approximate.
        assert!(
            (0.9979..=1.0 + 1e-6).contains(&s),
            "symmetry {s} at d = {d}"
        );
    }
    // Zero beyond R, where the bare polynomial is positive (up to 1.5 R) and then negative.
    for i in 0..200 {
        assert_eq!(wyvill(r * (1.0 + i as f32 * 0.02), r), 0.0);
    }
}

fn cumulus(form: BlendForm, frame: u32) -> Cloud {
    let p = CloudParams {
        blend_form: form,
        frame,
        ..CloudParams::cumulus()
    };
    cloud(nine_sphere_cumulus(), p, 11).unwrap()
}

// A13.2 and A13.3: support and the product blend.
#[test]
fn implicit_field_is_zero_outside_the_supports_and_the_product_blend_with_it() {
    let prims = nine_sphere_cumulus();
    let imp = Implicit::new(prims.clone()).unwrap();
    let big = Aabb {
        min: imp.bounds().min - 5.0,
        max: imp.bounds().max + 5.0,
    };
    let c = cumulus(BlendForm::Product, 40);
    let margin = c.params().displacement; // parms[4]·max turb, turb ≤ 1
    let mut outside = 0;
    for p in pts(20_000, big, 1) {
        let inside = prims.iter().any(|q| q.distance_sq(p) < q.radius * q.radius);
        if !inside {
            assert_eq!(imp.eval(p), 0.0, "{p}");
        }
        // The cloud's point is displaced by at most `margin` along (1, 1, −1) before the implicit
        // evaluation: outside every support grown by √3·margin, the density is zero.
        let near = prims.iter().any(|q| {
            let r = q.radius + margin * 3f32.sqrt();
            q.distance_sq(p) < r * r
        });
        if !near {
            outside += 1;
            assert_eq!(c.density(p), 0.0, "{p}");
        }
        let (d, m, _) = c.evaluate(p);
        if m == 0.0 {
            assert_eq!(d, 0.0);
        }
    }
    assert!(outside > 1000);
    // The additive form puts gas where the implicit density is zero.
    let a = cumulus(BlendForm::Additive, 40);
    let gas_outside = pts(5000, big, 2)
        .into_iter()
        .filter(|&p| a.evaluate(p).1 == 0.0 && a.evaluate(p).0 > 0.0)
        .count();
    assert!(gas_outside > 0);
}

// A13.4 and A13.7 over the valid parameter ranges.
proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn density_in_unit_interval_for_valid_parameters(
        scale in 0.01f32..1.0, exponent in 0.1f32..10.0, blend in 0.0f32..=1.0,
        disp in 0.0f32..2.0, frame in 0u32..2000, additive in any::<bool>(),
        x in -8.0f32..8.0, y in -8.0f32..8.0, z in -2.0f32..10.0,
    ) {
        let p = CloudParams {
            density_scale: scale, exponent, blend, displacement: disp, frame,
            blend_form: if additive { BlendForm::Additive } else { BlendForm::Product },
            ..CloudParams::cumulus()
        };
        let c = cloud(nine_sphere_cumulus(), p, 5).unwrap();
        let q = Vec3::new(x, y, z);
        let d = c.density(q);
        prop_assert!((0.0..=1.0).contains(&d));
        prop_assert!(d <= c.max_density() + 1e-6);
        let r = Aabb { min: q - 0.01, max: q + 0.01 };
        prop_assert!(d <= c.bound_in(&r) + 1e-6);
    }

    #[test]
    fn shaping_functions_map_unit_interval_monotonically(d in 0.0f32..=1.0, e in 0.05f32..20.0) {
        for s in [DensityShaping::Pow(e), DensityShaping::Exp(e), DensityShaping::Sine] {
            let v = s.apply(d);
            prop_assert!((0.0..=1.0).contains(&v));
            prop_assert!(s.apply((d + 0.01).min(1.0)) >= v);
        }
        prop_assert!(DensityShaping::Pow(e).apply(0.0) == 0.0 && (DensityShaping::Pow(e).apply(1.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn larger_exponent_is_wispier(d in 0.001f32..0.999, e in 0.1f32..8.0, de in 0.01f32..4.0) {
        prop_assert!(DensityShaping::Pow(e + de).apply(d) <= DensityShaping::Pow(e).apply(d));
    }
}

#[test]
fn larger_exponent_gives_less_cloud() {
    let q = pts(
        3000,
        Implicit::new(nine_sphere_cumulus()).unwrap().bounds(),
        3,
    );
    let mut last = f32::INFINITY;
    for e in [0.5, 1.0, 2.0, 4.0] {
        let c = cloud(
            nine_sphere_cumulus(),
            CloudParams {
                exponent: e,
                ..CloudParams::cumulus()
            },
            9,
        )
        .unwrap();
        let total: f32 = q.iter().map(|&p| c.density(p)).sum();
        assert!(total < last, "exponent {e}: {total} ≥ {last}");
        last = total;
    }
}

// A13.5: determinism; per-frame constants are a pure function of the frame.
#[test]
fn same_seed_frame_and_point_give_the_same_bits() {
    let a = cumulus(BlendForm::Product, 123);
    let b = cumulus(BlendForm::Product, 0).at_frame(123);
    for p in pts(2000, a.bounds(), 4) {
        assert_eq!(a.density(p).to_bits(), b.density(p).to_bits());
    }
    assert_eq!(FrameConstants::new(77), FrameConstants::new(77));
    let other = cloud(nine_sphere_cumulus(), CloudParams::cumulus(), 12).unwrap();
    let differ = pts(500, a.bounds(), 5)
        .into_iter()
        .filter(|&p| other.density(p) != a.at_frame(0).density(p))
        .count();
    assert!(differ > 0, "the seed changes the turbulence");
}

// A13.6: the swirl period, with the corrected constant 2π/600.
#[test]
fn swirl_angle_has_a_600_frame_period() {
    assert_eq!(SWIRL_PERIOD, 600);
    for f in [0u32, 1, 17, 299, 599, 1234] {
        let a = FrameConstants::new(f);
        let b = FrameConstants::new(f + 600);
        assert_eq!(a.theta.to_bits(), b.theta.to_bits());
        assert!(a.theta < std::f32::consts::TAU);
    }
    // 600 frames are one full turn: the last frame is one step short of 2π.
    let last = FrameConstants::new(599).theta;
    assert!((last - (std::f32::consts::TAU - 0.010_471_96)).abs() < 1e-4);
    assert!((FrameConstants::new(150).theta.sin() - 1.0).abs() < 1e-5);
}

// A13.9: warps and easing.
#[test]
fn zero_warp_is_identity_and_easing_is_monotone() {
    for p in pts(
        100,
        Aabb {
            min: Vec3::splat(-9.0),
            max: Vec3::splat(9.0),
        },
        6,
    ) {
        assert_eq!(warp(p, Vec3::new(3.0, -1.0, 0.5), 0.0, 0.7), p);
    }
    assert_eq!(ease(0.0), 0.0);
    assert_eq!(ease(1.0), 1.0);
    let mut prev = 0.0;
    for i in 0..=1000 {
        let e = ease(i as f32 / 1000.0);
        assert!(e >= prev);
        prev = e;
    }
    assert_eq!(eased_amount(0, 10, 70), 0.0);
    assert_eq!(eased_amount(70, 10, 70), 1.0);
    assert!((eased_amount(40, 10, 70) - 0.5).abs() < 1e-6);
    // A jet stream of amount 0 gives the unwarped cloud.
    let plain = cumulus(BlendForm::Product, 5);
    let mut p = CloudParams::cirrus(Vec3::new(4.0, 0.0, 0.0));
    p = CloudParams {
        jet_stream: p.jet_stream.map(|mut j| {
            j.amount = 0.0;
            j
        }),
        frame: 5,
        ..CloudParams::cumulus()
    };
    let jet0 = cloud(nine_sphere_cumulus(), p, 11).unwrap();
    for q in pts(500, plain.bounds(), 7) {
        assert_eq!(plain.evaluate(q).0.to_bits(), jet0.evaluate(q).0.to_bits());
    }
}

#[test]
fn cloud_is_born_merges_and_grows() {
    let keys = cloud_is_born();
    let a = keyed_implicit(&keys, 0.0).unwrap();
    let b = keyed_implicit(&keys, 1.0).unwrap();
    let spread = |i: &Implicit| {
        let bb = i.bounds();
        bb.max - bb.min
    };
    assert!(spread(&b).x < spread(&a).x, "the elements move together");
    let r = |i: &Implicit| i.primitives().iter().map(|p| p.radius).sum::<f32>();
    assert!(r(&b) > 2.0 * r(&a), "and grow");
}

#[test]
fn implicit_particles_rise_multiply_and_stay() {
    let seeds: Vec<ImplicitPrimitive> = (0..12)
        .map(|i| {
            ImplicitPrimitive::sphere(
                Vec3::new((i % 4) as f32 * 2.0, (i / 4) as f32 * 2.0, 0.0),
                1.0,
            )
        })
        .collect();
    let run = || {
        let mut s = ImplicitParticles::new(&seeds, ParticleParams::default(), 3).unwrap();
        for _ in 0..200 {
            s.step(1.0 / 24.0).unwrap();
        }
        s
    };
    let s = run();
    let n = s.particles().len();
    // Ebert: a dozen seeds grow to about fifty primitives.
    assert!((25..=120).contains(&n), "{n} particles");
    let mean_z: f32 = s
        .particles()
        .iter()
        .map(|p| p.primitive.support().min.z + p.primitive.radius)
        .sum::<f32>()
        / n as f32;
    assert!(mean_z > 0.5, "they rise: {mean_z}");
    // Deterministic for a seed; particles never die (the count never falls).
    assert_eq!(run().particles(), s.particles());
    assert!(s.implicit().is_ok());
    let mut t = ImplicitParticles::new(&seeds, ParticleParams::default(), 3).unwrap();
    assert!(t.step(0.0).is_err());
    assert!(t.step(f32::NAN).is_err());
}

#[test]
fn steam_and_fog_stay_in_range_and_bounds() {
    let s = Steam::new(SteamParams::default(), 2).unwrap();
    let b = s.bounds();
    let wide = Aabb {
        min: b.min - 0.05,
        max: b.max + 0.05,
    };
    let mut any = false;
    for p in pts(5000, wide, 8) {
        let d = s.density(p);
        assert!((0.0..=1.0).contains(&d));
        if !b.contains(p) {
            assert_eq!(d, 0.0);
        }
        any |= d > 0.0;
    }
    assert!(any);
    let region = Aabb {
        min: Vec3::ZERO,
        max: Vec3::new(10.0, 10.0, 3.0),
    };
    let f = Fog::new(region, 1.0, 0.5, 1.0, 1.0, 1).unwrap();
    for p in pts(2000, region, 9) {
        assert!((0.0..=1.0).contains(&f.density(p)));
    }
    assert!(matches!(
        Fog::new(
            Aabb {
                min: Vec3::ONE,
                max: Vec3::ZERO
            },
            1.0,
            0.5,
            1.0,
            1.0,
            1
        ),
        Err(VolumeError::InvalidBounds { .. })
    ));
    assert!(Fog::new(region, 0.0, 0.5, 1.0, 1.0, 1).is_err());
}

#[test]
fn cloud_types_differ_as_the_source_says() {
    // Cirrus is thinner than cumulus; stratus denser; the mackerel sky modulated.
    let prims = vec![ImplicitPrimitive::ellipsoid(
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::new(20.0, 20.0, 3.0),
    )];
    let mean = |p: CloudParams| {
        let c = cloud(prims.clone(), p, 4).unwrap();
        let q = pts(
            4000,
            Aabb {
                min: Vec3::new(-15.0, -15.0, 4.0),
                max: Vec3::new(15.0, 15.0, 6.0),
            },
            10,
        );
        q.iter().map(|&x| c.density(x)).sum::<f32>() / q.len() as f32
    };
    let cu = mean(CloudParams::cumulus());
    let ci = mean(CloudParams::cirrus(Vec3::new(5.0, 0.0, 0.0)));
    let st = mean(CloudParams::stratus());
    let cs = mean(CloudParams::cirrostratus());
    let mk = mean(CloudParams::mackerel(4.0));
    assert!(ci < cu, "cirrus {ci} vs cumulus {cu}");
    assert!(st > cu, "stratus {st} vs cumulus {cu}");
    assert!(
        cs < st && mk < st,
        "cirrostratus {cs}, mackerel {mk}, stratus {st}"
    );
}

#[test]
fn bad_cloud_parameters_are_typed_errors() {
    for p in [
        CloudParams {
            density_scale: f32::NAN,
            ..CloudParams::default()
        },
        CloudParams {
            exponent: 0.0,
            ..CloudParams::default()
        },
        CloudParams {
            blend: 1.5,
            ..CloudParams::default()
        },
        CloudParams {
            displacement: -1.0,
            ..CloudParams::default()
        },
        CloudParams {
            noise_frequency: f32::INFINITY,
            ..CloudParams::default()
        },
    ] {
        assert!(matches!(
            cloud(nine_sphere_cumulus(), p, 1),
            Err(VolumeError::InvalidParameter { .. })
        ));
    }
}

#[test]
fn layer_clouds_follow_coverage_and_stay_in_the_layer() {
    let clear = LayerClouds::new(
        LayerParams {
            coverage: 0.0,
            ..LayerParams::default()
        },
        1,
    )
    .unwrap();
    let over = LayerClouds::new(
        LayerParams {
            coverage: 1.0,
            ..LayerParams::default()
        },
        1,
    )
    .unwrap();
    let mid = LayerClouds::new(LayerParams::default(), 1).unwrap();
    let b = mid.bounds();
    let q = pts(4000, b, 11);
    let frac =
        |l: &LayerClouds| q.iter().filter(|&&p| l.density(p) > 0.0).count() as f32 / q.len() as f32;
    let (c0, c5, c1) = (frac(&clear), frac(&mid), frac(&over));
    assert!(c0 < c5 && c5 < c1, "coverage 0: {c0}, 0.5: {c5}, 1: {c1}");
    assert!(c0 < 0.05 && c1 > 0.3, "{c0} {c1}");
    for p in &q {
        let d = mid.density(*p);
        assert!(d.is_finite() && d >= 0.0 && d <= mid.max_density());
    }
    assert_eq!(mid.density(Vec3::new(0.0, 0.0, 100.0)), 0.0);
    assert_eq!(mid.density(Vec3::new(0.0, 0.0, 5000.0)), 0.0);
    assert!(
        LayerClouds::new(
            LayerParams {
                base_m: 3000.0,
                top_m: 1500.0,
                ..LayerParams::default()
            },
            1
        )
        .is_err()
    );
}

#[test]
fn baked_grid_matches_brute_force_trilinear() {
    // A linear field is reproduced exactly by trilinear interpolation inside the grid.
    let g = Grid3::from_fn(9, 7, 5, |i, j, k| {
        0.1 * i as f32 + 0.2 * j as f32 + 0.05 * k as f32
    })
    .unwrap();
    let origin = Vec3::new(-1.0, 2.0, 0.5);
    let cell = 0.25;
    let d = GridDensity::new(g.clone(), origin, cell).unwrap();
    let inner = Aabb {
        min: origin + cell * 0.5,
        max: origin + Vec3::new(8.5, 6.5, 4.5) * cell,
    };
    for p in pts(3000, inner, 12) {
        let u = (p - origin) / cell - 0.5;
        let exact = 0.1 * u.x + 0.2 * u.y + 0.05 * u.z;
        assert!((d.density(p) - exact).abs() < 1e-5, "{p}");
        // natura-core's own trilinear sampler agrees.
        let core = g.sample_trilinear(u.x, u.y, u.z, natura_core::Boundary::Clamp);
        assert!((d.density(p) - core).abs() < 1e-5);
    }
    // Baking a cloud and sampling at voxel centres returns the cloud's values.
    let c = cumulus(BlendForm::Product, 0);
    let baked = GridDensity::bake(&c, 0.5).unwrap();
    let (nx, ny, nz) = baked.grid().dims();
    for (i, j, k) in [(3, 4, 5), (nx / 2, ny / 2, nz / 2), (1, 1, 1)] {
        let p = baked.origin() + (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * 0.5;
        assert!((baked.density(p) - c.density(p)).abs() < 1e-6);
    }
    // The block majorant bounds the samples everywhere.
    for p in pts(3000, baked.bounds(), 13) {
        let r = Aabb {
            min: p - 0.3,
            max: p + 0.3,
        };
        assert!(baked.density(p) <= baked.bound_in(&r) + 1e-6);
    }
}

#[test]
fn batch_density_agrees_with_the_point_path() {
    // The batch path evaluates the noise in f32 SIMD lanes where the point
    // path uses f64; the stated tolerance is 1e-5 absolute (measured at most
    // 1.4e-6 on these points).
    let clouds = [
        cumulus(BlendForm::Product, 0),
        cumulus(BlendForm::Additive, 37),
        cloud(
            vec![ImplicitPrimitive::ellipsoid(
                Vec3::new(0.0, 0.0, 3.0),
                Vec3::new(8.0, 5.0, 1.2),
            )],
            CloudParams::cirrus(Vec3::new(2.0, 0.0, 0.0)),
            5,
        )
        .unwrap(),
    ];
    for c in &clouds {
        let b = c.bounds();
        // Some points outside the bounds too.
        let big = Aabb {
            min: b.min - Vec3::ONE,
            max: b.max + Vec3::ONE,
        };
        let p = pts(1000, big, 3);
        let (x, y, z): (Vec<f32>, Vec<f32>, Vec<f32>) = (
            p.iter().map(|q| q.x).collect(),
            p.iter().map(|q| q.y).collect(),
            p.iter().map(|q| q.z).collect(),
        );
        let mut out = vec![0.0f32; p.len()];
        c.density_batch(&x, &y, &z, &mut out).unwrap();
        let mut worst = 0.0f32;
        let mut inside = 0;
        for (q, &v) in p.iter().zip(&out) {
            let d = c.density(*q);
            worst = worst.max((d - v).abs());
            if d > 0.0 {
                inside += 1;
            }
            if !b.contains(*q) {
                assert_eq!(v, 0.0);
            }
        }
        eprintln!(
            "batch vs point: max |Δρ| = {worst:.2e} over {} points ({inside} inside)",
            p.len()
        );
        assert!(inside > 100, "{inside}");
        assert!(worst < 1e-5, "batch vs point: {worst}");
        // The trait's default (point by point) is exact.
        let g = GridDensity::bake(c, 0.5).unwrap();
        g.density_batch(&x, &y, &z, &mut out).unwrap();
        for (q, &v) in p.iter().zip(&out) {
            assert_eq!(v, g.density(*q));
        }
        // Unequal lengths are a typed error.
        assert!(matches!(
            c.density_batch(&x[..5], &y, &z, &mut out),
            Err(VolumeError::SizeMismatch { .. })
        ));
    }
}

/// A 24 × 20 × 12 grid of cells of 0.5 m, empty but for `spots` voxels.
fn sparse_grid(spots: &[(usize, usize, usize, f32)]) -> GridDensity {
    let mut g = Grid3::new(24, 20, 12, 0.0f32).unwrap();
    for &(i, j, k, v) in spots {
        g.row_mut(j, k)[i] = v;
    }
    GridDensity::new(g, Vec3::new(-3.0, 2.0, -1.0), 0.5).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// The bounds of a box round a step (`bound_near`) and of a box
    /// (`bound_in`) bound every sample in the box, whatever the box's size
    /// and place (inside, across the faces, outside the grid).
    #[test]
    fn the_grids_bounds_hold_over_their_boxes(
        spots in proptest::collection::vec((0usize..24, 0usize..20, 0usize..12, 0.01f32..5.0), 1..6),
        dx in -2.5f32..2.5, dy in -2.5f32..2.5, dz in -2.5f32..2.5,
        radius in 0.0f32..3.0,
        seed in 0u64..1000,
    ) {
        let g = sparse_grid(&spots);
        // Round the first spot, where the bounds have something to miss.
        let (i, j, k, _) = spots[0];
        let spot = g.origin() + (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * g.cell();
        let c = spot + Vec3::new(dx, dy, dz);
        let r = Aabb { min: c - radius, max: c + radius };
        let (near, within) = (g.bound_near(c, radius), g.bound_in(&r));
        let mut max = 0.0f32;
        for p in pts(400, r, seed).into_iter().chain([r.min, r.max, c]) {
            max = max.max(g.density(p));
        }
        prop_assert!(max <= near, "{max} > bound_near {near}");
        prop_assert!(max <= within, "{max} > bound_in {within}");
    }
}

#[test]
fn a_short_step_far_from_the_density_is_bound_by_zero() {
    // One dense voxel at a corner: steps a few cells away read an empty
    // neighbourhood, not the coarse blocks' reach of eight voxels.
    let g = sparse_grid(&[(1, 1, 1, 2.0)]);
    let far = g.origin() + Vec3::new(8.0, 8.0, 4.0);
    assert_eq!(g.bound_near(far, 0.4), 0.0);
    assert_eq!(
        g.bound_in(&Aabb {
            min: far - 0.4,
            max: far + 0.4
        }),
        0.0
    );
    // Near the voxel the bounds see it.
    let at = g.origin() + Vec3::splat(0.75);
    assert!(g.bound_near(at + 0.3, 0.4) >= g.density(at));
    assert_eq!(g.bound_near(at, 100.0), 2.0);
}
