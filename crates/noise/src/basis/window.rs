//! Batch rows window by window: the lattice bases' kernel for rows of 1 to
//! 64 points a cell.
//!
//! At these steps a row has too few points per cell for a span kernel (one
//! cell's set-up, then its points) to amortise the set-up, yet enough points
//! on each lattice column that a per-lane kernel, which hashes every
//! point's corners, repeats most of its work. Here each chunk of
//! [`WINDOW_CHUNK`] points has its lattice columns prepared once (hashed
//! into the basis's column terms, [`Window::columns`]), and each group of
//! [`WINDOW`] points, which starts in some cell and spans at most
//! [`WINDOW`] cells, hands its lanes' cells (relative to the group's first)
//! and fractions to [`Window::group`], which looks their columns' terms up
//! by permutes (`natura_simd::lookup16`) and evaluates the basis's formula
//! in the cell. No hashing per point.
//!
//! The rows of a grid share their points' x: [`rows_windows`] computes each
//! group's cells and fractions once for a block of rows (a grid's fill, one
//! octave of a fractal's), and only the columns, which depend on the row's
//! y, row by row; and consecutive rows share the corner terms of the
//! lattice rows they have in common ([`Window::columns_shared`]). Perlin
//! 2-D grids: 0.65 → 0.39 ns a point at 1/16, 1.11 → 0.66 at 1 (Intel Xeon).

use crate::lattice_math::{Simd, split_fast};

/// Steps (lattice cells per point) above this go window by window rather
/// than span by span: below 64 points a cell, the set-up of each cell costs
/// more than the lookups (Perlin noise; value noise, whose cells cost less
/// to set up, from 1/32).
pub(crate) const WINDOW_MIN_STEP: f64 = 1.0 / 64.0;

/// Largest step [`row_windows`] takes: a group of [`WINDOW`] points then
/// spans at most [`WINDOW`] cells.
pub(crate) const WINDOW_MAX_STEP: f64 = 1.0;

/// Points per group (the lanes of one lookup).
pub(crate) const WINDOW: usize = 16;

/// Points whose lattice columns are prepared in one batch.
pub(crate) const WINDOW_CHUNK: usize = 256;

/// Columns a chunk may need: its cells, and a window's reach past the last
/// group's first cell (a lane's cell and the column to its right).
pub(crate) const WINDOW_COLUMNS: usize = WINDOW_CHUNK + WINDOW + 2;

/// Whether a row of spacing `step` goes window by window, for a basis
/// whose span kernel is the faster up to `min` (at most 1/64).
#[inline(always)]
pub(crate) fn takes_windows(step: f64, min: f64) -> bool {
    step > min.max(WINDOW_MIN_STEP) && step <= WINDOW_MAX_STEP
}

/// A basis's side of [`row_windows`]: its column terms and its formula in a
/// cell. Implementations are structs with `#[inline(always)]` methods (a
/// closure is not always inlined into the level's `#[target_feature]`
/// function, and then runs at the baseline level).
pub(crate) trait Window<const T: usize> {
    /// What consecutive rows of a grid can share of their columns' work
    /// (their lattice rows' corner terms), carried from row to row within a
    /// chunk by [`rows_windows`].
    type Shared;

    /// An empty [`Shared`](Self::Shared) (nothing computed yet).
    fn shared(&self) -> Self::Shared;

    /// Fills the `T` tables of terms of the lattice columns `first, first +
    /// 1, …`, `n ≤ WINDOW_COLUMNS` of them (table index 0 is column `first`).
    fn columns(&self, first: u32, n: usize, tables: &mut [[f32; WINDOW_COLUMNS]; T]);

    /// [`columns`](Self::columns), reusing what `shared` holds for the same
    /// chunk (`first`, `n`) from the rows before, and leaving there what the
    /// rows after can use. The same tables bit for bit.
    fn columns_shared(
        &self,
        first: u32,
        n: usize,
        shared: &mut Self::Shared,
        tables: &mut [[f32; WINDOW_COLUMNS]; T],
    ) {
        let _ = shared;
        self.columns(first, n, tables);
    }

    /// The values of a group's lanes: lane `l` lies in the cell between
    /// table columns `cell + index[l]` and `cell + index[l] + 1`, at fraction
    /// `t[l]` in `[0, 1]`. (The fraction's interpolation weight is computed
    /// here, not cached with the fraction for the rows of a grid: loaded
    /// from memory, it kept this loop from vectorising at the full width.)
    fn group(
        &self,
        simd: Simd,
        tables: &[[f32; WINDOW_COLUMNS]; T],
        cell: usize,
        index: &[u32; WINDOW],
        t: &[f32; WINDOW],
    ) -> [f32; WINDOW];
}

/// The row `out[i]` at `x0 + i·step` (`WINDOW_MIN_STEP < step ≤
/// WINDOW_MAX_STEP`, inside the fast-split range), window by window (see
/// the module docs). Equal at every SIMD level. (Not [`rows_windows`] of
/// one row: that keeps its groups' x parts in arrays across the chunk,
/// which is right for many rows but made a single row take twice as long
/// as this loop, which uses each group's straight away.)
#[inline(always)]
pub(crate) fn row_windows<const T: usize, W: Window<T>>(
    simd: Simd,
    basis: &W,
    x0: f64,
    step: f64,
    out: &mut [f32],
) {
    // The column tables live here, on the kernel's stack, not in `basis`:
    // held behind a reference they kept the loops from vectorising.
    let mut tables = [[0.0f32; WINDOW_COLUMNS]; T];
    let offset = lane_offsets(step);
    for (c, chunk) in out.chunks_mut(WINDOW_CHUNK).enumerate() {
        let (first, fx, ncol) = chunk_start(x0, step, c, chunk.len());
        basis.columns(first, ncol, &mut tables);
        for (g, group) in chunk.chunks_mut(WINDOW).enumerate() {
            let (cell, index, t) = group_x(fx, step, g, &offset);
            store(group, basis.group(simd, &tables, cell, &index, &t));
        }
    }
}

/// Rows of a grid at once: row `r` of `out` (`out.len() / bases.len()`
/// points, rows one after another) is [`row_windows`]'s row of
/// `bases[r]`, and equals it bit for bit. The rows share their points'
/// x, so each group's cells and fractions are computed once for all of
/// them; each row then hashes its own columns (they depend on its y).
#[inline(always)]
pub(crate) fn rows_windows<const T: usize, W: Window<T>>(
    simd: Simd,
    bases: &[W],
    x0: f64,
    step: f64,
    out: &mut [f32],
) {
    if bases.is_empty() {
        return;
    }
    let n = out.len() / bases.len();
    if n == 0 {
        return;
    }
    let mut tables = [[0.0f32; WINDOW_COLUMNS]; T];
    const GROUPS: usize = WINDOW_CHUNK / WINDOW;
    let mut cells = [0usize; GROUPS];
    let mut indices = [[0u32; WINDOW]; GROUPS];
    let mut fractions = [[0.0f32; WINDOW]; GROUPS];
    let offset = lane_offsets(step);
    for c in 0..n.div_ceil(WINDOW_CHUNK) {
        let len = WINDOW_CHUNK.min(n - c * WINDOW_CHUNK);
        let (first, fx, ncol) = chunk_start(x0, step, c, len);
        let groups = len.div_ceil(WINDOW);
        // What the rows share is per chunk.
        let mut shared = bases[0].shared();
        for g in 0..groups {
            let (cell, index, t) = group_x(fx, step, g, &offset);
            cells[g] = cell;
            indices[g] = index;
            fractions[g] = t;
        }
        for (r, basis) in bases.iter().enumerate() {
            basis.columns_shared(first, ncol, &mut shared, &mut tables);
            let chunk = &mut out[r * n + c * WINDOW_CHUNK..][..len];
            for (g, group) in chunk.chunks_mut(WINDOW).enumerate() {
                store(
                    group,
                    basis.group(simd, &tables, cells[g], &indices[g], &fractions[g]),
                );
            }
        }
    }
}

/// Each lane's offset from its group's first point, in cells.
#[inline(always)]
fn lane_offsets(step: f64) -> [f32; WINDOW] {
    let s32 = step as f32;
    core::array::from_fn(|l| (l as i32) as f32 * s32)
}

/// Chunk `c` (of `len` points): its first point's lattice column and
/// fraction, and how many columns its groups reach.
#[inline(always)]
fn chunk_start(x0: f64, step: f64, c: usize, len: usize) -> (u32, f64, usize) {
    let (first, fx) = split_fast(x0 + (c * WINDOW_CHUNK) as f64 * step);
    // The last group's first cell, relative to `first`, and its window.
    let reach = fx + ((len - 1) / WINDOW * WINDOW) as f64 * step;
    (first, fx, (reach as usize + WINDOW + 2).min(WINDOW_COLUMNS))
}

/// Group `g` of a chunk whose first point lies at `fx` in its first
/// column: the group's first cell from the chunk's, and each lane's cell
/// from the group's and fraction.
#[inline(always)]
fn group_x(
    fx: f64,
    step: f64,
    g: usize,
    offset: &[f32; WINDOW],
) -> (usize, [u32; WINDOW], [f32; WINDOW]) {
    // The group's start from the chunk's first cell (≥ 0, below
    // WINDOW_CHUNK + 1): its cell and fraction.
    let u = fx + ((g * WINDOW) as f64) * step;
    let cell = u as usize;
    let f = (u - cell as f64) as f32;
    let mut index = [0u32; WINDOW];
    let mut t = [0.0f32; WINDOW];
    for l in 0..WINDOW {
        // The lane's point from the group's cell, in [0, 16]: its floor by
        // rounding at 2²³ (whose integer sits in the low mantissa bits) and
        // a correction, as `split_fast` does in f64 (a float-to-int cast is
        // a compare and a scalar convert per lane). A sum rounded up to 16
        // stays in cell 15 at fraction 1, the same point.
        const M: f32 = 8_388_608.0;
        let s = f + offset[l];
        let r = s + M;
        let n = r - M;
        let down = n > s;
        let i = (r.to_bits() & 0xff).wrapping_sub(u32::from(down));
        let i = i.min(WINDOW as u32 - 1);
        index[l] = i;
        t[l] = s - (i as i32) as f32;
    }
    (cell, index, t)
}

/// A whole group as one fixed-size store (a slice copy of unknown length
/// is a library call per group); a short last group lane by lane.
#[inline(always)]
fn store(group: &mut [f32], v: [f32; WINDOW]) {
    match <&mut [f32; WINDOW]>::try_from(&mut *group) {
        Ok(whole) => *whole = v,
        Err(_) => {
            for (o, x) in group.iter_mut().zip(v) {
                *o = x;
            }
        }
    }
}

/// The [`WINDOW`] table entries from `from` on.
#[inline(always)]
pub(crate) fn window_at(table: &[f32; WINDOW_COLUMNS], from: usize) -> [f32; WINDOW] {
    table[from..from + WINDOW].try_into().unwrap()
}
