use super::super::cells::Flight;
use super::trace::OPAQUE;
use super::*;
use crate::animate::unit;
use crate::density::Homogeneous;
use crate::phase::CloudPhase;
use natura_core::Seed;

/// A homogeneous slab 12 m wide, `2·half` thick (unit density), and an
/// isotropic medium of extinction 1 /m and `albedo`.
fn isotropic_slab(half: f32, albedo: f32) -> (Homogeneous, MediumParams) {
    let region = Aabb {
        min: Vec3::new(-6.0, -6.0, -half),
        max: Vec3::new(6.0, 6.0, half),
    };
    let medium = MediumParams {
        extinction: 1.0,
        albedo,
        phase: CloudPhase::Isotropic,
    };
    (Homogeneous::new(region, 1.0).unwrap(), medium)
}

#[test]
fn a_line_walked_to_the_opaque_depth_gives_the_whole_lines_collision() {
    // Lines through a ball of optical diameter 60 and past its edge: the
    // chance of a collision, and the collision of every forced depth
    // (the largest `unit` gives included), are the same bits whether the
    // line is walked to its end or only until its depth reaches OPAQUE.
    let ball = crate::density::Ball::new(Vec3::ZERO, 3.0, 1.0).unwrap();
    let grid = CellGrid::new(&ball, 10.0, 32).unwrap();
    let mut rng = Seed(5).rng();
    let (mut full, mut cut) = (Vec::new(), Vec::new());
    let mut shortened = 0;
    for _ in 0..2000 {
        let d = Vec3::new(unit(&mut rng) - 0.5, unit(&mut rng) - 0.5, 1.0).normalize();
        let (a, b) = d.any_orthonormal_pair();
        let o = (a * (unit(&mut rng) - 0.5) + b * (unit(&mut rng) - 0.5)) * 7.0 - d * 10.0;
        let tau = grid.line(o, d, f32::INFINITY, &mut full);
        let tau_cut = grid.line(o, d, OPAQUE, &mut cut);
        if cut.len() < full.len() {
            shortened += 1;
        }
        let p_hit = -(-tau).exp_m1();
        assert_eq!(p_hit.to_bits(), (-(-tau_cut).exp_m1()).to_bits());
        for u in [unit(&mut rng), 1.0 - 1.0 / (1u32 << 24) as f32] {
            let target = -(-u * p_hit).ln_1p();
            let at = |line: &[(usize, f32, f32)], tau: f32| match grid.fly_line(
                o,
                d,
                target.min(tau),
                line,
            ) {
                Flight::Collided(x) => Some(x.to_array().map(f32::to_bits)),
                Flight::Left => None,
            };
            assert_eq!(at(&full, tau), at(&cut, tau_cut));
        }
    }
    assert!(shortened > 500, "{shortened}");
}

#[test]
fn deep_in_a_thick_slab_the_cells_gradient_is_the_diffusion_decay() {
    // A slab of optical thickness 20, isotropic, albedo 0.8, lit from
    // straight above: a few mean free paths below its lit face the
    // fluence decays as e^{−ντ}, ν = 0.71 (the transport equation's
    // asymptotic mode, `ω·artanh(ν)/ν = 1`; diffusion's own estimate is
    // √(3(1 − ω)) = 0.775), so Fick's law read from band 1 must give the
    // cells there a relative gradient pointing up, toward the light, of
    // about ν per metre; carried by it, the light falls with depth.
    let (d, medium) = isotropic_slab(10.0, 0.8);
    let params = CacheParams {
        cells: 40,
        events: 4_000_000,
        order: 1,
        zonal: 0,
        ..CacheParams::default()
    };
    let c = ScatterCache::new(&d, &medium, Vec3::Z, &params).unwrap();
    let nu = 0.71f32;
    // Four to six mean free paths below the lit face (z = 10), the mean
    // over the nine cells round the axis.
    for z in [6.0f32, 5.0, 4.0] {
        let mut g = Vec3::ZERO;
        for (dx, dy) in (-1..=1).flat_map(|a| (-1..=1).map(move |b| (a, b))) {
            let p = Vec3::new(dx as f32 * 0.5, dy as f32 * 0.5, z);
            let (i, _, _) = c.grid.corners(p);
            g += c.log_gradient(c.grid.index(i[0], i[1], i[2])) / 9.0;
        }
        assert!(
            g.x.abs() < 0.25 * nu && g.y.abs() < 0.25 * nu,
            "at z {z}: {g}"
        );
        assert!((g.z - nu).abs() < 0.25 * nu, "at z {z}: {g} against ν {nu}");
    }
    let basis = c.eye_basis(-Vec3::Z);
    let at = |z: f32| c.toward_eye(Vec3::new(0.1, 0.1, z), &basis);
    assert!(
        at(4.2) < at(4.8) && at(4.8) < at(5.4),
        "{} {} {}",
        at(4.2),
        at(4.8),
        at(5.4)
    );
}

#[test]
fn an_isotropic_cache_holds_the_slab_fluence() {
    // A thin homogeneous slab lit from straight above, isotropic,
    // conservative: at its middle, the fluence of once-scattered light is
    // `(ω/2)·∫ E₁(|τ − τ'|) dτ'` over the slab (ω = 1), about 0.358 at
    // optical thickness 0.3 (within the extent's edge effects, the
    // slab is 40 times wider than thick).
    let (d, medium) = isotropic_slab(0.15, 1.0);
    let params = CacheParams {
        cells: 80,
        events: 2_000_000,
        order: 1,
        ..CacheParams::default()
    };
    let c = ScatterCache::new(&d, &medium, Vec3::Z, &params).unwrap();
    let phi = c.mean(Vec3::ZERO) * 4.0 * std::f32::consts::PI;
    // Second and higher orders add about 0.358² · … ≈ 0.1 more.
    assert!(phi > 0.36 && phi < 0.55, "fluence {phi}");
    // The same on any number of threads, and for a fixed seed.
    let again = ScatterCache::new(&d, &medium, Vec3::Z, &params).unwrap();
    assert_eq!(c.coeffs, again.coeffs);
}

#[test]
fn a_zonal_tail_holds_the_bands_of_light_symmetric_about_the_beam() {
    // A wide thin slab lit from straight above scatters light that is
    // symmetric about the vertical beam at its middle: there the zonal
    // tail of bands 4..=7 must give what the full series to band 7 gives
    // (the same photons: the seed fixes them, the order only how they
    // are scored), and the series cut after band 3 must not.
    let region = Aabb {
        min: Vec3::new(-6.0, -6.0, -0.25),
        max: Vec3::new(6.0, 6.0, 0.25),
    };
    let d = crate::density::Homogeneous::new(region, 1.0).unwrap();
    let medium = MediumParams {
        extinction: 2.0,
        albedo: 0.99,
        phase: CloudPhase::HenyeyGreenstein(0.8),
    };
    let cache = |order: u32, zonal: u32| {
        let params = CacheParams {
            cells: 8,
            events: 2_000_000,
            order,
            zonal,
            ..CacheParams::default()
        };
        ScatterCache::new(&d, &medium, Vec3::Z, &params).unwrap()
    };
    let (full, tail, cut) = (cache(7, 0), cache(3, 7), cache(3, 0));
    let (mut worst_tail, mut worst_cut) = (0.0f32, 0.0f32);
    for k in 0..=12 {
        // Eye directions from straight down (the light it sees travels
        // up, against the beam) to straight up (into the beam's peak).
        let theta = std::f32::consts::PI * k as f32 / 12.0;
        let eye = Vec3::new(theta.sin(), 0.0, -theta.cos());
        let at = |c: &ScatterCache| c.toward_eye(Vec3::ZERO, &c.eye_basis(eye));
        let want = at(&full);
        assert!(want > 0.0, "{k}: {want}");
        worst_tail = worst_tail.max((at(&tail) - want).abs() / want);
        worst_cut = worst_cut.max((at(&cut) - want).abs() / want);
    }
    // The tail's difference is the cache's noise in the bands' parts
    // that are not symmetric (1.7 % at most here).
    assert!(worst_tail < 0.025, "tail {worst_tail}");
    assert!(worst_cut > 0.1, "cut {worst_cut}");
}

#[test]
fn bad_settings_name_their_key() {
    for (p, key) in [
        (
            CacheParams {
                cells: 2,
                ..CacheParams::default()
            },
            "cache.cells",
        ),
        (
            CacheParams {
                order: 0,
                ..CacheParams::default()
            },
            "cache.order",
        ),
        (
            CacheParams {
                order: 9,
                ..CacheParams::default()
            },
            "cache.order",
        ),
        (
            CacheParams {
                events: 10,
                ..CacheParams::default()
            },
            "cache.events",
        ),
        (
            CacheParams {
                order: 7,
                zonal: 5,
                ..CacheParams::default()
            },
            "cache.zonal",
        ),
        (
            CacheParams {
                order: 3,
                zonal: 32,
                ..CacheParams::default()
            },
            "cache.zonal",
        ),
        (
            CacheParams {
                local: 5,
                ..CacheParams::default()
            },
            "cache.local",
        ),
    ] {
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains(key), "{e}");
    }
}
