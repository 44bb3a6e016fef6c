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
use std::collections::{BinaryHeap, HashMap};

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
    scratch: StackScratch,
}

/// Reusable buffers of [`build_stack_into`].
#[derive(Clone, Debug, Default)]
pub(crate) struct StackScratch {
    offsets: Vec<u32>,
    donors: Vec<u32>,
    todo: Vec<u32>,
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
    pub fn build(h: &mut [f32], nx: usize, ny: usize, depressions: Depressions) -> Self {
        let mut g = Self::empty();
        g.rebuild(h, nx, ny, depressions);
        g
    }

    /// A graph of no cells, whose buffers [`FlowGraph::rebuild`] grows.
    pub(crate) fn empty() -> Self {
        FlowGraph {
            nx: 0,
            ny: 0,
            receiver: Vec::new(),
            distance: Vec::new(),
            stack: Vec::new(),
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
        self.nx = nx;
        self.ny = ny;
        d8_receivers_into(h, nx, ny, &mut self.receiver, &mut self.distance);
        // Pits are routed on the raw receivers (labelling needs no stack), so
        // the stack is built once, on the final receivers.
        if depressions != Depressions::Keep {
            self.route_pits(h);
        }
        build_stack_into(&self.receiver, &mut self.stack, &mut self.scratch);
        if depressions == Depressions::Fill {
            fill_along(h, &self.receiver, &self.stack, filled);
        }
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
    /// any receiver changed.
    fn route_pits(&mut self, h: &[f32]) -> bool {
        let (nx, ny) = (self.nx, self.ny);
        let n = nx * ny;
        // Basin labels; basin 0 is "the outside" (all edge outlets), pits are
        // numbered in increasing cell order. Receivers are strictly downhill
        // here (no cycles), so every path ends at a root.
        let mut basin = std::mem::take(&mut self.scratch.basin);
        basin.clear();
        basin.resize(n, u32::MAX);
        let mut pits: Vec<u32> = vec![u32::MAX]; // pit cell of each basin (index 0 unused)
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
            self.scratch.basin = basin;
            return false; // no interior pit: nothing to route
        }
        // Follow each unlabelled cell's receivers to a labelled one and label the path.
        let mut path = std::mem::take(&mut self.scratch.todo);
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
        self.scratch.todo = path;
        // Lowest pass between each pair of adjacent basins, found per band and
        // merged with a total order, so the result is scheduling-independent.
        let basin_ref = &basin;
        let band_maps: Vec<HashMap<(u32, u32), Pass>> = par::reduce_bands(ny, |y0, y1| {
            let mut m: HashMap<(u32, u32), Pass> = HashMap::new();
            for y in y0..y1 {
                for x in 0..nx {
                    let i = y * nx + x;
                    for &(dx, dy) in &[(1i32, 0i32), (0, 1), (1, 1), (-1, 1)] {
                        let (xj, yj) = (x as i64 + i64::from(dx), y as i64 + i64::from(dy));
                        if xj < 0 || yj >= ny as i64 || xj >= nx as i64 {
                            continue;
                        }
                        let j = yj as usize * nx + xj as usize;
                        let (bi, bj) = (basin_ref[i], basin_ref[j]);
                        if bi == bj {
                            continue;
                        }
                        let pass = Pass::new(h[i].max(h[j]), i as u32, j as u32);
                        let key = (bi.min(bj), bi.max(bj));
                        m.entry(key)
                            .and_modify(|p| *p = (*p).min(pass))
                            .or_insert(pass);
                    }
                }
            }
            m
        });
        let mut adjacency: Vec<Vec<(u32, Pass)>> = vec![Vec::new(); pits.len()];
        let mut merged: HashMap<(u32, u32), Pass> = HashMap::new();
        for m in band_maps {
            for (k, p) in m {
                merged
                    .entry(k)
                    .and_modify(|q| *q = (*q).min(p))
                    .or_insert(p);
            }
        }
        let mut keys: Vec<_> = merged.keys().copied().collect();
        keys.sort_unstable();
        for k in keys {
            let p = merged[&k];
            adjacency[k.0 as usize].push((k.1, p));
            adjacency[k.1 as usize].push((k.0, p));
        }
        // Prim's algorithm from the outside: a minimax spanning tree.
        let mut done = vec![false; pits.len()];
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
        // Reverse receivers from the pass cell inside each basin down to its pit,
        // then drain the pass cell across to the neighbouring basin.
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
        self.scratch.basin = basin;
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
    par::map_bands(nx, ny, [rec.as_mut_slice()], |y0, y1, [r]| {
        for y in y0..y1 {
            let row = &mut r[(y - y0) * nx..(y - y0 + 1) * nx];
            let i0 = y * nx;
            // Edge cells are outlets.
            row[0] = i0 as u32;
            row[nx - 1] = (i0 + nx - 1) as u32;
            if y == 0 || y == ny - 1 || nx < 3 {
                for (x, v) in row.iter_mut().enumerate() {
                    *v = (i0 + x) as u32;
                }
            } else {
                d8_row(h, i0 + 1, nx, &mut row[1..nx - 1]);
            }
        }
    });
    // Distances in parallel too: the receiver is a neighbour (or the cell itself).
    par::map_bands(nx, ny, [dist.as_mut_slice()], |y0, _y1, [d]| {
        let base = y0 * nx;
        for (k, d) in d.iter_mut().enumerate() {
            let i = base + k;
            let r = rec[i] as usize;
            *d = if r == i {
                0.0
            } else if r + 1 == i || i + 1 == r || r + nx == i || i + nx == r {
                1.0
            } else {
                std::f32::consts::SQRT_2
            };
        }
    });
}

crate::simd::multiversion! {
/// D8 steepest descent for the interior cells `i0..i0 + out.len()` of one
/// row (all eight neighbours exist): the same divisions and comparisons, in
/// the order of [`D8`], as a per-cell loop (dividing by an axial distance of
/// 1 is the identity), written over row slices so it vectorises.
fn d8_row<'a>(h: &'a [f32], i0: usize, nx: usize, out: &'a mut [u32]) {
    let m = out.len();
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
        let mut step = |s: f32, j: u32| {
            if s > slope {
                slope = s;
                best = j;
            }
        };
        step(hi - e[x], i + 1);
        step(hi - w[x], i - 1);
        step(hi - n[x], i + nx32);
        step(hi - s[x], i - nx32);
        step((hi - ne[x]) / r2, i + nx32 + 1);
        step((hi - nw[x]) / r2, i + nx32 - 1);
        step((hi - se[x]) / r2, i - nx32 + 1);
        step((hi - sw[x]) / r2, i - nx32 - 1);
        out[x] = best;
    }
}
}

/// Braun & Willett's stack (outlets and pits first, each followed
/// depth-first by its donors) into reusable buffers: donor lists by a counting sort
/// (donors of each cell in increasing index order), then an iterative
/// depth-first walk from every outlet. O(n).
pub(crate) fn build_stack_into(rec: &[u32], stack: &mut Vec<u32>, s: &mut StackScratch) {
    let n = rec.len();
    let StackScratch {
        offsets,
        donors,
        todo,
        ..
    } = s;
    // offsets[r] counts r's donors, then (inclusive prefix sum) marks the end of
    // its group; filling backwards moves it to the group's start, and
    // offsets[r + 1] (the next group's start) is its end.
    offsets.clear();
    offsets.resize(n + 1, 0);
    for (i, &r) in rec.iter().enumerate() {
        if r as usize != i {
            offsets[r as usize] += 1;
        }
    }
    let mut acc = 0u32;
    for o in offsets.iter_mut().take(n) {
        acc += *o;
        *o = acc;
    }
    offsets[n] = acc;
    donors.clear();
    donors.resize(acc as usize, 0);
    for (i, &r) in rec.iter().enumerate().rev() {
        if r as usize != i {
            offsets[r as usize] -= 1;
            donors[offsets[r as usize] as usize] = i as u32;
        }
    }
    // The trees of different outlets are disjoint: walk groups of outlets
    // (consecutive in index order, a fixed number per group) in parallel and
    // concatenate their stacks in group order — the same stack as one walk.
    todo.clear();
    todo.extend((0..n as u32).filter(|&i| rec[i as usize] == i));
    let per = todo.len().div_ceil(STACK_GROUPS).max(1);
    let (offsets, donors) = (&*offsets, &*donors);
    let parts: Vec<Vec<u32>> = par::run(todo.chunks(per).collect(), |roots: &[u32]| {
        let mut part = Vec::new();
        let mut work = Vec::new();
        for &root in roots {
            work.push(root);
            while let Some(c) = work.pop() {
                part.push(c);
                let c = c as usize;
                // A cell has at most 8 donors: push them one by one (a
                // `memcpy` call per cell costs more than the copy).
                for &d in &donors[offsets[c] as usize..offsets[c + 1] as usize] {
                    work.push(d);
                }
            }
        }
        part
    });
    stack.clear();
    stack.reserve(n);
    for part in parts {
        stack.extend_from_slice(&part);
    }
}

/// Outlet groups walked in parallel by [`build_stack_into`].
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
pub fn fill_depressions(hf: &HeightField) -> crate::Result<(HeightField, Grid2<f32>)> {
    hf.check_finite()?;
    let (nx, ny) = (hf.nx(), hf.ny());
    let mut h = hf.heights().as_slice().to_vec();
    FlowGraph::build(&mut h, nx, ny, Depressions::Fill);
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
#[must_use]
pub fn priority_flood_levels(h: &[f32], nx: usize, ny: usize) -> Vec<f32> {
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
    out
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

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn every_cell_reaches_the_edge_after_routing_and_fill() {
        for seed in 0..5 {
            let n = 48;
            for mode in [Depressions::Route, Depressions::Fill] {
                let mut h = rough(n, seed);
                let g = FlowGraph::build(&mut h, n, n, mode);
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
                    let pf = priority_flood_levels(&orig, n, n);
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
            build_stack_into(&rec, &mut stack, &mut scratch);
            assert_eq!(stack, build_stack_reference(&rec), "raw D8, n = {n}");
            let mut hr = h.clone();
            let g = FlowGraph::build(&mut hr, n, n, Depressions::Route);
            build_stack_into(&g.receiver, &mut stack, &mut scratch);
            assert_eq!(stack, build_stack_reference(&g.receiver), "routed, n = {n}");
            assert_eq!(g.stack, stack);
        }
        let mut reused = FlowGraph::build(&mut rough(40, 8), 40, 40, Depressions::Fill);
        for seed in [5u64, 6] {
            let (mut a, mut b) = (rough(40, seed), rough(40, seed));
            reused.rebuild(&mut a, 40, 40, Depressions::Fill);
            let fresh = FlowGraph::build(&mut b, 40, 40, Depressions::Fill);
            assert_eq!(a, b);
            assert_eq!(reused.receiver, fresh.receiver);
            assert_eq!(reused.distance, fresh.distance);
            assert_eq!(reused.stack, fresh.stack);
        }
    }

    #[test]
    fn stack_puts_receivers_first_and_area_sums() {
        let n = 32;
        let mut h = rough(n, 9);
        let g = FlowGraph::build(&mut h, n, n, Depressions::Route);
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
