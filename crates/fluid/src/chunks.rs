//! Deterministic parallel helpers: rayon behind the `parallel` feature.
//!
//! Every helper hands each output chunk to exactly one call and combines
//! reductions in a fixed order, so results are bit-identical for any number
//! of threads (and without the feature).

/// Below this many elements work runs serially (rayon's overhead dominates).
#[cfg(feature = "parallel")]
const SERIAL_BELOW: usize = 1 << 14;

/// Calls `f(chunk_index, chunk)` for each `chunk`-sized piece of `data`.
pub(crate) fn for_chunks<T: Send>(
    data: &mut [T],
    chunk: usize,
    f: impl Fn(usize, &mut [T]) + Sync + Send,
) {
    let chunk = chunk.max(1);
    #[cfg(feature = "parallel")]
    if data.len() >= SERIAL_BELOW {
        use rayon::prelude::*;
        // Group small rows so each task does a useful amount of work.
        data.par_chunks_mut(chunk)
            .with_min_len((4096 / chunk).max(1))
            .enumerate()
            .for_each(|(i, c)| f(i, c));
        return;
    }
    data.chunks_mut(chunk)
        .enumerate()
        .for_each(|(i, c)| f(i, c));
}

/// Like [`for_chunks`] over two equally chunked slices at once.
pub(crate) fn for_chunks2<T: Send, U: Send>(
    a: &mut [T],
    b: &mut [U],
    chunk: usize,
    f: impl Fn(usize, &mut [T], &mut [U]) + Sync + Send,
) {
    let chunk = chunk.max(1);
    #[cfg(feature = "parallel")]
    if a.len() >= SERIAL_BELOW {
        use rayon::prelude::*;
        a.par_chunks_mut(chunk)
            .zip(b.par_chunks_mut(chunk))
            .with_min_len((4096 / chunk).max(1))
            .enumerate()
            .for_each(|(i, (x, y))| f(i, x, y));
        return;
    }
    a.chunks_mut(chunk)
        .zip(b.chunks_mut(chunk))
        .enumerate()
        .for_each(|(i, (x, y))| f(i, x, y));
}

/// Calls `f(band_index, bands)` for each `band`-sized piece of every slice
/// of `data` at once (all slices equally long): `bands[s]` is piece
/// `band_index` of `data[s]`.
pub(crate) fn for_bands(
    data: &mut [&mut [f32]],
    band: usize,
    f: impl Fn(usize, &mut [&mut [f32]]) + Sync + Send,
) {
    let band = band.max(1);
    let len = data.first().map_or(0, |d| d.len());
    let mut bands: Vec<Vec<&mut [f32]>> = (0..len.div_ceil(band))
        .map(|_| Vec::with_capacity(data.len()))
        .collect();
    for d in data.iter_mut() {
        debug_assert_eq!(d.len(), len);
        for (b, c) in d.chunks_mut(band).enumerate() {
            bands[b].push(c);
        }
    }
    #[cfg(feature = "parallel")]
    if len >= SERIAL_BELOW {
        use rayon::prelude::*;
        bands
            .into_par_iter()
            .enumerate()
            .for_each(|(i, mut v)| f(i, &mut v));
        return;
    }
    bands
        .into_iter()
        .enumerate()
        .for_each(|(i, mut v)| f(i, &mut v));
}

/// Like [`for_chunks`], returning `Σ f(chunk_index, chunk)` with the
/// per-chunk partials added in chunk order (deterministic).
pub(crate) fn for_chunks_sum<T: Send>(
    data: &mut [T],
    chunk: usize,
    f: impl Fn(usize, &mut [T]) -> f64 + Sync + Send,
) -> f64 {
    let chunk = chunk.max(1);
    #[cfg(feature = "parallel")]
    if data.len() >= SERIAL_BELOW {
        use rayon::prelude::*;
        let parts: Vec<f64> = data
            .par_chunks_mut(chunk)
            .with_min_len((4096 / chunk).max(1))
            .enumerate()
            .map(|(i, c)| f(i, c))
            .collect();
        return parts.into_iter().sum();
    }
    data.chunks_mut(chunk)
        .enumerate()
        .map(|(i, c)| f(i, c))
        .sum()
}

/// Like [`for_chunks2`], returning the chunk-ordered sums of the two
/// partials `f` returns per chunk (deterministic).
pub(crate) fn for_chunks2_sum2<T: Send, U: Send>(
    a: &mut [T],
    b: &mut [U],
    chunk: usize,
    f: impl Fn(usize, &mut [T], &mut [U]) -> (f64, f64) + Sync + Send,
) -> (f64, f64) {
    let chunk = chunk.max(1);
    let add = |(s, t): (f64, f64), (x, y): (f64, f64)| (s + x, t + y);
    #[cfg(feature = "parallel")]
    if a.len() >= SERIAL_BELOW {
        use rayon::prelude::*;
        let parts: Vec<(f64, f64)> = a
            .par_chunks_mut(chunk)
            .zip(b.par_chunks_mut(chunk))
            .with_min_len((4096 / chunk).max(1))
            .enumerate()
            .map(|(i, (x, y))| f(i, x, y))
            .collect();
        return parts.into_iter().fold((0.0, 0.0), add);
    }
    a.chunks_mut(chunk)
        .zip(b.chunks_mut(chunk))
        .enumerate()
        .map(|(i, (x, y))| f(i, x, y))
        .fold((0.0, 0.0), add)
}

/// Like [`for_chunks2`] over three equally chunked slices, returning
/// `Σ f(chunk_index, a, b, c)` with the partials added in chunk order
/// (deterministic).
pub(crate) fn for_chunks3_sum<T: Send, U: Send, V: Send>(
    a: &mut [T],
    b: &mut [U],
    c: &mut [V],
    chunk: usize,
    f: impl Fn(usize, &mut [T], &mut [U], &mut [V]) -> f64 + Sync + Send,
) -> f64 {
    let chunk = chunk.max(1);
    #[cfg(feature = "parallel")]
    if a.len() >= SERIAL_BELOW {
        use rayon::prelude::*;
        let parts: Vec<f64> = a
            .par_chunks_mut(chunk)
            .zip(b.par_chunks_mut(chunk))
            .zip(c.par_chunks_mut(chunk))
            .with_min_len((4096 / chunk).max(1))
            .enumerate()
            .map(|(i, ((x, y), z))| f(i, x, y, z))
            .collect();
        return parts.into_iter().sum();
    }
    a.chunks_mut(chunk)
        .zip(b.chunks_mut(chunk))
        .zip(c.chunks_mut(chunk))
        .enumerate()
        .map(|(i, ((x, y), z))| f(i, x, y, z))
        .sum()
}

/// Returns `Σ_i f(i)` over `0..n` blocks, each block's partial computed
/// independently and the partials added in index order (deterministic).
pub(crate) fn sum_blocks(
    n: usize,
    work_per_block: usize,
    f: impl Fn(usize) -> f64 + Sync + Send,
) -> f64 {
    #[cfg(feature = "parallel")]
    if n > 1 && n * work_per_block >= SERIAL_BELOW {
        use rayon::prelude::*;
        let parts: Vec<f64> = (0..n).into_par_iter().map(&f).collect();
        return parts.into_iter().sum();
    }
    let _ = work_per_block;
    (0..n).map(f).sum()
}

/// Maps `f` over `0..n` into a vector, in parallel when large.
pub(crate) fn map_collect<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    #[cfg(feature = "parallel")]
    if n >= 64 {
        use rayon::prelude::*;
        return (0..n).into_par_iter().map(f).collect();
    }
    (0..n).map(f).collect()
}

/// Fixed block length for deterministic reductions over flat arrays.
pub(crate) const BLOCK: usize = 8192;

/// `max(f(r0, r1))` over bands `[r0, r1)` of `rows` rows of `row_len`
/// elements each (`f` folds a band and returns its maximum; `f32::max`, so
/// the result does not depend on how the rows are split into bands).
pub(crate) fn max_over_rows(
    rows: usize,
    row_len: usize,
    f: impl Fn(usize, usize) -> f32 + Sync + Send,
) -> f32 {
    #[cfg(feature = "parallel")]
    if rows * row_len >= SERIAL_BELOW {
        use rayon::prelude::*;
        let band = (4096 / row_len.max(1)).max(1);
        return (0..rows.div_ceil(band))
            .into_par_iter()
            .map(|b| f(b * band, ((b + 1) * band).min(rows)))
            .reduce(|| 0.0f32, f32::max);
    }
    f(0, rows)
}
