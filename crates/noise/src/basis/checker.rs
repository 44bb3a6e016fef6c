//! Musgrave's checkerboard basis (Musgrave 2001, "Checkerboard").

use glam::{DVec2, DVec3};

use crate::field::Field;
use crate::lattice_math::split;

/// `+1` / `−1` alternating over unit lattice cells (Musgrave 2001,
/// "Checkerboard"): `+1` where `⌊x⌋ + ⌊y⌋ (+ ⌊z⌋)` is even. Discontinuous
/// (infinite Lipschitz constant, zero gradient inside cells).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Checkerboard;

#[inline]
fn parity(sum: u32) -> f64 {
    if sum & 1 == 0 { 1.0 } else { -1.0 }
}

impl Field for Checkerboard {
    fn eval2(&self, p: DVec2) -> f64 {
        if !p.is_finite() {
            return f64::NAN;
        }
        parity(split(p.x).0.wrapping_add(split(p.y).0))
    }
    fn eval3(&self, p: DVec3) -> f64 {
        if !p.is_finite() {
            return f64::NAN;
        }
        parity(
            split(p.x)
                .0
                .wrapping_add(split(p.y).0)
                .wrapping_add(split(p.z).0),
        )
    }
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        (self.eval2(p), DVec2::ZERO)
    }
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        (self.eval3(p), DVec3::ZERO)
    }
    fn bound(&self) -> f64 {
        1.0
    }
    fn lipschitz2(&self) -> f64 {
        f64::INFINITY
    }
    fn lipschitz3(&self) -> f64 {
        f64::INFINITY
    }
}
