//! Braun & Willett 2013's stack order: receivers before their donors,
//! grouped into independent drainage trees, and the drainage area
//! accumulated along it.

use super::FlowGraph;
use super::receivers::nb_offsets;
#[cfg(test)]
use super::{
    StackScratch,
    receivers::{donor_masks_into, find_roots},
};
use crate::bands;
#[cfg(test)]
use natura_core::simd::Simd;

impl FlowGraph {
    /// Braun & Willett's stack (outlets and pits first, each followed
    /// depth-first by its donors, visited in increasing index order) from the
    /// roots and donor masks: groups of consecutive roots are walked in
    /// parallel and concatenated in order (the same stack as one walk), and
    /// the group bounds and each entry's receiver position are kept for the
    /// group-parallel passes. O(n).
    pub(super) fn build_stack(&mut self) {
        let n = self.receiver.len();
        let off = nb_offsets(self.nx);
        let roots = &self.scratch.roots;
        let masks = &self.scratch.masks;
        let per = roots.len().div_ceil(STACK_GROUPS).max(1);
        let parts: Vec<(Vec<u32>, Vec<u32>)> =
            bands::run(roots.chunks(per).collect(), |roots: &[u32]| {
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
        bands::run(jobs, |(a, c, (p, r))| {
            a.copy_from_slice(&p);
            c.copy_from_slice(&r);
        });
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
}

/// The stack of receivers `rec` (`nx × ny`) through the graph builder's own
/// path (roots, donor masks, grouped walk), for tests against the reference.
#[cfg(test)]
pub(super) fn build_stack_into(
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
    donor_masks_into(Simd::best(), rec, nx, ny, &mut g.scratch.masks);
    g.build_stack();
    *stack = std::mem::take(&mut g.stack);
    *s = g.scratch;
}

/// Outlet groups walked in parallel by [`FlowGraph::build_stack`].
const STACK_GROUPS: usize = 64;

/// The original two-pass stack builder, the reference for [`build_stack_into`].
#[cfg(test)]
pub(super) fn build_stack_reference(rec: &[u32]) -> Vec<u32> {
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
