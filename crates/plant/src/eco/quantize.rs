//! Vector quantization of plant parameters for approximate instancing.
//!
//! Deussen et al. 1998, §5: every plant is a parameter vector; a code book of
//! representatives is found by the variance-based splitting of Wan, Wong &
//! Prusinkiewicz, extended with a per-vector importance weight, and every plant
//! is drawn as its nearest representative. Here the parameter is one number
//! (the plant's size within its species), where hyperbox splitting reduces to
//! splitting a sorted run at the point that minimises the two halves' weighted
//! variance; the cluster with the largest weighted variance is split first.

use crate::error::{PlantError, Result};

/// A code book and the entry of every value.
#[derive(Clone, Debug, PartialEq)]
pub struct Quantization {
    /// Representatives (weighted means of their clusters), ascending.
    pub codebook: Vec<f32>,
    /// Code-book index of every input value, in input order.
    pub index: Vec<u32>,
    /// Weighted sum of squared distances to the representatives.
    pub error: f64,
}

/// Weighted sum of squares of a sorted run from prefix sums.
fn sse(w: &[f64], wx: &[f64], wxx: &[f64], a: usize, b: usize) -> f64 {
    let sw = w[b] - w[a];
    if sw <= 0.0 {
        return 0.0;
    }
    let s = wx[b] - wx[a];
    ((wxx[b] - wxx[a]) - s * s / sw).max(0.0)
}

/// The values' order (ascending, ties by index) and the prefix sums along it
/// of the weight, weight·x and weight·x².
fn sorted_sums(values: &[f32], weights: &[f32]) -> (Vec<u32>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = values.len();
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_by(|&a, &b| {
        values[a as usize]
            .total_cmp(&values[b as usize])
            .then(a.cmp(&b))
    });
    let (mut w, mut wx, mut wxx) = (vec![0.0; n + 1], vec![0.0; n + 1], vec![0.0; n + 1]);
    for (r, &i) in order.iter().enumerate() {
        // A zero weight would leave a cluster without a mean; a tiny floor keeps every value counted.
        let wi = f64::from(weights[i as usize]).max(1e-12);
        let x = f64::from(values[i as usize]);
        w[r + 1] = w[r] + wi;
        wx[r + 1] = wx[r] + wi * x;
        wxx[r + 1] = wxx[r] + wi * x * x;
    }
    (order, w, wx, wxx)
}

/// A run's best split point and the run's own weighted error.
type Split = (usize, f64);

/// Quantizes `values` (weighted by `weights`) into at most `k` representatives.
///
/// # Errors
///
/// [`PlantError::InvalidParameter`] if `k` is 0, the slices differ in length,
/// or a value or weight is not finite or a weight is negative.
pub fn quantize(values: &[f32], weights: &[f32], k: usize) -> Result<Quantization> {
    let bad = |name, value: String, reason: &str| PlantError::InvalidParameter {
        name,
        value,
        reason: reason.into(),
    };
    if k == 0 {
        return Err(bad("k", "0".into(), "at least one representative"));
    }
    if values.len() != weights.len() {
        return Err(bad(
            "weights",
            weights.len().to_string(),
            "one weight per value",
        ));
    }
    if let Some(v) = values.iter().find(|v| !v.is_finite()) {
        return Err(bad("values", v.to_string(), "finite numbers"));
    }
    if let Some(w) = weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
        return Err(bad("weights", w.to_string(), "finite non-negative numbers"));
    }
    let n = values.len();
    let (order, w, wx, wxx) = sorted_sums(values, weights);
    // The best split of run [a, b): only between different values, at the
    // point that minimises the halves' summed error; with the run's error.
    let best_split = |a: usize, b: usize| -> Option<Split> {
        let e = sse(&w, &wx, &wxx, a, b);
        if e <= 0.0 {
            return None;
        }
        let mut split: Option<(usize, f64)> = None;
        for m in a + 1..b {
            if values[order[m - 1] as usize] == values[order[m] as usize] {
                continue;
            }
            let s = sse(&w, &wx, &wxx, a, m) + sse(&w, &wx, &wxx, m, b);
            if split.is_none_or(|(_, v)| s < v) {
                split = Some((m, s));
            }
        }
        split.map(|(m, _)| (m, e))
    };
    // Clusters as sorted runs [a, b), each with its best split (found once,
    // when the run is made); the worst run that splits is split first (the
    // first of equals) until k runs or nothing splits.
    let mut runs: Vec<(usize, usize, Option<Split>)> = if n == 0 {
        Vec::new()
    } else {
        vec![(0, n, best_split(0, n))]
    };
    while runs.len() < k {
        let mut best: Option<(usize, usize, f64)> = None;
        for (ci, &(_, _, split)) in runs.iter().enumerate() {
            if let Some((m, e)) = split
                && best.is_none_or(|(_, _, be)| e > be)
            {
                best = Some((ci, m, e));
            }
        }
        let Some((ci, m, _)) = best else { break };
        let (a, b, _) = runs[ci];
        runs[ci] = (a, m, best_split(a, m));
        runs.insert(ci + 1, (m, b, best_split(m, b)));
    }
    let codebook: Vec<f32> = runs
        .iter()
        .map(|&(a, b, _)| ((wx[b] - wx[a]) / (w[b] - w[a])) as f32)
        .collect();
    // Each value maps to its nearest representative (a run's edge may lie nearer
    // the neighbouring mean when weights differ); the code book is ascending.
    let mut index = vec![0u32; n];
    let mut error = 0.0;
    for (i, &v) in values.iter().enumerate() {
        let c = codebook.partition_point(|&e| e < v);
        let k = match (c.checked_sub(1), (c < codebook.len()).then_some(c)) {
            (Some(lo), Some(hi)) if v - codebook[lo] <= codebook[hi] - v => lo,
            (_, Some(hi)) => hi,
            (Some(lo), None) => lo,
            (None, None) => 0,
        };
        index[i] = k as u32;
        let d = f64::from(v - codebook[k]);
        error += f64::from(weights[i]) * d * d;
    }
    Ok(Quantization {
        codebook,
        index,
        error,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enough_entries_give_zero_error_and_error_never_grows_with_k() {
        let v: Vec<f32> = (0..50).map(|i| ((i * 37) % 11) as f32 * 0.5).collect();
        let w: Vec<f32> = (0..50).map(|i| 1.0 + (i % 3) as f32).collect();
        let q = quantize(&v, &w, 11).unwrap();
        assert_eq!(q.codebook.len(), 11);
        assert!(q.error < 1e-9, "{}", q.error);
        let mut last = f64::INFINITY;
        for k in 1..=11 {
            let q = quantize(&v, &w, k).unwrap();
            assert!(q.error <= last + 1e-9);
            last = q.error;
            // Every value maps to exactly one entry, its nearest.
            for (i, &c) in q.index.iter().enumerate() {
                let d = (q.codebook[c as usize] - v[i]).abs();
                for &e in &q.codebook {
                    assert!(d <= (e - v[i]).abs() + 1e-4);
                }
            }
        }
    }

    /// The splitting done plainly: every round re-scans every run for its
    /// error and best split (what [`quantize`] keeps from round to round).
    fn runs_by_rescanning(values: &[f32], weights: &[f32], k: usize) -> Vec<f32> {
        let (order, w, wx, wxx) = sorted_sums(values, weights);
        let mut runs = vec![(0, values.len())];
        while runs.len() < k {
            let mut best: Option<(usize, usize, f64)> = None;
            for (ci, &(a, b)) in runs.iter().enumerate() {
                let e = sse(&w, &wx, &wxx, a, b);
                if e <= 0.0 {
                    continue;
                }
                let mut split: Option<(usize, f64)> = None;
                for m in a + 1..b {
                    if values[order[m - 1] as usize] == values[order[m] as usize] {
                        continue;
                    }
                    let s = sse(&w, &wx, &wxx, a, m) + sse(&w, &wx, &wxx, m, b);
                    if split.is_none_or(|(_, v)| s < v) {
                        split = Some((m, s));
                    }
                }
                if let Some((m, _)) = split
                    && best.is_none_or(|(_, _, be)| e > be)
                {
                    best = Some((ci, m, e));
                }
            }
            let Some((ci, m, _)) = best else { break };
            let (a, b) = runs[ci];
            runs[ci] = (a, m);
            runs.insert(ci + 1, (m, b));
        }
        runs.iter()
            .map(|&(a, b)| ((wx[b] - wx[a]) / (w[b] - w[a])) as f32)
            .collect()
    }

    proptest::proptest! {
        /// The kept splits give the code book of re-scanning every round,
        /// bit for bit (repeated values and zero weights included).
        #[test]
        fn kept_splits_equal_rescanning(
            vw in proptest::collection::vec((0u8..40, 0u8..4), 1..200),
            k in 1usize..24,
        ) {
            let values: Vec<f32> = vw.iter().map(|&(v, _)| f32::from(v) * 0.25).collect();
            let weights: Vec<f32> = vw.iter().map(|&(_, w)| f32::from(w)).collect();
            let q = quantize(&values, &weights, k).unwrap();
            let want = runs_by_rescanning(&values, &weights, k);
            proptest::prop_assert_eq!(
                q.codebook.iter().map(|c| c.to_bits()).collect::<Vec<_>>(),
                want.iter().map(|c| c.to_bits()).collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn bad_input_is_a_typed_error() {
        assert!(quantize(&[1.0], &[1.0], 0).is_err());
        assert!(quantize(&[1.0], &[], 1).is_err());
        assert!(quantize(&[f32::NAN], &[1.0], 1).is_err());
        assert!(quantize(&[1.0], &[-1.0], 1).is_err());
        assert!(quantize(&[], &[], 3).unwrap().codebook.is_empty());
    }
}
