//! Connected water bodies: the 4-connected components of a mask, kept when
//! large enough. A plain flood fill (natura's own; no source).

use natura_core::Grid2;

use crate::error::Result;

/// Marks the cells of the 4-connected components of `mask` (neighbours along
/// x and y, not diagonals) that hold at least `min_cells` cells; every other
/// cell is `false`. With `min_cells` 0 or 1, the result is `mask` itself.
///
/// The components are found by a depth-first flood fill from each unvisited
/// `true` cell in row order (natura's own construction); the result does not
/// depend on that order.
///
/// # Errors
///
/// Returns [`TerrainError::Core`](crate::TerrainError::Core) if the result
/// cannot be allocated.
pub fn large_components(mask: &Grid2<bool>, min_cells: usize) -> Result<Grid2<bool>> {
    let (nx, ny) = mask.dims();
    let mask = mask.as_slice();
    let mut keep = vec![false; mask.len()];
    let mut seen = vec![false; mask.len()];
    let mut stack = Vec::new();
    let mut comp = Vec::new();
    for start in 0..mask.len() {
        if !mask[start] || seen[start] {
            continue;
        }
        comp.clear();
        stack.push(start);
        seen[start] = true;
        while let Some(k) = stack.pop() {
            comp.push(k);
            let (x, y) = (k % nx, k / nx);
            let mut visit = |n: usize| {
                if mask[n] && !seen[n] {
                    seen[n] = true;
                    stack.push(n);
                }
            };
            if x > 0 {
                visit(k - 1);
            }
            if x + 1 < nx {
                visit(k + 1);
            }
            if y > 0 {
                visit(k - nx);
            }
            if y + 1 < ny {
                visit(k + nx);
            }
        }
        if comp.len() >= min_cells {
            for &k in &comp {
                keep[k] = true;
            }
        }
    }
    Ok(Grid2::from_vec(nx, ny, keep)?)
}
