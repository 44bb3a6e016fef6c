use super::receivers::{d8_receivers, donor_masks_into};
use super::stack::{build_stack_into, build_stack_reference};
use super::*;
use natura_core::Seed;
use natura_core::simd::Simd;

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

/// The receiver and donor-mask row kernels give the same bits at every
/// instruction set this CPU supports as at the widest (which the tests above
/// hold to the per-cell loops), on rough fields, plateaus and thin grids.
#[test]
fn flow_kernels_agree_at_every_level() {
    for (nx, ny, seed) in [(37usize, 29usize, 11u64), (3, 17, 12), (131, 6, 13)] {
        let s = Seed(seed);
        let h: Vec<f32> = (0..nx * ny)
            .map(|i| (8.0 * s.uniform2((i % nx) as i64, (i / nx) as i64)).floor() as f32)
            .collect();
        let at = |simd: Simd| {
            let (mut rec, mut dist, mut masks) = (Vec::new(), Vec::new(), Vec::new());
            d8_receivers_into(simd, &h, nx, ny, &mut rec, &mut dist);
            donor_masks_into(simd, &rec, nx, ny, &mut masks);
            (
                rec,
                dist.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
                masks,
            )
        };
        let best = at(Simd::best());
        for simd in Simd::supported() {
            assert_eq!(at(simd), best, "{nx}×{ny} at {}", simd.level().name());
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
                            let j = (i as i64 + i64::from(dy) * nx as i64 + i64::from(dx)) as usize;
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
        d8_receivers_into(Simd::best(), &h, nx, ny, &mut r.receiver, &mut r.distance);
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
