//! Unit tests of crate-internal pieces.

use crate::diffuse::{DIRICHLET, FREE, diffuse};

#[test]
fn implicit_diffusion_is_a_contraction_and_conserves_mass() {
    let n = [20usize, 1, 17];
    let len = n[0] * n[2];
    let data: Vec<f32> = (0..len)
        .map(|i| ((natura_core::mix64(i as u64) % 1000) as f32) / 100.0)
        .collect();
    let mut x = data.clone();
    diffuse(&mut x, n, 2.5, &vec![FREE; len]);
    let l2 = |v: &[f32]| v.iter().map(|&a| f64::from(a).powi(2)).sum::<f64>();
    assert!(l2(&x) < l2(&data));
    let (lo, hi) = data
        .iter()
        .fold((f32::MAX, f32::MIN), |(l, h), &v| (l.min(v), h.max(v)));
    assert!(x.iter().all(|&v| v >= lo - 1e-4 && v <= hi + 1e-4));
    let s0: f64 = data.iter().map(|&v| f64::from(v)).sum();
    let s1: f64 = x.iter().map(|&v| f64::from(v)).sum();
    assert!(((s1 - s0) / s0).abs() < 1e-5, "{s0} {s1}");
    // Zero Dirichlet samples on one side drain mass.
    let mut role = vec![FREE; len];
    role[..n[0]].fill(DIRICHLET);
    let mut y = data.clone();
    y[..n[0]].fill(0.0);
    let before: f64 = y.iter().map(|&v| f64::from(v)).sum();
    diffuse(&mut y, n, 2.5, &role);
    let after: f64 = y.iter().map(|&v| f64::from(v)).sum();
    assert!(after < before);
}

/// Hashed diffusion data in `[−shift, 10 − shift)` on an `n` grid and
/// sample roles (one in `roles` Dirichlet, one excluded, the rest free);
/// `salt` seeds the data and the roles.
fn diffusion_case(n: [usize; 3], salt: [u64; 2], shift: f32, roles: u64) -> (Vec<f32>, Vec<u8>) {
    use crate::diffuse::EXCLUDED;
    let len = n[0] * n[1] * n[2];
    let data = (0..len)
        .map(|i| ((natura_core::mix64(i as u64 ^ salt[0]) % 1000) as f32) / 100.0 - shift)
        .collect();
    let role = (0..len)
        .map(|i| match natura_core::mix64(i as u64 ^ salt[1]) % roles {
            0 => DIRICHLET,
            1 => EXCLUDED,
            _ => FREE,
        })
        .collect();
    (data, role)
}

#[test]
fn row_wise_diffusion_matches_general_form() {
    use crate::diffuse::diffuse_ref;
    for n in [[23usize, 1, 19], [9, 7, 11], [1, 1, 40]] {
        let (data, role) = diffusion_case(n, [77, 99], 3.0, 9);
        for coef in [0.05f32, 2.5] {
            let (mut a, mut b) = (data.clone(), data.clone());
            diffuse(&mut a, n, coef, &role);
            diffuse_ref(&mut b, n, coef, &role);
            for (i, (&x, &y)) in a.iter().zip(&b).enumerate() {
                assert!((x - y).abs() <= 1e-4, "{n:?} coef {coef} [{i}]: {x} vs {y}");
            }
        }
    }
}

#[test]
fn row_wise_fixed_faces_match_per_face_rule() {
    use crate::grid::{Boundaries, CellKind, Dims, Side};
    use crate::mac::{face_fixed, fixed_row};
    let mut mixed = Boundaries::closed();
    mixed.x[1] = Side::Open;
    mixed.z[1] = Side::Open;
    mixed.y[0] = Side::Open;
    for d in [Dims::plane(13, 9).unwrap(), Dims::new(7, 6, 5).unwrap()] {
        let kinds: Vec<CellKind> = (0..d.cells())
            .map(|c| match natura_core::mix64(c as u64 ^ 5) % 5 {
                0 => CellKind::Solid,
                1 => CellKind::Air,
                _ => CellKind::Fluid,
            })
            .collect();
        for bounds in [Boundaries::closed(), mixed] {
            for a in (0..3).filter(|&a| d.active(a)) {
                let fd = d.face_dims(a);
                for k in 0..fd[2] {
                    for j in 0..fd[1] {
                        let mut row = vec![false; fd[0]];
                        fixed_row(d, &kinds, &bounds, a, j, k, &mut row);
                        for (i, &v) in row.iter().enumerate() {
                            assert_eq!(v, face_fixed(d, &kinds, &bounds, a, [i, j, k]));
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn grid_point_velocity_matches_general_sampling_bit_for_bit() {
    use crate::advect::{VelSampler, centre_sampler, face_sampler};
    use crate::grid::{Dims, MacVelocity};
    for d in [Dims::plane(11, 8).unwrap(), Dims::new(6, 5, 7).unwrap()] {
        let mut vel = MacVelocity::zeros(d).unwrap();
        for a in 0..3 {
            for (i, v) in vel.comp_mut(a).as_mut_slice().iter_mut().enumerate() {
                *v = ((natura_core::mix64((a * 1000 + i) as u64) % 2001) as f32 / 1000.0) - 1.0;
            }
        }
        let vs = VelSampler::mac(&vel);
        let centre = d.zeros().unwrap();
        let mut grids = vec![centre_sampler(&centre, false)];
        for a in (0..3).filter(|&a| d.active(a)) {
            grids.push(face_sampler(vel.comp(a), a));
        }
        for g in grids {
            let w = vs.grid_weights(g.n, g.off);
            for k in 0..g.n[2] {
                for j in 0..g.n[1] {
                    for i in 0..g.n[0] {
                        let p = [
                            i as f32 + g.off[0],
                            j as f32 + g.off[1],
                            k as f32 + g.off[2],
                        ];
                        let a = vs.at_grid(&w, i, j, k);
                        let b = vs.at(p);
                        for c in 0..3 {
                            assert_eq!(a[c].to_bits(), b[c].to_bits(), "{d:?} {p:?}");
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn shared_path_advection_matches_per_field_bit_for_bit() {
    use crate::advect::{Advection, Solids, VelSampler, advect, advect_many, centre_sampler};
    use crate::grid::{CellKind, Dims, MacVelocity};
    for d in [Dims::plane(17, 13).unwrap(), Dims::new(9, 8, 10).unwrap()] {
        let mut vel = MacVelocity::zeros(d).unwrap();
        for a in 0..3 {
            for (i, v) in vel.comp_mut(a).as_mut_slice().iter_mut().enumerate() {
                *v = ((natura_core::mix64((a * 7919 + i) as u64) % 2001) as f32 / 400.0) - 2.5;
            }
        }
        let kinds: Vec<CellKind> = (0..d.cells())
            .map(|c| {
                if natura_core::mix64(c as u64 ^ 3).is_multiple_of(7) {
                    CellKind::Solid
                } else {
                    CellKind::Fluid
                }
            })
            .collect();
        let solids = Solids {
            kinds: &kinds,
            dims: d,
        };
        let f: Vec<natura_core::Grid3<f32>> = (0..2u64)
            .map(|s| {
                let mut g = d.zeros().unwrap();
                for (i, v) in g.as_mut_slice().iter_mut().enumerate() {
                    *v = (natura_core::mix64(i as u64 ^ (s << 20)) % 1000) as f32;
                }
                g
            })
            .collect();
        let vs = VelSampler::mac(&vel);
        let adv = Advection::default();
        let (mut a0, mut a1) = (f[0].as_slice().to_vec(), f[1].as_slice().to_vec());
        let (mut b0, mut b1) = (a0.clone(), a1.clone());
        let srcs = [centre_sampler(&f[0], false), centre_sampler(&f[1], false)];
        advect_many(
            &mut [&mut a0, &mut a1],
            &srcs,
            &vs,
            0.7,
            &adv,
            Some(&solids),
        );
        advect(&mut b0, &srcs[0], &vs, 0.7, &adv, Some(&solids));
        advect(&mut b1, &srcs[1], &vs, 0.7, &adv, Some(&solids));
        assert!(a0.iter().zip(&b0).all(|(x, y)| x.to_bits() == y.to_bits()));
        assert!(a1.iter().zip(&b1).all(|(x, y)| x.to_bits() == y.to_bits()));
    }
}

#[test]
fn face_cell_rows_match_face_coordinates() {
    use crate::grid::Dims;
    use crate::mac::face_cells;
    for d in [Dims::plane(6, 5).unwrap(), Dims::new(4, 3, 5).unwrap()] {
        let n = d.n();
        for a in (0..3).filter(|&a| d.active(a)) {
            let fd = d.face_dims(a);
            for k in 0..fd[2] {
                for j in 0..fd[1] {
                    let (lo, hi) = face_cells(d, a, j, k);
                    for i in 0..fd[0] {
                        let f = [i, j, k];
                        let want_lo = (f[a] > 0).then(|| {
                            let mut c = f;
                            c[a] -= 1;
                            d.idx(c[0], c[1], c[2])
                        });
                        let want_hi = (f[a] < n[a]).then(|| d.idx(f[0], f[1], f[2]));
                        assert_eq!((lo(i), hi(i)), (want_lo, want_hi), "{d:?} a{a} {f:?}");
                    }
                }
            }
        }
    }
}

#[test]
fn lane_advection_matches_general_code_bit_for_bit() {
    use crate::advect::{
        Advection, Solids, TraceIntegrator, VelSampler, centre_sampler, face_sampler,
        sl_pass_general,
    };
    use crate::advect_linear::sl_linear;
    use crate::grid::{CellKind, Dims, MacVelocity};
    // Sizes that are not multiples of the 16 lanes, thin grids, 2-D and 3-D.
    for d in [
        Dims::plane(37, 21).unwrap(),
        Dims::plane(2, 2).unwrap(),
        Dims::new(19, 7, 11).unwrap(),
        Dims::new(2, 2, 3).unwrap(),
    ] {
        let mut vel = MacVelocity::zeros(d).unwrap();
        for a in 0..3 {
            for (i, v) in vel.comp_mut(a).as_mut_slice().iter_mut().enumerate() {
                *v = ((natura_core::mix64((a * 7919 + i) as u64) % 2001) as f32 / 400.0) - 2.5;
            }
        }
        let kinds: Vec<CellKind> = (0..d.cells())
            .map(|c| {
                if natura_core::mix64(c as u64 ^ 5).is_multiple_of(6) {
                    CellKind::Solid
                } else {
                    CellKind::Fluid
                }
            })
            .collect();
        let solids = Solids {
            kinds: &kinds,
            dims: d,
        };
        let vs = VelSampler::mac(&vel);
        let f: natura_core::Grid3<f32> = {
            let mut g = d.zeros().unwrap();
            for (i, v) in g.as_mut_slice().iter_mut().enumerate() {
                *v = (natura_core::mix64(i as u64 ^ 77) % 1000) as f32 / 7.0;
            }
            g
        };
        let mut samplers = vec![centre_sampler(&f, false)];
        for a in (0..3).filter(|&a| d.active(a)) {
            samplers.push(face_sampler(vel.comp(a), a));
        }
        for tracer in [TraceIntegrator::Euler, TraceIntegrator::Rk2] {
            let adv = Advection {
                tracer,
                ..Default::default()
            };
            // Small, large (feet far outside) and negative (backward) steps.
            for dt_h in [0.3f32, 4.0, -1.7] {
                for sol in [None, Some(&solids)] {
                    for src in &samplers {
                        let mut fast = vec![f32::NAN; src.data.len()];
                        let mut slow = fast.clone();
                        assert!(sl_linear(&mut [&mut fast], &[*src], &vs, dt_h, tracer, sol));
                        sl_pass_general(&mut slow, None, src, &vs, dt_h, &adv, sol);
                        for (c, (x, y)) in fast.iter().zip(&slow).enumerate() {
                            assert_eq!(
                                x.to_bits(),
                                y.to_bits(),
                                "{d:?} {tracer:?} dt_h {dt_h} off {:?} sample {c}: {x} vs {y}",
                                src.off
                            );
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn lane_advection_declines_periodic_grids() {
    use crate::advect::{TraceIntegrator, VelSampler, centre_sampler};
    use crate::advect_linear::sl_linear;
    use crate::grid::Dims;
    let d = Dims::plane(8, 8).unwrap();
    let comps = [d.zeros().unwrap(), d.zeros().unwrap(), d.zeros().unwrap()];
    let vs = VelSampler::collocated(&comps, d);
    let f = d.zeros().unwrap();
    let mut out = vec![0.0f32; 64];
    assert!(!sl_linear(
        &mut [&mut out],
        &[centre_sampler(&f, true)],
        &vs,
        0.5,
        TraceIntegrator::Rk2,
        None
    ));
}

#[test]
fn diffusion_with_reused_work_vectors_matches_fresh_ones() {
    use crate::diffuse::{Scratch, diffuse_in};
    let mut scratch = Scratch::default();
    // Dirty the work vectors with a larger, different problem first.
    let mut big: Vec<f32> = (0..40 * 30).map(|i| (i % 17) as f32).collect();
    diffuse_in(
        &mut scratch,
        &mut big,
        [40, 1, 30],
        1.5,
        &vec![FREE; 40 * 30],
    );
    let n = [23usize, 1, 19];
    let len = n[0] * n[2];
    let data: Vec<f32> = (0..len)
        .map(|i| ((natura_core::mix64(i as u64 ^ 5) % 1000) as f32) / 100.0)
        .collect();
    let role: Vec<u8> = (0..len)
        .map(|i| if i % 11 == 0 { DIRICHLET } else { FREE })
        .collect();
    let (mut a, mut b) = (data.clone(), data);
    let ia = diffuse_in(&mut scratch, &mut a, n, 0.7, &role);
    let ib = diffuse(&mut b, n, 0.7, &role);
    assert_eq!(ia, ib);
    assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
}

#[test]
fn row_slice_divergence_matches_per_face_form() {
    use crate::grid::{Dims, MacVelocity};
    use crate::mac::divergence;
    for d in [Dims::plane(13, 9).unwrap(), Dims::new(7, 6, 5).unwrap()] {
        let mut vel = MacVelocity::zeros(d).unwrap();
        for a in 0..3 {
            for (i, v) in vel.comp_mut(a).as_mut_slice().iter_mut().enumerate() {
                *v = ((natura_core::mix64((a * 31 + i) as u64) % 2001) as f32 / 1000.0) - 1.0;
            }
        }
        let h = 0.37;
        let div = divergence(&vel, h).unwrap();
        let c = vel.comps();
        for k in 0..d.n()[2] {
            for j in 0..d.n()[1] {
                for i in 0..d.n()[0] {
                    let mut s = 0.0f32;
                    if d.active(0) {
                        s += c[0][(i + 1, j, k)] - c[0][(i, j, k)];
                    }
                    if d.active(1) {
                        s += c[1][(i, j + 1, k)] - c[1][(i, j, k)];
                    }
                    if d.active(2) {
                        s += c[2][(i, j, k + 1)] - c[2][(i, j, k)];
                    }
                    assert_eq!(div[(i, j, k)].to_bits(), (s * (1.0 / h)).to_bits());
                }
            }
        }
    }
}

#[test]
fn one_pass_max_divergence_equals_the_divergence_grid_maximum() {
    use crate::grid::{CellKind, Dims, MacVelocity};
    use crate::mac::{divergence, max_fluid_divergence};
    use natura_core::Grid3;
    // Small (serial) and large enough for the banded parallel fold, 2-D and 3-D.
    for d in [
        Dims::plane(13, 9).unwrap(),
        Dims::new(7, 6, 5).unwrap(),
        Dims::plane(160, 90).unwrap(),
        Dims::new(40, 33, 21).unwrap(),
    ] {
        let mut vel = MacVelocity::zeros(d).unwrap();
        for a in (0..3).filter(|&a| d.active(a)) {
            for (f, v) in vel.comp_mut(a).as_mut_slice().iter_mut().enumerate() {
                let x = natura_core::mix64(f as u64 * 3 + a as u64) >> 40;
                *v = x as f32 / (1u64 << 24) as f32 - 0.5;
            }
        }
        let kinds = Grid3::from_vec(
            d.nx,
            d.ny,
            d.nz,
            (0..d.cells())
                .map(|c| match natura_core::mix64(c as u64 ^ 11) % 4 {
                    0 => CellKind::Solid,
                    1 => CellKind::Air,
                    _ => CellKind::Fluid,
                })
                .collect(),
        )
        .unwrap();
        let h = 0.37;
        let div = divergence(&vel, h).unwrap();
        let want = div
            .as_slice()
            .iter()
            .zip(kinds.as_slice())
            .filter(|(_, k)| **k == CellKind::Fluid)
            .fold(0.0f32, |m, (v, _)| m.max(v.abs()));
        assert!(want > 0.0);
        let got = max_fluid_divergence(&vel, &kinds, h).unwrap();
        assert_eq!(got.to_bits(), want.to_bits(), "{d}");
    }
}

/// The row-wise pressure gradient equals the per-face form it replaced
/// (face cells looked up one face at a time), bit for bit, with solids,
/// air, open and wall sides, in 2-D and 3-D.
#[test]
fn row_wise_pressure_gradient_matches_per_face_form() {
    use crate::grid::{Boundaries, CellKind, Dims, MacVelocity, Side};
    use crate::mac::{apply_pressure, face_cells, fixed_row};
    let mut mixed = Boundaries::closed();
    mixed.x[1] = Side::Open;
    mixed.z[1] = Side::Open;
    mixed.y[0] = Side::Open;
    for d in [Dims::plane(13, 9).unwrap(), Dims::new(7, 6, 5).unwrap()] {
        let kinds: Vec<CellKind> = (0..d.cells())
            .map(|c| match natura_core::mix64(c as u64 ^ 11) % 5 {
                0 => CellKind::Solid,
                1 => CellKind::Air,
                _ => CellKind::Fluid,
            })
            .collect();
        let p: Vec<f64> = (0..d.cells())
            .map(|c| ((natura_core::mix64(c as u64 ^ 3) % 20001) as f64 / 1e4 - 1.0) * 1e3)
            .collect();
        for bounds in [Boundaries::closed(), mixed] {
            let mut vel = MacVelocity::zeros(d).unwrap();
            for a in 0..3 {
                for (i, v) in vel.comp_mut(a).as_mut_slice().iter_mut().enumerate() {
                    *v = ((natura_core::mix64((a * 977 + i) as u64) % 2001) as f32 / 1000.0) - 1.0;
                }
            }
            let mut want = vel.clone();
            let h = 0.37f32;
            let inv = 1.0 / f64::from(h);
            let pv = |i: usize| {
                if kinds[i] == CellKind::Fluid {
                    p[i]
                } else {
                    0.0
                }
            };
            for a in (0..3).filter(|&a| d.active(a)) {
                let fd = d.face_dims(a);
                let g = want.comp_mut(a).as_mut_slice();
                for k in 0..fd[2] {
                    for j in 0..fd[1] {
                        let mut fx = vec![false; fd[0]];
                        fixed_row(d, &kinds, &bounds, a, j, k, &mut fx);
                        let (lo, hi) = face_cells(d, a, j, k);
                        for i in 0..fd[0] {
                            if fx[i] {
                                continue;
                            }
                            let side = |c: Option<usize>| match c {
                                Some(c) => (pv(c), kinds[c] == CellKind::Fluid),
                                None => (0.0, false),
                            };
                            let ((p0, f0), (p1, f1)) = (side(lo(i)), side(hi(i)));
                            if f0 || f1 {
                                let v = &mut g[i + fd[0] * (j + fd[1] * k)];
                                *v = (f64::from(*v) - (p1 - p0) * inv) as f32;
                            }
                        }
                    }
                }
            }
            apply_pressure(&mut vel, &kinds, &bounds, h, &p);
            for a in (0..3).filter(|&a| d.active(a)) {
                for (i, (x, y)) in vel
                    .comp(a)
                    .as_slice()
                    .iter()
                    .zip(want.comp(a).as_slice())
                    .enumerate()
                {
                    assert_eq!(x.to_bits(), y.to_bits(), "axis {a} face {i} on {d:?}");
                }
            }
        }
    }
}

/// The row-wise centre-force pass equals the per-face form it replaced
/// (face cells looked up one face at a time), bit for bit.
#[test]
fn row_wise_centre_forces_match_per_face_form() {
    use crate::grid::{Boundaries, CellKind, Dims, MacVelocity, Side};
    use crate::mac::{add_centre_forces, face_cells, fixed_row};
    let mut mixed = Boundaries::closed();
    mixed.x[1] = Side::Open;
    mixed.z[0] = Side::Open;
    mixed.y[1] = Side::Open;
    for d in [Dims::plane(13, 9).unwrap(), Dims::new(7, 6, 5).unwrap()] {
        let kinds: Vec<CellKind> = (0..d.cells())
            .map(|c| match natura_core::mix64(c as u64 ^ 13) % 4 {
                0 => CellKind::Solid,
                _ => CellKind::Fluid,
            })
            .collect();
        let force: [natura_core::Grid3<f32>; 3] = std::array::from_fn(|a| {
            let mut g = d.zeros().unwrap();
            for (i, v) in g.as_mut_slice().iter_mut().enumerate() {
                *v = ((natura_core::mix64((a * 31 + i) as u64) % 2001) as f32 / 100.0) - 10.0;
            }
            g
        });
        for bounds in [Boundaries::closed(), mixed] {
            let mut vel = MacVelocity::zeros(d).unwrap();
            for a in 0..3 {
                for (i, v) in vel.comp_mut(a).as_mut_slice().iter_mut().enumerate() {
                    *v = ((natura_core::mix64((a * 577 + i) as u64) % 2001) as f32 / 1000.0) - 1.0;
                }
            }
            let mut want = vel.clone();
            let dt = 0.013f32;
            for a in (0..3).filter(|&a| d.active(a)) {
                let fd = d.face_dims(a);
                let fa = force[a].as_slice();
                let g = want.comp_mut(a).as_mut_slice();
                for k in 0..fd[2] {
                    for j in 0..fd[1] {
                        let mut fx = vec![false; fd[0]];
                        fixed_row(d, &kinds, &bounds, a, j, k, &mut fx);
                        let (lo, hi) = face_cells(d, a, j, k);
                        for i in 0..fd[0] {
                            if fx[i] {
                                continue;
                            }
                            let val = match (lo(i), hi(i)) {
                                (Some(c0), Some(c1)) => 0.5 * (fa[c0] + fa[c1]),
                                (Some(c), None) | (None, Some(c)) => fa[c],
                                (None, None) => 0.0,
                            };
                            g[i + fd[0] * (j + fd[1] * k)] += dt * val;
                        }
                    }
                }
            }
            add_centre_forces(&mut vel, &force, dt, &kinds, &bounds);
            for a in (0..3).filter(|&a| d.active(a)) {
                for (i, (x, y)) in vel
                    .comp(a)
                    .as_slice()
                    .iter()
                    .zip(want.comp(a).as_slice())
                    .enumerate()
                {
                    assert_eq!(x.to_bits(), y.to_bits(), "axis {a} face {i} on {d:?}");
                }
            }
        }
    }
}

#[test]
fn cached_diffusion_roles_follow_a_moving_obstacle() {
    use crate::grid::{CellKind, Dims};
    use crate::shape::{Obstacle, Shape};
    use crate::stable::{BoundedFluid, StableParams, Substance};
    use glam::Vec3;
    let (nx, nz) = (40usize, 32usize);
    let h = 1.0 / nx as f32;
    let d = Dims::plane(nx, nz).unwrap();
    let params = StableParams {
        viscosity: 0.02,
        ..Default::default()
    };
    let mut a = BoundedFluid::new(d, h, params).unwrap();
    let id = a
        .add_substance(Substance {
            name: "dye".into(),
            diffusion: 0.01,
            dissipation: 0.0,
        })
        .unwrap();
    a.add_obstacle(Obstacle {
        velocity: Vec3::new(2.0, 0.0, 0.5),
        ..Obstacle::fixed(Shape::Sphere {
            centre: Vec3::new(0.3, 0.5 * h, 0.4),
            radius: 0.12,
        })
    })
    .unwrap();
    for (i, v) in a
        .substance_mut(id)
        .unwrap()
        .as_mut_slice()
        .iter_mut()
        .enumerate()
    {
        *v = ((natura_core::mix64(i as u64) % 1000) as f32) / 1000.0;
    }
    for (i, v) in a
        .velocity_mut()
        .comp_mut(0)
        .as_mut_slice()
        .iter_mut()
        .enumerate()
    {
        *v = ((natura_core::mix64(i as u64 ^ 3) % 1000) as f32) / 2000.0 - 0.25;
    }
    let mut b = a.clone();
    let solid = |f: &BoundedFluid| -> Vec<bool> {
        f.cell_kinds()
            .as_slice()
            .iter()
            .map(|&k| k == CellKind::Solid)
            .collect()
    };
    let first = solid(&a);
    for _ in 0..12 {
        a.step(0.01).unwrap();
        // `b` rebuilds its roles every step: the cache must give the same.
        b.forget_roles();
        b.step(0.01).unwrap();
        for c in [0, 2] {
            let (x, y) = (
                a.velocity().comp(c).as_slice(),
                b.velocity().comp(c).as_slice(),
            );
            assert!(x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()));
        }
        let (x, y) = (a.substance(id).unwrap(), b.substance(id).unwrap());
        assert!(
            x.as_slice()
                .iter()
                .zip(y.as_slice())
                .all(|(p, q)| p.to_bits() == q.to_bits())
        );
    }
    // The obstacle moved by several cells, so the kinds (and roles) changed.
    let moved = first
        .iter()
        .zip(solid(&a))
        .filter(|(p, q)| **p != *q)
        .count();
    assert!(moved > 20, "{moved}");
}

#[test]
fn chebyshev_diffusion_meets_the_stated_residual() {
    use crate::diffuse::{EXCLUDED, diffuse};
    // The true residual ‖b − A x‖₂ / ‖b‖₂ of the returned field, evaluated
    // in f64 from the general form of the system, is at most 1e-6 (f32
    // round-off allowed for), for mild and stiff systems, 1-D to 3-D.
    for n in [[31usize, 1, 27], [9, 7, 11], [1, 1, 40], [64, 1, 64]] {
        let (data, role) = diffusion_case(n, [11, 13], 2.0, 10);
        for coef in [0.05f32, 0.5, 20.0] {
            let mut x = data.clone();
            let it = diffuse(&mut x, n, coef, &role);
            assert!(it > 0);
            let st = [1usize, n[0], n[0] * n[1]];
            let (mut rr, mut bb) = (0.0f64, 0.0f64);
            for s in 0..data.len() {
                if role[s] != FREE {
                    assert_eq!(
                        x[s].to_bits(),
                        data[s].to_bits(),
                        "fixed samples keep their value"
                    );
                    continue;
                }
                let c = [s % n[0], (s / n[0]) % n[1], s / (n[0] * n[1])];
                let (mut ax, mut b) = (f64::from(x[s]), f64::from(data[s]));
                for a in 0..3 {
                    for (ok, nb) in [
                        (c[a] > 0, s.wrapping_sub(st[a])),
                        (c[a] + 1 < n[a], s + st[a]),
                    ] {
                        if !ok || role[nb] == EXCLUDED {
                            continue;
                        }
                        let k = f64::from(coef);
                        if role[nb] == DIRICHLET {
                            b += k * f64::from(data[nb]);
                            ax += k * f64::from(x[s]);
                        } else {
                            ax += k * (f64::from(x[s]) - f64::from(x[nb]));
                        }
                    }
                }
                rr += (b - ax).powi(2);
                bb += b * b;
            }
            let rel = (rr / bb).sqrt();
            assert!(
                rel <= 1.5e-6,
                "{n:?} coef {coef}: {rel:.2e} after {it} steps"
            );
        }
    }
}

#[test]
fn finiteness_scan_and_energy_sums_match_the_plain_forms() {
    use crate::grid::{Dims, MacVelocity, all_finite, check_grid};
    use natura_core::Grid3;
    for len in [1usize, 7, 8191, 8192, 8193, 40_000] {
        let v: Vec<f32> = (0..len).map(|i| i as f32 * 0.25 - 3.0).collect();
        assert!(all_finite(&v));
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            for at in [0, len / 2, len - 1] {
                let mut w = v.clone();
                w[at] = bad;
                assert!(!all_finite(&w), "{len} {at}");
                let g = Grid3::from_vec(len, 1, 1, w).unwrap();
                match check_grid(&g, "u", "test") {
                    Err(crate::FluidError::NonFinite { index, .. }) => {
                        assert_eq!(index, [at, 0, 0])
                    }
                    other => panic!("{other:?}"),
                }
            }
        }
    }
    // Kinetic energy in lane sums against a compensated sum, and the same
    // bits on 1 and 2 threads.
    let d = Dims::new(70, 3, 90).unwrap();
    let mut vel = MacVelocity::zeros(d).unwrap();
    for a in 0..3 {
        for (i, v) in vel.comp_mut(a).as_mut_slice().iter_mut().enumerate() {
            *v = ((natura_core::mix64((i * 3 + a) as u64) % 20_001) as f32) / 1000.0 - 10.0;
        }
    }
    let h = 0.01f32;
    let (mut sum, mut comp) = (0.0f64, 0.0f64);
    for a in 0..3 {
        for &v in vel.comp(a).as_slice() {
            let y = f64::from(v) * f64::from(v) - comp;
            let t = sum + y;
            comp = (t - sum) - y;
            sum = t;
        }
    }
    let exact = 0.5 * f64::from(h).powi(3) * sum;
    let ke = |t: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap()
            .install(|| vel.kinetic_energy(h))
    };
    let (k1, k2) = (ke(1), ke(2));
    assert_eq!(k1.to_bits(), k2.to_bits());
    assert!(((k1 - exact) / exact).abs() < 1e-13, "{k1} vs {exact}");
}

#[test]
fn a_force_field_of_the_wrong_size_is_an_error() {
    use crate::grid::Dims;
    use crate::stable::{BoundedFluid, StableParams};
    let d = Dims::plane(16, 12).unwrap();
    let mut f = BoundedFluid::new(d, 0.1, StableParams::default()).unwrap();
    f.force_mut()[2] = natura_core::Grid3::new(5, 1, 5, 1.0f32).unwrap();
    assert!(matches!(
        f.step(0.01),
        Err(crate::FluidError::SizeMismatch { .. })
    ));
}
