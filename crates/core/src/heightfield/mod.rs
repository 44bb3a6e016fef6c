//! `HeightField`: a regular grid of altitudes in metres with a horizontal cell size.
//!
//! Conventions: z up, metres. Sample `(i, j)` of the
//! grid sits at world position `(i·cell_size, j·cell_size, h[i, j])`, so the
//! field covers `[0, (nx − 1)·cell_size] × [0, (ny − 1)·cell_size]`. This is
//! Musgrave's "regular height field" (Musgrave et al. 1989, §2).
//!
//! Files (PNG, EXR, raw) store rows in **map order**: the first row in the
//! file is the row of largest y (north up), as DEM tools and image viewers
//! expect. Reading and writing flip rows accordingly; round trips are exact.
//!
//! This file holds the field and its geometry (positions, interpolation,
//! gradients, normals, slopes, hill shading); `files.rs` reads and writes it
//! as raw, EXR and 16-bit PNG.

mod files;
#[cfg(test)]
mod tests;

use glam::{Vec2, Vec3};

use crate::check::positive;
use crate::error::{CoreError, Result};
use crate::grid2::Grid2;
use crate::sample::Boundary;

/// An axis-aligned box in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Aabb {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box's extent along each axis.
    #[must_use]
    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }

    /// The centre of the box.
    #[must_use]
    pub fn centre(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Whether `p` lies inside or on the box.
    #[must_use]
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

/// Key of the tEXt chunk / EXR attribute holding the height range of a 16-bit PNG.
const RANGE_KEY: &str = "natura:height_range_m";
/// Key of the attribute holding the cell size.
const CELL_KEY: &str = "natura:cell_size_m";

/// A height field: altitudes in metres on a regular grid with square cells.
///
/// Constructors refuse NaN or infinite heights (naming the first bad cell)
/// and a cell size that is not finite and positive. [`HeightField::heights_mut`]
/// hands out the grid for in-place algorithms (erosion); consumers that need
/// finiteness re-check with [`HeightField::check_finite`].
#[derive(Clone, Debug, PartialEq)]
pub struct HeightField {
    heights: Grid2<f32>,
    cell_size: f32,
}

impl HeightField {
    /// Wraps a grid of heights (metres) with `cell_size` metres between samples.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) if `cell_size` is not
    /// finite and positive.
    pub fn new(heights: Grid2<f32>, cell_size: f32) -> Result<Self> {
        positive("cell_size", f64::from(cell_size))?;
        heights.check_finite()?;
        Ok(Self { heights, cell_size })
    }

    /// A field of `nx × ny` samples whose height at sample `(i, j)` is `f(i, j)`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) if `cell_size` is not finite and positive.
    pub fn from_fn(
        nx: usize,
        ny: usize,
        cell_size: f32,
        f: impl FnMut(usize, usize) -> f32,
    ) -> Result<Self> {
        Self::new(Grid2::from_fn(nx, ny, f)?, cell_size)
    }

    /// A flat field at height `h`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) if `cell_size` is not finite and positive.
    pub fn flat(nx: usize, ny: usize, cell_size: f32, h: f32) -> Result<Self> {
        Self::new(Grid2::new(nx, ny, h)?, cell_size)
    }

    /// The heights, metres.
    #[inline]
    #[must_use]
    pub fn heights(&self) -> &Grid2<f32> {
        &self.heights
    }

    /// The heights, mutably (keep them finite; see [`HeightField::check_finite`]).
    #[inline]
    pub fn heights_mut(&mut self) -> &mut Grid2<f32> {
        &mut self.heights
    }

    /// Consumes the field, returning its heights.
    #[must_use]
    pub fn into_heights(self) -> Grid2<f32> {
        self.heights
    }

    /// Horizontal distance between neighbouring samples, metres.
    #[inline]
    #[must_use]
    pub fn cell_size(&self) -> f32 {
        self.cell_size
    }

    /// Samples along x.
    #[inline]
    #[must_use]
    pub fn nx(&self) -> usize {
        self.heights.width()
    }

    /// Samples along y.
    #[inline]
    #[must_use]
    pub fn ny(&self) -> usize {
        self.heights.height()
    }

    /// World extent `((nx − 1)·cell, (ny − 1)·cell)`, metres.
    #[must_use]
    pub fn extent(&self) -> Vec2 {
        Vec2::new((self.nx() - 1) as f32, (self.ny() - 1) as f32) * self.cell_size
    }

    /// The height of sample `(i, j)`; `None` outside the grid.
    #[inline]
    #[must_use]
    pub fn get(&self, i: usize, j: usize) -> Option<f32> {
        self.heights.get(i, j).copied()
    }

    /// World position of sample `(i, j)`.
    ///
    /// # Panics
    ///
    /// Panics if `i ≥ nx` or `j ≥ ny` (an index bug in the caller); use
    /// [`try_point`](Self::try_point) for indices that come from user data.
    #[inline]
    #[must_use]
    pub fn point(&self, i: usize, j: usize) -> Vec3 {
        Vec3::new(
            i as f32 * self.cell_size,
            j as f32 * self.cell_size,
            self.heights[(i, j)],
        )
    }

    /// World position of sample `(i, j)`, or `None` outside the grid.
    #[inline]
    #[must_use]
    pub fn try_point(&self, i: usize, j: usize) -> Option<Vec3> {
        self.get(i, j)
            .map(|z| Vec3::new(i as f32 * self.cell_size, j as f32 * self.cell_size, z))
    }

    /// Bilinearly interpolated height at world `(x, y)`; `None` outside the field or for NaN.
    #[must_use]
    pub fn height_at(&self, x: f32, y: f32) -> Option<f32> {
        let e = self.extent();
        if !(x >= 0.0 && y >= 0.0 && x <= e.x && y <= e.y) {
            return None;
        }
        Some(self.sample(x, y, Boundary::Clamp))
    }

    /// Bilinearly interpolated height at world `(x, y)` with `boundary` outside the field.
    #[must_use]
    pub fn sample(&self, x: f32, y: f32, boundary: Boundary<f32>) -> f32 {
        let inv = 1.0 / self.cell_size;
        self.heights.sample_bilinear(x * inv, y * inv, boundary)
    }

    /// Height gradient `(∂h/∂x, ∂h/∂y)` at sample `(i, j)` by central differences
    /// (one-sided on the border; zero along an axis with a single sample).
    #[must_use]
    pub fn gradient_at_sample(&self, i: usize, j: usize) -> Vec2 {
        let (nx, ny) = self.heights.dims();
        let h = &self.heights;
        let d = |lo: usize, hi: usize, v: f32, w: f32| {
            if hi > lo {
                Self::central_difference(v, w, (hi - lo) as f32 * self.cell_size)
            } else {
                0.0
            }
        };
        let (x0, x1) = (i.saturating_sub(1), (i + 1).min(nx - 1));
        let (y0, y1) = (j.saturating_sub(1), (j + 1).min(ny - 1));
        Vec2::new(
            d(x0, x1, h[(x0, j)], h[(x1, j)]),
            d(y0, y1, h[(i, y0)], h[(i, y1)]),
        )
    }

    /// Unit surface normal at sample `(i, j)` from central differences, `(−∂h/∂x, −∂h/∂y, 1)` normalised.
    #[must_use]
    pub fn normal_at_sample(&self, i: usize, j: usize) -> Vec3 {
        let g = self.gradient_at_sample(i, j);
        Self::normal_from_gradient(g.x, g.y)
    }

    /// The difference quotient `(w − v) / span` between heights `v` and `w`
    /// a distance `span` apart: the one formula behind every sample
    /// gradient, exposed so that batch code reading the heights directly
    /// computes the same bits.
    #[inline(always)]
    #[must_use]
    pub fn central_difference(v: f32, w: f32, span: f32) -> f32 {
        (w - v) / span
    }

    /// The unit normal `(−gx, −gy, 1)` normalised of the height gradient
    /// `(gx, gy)`.
    #[inline(always)]
    #[must_use]
    pub fn normal_from_gradient(gx: f32, gy: f32) -> Vec3 {
        Vec3::new(-gx, -gy, 1.0).normalize()
    }

    /// Gradient at world `(x, y)`: the central-difference gradients of the four
    /// surrounding samples, bilinearly interpolated. `None` outside the field.
    #[must_use]
    pub fn gradient_at(&self, x: f32, y: f32) -> Option<Vec2> {
        self.height_at(x, y)?;
        let fx = x / self.cell_size;
        let fy = y / self.cell_size;
        let i0 = (fx.floor() as usize).min(self.nx() - 1);
        let j0 = (fy.floor() as usize).min(self.ny() - 1);
        let i1 = (i0 + 1).min(self.nx() - 1);
        let j1 = (j0 + 1).min(self.ny() - 1);
        let (tx, ty) = (fx - i0 as f32, fy - j0 as f32);
        let g = |i, j| self.gradient_at_sample(i, j);
        let a = g(i0, j0).lerp(g(i1, j0), tx);
        let b = g(i0, j1).lerp(g(i1, j1), tx);
        Some(a.lerp(b, ty))
    }

    /// Unit surface normal at world `(x, y)` (see [`HeightField::gradient_at`]).
    #[must_use]
    pub fn normal_at(&self, x: f32, y: f32) -> Option<Vec3> {
        self.gradient_at(x, y)
            .map(|g| Vec3::new(-g.x, -g.y, 1.0).normalize())
    }

    /// Slope angle from horizontal at world `(x, y)`, radians in `[0, π/2)`.
    #[must_use]
    pub fn slope_at(&self, x: f32, y: f32) -> Option<f32> {
        self.gradient_at(x, y).map(|g| g.length().atan())
    }

    /// Slope angle at sample `(i, j)`, radians.
    #[must_use]
    pub fn slope_at_sample(&self, i: usize, j: usize) -> f32 {
        self.gradient_at_sample(i, j).length().atan()
    }

    /// The field shrunk by an integer `factor`: heights box-filtered over
    /// `factor × factor` blocks (see [`Grid2::box_downsample`]) and the
    /// cell size multiplied by `factor`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter)
    /// if `factor` is zero or larger than either side, and the errors of
    /// [`HeightField::new`] if the coarser cell size overflows.
    pub fn box_downsample(&self, factor: usize) -> Result<HeightField> {
        let heights = self.heights.box_downsample(factor)?;
        HeightField::new(heights, self.cell_size * factor as f32)
    }

    /// `(lowest, highest)` height.
    #[must_use]
    pub fn min_max(&self) -> (f32, f32) {
        self.heights.min_max()
    }

    /// The world-space bounding box of the surface.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        let (lo, hi) = self.min_max();
        let e = self.extent();
        Aabb {
            min: Vec3::new(0.0, 0.0, lo),
            max: Vec3::new(e.x, e.y, hi),
        }
    }

    /// Fails with [`CoreError::NonFinite`] naming the first NaN or infinite height.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::NonFinite`](crate::CoreError::NonFinite) naming the first NaN or infinite value.
    pub fn check_finite(&self) -> Result<()> {
        self.heights.check_finite()
    }

    /// Lambertian hill shade `max(0, n·sun)` at every sample, for a unit `sun`
    /// direction (toward the sun, z up). Refuses a non-finite or zero `sun`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter) naming `sun` if it is zero or
    /// not finite.
    pub fn hillshade(&self, sun: Vec3) -> Result<Grid2<f32>> {
        let s = sun.try_normalize().ok_or(CoreError::InvalidParameter {
            name: "sun",
            value: format!("{sun}"),
            reason: "must be a finite non-zero direction",
        })?;
        Grid2::from_fn(self.nx(), self.ny(), |i, j| {
            self.normal_at_sample(i, j).dot(s).max(0.0)
        })
    }
}
