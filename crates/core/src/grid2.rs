//! `Grid2<T>`: a dense, row-major 2-D array with checked construction.

use crate::error::{CoreError, Result};
use crate::sample::{Boundary, Interpolate, resolve, split};

/// The largest grid, image or volume natura will allocate, in bytes (16 GiB).
///
/// Constructors refuse anything larger with [`CoreError::TooLarge`], so that a
/// typo in a size or a corrupt file header fails with a message instead of
/// exhausting memory.
pub const MAX_GRID_BYTES: u64 = 16 << 30;

/// Checks that `dims` are all non-zero and that their product times
/// `size_of::<T>()` fits under [`MAX_GRID_BYTES`]; returns the element count.
///
/// # Errors
///
/// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
/// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
pub fn checked_len<T>(dims: &[usize]) -> Result<usize> {
    let describe = || {
        dims.iter()
            .map(|d| d.to_string())
            .collect::<Vec<_>>()
            .join(" × ")
    };
    if dims.contains(&0) {
        return Err(CoreError::ZeroDimension { dims: describe() });
    }
    let elem = std::mem::size_of::<T>().max(1) as u128;
    let mut count: u128 = 1;
    for &d in dims {
        // u128 holds the product of three usizes times an element size without
        // overflow on every platform we target; saturate beyond that.
        count = count.saturating_mul(d as u128);
    }
    let bytes = count.saturating_mul(elem);
    if bytes > u128::from(MAX_GRID_BYTES) || count > usize::MAX as u128 {
        return Err(CoreError::TooLarge {
            dims: describe(),
            bytes,
            cap: MAX_GRID_BYTES,
        });
    }
    Ok(count as usize)
}

/// Writes the methods the dense grids ([`Grid2`], [`crate::Grid3`]) share,
/// over their row-major `data` and their coordinates `$c` (x fastest): the
/// sample count, checked access by position (through the grid's own
/// `contains` and `index`), the flat sample slice, and the `f32` grids'
/// statistics.
macro_rules! dense_grid {
    ($grid:ident, $($c:ident),+) => {
        impl<T> $grid<T> {
            /// Number of samples (never zero).
            #[inline]
            #[must_use]
            pub fn len(&self) -> usize {
                self.data.len()
            }

            /// Always `false`: a grid has at least one sample. Present for API symmetry.
            #[inline]
            #[must_use]
            pub fn is_empty(&self) -> bool {
                self.data.is_empty()
            }

            #[doc = concat!("The sample at `(", stringify!($($c),+), ")`, or `None` outside the grid.")]
            #[inline]
            #[must_use]
            pub fn get(&self, $($c: usize),+) -> Option<&T> {
                self.contains($($c),+).then(|| &self.data[self.index($($c),+)])
            }

            #[doc = concat!("The sample at `(", stringify!($($c),+), ")` mutably, or `None` outside the grid.")]
            #[inline]
            pub fn get_mut(&mut self, $($c: usize),+) -> Option<&mut T> {
                if self.contains($($c),+) {
                    let i = self.index($($c),+);
                    Some(&mut self.data[i])
                } else {
                    None
                }
            }

            #[doc = concat!("Sets the sample at `(", stringify!($($c),+), ")` and returns the previous value, or `None` (and")]
            /// changes nothing) outside the grid.
            #[inline]
            pub fn set(&mut self, $($c: usize,)+ value: T) -> Option<T> {
                self.get_mut($($c),+)
                    .map(|slot| std::mem::replace(slot, value))
            }

            /// All samples, x fastest.
            #[inline]
            #[must_use]
            pub fn as_slice(&self) -> &[T] {
                &self.data
            }

            /// All samples, x fastest, mutably.
            #[inline]
            pub fn as_mut_slice(&mut self) -> &mut [T] {
                &mut self.data
            }

            /// Consumes the grid and returns its samples, x fastest.
            #[must_use]
            pub fn into_vec(self) -> Vec<T> {
                self.data
            }
        }

        impl $grid<f32> {
            /// `(min, max)` in one pass (NaN samples are skipped; NaN if all are NaN).
            #[must_use]
            pub fn min_max(&self) -> (f32, f32) {
                self.data
                    .iter()
                    .fold((f32::NAN, f32::NAN), |(lo, hi), &v| (lo.min(v), hi.max(v)))
            }

            /// Smallest sample (NaN samples are skipped; NaN if all are NaN).
            #[must_use]
            pub fn min(&self) -> f32 {
                self.data.iter().copied().fold(f32::NAN, f32::min)
            }

            /// Largest sample (NaN samples are skipped; NaN if all are NaN).
            #[must_use]
            pub fn max(&self) -> f32 {
                self.data.iter().copied().fold(f32::NAN, f32::max)
            }

            /// Sum of all samples, accumulated in `f64` with pairwise (blocked) summation.
            #[must_use]
            pub fn sum(&self) -> f64 {
                self.data
                    .chunks(4096)
                    .map(|c| c.iter().map(|&v| f64::from(v)).sum::<f64>())
                    .sum()
            }

            /// Arithmetic mean, accumulated in `f64` so large grids do not lose precision.
            #[must_use]
            pub fn mean(&self) -> f64 {
                self.sum() / self.data.len() as f64
            }
        }
    };
}
pub(crate) use dense_grid;

/// A dense 2-D grid of `T`, stored row by row (`x` fastest).
///
/// Sample `(x, y)` lives at index `y·width + x`. The grid is never empty:
/// constructors refuse zero dimensions and sizes over [`MAX_GRID_BYTES`].
#[derive(Clone, Debug, PartialEq)]
pub struct Grid2<T> {
    width: usize,
    height: usize,
    data: Vec<T>,
}

impl<T: Clone> Grid2<T> {
    /// Returns a `width × height` grid filled with `value`.
    ///
    /// Fails with [`CoreError::ZeroDimension`] or [`CoreError::TooLarge`].
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    pub fn new(width: usize, height: usize, value: T) -> Result<Self> {
        let len = checked_len::<T>(&[width, height])?;
        Ok(Self {
            width,
            height,
            data: vec![value; len],
        })
    }
}

impl<T> Grid2<T> {
    /// Returns a grid whose sample `(x, y)` is `f(x, y)`, filled row by row.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    pub fn from_fn(
        width: usize,
        height: usize,
        mut f: impl FnMut(usize, usize) -> T,
    ) -> Result<Self> {
        let len = checked_len::<T>(&[width, height])?;
        let mut data = Vec::with_capacity(len);
        for y in 0..height {
            for x in 0..width {
                data.push(f(x, y));
            }
        }
        Ok(Self {
            width,
            height,
            data,
        })
    }

    /// Wraps row-major `data` as a `width × height` grid.
    ///
    /// Fails if the dimensions are invalid or `data.len() != width·height`.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::SizeMismatch`](crate::CoreError::SizeMismatch) if `data.len()` is not
    /// `width × height`, and the errors of [`checked_len`].
    pub fn from_vec(width: usize, height: usize, data: Vec<T>) -> Result<Self> {
        let len = checked_len::<T>(&[width, height])?;
        if data.len() != len {
            return Err(CoreError::SizeMismatch {
                expected: format!("{width} × {height} = {len} values"),
                actual: format!("{} values", data.len()),
            });
        }
        Ok(Self {
            width,
            height,
            data,
        })
    }

    /// Number of columns (samples along x).
    #[inline]
    #[must_use]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of rows (samples along y).
    #[inline]
    #[must_use]
    pub fn height(&self) -> usize {
        self.height
    }

    /// `(width, height)`.
    #[inline]
    #[must_use]
    pub fn dims(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// Whether `(x, y)` lies inside the grid.
    #[inline]
    fn contains(&self, x: usize, y: usize) -> bool {
        x < self.width && y < self.height
    }

    /// Returns the linear index of `(x, y)`; `x < width`, `y < height` are the caller's contract
    /// (checked in debug builds).
    #[inline]
    #[must_use]
    pub fn index(&self, x: usize, y: usize) -> usize {
        debug_assert!(x < self.width && y < self.height);
        y * self.width + x
    }

    /// Row `y` as a slice of `width` samples. Panics if `y >= height` (an index bug,
    /// not user input).
    #[inline]
    #[must_use]
    pub fn row(&self, y: usize) -> &[T] {
        &self.data[y * self.width..(y + 1) * self.width]
    }

    /// Row `y`, mutably. Panics if `y >= height`.
    #[inline]
    pub fn row_mut(&mut self, y: usize) -> &mut [T] {
        &mut self.data[y * self.width..(y + 1) * self.width]
    }

    /// Iterates over the rows, top (`y = 0`) to bottom.
    pub fn rows(&self) -> std::slice::ChunksExact<'_, T> {
        self.data.chunks_exact(self.width)
    }

    /// Iterates mutably over the rows.
    pub fn rows_mut(&mut self) -> std::slice::ChunksExactMut<'_, T> {
        self.data.chunks_exact_mut(self.width)
    }

    /// Returns a new grid with `f` applied to every sample.
    #[must_use]
    pub fn map<U>(&self, f: impl FnMut(&T) -> U) -> Grid2<U> {
        Grid2 {
            width: self.width,
            height: self.height,
            data: self.data.iter().map(f).collect(),
        }
    }

    /// Returns `f(a, b)` for each pair of samples of `self` and `other`.
    ///
    /// Fails with [`CoreError::SizeMismatch`] if the grids differ in size.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::SizeMismatch`](crate::CoreError::SizeMismatch) if the grids differ in size. Allocation errors as [`Grid2::new`].
    pub fn zip_map<U, V>(
        &self,
        other: &Grid2<U>,
        mut f: impl FnMut(&T, &U) -> V,
    ) -> Result<Grid2<V>> {
        if self.dims() != other.dims() {
            return Err(CoreError::SizeMismatch {
                expected: format!("{} × {}", self.width, self.height),
                actual: format!("{} × {}", other.width, other.height),
            });
        }
        let data = self
            .data
            .iter()
            .zip(&other.data)
            .map(|(a, b)| f(a, b))
            .collect();
        Ok(Grid2 {
            width: self.width,
            height: self.height,
            data,
        })
    }

    /// Returns the first sample (row-major order) for which `bad` holds, with its position.
    pub fn find(&self, mut bad: impl FnMut(&T) -> bool) -> Option<(usize, usize, &T)> {
        self.data
            .iter()
            .position(&mut bad)
            .map(|i| (i % self.width, i / self.width, &self.data[i]))
    }
}

impl<T> Grid2<T>
where
    T: Copy + Default + std::ops::Add<Output = T> + std::ops::Mul<f32, Output = T>,
{
    /// The grid shrunk by an integer `factor`: each output cell is the mean
    /// of a `factor × factor` block (a box filter). Cells past the last whole
    /// block (when a side is not a multiple of `factor`) are dropped.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::InvalidParameter`](crate::CoreError::InvalidParameter)
    /// if `factor` is zero or larger than either side.
    pub fn box_downsample(&self, factor: usize) -> Result<Grid2<T>> {
        if factor == 0 || factor > self.width || factor > self.height {
            return Err(CoreError::InvalidParameter {
                name: "factor",
                value: factor.to_string(),
                reason: "must lie in [1, the smaller side of the grid]",
            });
        }
        let weight = 1.0 / (factor * factor) as f32;
        Grid2::from_fn(self.width / factor, self.height / factor, |i, j| {
            let mut sum = T::default();
            for dj in 0..factor {
                for di in 0..factor {
                    sum = sum + self[(i * factor + di, j * factor + dj)];
                }
            }
            sum * weight
        })
    }
}

#[cfg(feature = "parallel")]
impl<T: Send + Sync> Grid2<T> {
    /// Calls `f(y, row)` for every row in parallel (rayon; with the
    /// `parallel` feature).
    ///
    /// Each row is handed to exactly one call, so the result never depends on
    /// scheduling as long as `f` only writes its own row.
    pub fn par_rows_mut(&mut self, f: impl Fn(usize, &mut [T]) + Sync + Send) {
        use rayon::prelude::*;
        self.data
            .par_chunks_exact_mut(self.width)
            .enumerate()
            .for_each(|(y, row)| f(y, row));
    }

    /// Calls `f(y, row)` for every row in parallel (rayon), read-only.
    pub fn par_rows(&self, f: impl Fn(usize, &[T]) + Sync + Send) {
        use rayon::prelude::*;
        self.data
            .par_chunks_exact(self.width)
            .enumerate()
            .for_each(|(y, row)| f(y, row));
    }

    /// Returns a grid whose sample `(x, y)` is `f(x, y)`, computed in parallel rows.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::ZeroDimension`](crate::CoreError::ZeroDimension) if a side is zero and
    /// [`CoreError::TooLarge`](crate::CoreError::TooLarge) if the grid would exceed [`MAX_GRID_BYTES`](crate::grid2::MAX_GRID_BYTES).
    pub fn par_from_fn(
        width: usize,
        height: usize,
        f: impl Fn(usize, usize) -> T + Sync + Send,
    ) -> Result<Self>
    where
        T: Default + Clone,
    {
        let mut g = Grid2::new(width, height, T::default())?;
        g.par_rows_mut(|y, row| {
            for (x, v) in row.iter_mut().enumerate() {
                *v = f(x, y);
            }
        });
        Ok(g)
    }
}

impl<T> std::ops::Index<(usize, usize)> for Grid2<T> {
    type Output = T;
    /// Panics outside the grid; use [`Grid2::get`] for a checked read.
    #[inline]
    fn index(&self, (x, y): (usize, usize)) -> &T {
        assert!(
            x < self.width && y < self.height,
            "({x}, {y}) outside {}×{} grid",
            self.width,
            self.height
        );
        &self.data[y * self.width + x]
    }
}

impl<T> std::ops::IndexMut<(usize, usize)> for Grid2<T> {
    #[inline]
    fn index_mut(&mut self, (x, y): (usize, usize)) -> &mut T {
        assert!(
            x < self.width && y < self.height,
            "({x}, {y}) outside {}×{} grid",
            self.width,
            self.height
        );
        &mut self.data[y * self.width + x]
    }
}

impl<T: Interpolate> Grid2<T> {
    /// Returns the sample at integer position `(x, y)` under `boundary`.
    #[inline]
    #[must_use]
    pub fn sample_nearest(&self, x: i64, y: i64, boundary: Boundary<T>) -> T {
        match (
            resolve(x, self.width, &boundary),
            resolve(y, self.height, &boundary),
        ) {
            (Some(x), Some(y)) => self.data[y * self.width + x],
            _ => match boundary {
                Boundary::Constant(c) => c,
                _ => unreachable!("clamp and wrap always resolve"),
            },
        }
    }

    /// Bilinearly interpolates at `(x, y)` in cell units (sample `i` at coordinate `i`).
    ///
    /// Reproduces the samples exactly at integer coordinates and is exact for
    /// functions linear in x and y inside the grid. Outside, `boundary` decides.
    /// A NaN coordinate yields NaN (for float `T`).
    #[must_use]
    pub fn sample_bilinear(&self, x: f32, y: f32, boundary: Boundary<T>) -> T {
        let (x0, fx) = split(x);
        let (y0, fy) = split(y);
        let s = |i: i64, j: i64| self.sample_nearest(i, j, boundary);
        let a = T::lerp(s(x0, y0), s(x0 + 1, y0), fx);
        let b = T::lerp(s(x0, y0 + 1), s(x0 + 1, y0 + 1), fx);
        T::lerp(a, b, fy)
    }
}

dense_grid!(Grid2, x, y);

impl Grid2<f32> {
    /// Returns the first NaN or infinite sample as an error naming its cell.
    ///
    /// # Errors
    ///
    /// Returns [`CoreError::NonFinite`](crate::CoreError::NonFinite) naming the first NaN or infinite value.
    pub fn check_finite(&self) -> Result<()> {
        match self.find(|v| !v.is_finite()) {
            Some((x, y, &value)) => Err(CoreError::NonFinite { x, y, value }),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn box_downsample_averages_blocks_and_drops_the_remainder() {
        let g = Grid2::from_fn(7, 5, |i, j| (i + 10 * j) as f32).unwrap();
        let d = g.box_downsample(2).unwrap();
        assert_eq!(d.dims(), (3, 2));
        // Block (1, 1) holds cells (2..4, 2..4): 22, 23, 32, 33.
        assert_eq!(d[(1, 1)], (22.0 + 23.0 + 32.0 + 33.0) / 4.0);
        assert_eq!(g.box_downsample(1).unwrap(), g);
        assert!(g.box_downsample(0).is_err());
        assert!(g.box_downsample(6).is_err());
    }

    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    #[test]
    fn refuses_zero_dimensions() {
        for (w, h) in [(0, 1), (1, 0), (0, 0)] {
            let err = Grid2::new(w, h, 0.0f32).unwrap_err();
            assert!(matches!(err, CoreError::ZeroDimension { .. }), "{err}");
            assert!(err.to_string().contains(&format!("{w} × {h}")), "{err}");
        }
    }

    #[test]
    fn refuses_oversize_and_overflowing_dimensions() {
        let err = Grid2::new(1 << 20, 1 << 20, 0.0f32).unwrap_err();
        match &err {
            CoreError::TooLarge { bytes, cap, dims } => {
                assert_eq!(*bytes, 4u128 << 40);
                assert_eq!(*cap, MAX_GRID_BYTES);
                assert_eq!(dims, "1048576 × 1048576");
            }
            other => panic!("unexpected {other}"),
        }
        let err = Grid2::new(usize::MAX, usize::MAX, 0u8).unwrap_err();
        assert!(matches!(err, CoreError::TooLarge { .. }));
        assert!(err.to_string().contains(&usize::MAX.to_string()));
    }

    #[test]
    fn from_vec_checks_length() {
        assert!(Grid2::from_vec(3, 2, vec![0; 6]).is_ok());
        let err = Grid2::from_vec(3, 2, vec![0; 5]).unwrap_err();
        assert!(matches!(err, CoreError::SizeMismatch { .. }));
    }

    #[test]
    fn get_set_rows() {
        let mut g = Grid2::from_fn(4, 3, |x, y| (10 * y + x) as i32).unwrap();
        assert_eq!(g.get(3, 2), Some(&23));
        assert_eq!(g.get(4, 0), None);
        assert_eq!(g.set(1, 1, -1), Some(11));
        assert_eq!(g.set(9, 9, 0), None);
        assert_eq!(g.row(1), &[10, -1, 12, 13]);
        assert_eq!(g.rows().count(), 3);
        assert_eq!(g[(2, 2)], 22);
    }

    #[test]
    fn statistics() {
        let g = Grid2::from_vec(2, 2, vec![1.0f32, -2.0, 5.0, 0.0]).unwrap();
        assert_eq!(g.min(), -2.0);
        assert_eq!(g.max(), 5.0);
        assert_eq!(g.min_max(), (-2.0, 5.0));
        assert_relative_eq!(g.mean(), 1.0);
        let bad = Grid2::from_vec(2, 2, vec![1.0f32, 1.0, f32::NAN, 1.0]).unwrap();
        let err = bad.check_finite().unwrap_err();
        assert!(
            matches!(err, CoreError::NonFinite { x: 0, y: 1, .. }),
            "{err}"
        );
    }

    #[test]
    fn zip_map_checks_dims() {
        let a = Grid2::new(2, 2, 1.0f32).unwrap();
        let b = Grid2::new(2, 3, 1.0f32).unwrap();
        assert!(a.zip_map(&b, |x, y| x + y).is_err());
        let c = a.zip_map(&a, |x, y| x + y).unwrap();
        assert!(c.as_slice().iter().all(|&v| v == 2.0));
    }

    #[cfg(feature = "parallel")]
    #[test]
    fn par_rows_matches_serial() {
        let serial = Grid2::from_fn(37, 23, |x, y| (x * 31 + y * 7) as f32).unwrap();
        let par = Grid2::par_from_fn(37, 23, |x, y| (x * 31 + y * 7) as f32).unwrap();
        assert_eq!(serial, par);
        let total = std::sync::atomic::AtomicUsize::new(0);
        par.par_rows(|_, row| {
            total.fetch_add(row.len(), std::sync::atomic::Ordering::Relaxed);
        });
        assert_eq!(total.into_inner(), 37 * 23);
    }

    #[test]
    fn nan_coordinate_gives_nan() {
        let g = Grid2::new(4, 4, 1.0f32).unwrap();
        assert!(g.sample_bilinear(f32::NAN, 1.0, Boundary::Clamp).is_nan());
    }

    proptest! {
        #[test]
        fn bilinear_reproduces_grid_points(w in 1usize..12, h in 1usize..12, seed in any::<u64>()) {
            let g = Grid2::from_fn(w, h, |x, y| ((x as u64 * 7919 + y as u64 * 104729) ^ seed) as f32 % 97.0).unwrap();
            for y in 0..h {
                for x in 0..w {
                    for b in [Boundary::Clamp, Boundary::Wrap, Boundary::Constant(-1.0)] {
                        prop_assert_eq!(g.sample_bilinear(x as f32, y as f32, b), g[(x, y)]);
                    }
                }
            }
        }

        #[test]
        fn bilinear_exact_for_linear_functions(
            a in -10.0f32..10.0, b in -10.0f32..10.0, c in -10.0f32..10.0,
            px in 0.0f32..15.0, py in 0.0f32..9.0,
        ) {
            let g = Grid2::from_fn(16, 10, |x, y| a * x as f32 + b * y as f32 + c).unwrap();
            let expect = a * px + b * py + c;
            let got = g.sample_bilinear(px, py, Boundary::Clamp);
            prop_assert!((got - expect).abs() <= 1e-4 * (1.0 + expect.abs()), "{} vs {}", got, expect);
        }

        #[test]
        fn wrap_is_periodic(px in -50.0f32..50.0, py in -50.0f32..50.0, kx in -3i32..3, ky in -3i32..3) {
            let g = Grid2::from_fn(8, 5, |x, y| ((x * 13 + y * 29) % 11) as f32).unwrap();
            let base = g.sample_bilinear(px, py, Boundary::Wrap);
            let shifted = g.sample_bilinear(px + (8 * kx) as f32, py + (5 * ky) as f32, Boundary::Wrap);
            prop_assert!((base - shifted).abs() < 1e-3, "{} vs {}", base, shifted);
        }

        #[test]
        fn clamp_extends_edges(px in -20.0f32..0.0, y in 0usize..5) {
            let g = Grid2::from_fn(8, 5, |x, y| (x + 10 * y) as f32).unwrap();
            prop_assert_eq!(g.sample_bilinear(px, y as f32, Boundary::Clamp), g[(0, y)]);
            prop_assert_eq!(g.sample_bilinear(px - 1.0, y as f32, Boundary::Constant(7.0)), 7.0);
        }
    }
}
