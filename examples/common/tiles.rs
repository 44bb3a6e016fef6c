//! Demo terrain shared by the `forest` example and the ecosystem benchmark,
//! so the benchmark times exactly the example's workload.

use natura::core::HeightField;
use natura::core::{Progress, Seed};
use natura::terrain::TerrainError;
use natura::terrain::erosion::{StreamPower, StreamPowerParams};
use natura::terrain::synth::{SpectralParams, spectral_synthesis};

/// A spectral terrain of `n`² samples `cell` metres apart, rescaled to 150 m
/// of relief and eroded by 40 stream-power steps (reported to `progress`
/// as the erosion's stage).
pub fn eroded_tile(
    n: usize,
    cell: f32,
    seed: u64,
    progress: &dyn Progress,
) -> Result<HeightField, TerrainError> {
    let sp = SpectralParams {
        sigma_m: 25.0,
        ..Default::default()
    };
    let mut hf = spectral_synthesis(n, n, cell, &sp, Seed(seed))?;
    let (lo, hi) = hf.min_max();
    for v in hf.heights_mut().as_mut_slice() {
        *v = (*v - lo) / (hi - lo).max(1e-6) * 150.0;
    }
    let p = StreamPowerParams {
        k: 4e-5,
        dt_yr: 10_000.0,
        uplift_m_per_yr: 0.0,
        ..Default::default()
    };
    let mut m = StreamPower::new(p, &hf)?;
    m.run(&mut hf, 40, progress)?;
    Ok(hf)
}
