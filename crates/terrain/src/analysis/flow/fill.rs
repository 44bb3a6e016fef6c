//! Filling along the routed graph (every cell raised to just above its
//! receiver, the equivalent of Barnes et al. 2014's Priority-Flood+ε), and
//! the plain Priority-Flood spill levels used as its oracle.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use natura_core::{Grid2, HeightField};

use super::receivers::D8;
use super::{Depressions, FlowGraph, check_slice};

/// Raises every cell not strictly above its receiver to the next representable
/// height above it, in stack order, adding each raise to `filled` if given.
pub(crate) fn fill_along(
    h: &mut [f32],
    rec: &[u32],
    stack: &[u32],
    mut filled: Option<&mut [f32]>,
) {
    for &i in stack {
        let (i, r) = (i as usize, rec[i as usize] as usize);
        if r != i && h[i] <= h[r] {
            let z = next_up(h[r]);
            if let Some(f) = filled.as_deref_mut() {
                f[i] += z - h[i];
            }
            h[i] = z;
        }
    }
}

/// The smallest `f32` greater than `x` (finite `x`).
#[inline]
pub(crate) fn next_up(x: f32) -> f32 {
    let step = (x.abs() * f32::EPSILON).max(1e-6);
    let y = x + step;
    if y > x {
        y
    } else {
        f32::from_bits(x.to_bits() + 1)
    }
}

/// Fills depressions of `hf` (every cell then drains to the edge by steepest
/// descent), returning the filled field and the depth of fill per cell.
///
/// # Errors
///
/// Returns [`TerrainError::Core`](crate::TerrainError::Core) naming the first NaN or infinite height, or if
/// the result cannot be allocated.
pub fn fill_depressions(hf: &HeightField) -> crate::Result<(HeightField, Grid2<f32>)> {
    hf.check_finite()?;
    let (nx, ny) = (hf.nx(), hf.ny());
    let mut h = hf.heights().as_slice().to_vec();
    FlowGraph::build(&mut h, nx, ny, Depressions::Fill)?;
    let depth: Vec<f32> = h
        .iter()
        .zip(hf.heights().as_slice())
        .map(|(a, b)| a - b)
        .collect();
    Ok((
        HeightField::new(Grid2::from_vec(nx, ny, h)?, hf.cell_size())?,
        Grid2::from_vec(nx, ny, depth)?,
    ))
}

/// Reference Priority-Flood (Barnes et al. 2014) without ε: the spill level of
/// every cell, O(n log n). Used as an oracle in tests.
///
/// # Errors
///
/// As [`FlowGraph::build`]: a slice whose length is not `nx·ny`, a zero side,
/// or a non-finite height.
pub fn priority_flood_levels(h: &[f32], nx: usize, ny: usize) -> crate::Result<Vec<f32>> {
    check_slice(h, nx, ny)?;
    #[derive(PartialEq)]
    struct Item(f32, usize);
    impl Eq for Item {}
    impl PartialOrd for Item {
        fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
            Some(self.cmp(o))
        }
    }
    impl Ord for Item {
        fn cmp(&self, o: &Self) -> Ordering {
            o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
        }
    }
    let mut out = h.to_vec();
    let mut seen = vec![false; h.len()];
    let mut pq = BinaryHeap::new();
    for y in 0..ny {
        for x in 0..nx {
            if x == 0 || y == 0 || x == nx - 1 || y == ny - 1 {
                let i = y * nx + x;
                seen[i] = true;
                pq.push(Item(h[i], i));
            }
        }
    }
    while let Some(Item(z, i)) = pq.pop() {
        let (x, y) = ((i % nx) as i64, (i / nx) as i64);
        for &(dx, dy, _) in &D8 {
            let (a, b) = (x + i64::from(dx), y + i64::from(dy));
            if a < 0 || b < 0 || a >= nx as i64 || b >= ny as i64 {
                continue;
            }
            let j = b as usize * nx + a as usize;
            if !seen[j] {
                seen[j] = true;
                out[j] = out[j].max(z);
                pq.push(Item(out[j], j));
            }
        }
    }
    Ok(out)
}
