//! Order-preserving parallel helpers (rayon behind the `parallel` feature).
//!
//! Every item is a pure function of its index (or of itself) and results keep
//! index order, so results are bit-identical on any number of threads.

/// Items per task: enough work per task to pay for the scheduling.
#[cfg(feature = "parallel")]
const MIN_LEN: usize = 2048;

/// Returns `[f(0), f(1), …, f(n − 1)]`, computed in parallel when the `parallel` feature is on.
pub(crate) fn map<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        (0..n)
            .into_par_iter()
            .with_min_len(MIN_LEN)
            .map(f)
            .collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        (0..n).map(f).collect()
    }
}

/// Applies `f(i, &mut v[i])` to every item of `v`.
pub(crate) fn for_each_mut<T: Send>(v: &mut [T], f: impl Fn(usize, &mut T) + Sync + Send) {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        v.par_iter_mut()
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(i, p)| f(i, p));
    }
    #[cfg(not(feature = "parallel"))]
    {
        v.iter_mut().enumerate().for_each(|(i, p)| f(i, p));
    }
}

/// Keeps the items `i` of `v` for which `keep(i, &v[i])` holds, in order
/// (a parallel `retain`: counts per block, then each block copies its kept
/// items into its own slice of the result).
pub(crate) fn retain<T: Copy + Send + Sync>(
    v: &mut Vec<T>,
    keep: impl Fn(usize, &T) -> bool + Sync + Send,
) {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        const BLOCK: usize = 1 << 14;
        if v.len() <= BLOCK {
            let mut k = 0;
            v.retain(|p| {
                k += 1;
                keep(k - 1, p)
            });
            return;
        }
        let flags: Vec<bool> = v
            .par_iter()
            .enumerate()
            .with_min_len(MIN_LEN)
            .map(|(i, p)| keep(i, p))
            .collect();
        let counts: Vec<usize> = flags
            .par_chunks(BLOCK)
            .map(|c| c.iter().filter(|&&f| f).count())
            .collect();
        let total = counts.iter().sum();
        let Some(&first) = v.first() else { return };
        let mut out = vec![first; total];
        let mut rest = out.as_mut_slice();
        let mut parts = Vec::with_capacity(counts.len());
        for &c in &counts {
            let (head, tail) = rest.split_at_mut(c);
            parts.push(head);
            rest = tail;
        }
        parts
            .into_par_iter()
            .zip(v.par_chunks(BLOCK).zip(flags.par_chunks(BLOCK)))
            .for_each(|(dst, (src, fl))| {
                let kept = src.iter().zip(fl).filter(|(_, f)| **f).map(|(p, _)| *p);
                for (d, s) in dst.iter_mut().zip(kept) {
                    *d = s;
                }
            });
        *v = out;
    }
    #[cfg(not(feature = "parallel"))]
    {
        let mut k = 0;
        v.retain(|p| {
            k += 1;
            keep(k - 1, p)
        });
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn retain_keeps_order_like_vec_retain() {
        for n in [0usize, 1, 100, 40_000, 100_003] {
            let v: Vec<u32> = (0..n as u32)
                .map(|i| i.wrapping_mul(2_654_435_761))
                .collect();
            let keep = |i: usize, x: &u32| !(x ^ i as u32).is_multiple_of(3);
            let mut a = v.clone();
            super::retain(&mut a, keep);
            let b: Vec<u32> = v
                .iter()
                .enumerate()
                .filter(|(i, x)| keep(*i, x))
                .map(|(_, x)| *x)
                .collect();
            assert_eq!(a, b, "n = {n}");
        }
    }
}
