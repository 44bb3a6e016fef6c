//! The grid a step runs on: its size and edges, and views of a plane's rows
//! around a cell or a row (no model arithmetic here).

use natura_core::simd::Simd;

use super::model::Coefficients;
use crate::erosion::Edges;

/// Pipe (and neighbour) index: left (x − 1).
pub(super) const L: usize = 0;
/// Right (x + 1).
pub(super) const R: usize = 1;
/// Below (y − 1).
pub(super) const B: usize = 2;
/// Above (y + 1).
pub(super) const T: usize = 3;

/// One step's setting: the model's coefficients on a grid of `nx × ny`
/// cells with the given edges.
#[derive(Clone, Copy, Debug)]
pub(super) struct Step {
    /// The model's coefficients.
    pub k: Coefficients,
    /// Cells per row.
    pub nx: usize,
    /// Rows.
    pub ny: usize,
    /// What lies beyond the grid.
    pub edges: Edges,
    /// The instruction set the row kernels run at; `None` sends every cell
    /// through the per-cell reference functions.
    pub simd: Option<Simd>,
}

impl Step {
    /// Row `y` (which may lie outside `0..ny`) resolved through the edges.
    #[inline]
    pub(super) fn row_at(&self, y: isize) -> Option<usize> {
        let ny = self.ny as isize;
        if (0..ny).contains(&y) {
            Some(y as usize)
        } else if self.edges == Edges::Periodic {
            Some(y.rem_euclid(ny) as usize)
        } else {
            None
        }
    }

    /// Rows `y − 1`, `y`, `y + 1` of the full plane `g`.
    #[inline]
    pub(super) fn rows<'a>(&self, g: &'a [f32], y: usize) -> Rows<'a> {
        let nx = self.nx;
        let row = |j: usize| &g[j * nx..(j + 1) * nx];
        Rows {
            b: self.row_at(y as isize - 1).map(row),
            c: row(y),
            t: self.row_at(y as isize + 1).map(row),
        }
    }

    /// Neighbour `k` (L, R, B, T) of cell `x` of the centre row of `p`,
    /// resolved through the edges.
    #[inline]
    pub(super) fn nb(&self, p: Rows<'_>, x: usize, k: usize) -> Option<f32> {
        let nx = self.nx;
        let periodic = self.edges == Edges::Periodic;
        match k {
            L if x > 0 => Some(p.c[x - 1]),
            L => periodic.then(|| p.c[nx - 1]),
            R if x + 1 < nx => Some(p.c[x + 1]),
            R => periodic.then(|| p.c[0]),
            B => p.b.map(|r| r[x]),
            _ => p.t.map(|r| r[x]),
        }
    }
}

/// Rows `y − 1`, `y` and `y + 1` of a plane; `None` beyond a closed or open
/// edge (periodic edges give the wrapped row).
#[derive(Clone, Copy)]
pub(super) struct Rows<'a> {
    /// Row `y − 1`.
    pub b: Option<&'a [f32]>,
    /// Row `y`.
    pub c: &'a [f32],
    /// Row `y + 1`.
    pub t: Option<&'a [f32]>,
}

impl<'a> Rows<'a> {
    /// The interior cells `1..nx − 1` and their four neighbours, if both
    /// neighbouring rows exist.
    #[inline]
    pub(super) fn around(self) -> Option<Around<'a>> {
        let (b, t) = (self.b?, self.t?);
        let n = self.c.len();
        Some(Around {
            c: &self.c[1..n - 1],
            l: &self.c[..n - 2],
            r: &self.c[2..],
            b: &b[1..n - 1],
            t: &t[1..n - 1],
        })
    }
}

/// A plane's values at the cells `i0..i0 + m` of one interior row and at their
/// left, right, lower and upper neighbours.
#[derive(Clone, Copy)]
pub(super) struct Around<'a> {
    /// The cells.
    pub c: &'a [f32],
    /// Their left neighbours.
    pub l: &'a [f32],
    /// Their right neighbours.
    pub r: &'a [f32],
    /// Their lower neighbours.
    pub b: &'a [f32],
    /// Their upper neighbours.
    pub t: &'a [f32],
}

impl Around<'_> {
    /// The same view restricted to the cells `a..b` of the row.
    #[inline(always)]
    pub(super) fn sub(&self, a: usize, b: usize) -> Self {
        Self {
            c: &self.c[a..b],
            l: &self.l[a..b],
            r: &self.r[a..b],
            b: &self.b[a..b],
            t: &self.t[a..b],
        }
    }
}

/// `p[r]`, or `p` itself if it is empty (a plane not kept).
#[inline]
pub(super) fn opt_rows(p: &mut [f32], r: std::ops::Range<usize>) -> &mut [f32] {
    if p.is_empty() { p } else { &mut p[r] }
}

/// Per-cell outflows through open edges, `(row, amount)` in row order.
pub(super) type Outflows = Vec<(usize, f64)>;
