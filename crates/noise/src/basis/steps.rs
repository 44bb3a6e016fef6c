//! Musgrave's "steps" basis: random levels in a cubic lattice (Musgrave 2001,
//! "Steps").

use glam::{DVec2, DVec3};

use crate::field::Field;
use crate::hash::{corner, row2, row3, seed32, signed_unit};
use crate::lattice_math::split;

const SALT: u64 = 0x5354_4550; // "STEP"

/// Piecewise-constant random levels, one per unit lattice cell, uniform in
/// `[-1, 1)` (Musgrave 2001, "Steps"). Discontinuous ("Mathematically Evil"
/// Musgrave 2001, "Steps"): it aliases, and its Lipschitz constant is infinite;
/// the gradient is 0 inside cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Steps {
    seed: u64,
    s: u32,
}

impl Steps {
    /// Steps with `seed`.
    #[must_use]
    pub const fn new(seed: u64) -> Self {
        Self {
            seed,
            s: seed32(seed, SALT),
        }
    }

    /// The seed.
    #[must_use]
    pub const fn seed(&self) -> u64 {
        self.seed
    }
}

impl Field for Steps {
    fn eval2(&self, p: DVec2) -> f64 {
        if !p.is_finite() {
            return f64::NAN;
        }
        let (ix, _) = split(p.x);
        let (iy, _) = split(p.y);
        f64::from(signed_unit(corner(ix, row2(iy, self.s))))
    }
    fn eval3(&self, p: DVec3) -> f64 {
        if !p.is_finite() {
            return f64::NAN;
        }
        let (ix, _) = split(p.x);
        let (iy, _) = split(p.y);
        let (iz, _) = split(p.z);
        f64::from(signed_unit(corner(ix, row3(iy, iz, self.s))))
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
