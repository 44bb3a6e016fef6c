//! Flow routing on a height field: D8 steepest-descent receivers (O'Callaghan &
//! Mark 1984), the stack order of Braun & Willett 2013 and drainage area, and
//! depression handling so every cell drains to the grid edge:
//! basins are linked through their lowest passes by a minimax spanning tree
//! over the basin graph (Cordonnier et al. 2019), then either routed
//! through (lakes kept, receivers reversed along the path from the pass to the
//! pit) or filled to the spill level with a minimal gradient (equivalent to
//! Barnes et al. 2014's Priority-Flood+ε along the routing tree).
//! Costs are O(n) plus O(b log b) for b basins.
//!
//! Cells on the grid edge are outlets (base level): water leaving them leaves
//! the map. Receivers are chosen among the 8 neighbours by the steepest drop
//! per unit distance, ties broken by a fixed neighbour order, so the graph is
//! deterministic.
//!
//! Layout: `receivers.rs` builds the graph's edges (D8 receivers, roots,
//! donor masks), `pits.rs` routes closed basins through their passes,
//! `stack.rs` orders the cells and accumulates drainage area, `fill.rs`
//! fills along the routed graph and holds the Priority-Flood oracle.

mod fill;
mod pits;
mod receivers;
mod stack;
#[cfg(test)]
mod tests;

pub(crate) use fill::{fill_along, next_up};
pub use fill::{fill_depressions, priority_flood_levels};
use natura_core::simd::Simd;
pub(crate) use receivers::D8;
use receivers::{d8_receivers_into, donor_masks_into, find_roots};

/// How closed depressions (pits) are handled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Depressions {
    /// Leave them: pits are sinks that do not reach the edge.
    Keep,
    /// Route flow through them to their lowest pass; heights are unchanged (lakes).
    Route,
    /// Route, then raise every cell below its receiver to just above it, so the
    /// surface itself drains everywhere (depressions filled to the spill level).
    Fill,
}

/// A flow graph: each cell's receiver, the stack order and drainage areas.
#[derive(Clone, Debug)]
pub struct FlowGraph {
    nx: usize,
    ny: usize,
    /// Receiver of each cell (itself for outlets and kept pits).
    pub receiver: Vec<u32>,
    /// Distance to the receiver, cells (0 for outlets).
    pub distance: Vec<f32>,
    /// Cells ordered so that every receiver precedes its donors (Braun & Willett's stack).
    pub stack: Vec<u32>,
    /// Bounds of the stack's outlet groups: group `k` is `stack[groups[k]..groups[k + 1]]`
    /// and holds whole drainage trees, so the groups can be processed independently.
    pub(crate) groups: Vec<usize>,
    /// For each stack entry, the position of its receiver within its group
    /// (its own position for outlets).
    pub(crate) rpos: Vec<u32>,
    scratch: StackScratch,
}

/// Reusable buffers of the graph builder.
#[derive(Clone, Debug, Default)]
pub(crate) struct StackScratch {
    /// Donor bit masks per cell (bit `k`: the neighbour at [`NB`]`[k]` drains here).
    masks: Vec<u8>,
    /// Cells that are their own receiver (outlets and pits), increasing.
    roots: Vec<u32>,
    /// Basin label per cell during pit routing; all zero between calls.
    basin: Vec<u32>,
}

impl FlowGraph {
    /// Grid width.
    #[must_use]
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// Grid height.
    #[must_use]
    pub fn ny(&self) -> usize {
        self.ny
    }

    /// D8 receivers of `h` (`nx × ny`, row-major) with depression handling;
    /// `Fill` modifies `h`.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch)
    /// if `h.len() ≠ nx·ny` or a side is zero, and
    /// [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) naming the
    /// first NaN or infinite height.
    pub fn build(
        h: &mut [f32],
        nx: usize,
        ny: usize,
        depressions: Depressions,
    ) -> crate::Result<Self> {
        check_slice(h, nx, ny)?;
        let mut g = Self::empty();
        g.rebuild(h, nx, ny, depressions);
        Ok(g)
    }

    /// A graph of no cells, whose buffers [`FlowGraph::rebuild`] grows.
    pub(crate) fn empty() -> Self {
        FlowGraph {
            nx: 0,
            ny: 0,
            receiver: Vec::new(),
            distance: Vec::new(),
            stack: Vec::new(),
            groups: Vec::new(),
            rpos: Vec::new(),
            scratch: StackScratch::default(),
        }
    }

    /// [`FlowGraph::build`] into this graph's buffers (no allocation once they
    /// have grown to the grid's size): the same graph, bit for bit.
    pub(crate) fn rebuild(
        &mut self,
        h: &mut [f32],
        nx: usize,
        ny: usize,
        depressions: Depressions,
    ) {
        self.rebuild_with_fill(h, nx, ny, depressions, None);
    }

    /// [`FlowGraph::rebuild`], adding to `filled` (one value per cell) how much
    /// `Fill` raised each cell.
    pub(crate) fn rebuild_with_fill(
        &mut self,
        h: &mut [f32],
        nx: usize,
        ny: usize,
        depressions: Depressions,
        filled: Option<&mut [f32]>,
    ) {
        self.rebuild_graph(h, nx, ny, depressions);
        if depressions == Depressions::Fill {
            fill_along(h, &self.receiver, &self.stack, filled);
        }
    }

    /// Receivers, pit routing (`Route` and `Fill` route alike) and the stack,
    /// without filling: `h` is not modified.
    pub(crate) fn rebuild_graph(
        &mut self,
        h: &[f32],
        nx: usize,
        ny: usize,
        depressions: Depressions,
    ) {
        self.nx = nx;
        self.ny = ny;
        let simd = Simd::best();
        d8_receivers_into(simd, h, nx, ny, &mut self.receiver, &mut self.distance);
        find_roots(&self.receiver, nx, ny, &mut self.scratch.roots);
        donor_masks_into(simd, &self.receiver, nx, ny, &mut self.scratch.masks);
        // Pits are routed on the raw receivers (labelling walks the donor
        // masks from each pit), so the stack is built once, on the final receivers.
        if depressions != Depressions::Keep {
            self.route_pits(h);
        }
        self.build_stack();
    }

    /// Whether cell `i` is on the grid edge.
    #[inline]
    #[must_use]
    pub fn is_edge(&self, i: usize) -> bool {
        let (x, y) = (i % self.nx, i / self.nx);
        x == 0 || y == 0 || x == self.nx - 1 || y == self.ny - 1
    }

    /// Follows receivers from `i` to the cell where flow stops (an outlet or a kept pit).
    #[must_use]
    pub fn terminus(&self, mut i: usize) -> usize {
        for _ in 0..=self.receiver.len() {
            let r = self.receiver[i] as usize;
            if r == i {
                return i;
            }
            i = r;
        }
        i
    }
}

/// Checks a row-major height slice against its stated size, and its values.
pub(super) fn check_slice(h: &[f32], nx: usize, ny: usize) -> crate::Result<()> {
    if nx == 0 || ny == 0 || nx.checked_mul(ny) != Some(h.len()) {
        return Err(crate::TerrainError::SizeMismatch {
            what: "height slice",
            expected: format!("{nx} × {ny} (non-zero) values"),
            actual: format!("{} values", h.len()),
        });
    }
    if let Some(i) = h.iter().position(|v| !v.is_finite()) {
        return Err(crate::TerrainError::NonFinite {
            what: "height slice",
            x: i % nx,
            y: i / nx,
            value: h[i],
        });
    }
    Ok(())
}
