//! Helpers shared by the integration tests (fixed-seed sampling, batch checks).
#![allow(dead_code, missing_docs, missing_debug_implementations)]

use glam::{DVec2, DVec3};
use natura_noise::{Field, Simd};

/// A tiny deterministic generator for test points (splitmix64).
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f()
    }
    pub fn p2(&mut self, r: f64) -> DVec2 {
        DVec2::new(self.range(-r, r), self.range(-r, r))
    }
    pub fn p3(&mut self, r: f64) -> DVec3 {
        DVec3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
    }
    pub fn unit3(&mut self) -> DVec3 {
        loop {
            let v = self.p3(1.0);
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

/// Asserts that batch rows at every supported SIMD level match point
/// evaluation within `tol·max(1, bound)`, for rows of several step sizes
/// (both the span path and the per-lane path), and are bit-identical across levels.
pub fn check_batch<F: Field>(f: &F, tol: f64, seed: u64) {
    let mut rng = Rng(seed);
    let scale_tol = tol * f.bound().max(1.0);
    for &step in &[0.003, 0.01, 0.07, 0.31, 1.37, 5.3] {
        for trial in 0..3 {
            let n = 37 + trial * 200;
            let o2 = rng.p2(50.0);
            let o3 = rng.p3(50.0);
            let mut reference2: Option<Vec<f32>> = None;
            let mut reference3: Option<Vec<f32>> = None;
            for simd in Simd::supported() {
                let mut row = vec![0.0f32; n];
                f.fill_row2_with(simd, o2, step, &mut row);
                for (i, &v) in row.iter().enumerate() {
                    let p = DVec2::new(o2.x + i as f64 * step, o2.y);
                    let e = f.eval2(p);
                    assert!(
                        (v as f64 - e).abs() <= scale_tol,
                        "2-D {simd:?} step {step} i {i}: batch {v} point {e}"
                    );
                }
                match &reference2 {
                    None => reference2 = Some(row),
                    Some(r) => assert_eq!(r, &row, "2-D levels differ at {simd:?} step {step}"),
                }
                let mut row = vec![0.0f32; n];
                f.fill_row3_with(simd, o3, step, &mut row);
                for (i, &v) in row.iter().enumerate() {
                    let p = DVec3::new(o3.x + i as f64 * step, o3.y, o3.z);
                    let e = f.eval3(p);
                    assert!(
                        (v as f64 - e).abs() <= scale_tol,
                        "3-D {simd:?} step {step} i {i}: batch {v} point {e}"
                    );
                }
                match &reference3 {
                    None => reference3 = Some(row),
                    Some(r) => assert_eq!(r, &row, "3-D levels differ at {simd:?} step {step}"),
                }
            }
        }
    }
}

/// Asserts the 2-D row from `o2` and the 3-D row from `o3`, `n` points
/// `step` apart along x, match the point path within `tol` at every SIMD
/// level, and that every level gives the same bits.
pub fn check_rows_bitwise<F: Field>(f: &F, step: f64, o2: DVec2, o3: DVec3, n: usize, tol: f64) {
    let mut reference: Option<Vec<u32>> = None;
    for simd in Simd::supported() {
        let (mut r2, mut r3) = (vec![0.0f32; n], vec![0.0f32; n]);
        f.fill_row2_with(simd, o2, step, &mut r2);
        f.fill_row3_with(simd, o3, step, &mut r3);
        for i in 0..n {
            let dx = i as f64 * step;
            let e2 = f.eval2(DVec2::new(o2.x + dx, o2.y));
            let e3 = f.eval3(DVec3::new(o3.x + dx, o3.y, o3.z));
            assert!(
                (f64::from(r2[i]) - e2).abs() <= tol,
                "2-D {simd:?} step {step} origin {o2} i {i}: row {}, point {e2}",
                r2[i]
            );
            assert!(
                (f64::from(r3[i]) - e3).abs() <= tol,
                "3-D {simd:?} step {step} origin {o3} i {i}: row {}, point {e3}",
                r3[i]
            );
        }
        let bits: Vec<u32> = r2.iter().chain(&r3).map(|v| v.to_bits()).collect();
        match &reference {
            None => reference = Some(bits),
            Some(r) => assert_eq!(r, &bits, "levels differ at {simd:?} step {step}"),
        }
    }
}

/// Asserts the analytic gradient matches central differences within `tol`
/// (relative to the Lipschitz constant).
pub fn check_gradient<F: Field>(f: &F, tol: f64, seed: u64, n: usize) {
    let mut rng = Rng(seed);
    let h = 1e-6;
    for _ in 0..n {
        let p = rng.p2(20.0);
        let (v, g) = f.eval_grad2(p);
        assert!(
            (v - f.eval2(p)).abs() < 1e-12 * f.bound().max(1.0),
            "value mismatch at {p}"
        );
        let fd = DVec2::new(
            (f.eval2(p + DVec2::X * h) - f.eval2(p - DVec2::X * h)) / (2.0 * h),
            (f.eval2(p + DVec2::Y * h) - f.eval2(p - DVec2::Y * h)) / (2.0 * h),
        );
        assert!(
            (g - fd).length() <= tol * f.lipschitz2().max(1.0),
            "2-D gradient at {p}: {g} vs {fd}"
        );
        let p = rng.p3(20.0);
        let (v, g) = f.eval_grad3(p);
        assert!((v - f.eval3(p)).abs() < 1e-12 * f.bound().max(1.0));
        let d = |e: DVec3| (f.eval3(p + e * h) - f.eval3(p - e * h)) / (2.0 * h);
        let fd = DVec3::new(d(DVec3::X), d(DVec3::Y), d(DVec3::Z));
        assert!(
            (g - fd).length() <= tol * f.lipschitz3().max(1.0),
            "3-D gradient at {p}: {g} vs {fd}"
        );
    }
}

/// Asserts `|f(p) − f(q)| ≤ L·|p − q|` on random close pairs, returning the
/// largest observed ratio over L (2-D and 3-D).
pub fn check_lipschitz<F: Field>(f: &F, seed: u64, n: usize, radius: f64) -> (f64, f64) {
    let mut rng = Rng(seed);
    let (l2, l3) = (f.lipschitz2(), f.lipschitz3());
    let (mut r2, mut r3) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let p = rng.p2(30.0);
        let q = p + rng.p2(radius);
        let d = (f.eval2(p) - f.eval2(q)).abs();
        let dist = (p - q).length();
        assert!(
            d <= l2 * dist * (1.0 + 1e-9) + 1e-12,
            "2-D Lipschitz {d} > {l2}·{dist}"
        );
        r2 = r2.max(d / (l2 * dist));
        let p = rng.p3(30.0);
        let q = p + rng.p3(radius);
        let d = (f.eval3(p) - f.eval3(q)).abs();
        let dist = (p - q).length();
        assert!(
            d <= l3 * dist * (1.0 + 1e-9) + 1e-12,
            "3-D Lipschitz {d} > {l3}·{dist}"
        );
        r3 = r3.max(d / (l3 * dist));
    }
    (r2, r3)
}

/// Asserts `f.fill_rows2_with` over the rows at `ys` equals `fill_row2_with`
/// row by row, bit for bit, at every SIMD level, for rows of `n` points
/// from `x0` at `step`; and that `fill_grid2` equals its rows.
pub fn check_rows_many<F: Field>(f: &F, x0: f64, ys: &[f64], step: f64, n: usize) {
    for simd in Simd::supported() {
        let mut many = vec![f32::NAN; ys.len() * n];
        f.fill_rows2_with(simd, x0, ys, step, &mut many);
        for (r, &y) in ys.iter().enumerate() {
            let mut row = vec![0.0f32; n];
            f.fill_row2_with(simd, DVec2::new(x0, y), step, &mut row);
            let (a, b): (Vec<u32>, Vec<u32>) = (
                row.iter().map(|v| v.to_bits()).collect(),
                many[r * n..(r + 1) * n]
                    .iter()
                    .map(|v| v.to_bits())
                    .collect(),
            );
            assert_eq!(a, b, "{simd:?} step {step} x0 {x0} row {r} (y {y})");
        }
    }
}
