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
