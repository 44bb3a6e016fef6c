//! Flow routing on a height field: D8 steepest-descent receivers (O'Callaghan &
//! Mark 1984), the Braun & Willett (2013) stack order and drainage area, and
//! depression handling so every cell drains to the grid edge:
//! basins are linked through their lowest passes by a minimax spanning tree
//! over the basin graph (Cordonnier, Bovy & Braun 2019), then either routed
//! through (lakes kept, receivers reversed along the path from the pass to the
//! pit) or filled to the spill level with a minimal gradient (equivalent to
//! Barnes et al. 2014's Priority-Flood+ε along the routing tree).
//! Costs are O(n) plus O(b log b) for b basins.
//!
//! Cells on the grid edge are outlets (base level): water leaving them leaves
//! the map. Receivers are chosen among the 8 neighbours by the steepest drop
//! per unit distance, ties broken by a fixed neighbour order, so the graph is
//! deterministic.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use natura_core::{Grid2, HeightField};

use crate::par;

/// Neighbour offsets in the fixed tie-break order, with distances in cells.
pub(crate) const D8: [(i32, i32, f32); 8] = [
    (1, 0, 1.0),
    (-1, 0, 1.0),
    (0, 1, 1.0),
    (0, -1, 1.0),
    (1, 1, std::f32::consts::SQRT_2),
    (-1, 1, std::f32::consts::SQRT_2),
    (1, -1, std::f32::consts::SQRT_2),
    (-1, -1, std::f32::consts::SQRT_2),
];

/// How closed depressions (pits) are handled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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

/// The eight neighbours in increasing index order (raster order of the 3 × 3
/// block): bit `k` of a donor mask stands for the neighbour at `NB[k]`.
const NB: [(isize, isize); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// Index offsets of [`NB`] on a grid `nx` wide.
#[inline]
fn nb_offsets(nx: usize) -> [isize; 8] {
    NB.map(|(dx, dy)| dy * nx as isize + dx)
}

/// The bit of neighbour `d` in the donor mask of cell `r` (8-neighbours).
#[inline]
fn nb_bit(r: usize, d: usize, nx: usize) -> u8 {
    let dx = (d % nx) as isize - (r % nx) as isize;
    let dy = (d / nx) as isize - (r / nx) as isize;
    let idx = (dy + 1) * 3 + (dx + 1);
    debug_assert!((0..9).contains(&idx) && idx != 4, "not a neighbour");
    1u8 << (idx - isize::from(idx > 4))
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
        d8_receivers_into(h, nx, ny, &mut self.receiver, &mut self.distance);
        find_roots(&self.receiver, nx, ny, &mut self.scratch.roots);
        donor_masks_into(&self.receiver, nx, ny, &mut self.scratch.masks);
        // Pits are routed on the raw receivers (labelling walks the donor
        // masks from each pit), so the stack is built once, on the final receivers.
        if depressions != Depressions::Keep {
            self.route_pits(h);
        }
        self.build_stack();
    }

    /// Braun & Willett's stack (outlets and pits first, each followed
    /// depth-first by its donors, visited in increasing index order) from the
    /// roots and donor masks: groups of consecutive roots are walked in
    /// parallel and concatenated in order (the same stack as one walk), and
    /// the group bounds and each entry's receiver position are kept for the
    /// group-parallel passes. O(n).
    fn build_stack(&mut self) {
        let n = self.receiver.len();
        let off = nb_offsets(self.nx);
        let roots = &self.scratch.roots;
        let masks = &self.scratch.masks;
        let per = roots.len().div_ceil(STACK_GROUPS).max(1);
        let parts: Vec<(Vec<u32>, Vec<u32>)> =
            par::run(roots.chunks(per).collect(), |roots: &[u32]| {
                let mut part = Vec::new();
                let mut rp = Vec::new();
                let mut work: Vec<(u32, u32)> = Vec::new();
                for &root in roots {
                    work.push((root, u32::MAX));
                    while let Some((c, r)) = work.pop() {
                        let k = part.len() as u32;
                        part.push(c);
                        rp.push(if r == u32::MAX { k } else { r });
                        let mut m = masks[c as usize];
                        while m != 0 {
                            let b = m.trailing_zeros() as usize;
                            m &= m - 1;
                            work.push(((c as isize + off[b]) as u32, k));
                        }
                    }
                }
                (part, rp)
            });
        self.groups.clear();
        self.groups.push(0);
        for (part, _) in &parts {
            self.groups
                .push(self.groups.last().copied().unwrap_or(0) + part.len());
        }
        debug_assert_eq!(self.groups.last().copied(), Some(n));
        self.stack.resize(n, 0);
        self.rpos.resize(n, 0);
        let mut jobs = Vec::with_capacity(parts.len());
        let (mut st, mut rp) = (self.stack.as_mut_slice(), self.rpos.as_mut_slice());
        for part in parts {
            let (a, b) = std::mem::take(&mut st).split_at_mut(part.0.len());
            let (c, d) = std::mem::take(&mut rp).split_at_mut(part.0.len());
            st = b;
            rp = d;
            jobs.push((a, c, part));
        }
        par::run(jobs, |(a, c, (p, r))| {
            a.copy_from_slice(&p);
            c.copy_from_slice(&r);
        });
    }

    /// Whether cell `i` is on the grid edge.
    #[inline]
    #[must_use]
    pub fn is_edge(&self, i: usize) -> bool {
        let (x, y) = (i % self.nx, i / self.nx);
        x == 0 || y == 0 || x == self.nx - 1 || y == self.ny - 1
    }

    /// Drainage area of each cell in cells (itself plus everything upstream).
    #[must_use]
    pub fn area(&self) -> Vec<f32> {
        let mut a = vec![0.0f32; self.receiver.len()];
        self.area_into(&mut a);
        a
    }

    /// [`FlowGraph::area`] into `a` (one value per cell).
    pub(crate) fn area_into(&self, a: &mut [f32]) {
        a.fill(1.0);
        for &i in self.stack.iter().rev() {
            let r = self.receiver[i as usize];
            if r != i {
                a[r as usize] += a[i as usize];
            }
        }
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

    /// Links every closed basin to the edge through its lowest pass; returns whether
    /// any receiver changed. Costs O(cells in closed basins) plus O(b log b)
    /// for b basins: nothing is scanned when no interior pit exists.
    fn route_pits(&mut self, h: &[f32]) -> bool {
        let (nx, n) = (self.nx, self.nx * self.ny);
        let off = nb_offsets(nx);
        // Basin 0 is "the outside" (all edge outlets); pits are numbered from 1
        // in increasing cell order.
        let mut pits: Vec<u32> = vec![u32::MAX]; // pit cell of each basin (index 0 unused)
        pits.extend(
            self.scratch
                .roots
                .iter()
                .copied()
                .filter(|&i| !self.is_edge(i as usize)),
        );
        if pits.len() == 1 {
            return false; // no interior pit: nothing to route
        }
        let StackScratch {
            masks,
            roots,
            basin,
        } = &mut self.scratch;
        if basin.len() != n {
            basin.clear();
            basin.resize(n, 0);
        }
        // Walk each pit's basin over the donor masks (groups of pits in
        // parallel), then label the cells: `cells` lists each basin's cells in
        // pit order.
        let nb_basins = pits.len() - 1;
        let per = nb_basins.div_ceil(64).max(1);
        let masks_ref = &*masks;
        let walks: Vec<Vec<u32>> = par::run(pits[1..].chunks(per).collect(), |group: &[u32]| {
            let mut out = Vec::new();
            let mut work: Vec<u32> = Vec::new();
            for &pit in group {
                // Each basin's cells end with a marker: its pit, flagged.
                work.push(pit);
                while let Some(c) = work.pop() {
                    out.push(c);
                    let mut m = masks_ref[c as usize];
                    while m != 0 {
                        let k = m.trailing_zeros() as usize;
                        m &= m - 1;
                        work.push((c as isize + off[k]) as u32);
                    }
                }
                out.push(u32::MAX);
            }
            out
        });
        let mut cells: Vec<u32> = Vec::new();
        let mut b = 1u32;
        for w in &walks {
            for &c in w {
                if c == u32::MAX {
                    b += 1;
                } else {
                    basin[c as usize] = b;
                    cells.push(c);
                }
            }
        }
        drop(walks);
        // Lowest pass between each pair of adjacent basins: every cell of a
        // closed basin is interior, so all eight neighbours exist. Equal
        // ranges of the basins' cells are scanned in parallel, each keeping
        // its lowest pass per basin pair; the pairs are then merged by
        // sorting, so the result is scheduling-independent (the same passes
        // as a scan of every edge of the grid: a pass is the same seen from
        // either side).
        let per = cells.len().div_ceil(64).max(1);
        let basin_ref = &*basin;
        let found: Vec<Vec<(u32, u32, Pass)>> =
            par::run(cells.chunks(per).collect(), |part: &[u32]| {
                let mut out: Vec<(u32, u32, Pass)> = Vec::new();
                for &c in part {
                    let c = c as usize;
                    let bc = basin_ref[c];
                    for &o in &off {
                        let j = (c as isize + o) as usize;
                        let bj = basin_ref[j];
                        if bj != bc {
                            let p = Pass::new(h[c].max(h[j]), c.min(j) as u32, c.max(j) as u32);
                            out.push((bc.min(bj), bc.max(bj), p));
                        }
                    }
                }
                out.sort_unstable();
                out.dedup_by_key(|e| (e.0, e.1));
                out
            });
        let mut pairs: Vec<(u32, u32, Pass)> = found.concat();
        pairs.sort_unstable();
        pairs.dedup_by_key(|e| (e.0, e.1));
        let mut adjacency: Vec<Vec<(u32, Pass)>> = vec![Vec::new(); pits.len()];
        for &(a, b, p) in &pairs {
            adjacency[a as usize].push((b, p));
            adjacency[b as usize].push((a, p));
        }
        let links = minimax_links(&adjacency);
        // Reverse receivers from the pass cell inside each basin down to its pit,
        // then drain the pass cell across to the neighbouring basin; the donor
        // masks follow every change.
        for (b, p) in links {
            let (inside, outside) = if basin[p.a as usize] == b {
                (p.a, p.b)
            } else {
                (p.b, p.a)
            };
            let pit = pits[b as usize];
            let mut prev = outside;
            let mut cur = inside;
            loop {
                let (c, pv) = (cur as usize, prev as usize);
                let next = self.receiver[c];
                if next != cur {
                    masks[next as usize] &= !nb_bit(next as usize, c, nx);
                }
                masks[pv] |= nb_bit(pv, c, nx);
                self.receiver[c] = prev;
                self.distance[c] = cell_distance(c, pv, nx);
                if cur == pit || next == cur {
                    break;
                }
                prev = cur;
                cur = next;
            }
        }
        for &c in &cells {
            basin[c as usize] = 0;
        }
        // Every pit now drains across its pass: only the edge outlets stay roots.
        let rec = &self.receiver;
        roots.retain(|&i| rec[i as usize] == i);
        true
    }
}

/// Prim's algorithm from the outside (basin 0) over the basin graph: a
/// minimax spanning tree, as `(basin, pass to its parent)` in the order the
/// basins join.
fn minimax_links(adjacency: &[Vec<(u32, Pass)>]) -> Vec<(u32, Pass)> {
    let mut done = vec![false; adjacency.len()];
    let mut heap = BinaryHeap::new();
    done[0] = true;
    for &(b, p) in &adjacency[0] {
        heap.push(std::cmp::Reverse((p, b)));
    }
    let mut links: Vec<(u32, Pass)> = Vec::new();
    while let Some(std::cmp::Reverse((p, b))) = heap.pop() {
        if done[b as usize] {
            continue;
        }
        done[b as usize] = true;
        links.push((b, p));
        for &(c, q) in &adjacency[b as usize] {
            if !done[c as usize] {
                heap.push(std::cmp::Reverse((q, c)));
            }
        }
    }
    links
}

/// Cells that are their own receiver (outlets and pits), in increasing order.
fn find_roots(rec: &[u32], nx: usize, ny: usize, roots: &mut Vec<u32>) {
    let bands = par::reduce_bands(ny, |y0, y1| {
        (y0 * nx..y1 * nx)
            .filter(|&i| rec[i] as usize == i)
            .map(|i| i as u32)
            .collect::<Vec<u32>>()
    });
    roots.clear();
    for b in bands {
        roots.extend_from_slice(&b);
    }
}

/// Donor masks of every cell: bit `k` set when the neighbour at [`NB`]`[k]`
/// has this cell as its receiver. Pure per cell, in parallel over bands.
fn donor_masks_into(rec: &[u32], nx: usize, ny: usize, masks: &mut Vec<u8>) {
    masks.resize(nx * ny, 0);
    par::map_bands(nx, ny, [masks.as_mut_slice()], |y0, y1, [m]| {
        for y in y0..y1 {
            let row = &mut m[(y - y0) * nx..(y - y0 + 1) * nx];
            let general = |x: usize| {
                let i = y * nx + x;
                let mut bits = 0u8;
                for (k, &(dx, dy)) in NB.iter().enumerate() {
                    let (xj, yj) = (x as isize + dx, y as isize + dy);
                    if xj >= 0 && yj >= 0 && (xj as usize) < nx && (yj as usize) < ny {
                        let j = yj as usize * nx + xj as usize;
                        if rec[j] as usize == i {
                            bits |= 1 << k;
                        }
                    }
                }
                bits
            };
            if y == 0 || y + 1 == ny || nx < 3 {
                for (x, v) in row.iter_mut().enumerate() {
                    *v = general(x);
                }
            } else {
                row[0] = general(0);
                row[nx - 1] = general(nx - 1);
                let rows = [
                    &rec[(y - 1) * nx..y * nx],
                    &rec[y * nx..(y + 1) * nx],
                    &rec[(y + 1) * nx..(y + 2) * nx],
                ];
                masks_row(rows, (y * nx) as u32, &mut row[1..nx - 1]);
            }
        }
    });
}

natura_core::simd::multiversion! {
/// Donor masks of the interior cells `1..nx − 1` of a row whose first cell
/// has index `i0`, from the receivers of the rows below, at and above it.
fn masks_row<'a>(rows: [&'a [u32]; 3], i0: u32, out: &'a mut [u8]) {
    let m = out.len();
    let [dn, md, up] = rows;
    let (d0, d1, d2) = (&dn[..m], &dn[1..m + 1], &dn[2..m + 2]);
    let (m0, m2) = (&md[..m], &md[2..m + 2]);
    let (u0, u1, u2) = (&up[..m], &up[1..m + 1], &up[2..m + 2]);
    for x in 0..m {
        let i = i0 + 1 + x as u32;
        out[x] = u8::from(d0[x] == i)
            | u8::from(d1[x] == i) << 1
            | u8::from(d2[x] == i) << 2
            | u8::from(m0[x] == i) << 3
            | u8::from(m2[x] == i) << 4
            | u8::from(u0[x] == i) << 5
            | u8::from(u1[x] == i) << 6
            | u8::from(u2[x] == i) << 7;
    }
}
}

impl FlowGraph {
    /// The original pit routing (labels by following receivers, lowest passes
    /// by a scan of every grid edge into hash maps), the reference for
    /// [`FlowGraph::route_pits`]: the same receivers and distances.
    #[cfg(test)]
    fn route_pits_reference(&mut self, h: &[f32]) -> bool {
        use std::collections::HashMap;
        let (nx, ny) = (self.nx, self.ny);
        let n = nx * ny;
        let mut basin = vec![u32::MAX; n];
        let mut pits: Vec<u32> = vec![u32::MAX];
        for (i, &r) in self.receiver.iter().enumerate() {
            if r as usize == i {
                basin[i] = if self.is_edge(i) {
                    0
                } else {
                    pits.push(i as u32);
                    (pits.len() - 1) as u32
                };
            }
        }
        if pits.len() == 1 {
            return false;
        }
        let mut path = Vec::new();
        for i in 0..n {
            let mut c = i;
            while basin[c] == u32::MAX {
                path.push(c as u32);
                c = self.receiver[c] as usize;
            }
            let b = basin[c];
            for &p in &path {
                basin[p as usize] = b;
            }
            path.clear();
        }
        let mut merged: HashMap<(u32, u32), Pass> = HashMap::new();
        for y in 0..ny {
            for x in 0..nx {
                let i = y * nx + x;
                for &(dx, dy) in &[(1i64, 0i64), (0, 1), (1, 1), (-1, 1)] {
                    let (xj, yj) = (x as i64 + dx, y as i64 + dy);
                    if xj < 0 || yj >= ny as i64 || xj >= nx as i64 {
                        continue;
                    }
                    let j = yj as usize * nx + xj as usize;
                    let (bi, bj) = (basin[i], basin[j]);
                    if bi == bj {
                        continue;
                    }
                    let pass = Pass::new(h[i].max(h[j]), i as u32, j as u32);
                    merged
                        .entry((bi.min(bj), bi.max(bj)))
                        .and_modify(|p| *p = (*p).min(pass))
                        .or_insert(pass);
                }
            }
        }
        let mut adjacency: Vec<Vec<(u32, Pass)>> = vec![Vec::new(); pits.len()];
        let mut keys: Vec<_> = merged.keys().copied().collect();
        keys.sort_unstable();
        for k in keys {
            let p = merged[&k];
            adjacency[k.0 as usize].push((k.1, p));
            adjacency[k.1 as usize].push((k.0, p));
        }
        for (b, p) in minimax_links(&adjacency) {
            let (inside, outside) = if basin[p.a as usize] == b {
                (p.a, p.b)
            } else {
                (p.b, p.a)
            };
            let pit = pits[b as usize];
            let mut prev = outside;
            let mut cur = inside;
            loop {
                let next = self.receiver[cur as usize];
                self.receiver[cur as usize] = prev;
                self.distance[cur as usize] = cell_distance(cur as usize, prev as usize, nx);
                if cur == pit || next == cur {
                    break;
                }
                prev = cur;
                cur = next;
            }
        }
        true
    }
}

/// A candidate pass between two basins: its height and the two cells.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pass {
    z: f32,
    a: u32,
    b: u32,
}

impl Pass {
    fn new(z: f32, a: u32, b: u32) -> Self {
        Self { z, a, b }
    }
}

impl Eq for Pass {}
impl PartialOrd for Pass {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Pass {
    fn cmp(&self, o: &Self) -> Ordering {
        self.z
            .total_cmp(&o.z)
            .then(self.a.cmp(&o.a))
            .then(self.b.cmp(&o.b))
    }
}

fn cell_distance(i: usize, j: usize, nx: usize) -> f32 {
    let (dx, dy) = (
        (i % nx) as i64 - (j % nx) as i64,
        (i / nx) as i64 - (j / nx) as i64,
    );
    if dx != 0 && dy != 0 {
        std::f32::consts::SQRT_2
    } else {
        1.0
    }
}

/// D8 steepest-descent receivers and distances (cells); edge cells are outlets.
#[cfg(test)]
pub(crate) fn d8_receivers(h: &[f32], nx: usize, ny: usize) -> (Vec<u32>, Vec<f32>) {
    let (mut rec, mut dist) = (Vec::new(), Vec::new());
    d8_receivers_into(h, nx, ny, &mut rec, &mut dist);
    (rec, dist)
}

/// D8 steepest-descent receivers and distances (cells) into reusable buffers
/// (resized to `nx × ny`); edge cells are outlets.
pub(crate) fn d8_receivers_into(
    h: &[f32],
    nx: usize,
    ny: usize,
    rec: &mut Vec<u32>,
    dist: &mut Vec<f32>,
) {
    let n = nx * ny;
    rec.resize(n, 0);
    dist.resize(n, 0.0);
    // Receivers and distances of each band of rows in one task.
    let chunk = nx * par::BAND_ROWS;
    let jobs: Vec<_> = rec
        .chunks_mut(chunk.max(1))
        .zip(dist.chunks_mut(chunk.max(1)))
        .enumerate()
        .collect();
    par::run(jobs, |(b, (r, d))| {
        let y0 = b * par::BAND_ROWS;
        for (y, (row, drow)) in (y0..).zip(r.chunks_mut(nx).zip(d.chunks_mut(nx))) {
            let i0 = y * nx;
            if y == 0 || y == ny - 1 || nx < 3 {
                // Edge cells are outlets.
                for (x, v) in row.iter_mut().enumerate() {
                    *v = (i0 + x) as u32;
                }
                drow.fill(0.0);
            } else {
                row[0] = i0 as u32;
                row[nx - 1] = (i0 + nx - 1) as u32;
                drow[0] = 0.0;
                drow[nx - 1] = 0.0;
                d8_row(h, i0 + 1, nx, &mut row[1..nx - 1], &mut drow[1..nx - 1]);
            }
        }
    });
}

natura_core::simd::multiversion! {
/// D8 steepest descent for the interior cells `i0..i0 + out.len()` of one
/// row (all eight neighbours exist), with the distance to the receiver
/// (cells; 0 for a pit) into `dist`: the same divisions and comparisons, in
/// the order of [`D8`], as a per-cell loop (dividing by an axial distance of
/// 1 is the identity), written over row slices so it vectorises.
fn d8_row<'a>(h: &'a [f32], i0: usize, nx: usize, out: &'a mut [u32], dist: &'a mut [f32]) {
    let m = out.len();
    let dist = &mut dist[..m];
    let at = |o: usize| &h[o..o + m];
    let c = at(i0);
    let (e, w, n, s) = (at(i0 + 1), at(i0 - 1), at(i0 + nx), at(i0 - nx));
    let (ne, nw, se, sw) = (at(i0 + nx + 1), at(i0 + nx - 1), at(i0 - nx + 1), at(i0 - nx - 1));
    let r2 = std::f32::consts::SQRT_2;
    let nx32 = nx as u32;
    for x in 0..m {
        let hi = c[x];
        let i = (i0 + x) as u32;
        let mut slope = 0.0f32;
        let mut best = i;
        let mut bd = 0.0f32;
        let mut step = |s: f32, j: u32, d: f32| {
            if s > slope {
                slope = s;
                best = j;
                bd = d;
            }
        };
        step(hi - e[x], i + 1, 1.0);
        step(hi - w[x], i - 1, 1.0);
        step(hi - n[x], i + nx32, 1.0);
        step(hi - s[x], i - nx32, 1.0);
        step((hi - ne[x]) / r2, i + nx32 + 1, r2);
        step((hi - nw[x]) / r2, i + nx32 - 1, r2);
        step((hi - se[x]) / r2, i - nx32 + 1, r2);
        step((hi - sw[x]) / r2, i - nx32 - 1, r2);
        out[x] = best;
        dist[x] = bd;
    }
}
}

/// The stack of receivers `rec` (`nx × ny`) through the graph builder's own
/// path (roots, donor masks, grouped walk), for tests against the reference.
#[cfg(test)]
pub(crate) fn build_stack_into(
    rec: &[u32],
    nx: usize,
    ny: usize,
    stack: &mut Vec<u32>,
    s: &mut StackScratch,
) {
    let mut g = FlowGraph::empty();
    g.nx = nx;
    g.ny = ny;
    g.receiver = rec.to_vec();
    g.scratch = std::mem::take(s);
    find_roots(rec, nx, ny, &mut g.scratch.roots);
    donor_masks_into(rec, nx, ny, &mut g.scratch.masks);
    g.build_stack();
    *stack = std::mem::take(&mut g.stack);
    *s = g.scratch;
}

/// Outlet groups walked in parallel by [`FlowGraph::build_stack`].
const STACK_GROUPS: usize = 64;

/// The original two-pass stack builder, the reference for [`build_stack_into`].
#[cfg(test)]
fn build_stack_reference(rec: &[u32]) -> Vec<u32> {
    let n = rec.len();
    // Donor lists by counting sort.
    let mut count = vec![0u32; n + 1];
    for (i, &r) in rec.iter().enumerate() {
        if r as usize != i {
            count[r as usize + 1] += 1;
        }
    }
    for i in 0..n {
        count[i + 1] += count[i];
    }
    let offset = count.clone();
    let mut fill = count;
    let mut donors = vec![0u32; offset[n] as usize];
    for (i, &r) in rec.iter().enumerate() {
        if r as usize != i {
            donors[fill[r as usize] as usize] = i as u32;
            fill[r as usize] += 1;
        }
    }
    let mut stack = Vec::with_capacity(n);
    let mut todo: Vec<u32> = Vec::new();
    for (i, &r) in rec.iter().enumerate() {
        if r as usize == i {
            todo.push(i as u32);
            while let Some(c) = todo.pop() {
                stack.push(c);
                let c = c as usize;
                todo.extend_from_slice(&donors[offset[c] as usize..offset[c + 1] as usize]);
            }
        }
    }
    stack
}

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

/// Checks a row-major height slice against its stated size, and its values.
fn check_slice(h: &[f32], nx: usize, ny: usize) -> crate::Result<()> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use natura_core::Seed;

    fn rough(n: usize, seed: u64) -> Vec<f32> {
        let s = Seed(seed);
        (0..n * n)
            .map(|i| (s.gaussian2((i % n) as i64, (i / n) as i64) * 10.0) as f32)
            .collect()
    }

    /// The row kernel of the D8 receivers against the per-cell loop over
    /// [`D8`] it replaced, on rough fields with plateaus (ties), odd widths
    /// and thin grids: the same receivers and distances, bit for bit.
    #[test]
    fn d8_row_kernel_equals_per_cell_loop() {
        for (nx, ny, seed) in [
            (37usize, 29usize, 1u64),
            (3, 17, 2),
            (130, 5, 3),
            (64, 64, 4),
        ] {
            let s = Seed(seed);
            // Quantised heights: many exact ties between neighbours.
            let h: Vec<f32> = (0..nx * ny)
                .map(|i| (8.0 * s.uniform2((i % nx) as i64, (i / nx) as i64)).floor() as f32)
                .collect();
            let (rec, dist) = d8_receivers(&h, nx, ny);
            for y in 0..ny {
                for x in 0..nx {
                    let i = y * nx + x;
                    let mut best = i;
                    if x > 0 && y > 0 && x < nx - 1 && y < ny - 1 {
                        let mut slope = 0.0f32;
                        for &(dx, dy, d) in &D8 {
                            let j = (i as i64 + i64::from(dy) * nx as i64 + i64::from(dx)) as usize;
                            let sl = (h[i] - h[j]) / d;
                            if sl > slope {
                                slope = sl;
                                best = j;
                            }
                        }
                    }
                    assert_eq!(rec[i] as usize, best, "{nx}×{ny}: cell ({x}, {y})");
                    let want = if best == i {
                        0.0
                    } else if best % nx == x || best / nx == y {
                        1.0
                    } else {
                        std::f32::consts::SQRT_2
                    };
                    assert_eq!(dist[i], want);
                }
            }
        }
    }

    /// The vectorised receivers and distances against the per-cell loop over
    /// [`D8`] on continuous random fields and on plateaus (large flat blocks
    /// and steps of one value: ties everywhere, flat pits), row widths that
    /// leave every SIMD tail length.
    #[test]
    fn d8_row_kernel_equals_per_cell_loop_on_plateaus() {
        for (nx, ny, seed) in [(40usize, 23usize, 5u64), (53, 19, 6), (18, 34, 7)] {
            let s = Seed(seed);
            let fields: [Vec<f32>; 2] = [
                (0..nx * ny)
                    .map(|i| (50.0 * s.gaussian2((i % nx) as i64, (i / nx) as i64)) as f32)
                    .collect(),
                (0..nx * ny)
                    .map(|i| {
                        let (x, y) = ((i % nx) as i64 / 5, (i / nx) as i64 / 4);
                        (2.0 * s.uniform2(x, y)).floor() as f32
                    })
                    .collect(),
            ];
            for h in &fields {
                let (rec, dist) = d8_receivers(h, nx, ny);
                for y in 0..ny {
                    for x in 0..nx {
                        let i = y * nx + x;
                        let (mut best, mut bd) = (i, 0.0f32);
                        if x > 0 && y > 0 && x < nx - 1 && y < ny - 1 {
                            let mut slope = 0.0f32;
                            for &(dx, dy, d) in &D8 {
                                let j =
                                    (i as i64 + i64::from(dy) * nx as i64 + i64::from(dx)) as usize;
                                let sl = (h[i] - h[j]) / d;
                                if sl > slope {
                                    (slope, best, bd) = (sl, j, d);
                                }
                            }
                        }
                        assert_eq!(rec[i] as usize, best, "{nx}×{ny}: cell ({x}, {y})");
                        assert_eq!(dist[i].to_bits(), bd.to_bits(), "{nx}×{ny}: ({x}, {y})");
                    }
                }
            }
        }
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn every_cell_reaches_the_edge_after_routing_and_fill() {
        for seed in 0..5 {
            let n = 48;
            for mode in [Depressions::Route, Depressions::Fill] {
                let mut h = rough(n, seed);
                let g = FlowGraph::build(&mut h, n, n, mode).unwrap();
                assert_eq!(g.stack.len(), n * n);
                for i in 0..n * n {
                    assert!(g.is_edge(g.terminus(i)), "{mode:?}: cell {i} ends in a pit");
                }
                if mode == Depressions::Fill {
                    // The filled surface itself has no pits, and its levels match Priority-Flood's spill levels.
                    let (rec, _) = d8_receivers(&h, n, n);
                    for i in 0..n * n {
                        let x = i % n;
                        let y = i / n;
                        let edge = x == 0 || y == 0 || x == n - 1 || y == n - 1;
                        assert!(edge || rec[i] as usize != i, "pit at {i} after fill");
                    }
                    let orig = rough(n, seed);
                    let pf = priority_flood_levels(&orig, n, n).unwrap();
                    for i in 0..n * n {
                        assert!(
                            h[i] >= pf[i] && h[i] <= pf[i] + 0.05,
                            "cell {i}: {} vs spill {}",
                            h[i],
                            pf[i]
                        );
                    }
                }
            }
        }
    }

    /// The buffer-reusing stack builder against the original one, on raw D8
    /// graphs (with pits) and routed ones, reusing one scratch across sizes;
    /// and a rebuilt graph against a fresh one.
    #[test]
    fn reused_stack_equals_reference() {
        let mut stack = Vec::new();
        let mut scratch = StackScratch::default();
        for (seed, n) in [(1u64, 40usize), (2, 7), (3, 64), (4, 3)] {
            let h = rough(n, seed);
            let (rec, _) = d8_receivers(&h, n, n);
            build_stack_into(&rec, n, n, &mut stack, &mut scratch);
            assert_eq!(stack, build_stack_reference(&rec), "raw D8, n = {n}");
            let mut hr = h.clone();
            let g = FlowGraph::build(&mut hr, n, n, Depressions::Route).unwrap();
            build_stack_into(&g.receiver, n, n, &mut stack, &mut scratch);
            assert_eq!(stack, build_stack_reference(&g.receiver), "routed, n = {n}");
            assert_eq!(g.stack, stack);
        }
        let mut reused = FlowGraph::build(&mut rough(40, 8), 40, 40, Depressions::Fill).unwrap();
        for seed in [5u64, 6] {
            let (mut a, mut b) = (rough(40, seed), rough(40, seed));
            reused.rebuild(&mut a, 40, 40, Depressions::Fill);
            let fresh = FlowGraph::build(&mut b, 40, 40, Depressions::Fill).unwrap();
            assert_eq!(a, b);
            assert_eq!(reused.receiver, fresh.receiver);
            assert_eq!(reused.distance, fresh.distance);
            assert_eq!(reused.stack, fresh.stack);
        }
    }

    /// Pit routing over donor masks and per-basin pass lists against the
    /// original (receiver-following labels, a hash map over every grid edge),
    /// on rough fields with many pits, quantised fields (ties between passes)
    /// and thin grids: the same receivers and distances; and the group
    /// bounds and receiver positions of the stack agree with the stack.
    #[test]
    fn routing_equals_reference_routing() {
        for (nx, ny, seed, quantised) in [
            (48usize, 48usize, 1u64, false),
            (64, 33, 2, true),
            (5, 70, 3, false),
            (129, 4, 4, true),
            (97, 101, 5, false),
        ] {
            let s = Seed(seed);
            let h: Vec<f32> = (0..nx * ny)
                .map(|i| {
                    let v = 10.0 * s.gaussian2((i % nx) as i64, (i / nx) as i64);
                    (if quantised { v.floor() } else { v }) as f32
                })
                .collect();
            let g = FlowGraph::build(&mut h.clone(), nx, ny, Depressions::Route).unwrap();
            let mut r = FlowGraph::empty();
            r.nx = nx;
            r.ny = ny;
            d8_receivers_into(&h, nx, ny, &mut r.receiver, &mut r.distance);
            let pits = (0..nx * ny)
                .filter(|&i| r.receiver[i] as usize == i && !r.is_edge(i))
                .count();
            assert!(nx < 8 || ny < 8 || pits > 3, "{nx}×{ny}: only {pits} pits");
            r.route_pits_reference(&h);
            assert_eq!(g.receiver, r.receiver, "{nx}×{ny} seed {seed}");
            assert_eq!(g.distance, r.distance, "{nx}×{ny} seed {seed}");
            assert_eq!(g.stack, build_stack_reference(&g.receiver));
            assert_eq!(g.groups.first(), Some(&0));
            assert_eq!(g.groups.last(), Some(&(nx * ny)));
            for w in g.groups.windows(2) {
                for k in w[0]..w[1] {
                    let rp = w[0] + g.rpos[k] as usize;
                    assert!(rp < w[1] && rp <= k);
                    assert_eq!(g.stack[rp], g.receiver[g.stack[k] as usize]);
                }
            }
        }
    }

    #[test]
    fn stack_puts_receivers_first_and_area_sums() {
        let n = 32;
        let mut h = rough(n, 9);
        let g = FlowGraph::build(&mut h, n, n, Depressions::Route).unwrap();
        let mut pos = vec![0usize; n * n];
        for (k, &i) in g.stack.iter().enumerate() {
            pos[i as usize] = k;
        }
        for i in 0..n * n {
            assert!(pos[g.receiver[i] as usize] <= pos[i]);
        }
        let a = g.area();
        let outlets: f32 = (0..n * n)
            .filter(|&i| g.receiver[i] as usize == i)
            .map(|i| a[i])
            .sum();
        assert_eq!(outlets, (n * n) as f32);
    }
}
