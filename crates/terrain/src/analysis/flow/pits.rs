//! Depression routing: every closed basin linked to the edge through its
//! lowest pass by a minimax spanning tree over the basin graph (Cordonnier
//! et al. 2019), receivers reversed along the path from the pass to
//! the pit.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::receivers::{cell_distance, nb_bit, nb_offsets};
use super::{FlowGraph, StackScratch};
use crate::bands;

impl FlowGraph {
    /// Links every closed basin to the edge through its lowest pass; returns whether
    /// any receiver changed. Costs O(cells in closed basins) plus O(b log b)
    /// for b basins: nothing is scanned when no interior pit exists.
    pub(super) fn route_pits(&mut self, h: &[f32]) -> bool {
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
        let cells = label_basins(masks, &pits, &off, basin);
        let adjacency = basin_graph(&cells, basin, h, &off, pits.len());
        // Reverse receivers from the pass cell inside each basin down to its pit,
        // then drain the pass cell across to the neighbouring basin; the donor
        // masks follow every change.
        for (b, p) in minimax_links(&adjacency) {
            let (inside, outside) = if basin[p.a as usize] == b {
                (p.a, p.b)
            } else {
                (p.b, p.a)
            };
            let path = Path {
                pit: pits[b as usize],
                inside,
                outside,
            };
            path.reverse(&mut self.receiver, &mut self.distance, masks, nx);
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

/// Walks each pit's basin over the donor `masks` (groups of pits in
/// parallel) and labels its cells in `basin` with the pit's number; returns
/// each basin's cells in pit order.
fn label_basins(masks: &[u8], pits: &[u32], off: &[isize; 8], basin: &mut [u32]) -> Vec<u32> {
    let nb_basins = pits.len() - 1;
    let per = nb_basins.div_ceil(64).max(1);
    let walks: Vec<Vec<u32>> = bands::run(pits[1..].chunks(per).collect(), |group: &[u32]| {
        let mut out = Vec::new();
        let mut work: Vec<u32> = Vec::new();
        for &pit in group {
            // Each basin's cells end with a marker: its pit, flagged.
            work.push(pit);
            while let Some(c) = work.pop() {
                out.push(c);
                let mut m = masks[c as usize];
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
    cells
}

/// The basin graph: for each of `nb_basins` basins, its neighbours and the
/// lowest pass to each. Every cell of a closed basin is interior, so all
/// eight neighbours exist. Equal ranges of the basins' `cells` are scanned
/// in parallel, each keeping its lowest pass per basin pair; the pairs are
/// then merged by sorting, so the result is scheduling-independent (the
/// same passes as a scan of every edge of the grid: a pass is the same seen
/// from either side).
fn basin_graph(
    cells: &[u32],
    basin: &[u32],
    h: &[f32],
    off: &[isize; 8],
    nb_basins: usize,
) -> Vec<Vec<(u32, Pass)>> {
    let per = cells.len().div_ceil(64).max(1);
    let found: Vec<Vec<(u32, u32, Pass)>> =
        bands::run(cells.chunks(per).collect(), |part: &[u32]| {
            let mut out: Vec<(u32, u32, Pass)> = Vec::new();
            // A basin's cells come one after another: its lowest pass to
            // each neighbouring basin is kept as they are scanned, so only
            // those (not every boundary edge) are sorted.
            let mut best = Neighbours::default();
            for &c in part {
                let c = c as usize;
                let bc = basin[c];
                if bc != best.basin {
                    best.flush(&mut out);
                    best.basin = bc;
                }
                for &o in off {
                    let j = (c as isize + o) as usize;
                    let bj = basin[j];
                    if bj != bc {
                        let p = Pass::new(h[c].max(h[j]), c.min(j) as u32, c.max(j) as u32);
                        best.offer(bj, p, &mut out);
                    }
                }
            }
            best.flush(&mut out);
            out.sort_unstable();
            out.dedup_by_key(|e| (e.0, e.1));
            out
        });
    let mut pairs: Vec<(u32, u32, Pass)> = found.concat();
    pairs.sort_unstable();
    pairs.dedup_by_key(|e| (e.0, e.1));
    let mut adjacency: Vec<Vec<(u32, Pass)>> = vec![Vec::new(); nb_basins];
    for &(a, b, p) in &pairs {
        adjacency[a as usize].push((b, p));
        adjacency[b as usize].push((a, p));
    }
    adjacency
}

/// The lowest pass found so far from one basin to each of its neighbours.
#[derive(Default)]
struct Neighbours {
    basin: u32,
    lowest: Vec<(u32, Pass)>,
}

impl Neighbours {
    /// The most neighbours kept; passes to further basins go straight to
    /// the output (the sort there keeps the lowest all the same).
    const MAX: usize = 32;

    /// A pass from this basin to basin `other`.
    #[inline]
    fn offer(&mut self, other: u32, p: Pass, out: &mut Vec<(u32, u32, Pass)>) {
        if let Some(e) = self.lowest.iter_mut().find(|e| e.0 == other) {
            if p < e.1 {
                e.1 = p;
            }
        } else if self.lowest.len() < Self::MAX {
            self.lowest.push((other, p));
        } else {
            out.push((self.basin.min(other), self.basin.max(other), p));
        }
    }

    /// Moves the passes kept to `out` as `(lower basin, higher basin, pass)`.
    fn flush(&mut self, out: &mut Vec<(u32, u32, Pass)>) {
        let b = self.basin;
        out.extend(self.lowest.drain(..).map(|(o, p)| (b.min(o), b.max(o), p)));
    }
}

/// The receiver path a basin's link reverses: from the pass cell `inside`
/// the basin down to its `pit`, the pass cell then draining to `outside`.
struct Path {
    pit: u32,
    inside: u32,
    outside: u32,
}

impl Path {
    /// Reverses the receivers along the path (each cell now drains to the
    /// one it received from, the pass cell to `outside`), updating the
    /// distances and the donor masks.
    fn reverse(&self, receiver: &mut [u32], distance: &mut [f32], masks: &mut [u8], nx: usize) {
        let mut prev = self.outside;
        let mut cur = self.inside;
        loop {
            let (c, pv) = (cur as usize, prev as usize);
            let next = receiver[c];
            if next != cur {
                masks[next as usize] &= !nb_bit(next as usize, c, nx);
            }
            masks[pv] |= nb_bit(pv, c, nx);
            receiver[c] = prev;
            distance[c] = cell_distance(c, pv, nx);
            if cur == self.pit || next == cur {
                break;
            }
            prev = cur;
            cur = next;
        }
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

impl FlowGraph {
    /// The original pit routing (labels by following receivers, lowest passes
    /// by a scan of every grid edge into hash maps), the reference for
    /// [`FlowGraph::route_pits`]: the same receivers and distances.
    #[cfg(test)]
    pub(super) fn route_pits_reference(&mut self, h: &[f32]) -> bool {
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
