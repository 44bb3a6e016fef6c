//! `Grid3<T>`: a dense 3-D array (x fastest, then y, then z) with checked construction.

use crate::error::{CoreError, Result};
use crate::grid2::{checked_len, dense_grid};
use crate::sample::{Boundary, Interpolate, resolve, split};

/// A dense 3-D grid of `T`. Sample `(x, y, z)` lives at index `(z·ny + y)·nx + x`.
///
/// Constructors refuse zero dimensions and sizes over [`crate::MAX_GRID_BYTES`].
#[derive(Clone, Debug, PartialEq)]
pub struct Grid3<T> {
    nx: usize,
    ny: usize,
    nz: usize,
    data: Vec<T>,
}

impl<T: Clone> Grid3<T> {
    /// Returns an `nx × ny × nz` grid filled with `value`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    pub fn new(nx: usize, ny: usize, nz: usize, value: T) -> Result<Self> {
        let len = checked_len::<T>(&[nx, ny, nz])?;
        Ok(Self {
            nx,
            ny,
            nz,
            data: vec![value; len],
        })
    }
}

impl<T> Grid3<T> {
    /// Returns a grid whose sample `(x, y, z)` is `f(x, y, z)`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    pub fn from_fn(
        nx: usize,
        ny: usize,
        nz: usize,
        mut f: impl FnMut(usize, usize, usize) -> T,
    ) -> Result<Self> {
        let len = checked_len::<T>(&[nx, ny, nz])?;
        let mut data = Vec::with_capacity(len);
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    data.push(f(x, y, z));
                }
            }
        }
        Ok(Self { nx, ny, nz, data })
    }

    /// Wraps `data` (x fastest) as an `nx × ny × nz` grid; fails on a length mismatch.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::SizeMismatch`](crate::CoreError::SizeMismatch) if `data.len()` is not
    /// `nx × ny × nz`, and the size errors of [`Grid3::new`].
    pub fn from_vec(nx: usize, ny: usize, nz: usize, data: Vec<T>) -> Result<Self> {
        let len = checked_len::<T>(&[nx, ny, nz])?;
        if data.len() != len {
            return Err(CoreError::SizeMismatch {
                expected: format!("{nx} × {ny} × {nz} = {len} values"),
                actual: format!("{} values", data.len()),
            });
        }
        Ok(Self { nx, ny, nz, data })
    }

    /// `(nx, ny, nz)`.
    #[inline]
    #[must_use]
    pub fn dims(&self) -> (usize, usize, usize) {
        (self.nx, self.ny, self.nz)
    }

    /// Samples along x.
    #[inline]
    #[must_use]
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// Samples along y.
    #[inline]
    #[must_use]
    pub fn ny(&self) -> usize {
        self.ny
    }

    /// Samples along z.
    #[inline]
    #[must_use]
    pub fn nz(&self) -> usize {
        self.nz
    }

    /// Whether `(x, y, z)` lies inside the grid.
    #[inline]
    fn contains(&self, x: usize, y: usize, z: usize) -> bool {
        x < self.nx && y < self.ny && z < self.nz
    }

    /// Linear index of `(x, y, z)`; bounds are the caller's contract (checked in debug builds).
    #[inline]
    #[must_use]
    pub fn index(&self, x: usize, y: usize, z: usize) -> usize {
        debug_assert!(x < self.nx && y < self.ny && z < self.nz);
        (z * self.ny + y) * self.nx + x
    }

    /// The row of `nx` samples at `(y, z)`. Panics outside (an index bug).
    #[inline]
    #[must_use]
    pub fn row(&self, y: usize, z: usize) -> &[T] {
        let s = (z * self.ny + y) * self.nx;
        &self.data[s..s + self.nx]
    }

    /// The row at `(y, z)`, mutably.
    #[inline]
    pub fn row_mut(&mut self, y: usize, z: usize) -> &mut [T] {
        let s = (z * self.ny + y) * self.nx;
        &mut self.data[s..s + self.nx]
    }

    /// The `nx·ny` samples of the z-slice `z`. Panics outside.
    #[inline]
    #[must_use]
    pub fn slice_z(&self, z: usize) -> &[T] {
        let n = self.nx * self.ny;
        &self.data[z * n..(z + 1) * n]
    }

    /// The z-slice `z`, mutably.
    #[inline]
    pub fn slice_z_mut(&mut self, z: usize) -> &mut [T] {
        let n = self.nx * self.ny;
        &mut self.data[z * n..(z + 1) * n]
    }

    /// A new grid with `f` applied to every sample.
    #[must_use]
    pub fn map<U>(&self, f: impl FnMut(&T) -> U) -> Grid3<U> {
        Grid3 {
            nx: self.nx,
            ny: self.ny,
            nz: self.nz,
            data: self.data.iter().map(f).collect(),
        }
    }

    /// `f(a, b)` for each pair of samples; fails if the sizes differ.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::SizeMismatch`](crate::CoreError::SizeMismatch) if the grids differ in size.
    pub fn zip_map<U, V>(
        &self,
        other: &Grid3<U>,
        mut f: impl FnMut(&T, &U) -> V,
    ) -> Result<Grid3<V>> {
        if self.dims() != other.dims() {
            return Err(CoreError::SizeMismatch {
                expected: format!("{} × {} × {}", self.nx, self.ny, self.nz),
                actual: format!("{} × {} × {}", other.nx, other.ny, other.nz),
            });
        }
        let data = self
            .data
            .iter()
            .zip(&other.data)
            .map(|(a, b)| f(a, b))
            .collect();
        Ok(Grid3 {
            nx: self.nx,
            ny: self.ny,
            nz: self.nz,
            data,
        })
    }
}

#[cfg(feature = "parallel")]
impl<T: Send + Sync> Grid3<T> {
    /// Calls `f(z, slice)` for every z-slice in parallel (rayon).
    pub fn par_slices_mut(&mut self, f: impl Fn(usize, &mut [T]) + Sync + Send) {
        use rayon::prelude::*;
        let n = self.nx * self.ny;
        self.data
            .par_chunks_exact_mut(n)
            .enumerate()
            .for_each(|(z, s)| f(z, s));
    }

    /// Calls `f(y, z, row)` for every x-row in parallel (rayon).
    pub fn par_rows_mut(&mut self, f: impl Fn(usize, usize, &mut [T]) + Sync + Send) {
        use rayon::prelude::*;
        let (nx, ny) = (self.nx, self.ny);
        self.data
            .par_chunks_exact_mut(nx)
            .enumerate()
            .for_each(|(i, r)| f(i % ny, i / ny, r));
    }
}

impl<T> std::ops::Index<(usize, usize, usize)> for Grid3<T> {
    type Output = T;
    /// Panics outside the grid; use [`Grid3::get`] for a checked read.
    #[inline]
    fn index(&self, (x, y, z): (usize, usize, usize)) -> &T {
        assert!(
            x < self.nx && y < self.ny && z < self.nz,
            "({x}, {y}, {z}) outside grid"
        );
        &self.data[(z * self.ny + y) * self.nx + x]
    }
}

impl<T> std::ops::IndexMut<(usize, usize, usize)> for Grid3<T> {
    #[inline]
    fn index_mut(&mut self, (x, y, z): (usize, usize, usize)) -> &mut T {
        assert!(
            x < self.nx && y < self.ny && z < self.nz,
            "({x}, {y}, {z}) outside grid"
        );
        &mut self.data[(z * self.ny + y) * self.nx + x]
    }
}

impl<T: Interpolate> Grid3<T> {
    /// The sample at integer position `(x, y, z)` under `boundary`.
    #[inline]
    #[must_use]
    pub fn sample_nearest(&self, x: i64, y: i64, z: i64, boundary: Boundary<T>) -> T {
        match (
            resolve(x, self.nx, &boundary),
            resolve(y, self.ny, &boundary),
            resolve(z, self.nz, &boundary),
        ) {
            (Some(x), Some(y), Some(z)) => self.data[(z * self.ny + y) * self.nx + x],
            _ => match boundary {
                Boundary::Constant(c) => c,
                _ => unreachable!("clamp and wrap always resolve"),
            },
        }
    }

    /// Trilinear interpolation at `(x, y, z)` in cell units; exact at samples and for
    /// functions linear in each coordinate.
    #[must_use]
    pub fn sample_trilinear(&self, x: f32, y: f32, z: f32, boundary: Boundary<T>) -> T {
        let (x0, fx) = split(x);
        let (y0, fy) = split(y);
        let (z0, fz) = split(z);
        let s = |i, j, k| self.sample_nearest(i, j, k, boundary);
        let plane = |k| {
            let a = T::lerp(s(x0, y0, k), s(x0 + 1, y0, k), fx);
            let b = T::lerp(s(x0, y0 + 1, k), s(x0 + 1, y0 + 1, k), fx);
            T::lerp(a, b, fy)
        };
        T::lerp(plane(z0), plane(z0 + 1), fz)
    }
}

dense_grid!(Grid3, x, y, z);

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn refuses_bad_sizes() {
        assert!(matches!(
            Grid3::new(4, 0, 4, 0.0f32),
            Err(CoreError::ZeroDimension { .. })
        ));
        let err = Grid3::new(1 << 12, 1 << 12, 1 << 12, 0.0f32).unwrap_err();
        assert!(matches!(err, CoreError::TooLarge { .. }), "{err}");
        assert!(err.to_string().contains("4096 × 4096 × 4096"));
    }

    #[test]
    fn layout_and_access() {
        let g = Grid3::from_fn(3, 4, 5, |x, y, z| (x + 10 * y + 100 * z) as i32).unwrap();
        assert_eq!(g[(2, 3, 4)], 432);
        assert_eq!(g.row(1, 2), &[210, 211, 212]);
        assert_eq!(g.slice_z(1).len(), 12);
        assert_eq!(g.get(3, 0, 0), None);
        assert_eq!(g.as_slice()[g.index(1, 2, 3)], 321);
    }

    #[cfg(feature = "parallel")]
    #[test]
    fn par_rows_visit_each_row_with_its_coordinates() {
        let mut g = Grid3::new(3, 4, 5, 0usize).unwrap();
        g.par_rows_mut(|y, z, r| {
            r.iter_mut()
                .enumerate()
                .for_each(|(x, v)| *v = x + 10 * y + 100 * z)
        });
        assert_eq!(
            g,
            Grid3::from_fn(3, 4, 5, |x, y, z| x + 10 * y + 100 * z).unwrap()
        );
    }

    proptest! {
        #[test]
        fn trilinear_exact_for_linear(a in -5.0f32..5.0, b in -5.0f32..5.0, c in -5.0f32..5.0,
                                      px in 0.0f32..4.0, py in 0.0f32..5.0, pz in 0.0f32..6.0) {
            let g = Grid3::from_fn(5, 6, 7, |x, y, z| a * x as f32 + b * y as f32 + c * z as f32).unwrap();
            let expect = a * px + b * py + c * pz;
            let got = g.sample_trilinear(px, py, pz, Boundary::Clamp);
            prop_assert!((got - expect).abs() < 1e-4 * (1.0 + expect.abs()));
        }

        #[test]
        fn trilinear_reproduces_samples_and_wraps(x in 0usize..5, y in 0usize..6, z in 0usize..7) {
            let g = Grid3::from_fn(5, 6, 7, |x, y, z| ((x * 7 + y * 13 + z * 3) % 17) as f32).unwrap();
            prop_assert_eq!(g.sample_trilinear(x as f32, y as f32, z as f32, Boundary::Clamp), g[(x, y, z)]);
            prop_assert_eq!(
                g.sample_trilinear((x + 5) as f32, y as f32 - 6.0, (z + 14) as f32, Boundary::Wrap),
                g[(x, y, z)]
            );
        }
    }
}
