//! Musgrave's sine basis: the product of sines along each axis (Musgrave 2001,
//! "Sine").

use glam::{DVec2, DVec3};

use crate::field::Field;

/// `sin x · sin y` (2-D) or `sin x · sin y · sin z` (3-D): periodic with period
/// 2π along every axis, values in `[-1, 1]`, mean 0 (Musgrave 2001, "Sine").
///
/// Lipschitz constant 1 in 2-D and 3-D: `|∇|² = a + b − 2ab` (2-D, with
/// `a = sin²x`, `b = sin²y`) and `ab + bc + ca − 3abc` (3-D) are at most 1 on `[0, 1]ⁿ`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sine;

impl Field for Sine {
    fn eval2(&self, p: DVec2) -> f64 {
        libm::sin(p.x) * libm::sin(p.y)
    }
    fn eval3(&self, p: DVec3) -> f64 {
        libm::sin(p.x) * libm::sin(p.y) * libm::sin(p.z)
    }
    fn eval_grad2(&self, p: DVec2) -> (f64, DVec2) {
        let (sx, cx) = (libm::sin(p.x), libm::cos(p.x));
        let (sy, cy) = (libm::sin(p.y), libm::cos(p.y));
        (sx * sy, DVec2::new(cx * sy, sx * cy))
    }
    fn eval_grad3(&self, p: DVec3) -> (f64, DVec3) {
        let (sx, cx) = (libm::sin(p.x), libm::cos(p.x));
        let (sy, cy) = (libm::sin(p.y), libm::cos(p.y));
        let (sz, cz) = (libm::sin(p.z), libm::cos(p.z));
        (
            sx * sy * sz,
            DVec3::new(cx * sy * sz, sx * cy * sz, sx * sy * cz),
        )
    }
    fn bound(&self) -> f64 {
        1.0
    }
    fn lipschitz2(&self) -> f64 {
        1.0
    }
    fn lipschitz3(&self) -> f64 {
        1.0
    }
}
