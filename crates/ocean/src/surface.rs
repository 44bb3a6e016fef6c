//! Periodic samplers of the water surface at world (x, y), for renderers.
//!
//! A [`Surface`] is a snapshot of one patch (height, displacement, the
//! slopes of the displaced surface and foam) that tiles the plane with the
//! patch's period. Queries are bilinear on the wrapped grid, in world
//! coordinates: because the choppy map moves water horizontally, the
//! surface point above world (x, y) belongs to the rest position x₀ with
//! x₀ + d(x₀) = (x, y), found by fixed-point iteration x₀ ← (x, y) − d(x₀)
//! (it converges where the surface does not fold, |∂d/∂x| < 1).

use glam::{Vec2, Vec3};
use natura_core::{Boundary, Grid2};

use crate::error::Result;
use crate::foam::Foam;
use crate::frame::Frame;

/// Fixed-point iterations used to invert the choppy map.
const INVERSION_STEPS: usize = 4;

/// Anything that can be sampled as a water surface at world (x, y), z up.
pub trait WaterSurface: Send + Sync {
    /// Returns the surface height (metres) above world point (x, y).
    fn height_at(&self, p: Vec2) -> f32;
    /// Returns the unit upward normal of the surface above (x, y).
    fn normal_at(&self, p: Vec2) -> Vec3;
    /// Returns the foam coverage in [0, 1] above (x, y).
    fn foam_at(&self, p: Vec2) -> f32;
}

/// A tiling snapshot of one ocean patch (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    extent: Vec2,
    cell: Vec2,
    height: Grid2<f32>,
    disp: Grid2<Vec2>,
    /// Slopes (∂z/∂x, ∂z/∂y) of the displaced surface: −n_x/n_z, −n_y/n_z.
    slope: Grid2<Vec2>,
    foam: Option<Grid2<f32>>,
    choppy: bool,
}

/// Largest slope stored; the displaced surface is vertical or overhanging
/// where it folds, which a height map cannot represent.
const MAX_SLOPE: f32 = 50.0;

impl Surface {
    /// Snapshots `frame` (and `foam`, if given, which must have its size).
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::SizeMismatch`](crate::OceanError::SizeMismatch) if `foam` is given with a size other than the frame's.
    pub fn new(frame: &Frame, foam: Option<&Foam>) -> Result<Self> {
        let (nx, ny) = frame.dims();
        if let Some(f) = foam
            && f.coverage().dims() != (nx, ny)
        {
            return Err(crate::OceanError::SizeMismatch {
                expected: format!("foam of {nx} × {ny}"),
                actual: format!("{:?}", f.coverage().dims()),
            });
        }
        let disp = Grid2::from_fn(nx, ny, |i, j| {
            Vec2::new(frame.disp_x()[(i, j)], frame.disp_y()[(i, j)])
        })?;
        let slope = Grid2::from_fn(nx, ny, |i, j| {
            let n = frame.normal_up(i, j);
            let s = Vec2::new(-n.x, -n.y) / n.z.max(1.0 / MAX_SLOPE);
            s.clamp_length_max(MAX_SLOPE)
        })?;
        let choppy = disp.as_slice().iter().any(|d| *d != Vec2::ZERO);
        Ok(Self {
            extent: frame.extent(),
            cell: frame.cell_size(),
            height: frame.height().clone(),
            disp,
            slope,
            foam: foam.map(|f| f.coverage().clone()),
            choppy,
        })
    }

    /// Returns the period (Lx, Ly) of the tiling, metres.
    #[must_use]
    pub fn extent(&self) -> Vec2 {
        self.extent
    }

    /// Returns the rest position whose displaced point lies above world `p`.
    #[must_use]
    pub fn rest_position(&self, p: Vec2) -> Vec2 {
        if !self.choppy {
            return p;
        }
        let mut x0 = p;
        for _ in 0..INVERSION_STEPS {
            x0 = p - self.displacement_at_rest(x0);
        }
        x0
    }

    fn grid_coord(&self, x0: Vec2) -> Vec2 {
        x0 / self.cell
    }

    /// Returns the horizontal displacement of the particle at rest position `x0`.
    #[must_use]
    pub fn displacement_at_rest(&self, x0: Vec2) -> Vec2 {
        let g = self.grid_coord(x0);
        self.disp.sample_bilinear(g.x, g.y, Boundary::Wrap)
    }

    /// Returns the slope (∂z/∂x, ∂z/∂y) of the surface above world `p`.
    #[must_use]
    pub fn slope_at(&self, p: Vec2) -> Vec2 {
        let g = self.grid_coord(self.rest_position(p));
        self.slope.sample_bilinear(g.x, g.y, Boundary::Wrap)
    }
}

impl WaterSurface for Surface {
    fn height_at(&self, p: Vec2) -> f32 {
        let g = self.grid_coord(self.rest_position(p));
        self.height.sample_bilinear(g.x, g.y, Boundary::Wrap)
    }

    fn normal_at(&self, p: Vec2) -> Vec3 {
        let s = self.slope_at(p);
        Vec3::new(-s.x, -s.y, 1.0).normalize()
    }

    fn foam_at(&self, p: Vec2) -> f32 {
        match &self.foam {
            Some(f) => {
                let g = self.grid_coord(self.rest_position(p));
                f.sample_bilinear(g.x, g.y, Boundary::Wrap)
            }
            None => 0.0,
        }
    }
}

/// The sum of several surfaces (e.g. the patches of a cascade): heights and
/// slopes add, foam takes the maximum. Each surface inverts its own
/// displacement, which is exact for one surface and a good approximation
/// when the others' displacements are small.
impl WaterSurface for [Surface] {
    fn height_at(&self, p: Vec2) -> f32 {
        self.iter().map(|s| s.height_at(p)).sum()
    }
    fn normal_at(&self, p: Vec2) -> Vec3 {
        let s: Vec2 = self.iter().map(|s| s.slope_at(p)).sum();
        Vec3::new(-s.x, -s.y, 1.0).normalize()
    }
    fn foam_at(&self, p: Vec2) -> f32 {
        self.iter().map(|s| s.foam_at(p)).fold(0.0, f32::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Ocean, OceanParams, Phillips, Seed};

    fn frame(chop: f64) -> (Ocean, Frame) {
        let p = OceanParams {
            nx: 64,
            ny: 32,
            lx: 128.0,
            ly: 64.0,
            choppiness: chop,
            ..OceanParams::default()
        };
        let s = Phillips {
            wind_speed: 9.0,
            small_wave_length: 0.2,
            ..Phillips::default()
        };
        let o = Ocean::new(&p, &s, Seed(12)).unwrap();
        let f = o.evaluate(3.0).unwrap();
        (o, f)
    }

    #[test]
    fn reproduces_grid_samples_and_wraps() {
        let (_, f) = frame(0.0);
        let s = Surface::new(&f, None).unwrap();
        let c = f.cell_size();
        for (i, j) in [(0usize, 0usize), (5, 9), (63, 31)] {
            let p = Vec2::new(i as f32 * c.x, j as f32 * c.y);
            assert!((s.height_at(p) - f.height()[(i, j)]).abs() < 1e-5);
            let n = s.normal_at(p);
            assert!(
                n.abs_diff_eq(f.normal(i, j), 1e-4),
                "{n} vs {}",
                f.normal(i, j)
            );
            for k in [Vec2::new(128.0, 0.0), Vec2::new(-256.0, 64.0)] {
                assert!((s.height_at(p + k) - s.height_at(p)).abs() < 1e-3);
            }
        }
        assert_eq!(s.foam_at(Vec2::ZERO), 0.0);
    }

    #[test]
    fn choppy_lookup_lands_on_the_displaced_particle() {
        let (_, f) = frame(0.8);
        let s = Surface::new(&f, None).unwrap();
        // Mildly choppy: the displaced grid point should report its own height.
        let mut worst = 0.0f32;
        for (i, j) in [(3usize, 4usize), (20, 10), (40, 30)] {
            if f.jacobian(i, j) < 0.5 {
                continue;
            }
            let p = f.position(i, j);
            worst = worst.max((s.height_at(p.truncate()) - p.z).abs());
        }
        let h_rms = f.height_variance().sqrt() as f32;
        assert!(worst < 0.05 * h_rms, "{worst} vs rms {h_rms}");
    }
}
