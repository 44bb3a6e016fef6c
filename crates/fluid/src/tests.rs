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

#[test]
fn row_wise_diffusion_matches_general_form() {
    use crate::diffuse::{EXCLUDED, diffuse_ref};
    for n in [[23usize, 1, 19], [9, 7, 11], [1, 1, 40]] {
        let len = n[0] * n[1] * n[2];
        let data: Vec<f32> = (0..len)
            .map(|i| ((natura_core::mix64(i as u64 ^ 77) % 1000) as f32) / 100.0 - 3.0)
            .collect();
        let role: Vec<u8> = (0..len)
            .map(|i| match natura_core::mix64(i as u64 ^ 99) % 9 {
                0 => DIRICHLET,
                1 => EXCLUDED,
                _ => FREE,
            })
            .collect();
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
