//! Order-preserving parallel map (rayon behind the `parallel` feature).
//!
//! Every item is a pure function of its index, and `collect` keeps index
//! order, so results are bit-identical on any number of threads.

/// Returns `[f(0), f(1), …, f(n − 1)]`, computed in parallel when the `parallel` feature is on.
pub(crate) fn map<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        (0..n).into_par_iter().with_min_len(2048).map(f).collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        (0..n).map(f).collect()
    }
}
