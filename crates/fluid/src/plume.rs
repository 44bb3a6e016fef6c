//! A preset: warm smoke rising from a spherical source past a fixed sphere
//! (Fedkiw, Stam & Jensen 2001, §5 and Fig. 5 in spirit: vorticity
//! confinement keeps the rolls that the grid's numerical dissipation would
//! smooth away, and monotone cubic advection keeps the smoke's edges), the
//! set-up of the `smoke3d` example and of the tests that compare its
//! rendering against the reference, in one place.

use glam::Vec3;

use crate::advect::Advection;
use crate::error::{FluidError, Result, non_negative, positive};
use crate::grid::Dims;
use crate::interp::{CubicLimiter, Interpolation};
use crate::shape::{Obstacle, Shape};
use crate::smoke::{Smoke, SmokeParams, SmokeSource};

/// The plume's settings: a box `width` across and twice as tall, `cells`
/// across.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plume {
    /// Cells across the box (4 to 512; the box is `cells × cells × 2·cells`).
    pub cells: usize,
    /// Width of the box (m).
    pub width: f32,
    /// Vorticity confinement strength ε (1/s).
    pub epsilon: f32,
}

impl Default for Plume {
    /// 48 cells across a box 1 m wide, ε = 4/s.
    fn default() -> Self {
        Self {
            cells: 48,
            width: 1.0,
            epsilon: 4.0,
        }
    }
}

impl Plume {
    /// Checks the fields.
    ///
    /// # Errors
    ///
    /// [`FluidError::InvalidParameter`] naming `cells` outside `4..=512`,
    /// `width` not finite and positive, or `epsilon` negative or not finite.
    pub fn validate(&self) -> Result<()> {
        if !(4..=512).contains(&self.cells) {
            return Err(FluidError::InvalidParameter {
                name: "cells",
                value: self.cells.to_string(),
                reason: "4 to 512 cells across",
            });
        }
        positive("width", f64::from(self.width))?;
        non_negative("epsilon", f64::from(self.epsilon))
    }

    /// The cell size (m).
    #[must_use]
    pub fn cell(&self) -> f32 {
        self.width / self.cells as f32
    }

    /// The fixed sphere the smoke rises past: its centre and radius (m),
    /// off the plume's axis so the smoke splits unevenly round it.
    #[must_use]
    pub fn sphere(&self) -> (Vec3, f32) {
        let w = self.width;
        (Vec3::new(0.45 * w, 0.5 * w, 0.85 * w), 0.15 * w)
    }

    /// The time step (s): half a cell per step at the plume's fastest
    /// speed, about 0.6 m/s per metre of width.
    #[must_use]
    pub fn dt(&self) -> f32 {
        0.5 * self.cell() / 0.6
    }

    /// The steps that cover `seconds`.
    #[must_use]
    pub fn steps(&self, seconds: f32) -> usize {
        (seconds / self.dt()).ceil() as usize
    }

    /// The solver at time 0: the box, the sphere as a fixed obstacle, and
    /// the source (a sphere low on the axis, emitting smoke at 330 K with
    /// an upward velocity of 0.3 m/s), with monotone cubic
    /// (Fritsch–Carlson) advection.
    ///
    /// # Errors
    ///
    /// As [`Plume::validate`]; as [`Smoke::new`].
    pub fn build(&self) -> Result<Smoke> {
        self.validate()?;
        let n = self.cells;
        let w = self.width;
        let mut smoke = Smoke::new(
            Dims::new(n, n, 2 * n)?,
            self.cell(),
            SmokeParams {
                epsilon: self.epsilon,
                advection: Advection {
                    interpolation: Interpolation::MonotoneCubic(CubicLimiter::FritschCarlson),
                    ..Advection::default()
                },
                ..SmokeParams::default()
            },
        )?;
        let (centre, radius) = self.sphere();
        smoke.add_obstacle(Obstacle::fixed(Shape::Sphere { centre, radius }))?;
        smoke.add_source(SmokeSource {
            shape: Shape::Sphere {
                centre: Vec3::new(0.5 * w, 0.5 * w, 0.15 * w),
                radius: 0.08 * w,
            },
            density: 1.0,
            temperature: 330.0,
            velocity: Some(Vec3::new(0.0, 0.0, 0.3)),
        })?;
        Ok(smoke)
    }

    /// The solver after `seconds` of simulation.
    ///
    /// # Errors
    ///
    /// As [`Plume::build`]; as [`Smoke::step`]; [`FluidError::InvalidParameter`]
    /// naming `seconds` when it is negative or not finite.
    pub fn simulate(&self, seconds: f32) -> Result<Smoke> {
        non_negative("seconds", f64::from(seconds))?;
        let mut smoke = self.build()?;
        let dt = self.dt();
        for _ in 0..self.steps(seconds) {
            smoke.step(dt)?;
        }
        Ok(smoke)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plume_rises_past_its_sphere() {
        let p = Plume {
            cells: 16,
            ..Plume::default()
        };
        // The smoke's height (its density-weighted mean cell row) rises.
        let height = |seconds: f32| {
            let smoke = p.simulate(seconds).unwrap();
            let d = smoke.density();
            let (mut m, mut mz) = (0.0f32, 0.0f32);
            for z in 0..32 {
                for y in 0..16 {
                    for x in 0..16 {
                        m += d[(x, y, z)];
                        mz += d[(x, y, z)] * z as f32;
                    }
                }
            }
            assert!(m > 0.0);
            mz / m
        };
        let (early, late) = (height(0.25), height(1.5));
        assert!(late > early + 0.8, "{early} → {late}");
    }

    #[test]
    fn bad_settings_name_their_field() {
        for (p, key) in [
            (
                Plume {
                    cells: 2,
                    ..Plume::default()
                },
                "cells",
            ),
            (
                Plume {
                    width: f32::NAN,
                    ..Plume::default()
                },
                "width",
            ),
            (
                Plume {
                    epsilon: -1.0,
                    ..Plume::default()
                },
                "epsilon",
            ),
        ] {
            let e = p.build().unwrap_err().to_string();
            assert!(e.contains(key), "{e}");
        }
        let e = Plume::default()
            .simulate(f32::INFINITY)
            .unwrap_err()
            .to_string();
        assert!(e.contains("seconds"), "{e}");
    }
}
