//! Band-parallel helpers: split output grids into horizontal bands of a fixed
//! number of rows and run a kernel on each band, in parallel with the
//! `parallel` feature and serially without it.
//!
//! Band boundaries depend only on the grid size (never on the thread count)
//! and per-band results come back in band order, so every caller is
//! bit-identical on any number of threads.

/// Rows per band: small enough to balance two to many cores, large enough to
/// amortise scheduling.
pub(crate) const BAND_ROWS: usize = 16;

/// Runs `f(y0, y1, outs)` for every band `[y0, y1)` of rows, where `outs[k]`
/// is the band's rows of output `k` (each output is `width × height`, row
/// major). Returns the per-band results in band order.
pub(crate) fn map_bands<T, R, const K: usize, F>(
    width: usize,
    height: usize,
    outs: [&mut [T]; K],
    f: F,
) -> Vec<R>
where
    T: Send,
    R: Send,
    F: Fn(usize, usize, &mut [&mut [T]; K]) -> R + Sync + Send,
{
    let chunk = width * BAND_ROWS;
    let nbands = height.div_ceil(BAND_ROWS);
    let mut iters = outs.map(|o| {
        debug_assert_eq!(o.len(), width * height);
        o.chunks_mut(chunk.max(1))
    });
    let mut jobs = Vec::with_capacity(nbands);
    for b in 0..nbands {
        let arr: [&mut [T]; K] = std::array::from_fn(|k| iters[k].next().unwrap_or_default());
        let y0 = b * BAND_ROWS;
        jobs.push((y0, (y0 + BAND_ROWS).min(height), arr));
    }
    run(jobs, |(y0, y1, mut arr)| f(y0, y1, &mut arr))
}

/// Runs `f` over the bands of a read-only pass and returns per-band results in order.
pub(crate) fn reduce_bands<R, F>(height: usize, f: F) -> Vec<R>
where
    R: Send,
    F: Fn(usize, usize) -> R + Sync + Send,
{
    let nbands = height.div_ceil(BAND_ROWS);
    let jobs: Vec<(usize, usize)> = (0..nbands)
        .map(|b| (b * BAND_ROWS, ((b + 1) * BAND_ROWS).min(height)))
        .collect();
    run(jobs, |(y0, y1)| f(y0, y1))
}

/// Maps `f` over `items`, in parallel with the `parallel` feature, keeping order.
pub(crate) fn run<I, R, F>(items: Vec<I>, f: F) -> Vec<R>
where
    I: Send,
    R: Send,
    F: Fn(I) -> R + Sync + Send,
{
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        items.into_par_iter().map(f).collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        items.into_iter().map(f).collect()
    }
}

/// Sums `f64` values in a fixed (pairwise-blocked) order.
pub(crate) fn sum_f32(v: &[f32]) -> f64 {
    v.chunks(4096)
        .map(|c| c.iter().map(|&x| f64::from(x)).sum::<f64>())
        .sum()
}
