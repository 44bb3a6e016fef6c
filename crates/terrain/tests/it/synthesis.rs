//! natura-terrain integration tests: statistical oracles for the synthesis
//! methods, 1- vs 2-thread bit-identity for every parallel model, and the
//! drainage guarantees of the erosion pipeline.

use natura_core::{HeightField, NoProgress, Seed};
use natura_terrain::analysis::{self, Depressions, FlowGraph};
use natura_terrain::erosion::{
    Diffusion, DiffusionParams, DropletErosion, DropletParams, Erodibility, MusgraveHydraulic,
    MusgraveParams, PipeModel, PipeParams, StreamPower, StreamPowerParams, Thermal, ThermalParams,
};
use natura_terrain::synth::{
    self, FaultParams, MidpointParams, SpectralParams, SraParams, SubdivisionParams,
    SubdivisionScheme, spectral_synthesis, subdivide,
};

fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
}

fn bits(hf: &HeightField) -> Vec<u32> {
    hf.heights()
        .as_slice()
        .iter()
        .map(|v| v.to_bits())
        .collect()
}

/// Spectral synthesis: the radially averaged periodogram over 16 seeds has slope
/// −(2H + 2) ± 0.2 over the middle decade; the variogram gives H ± 0.1.
#[test]
fn spectral_synthesis_has_the_fbm_spectrum_and_variogram() {
    for h in [0.3, 0.5, 0.8] {
        let n = 128;
        let p = SpectralParams {
            h,
            ..Default::default()
        };
        let mut mean_power: Vec<f64> = Vec::new();
        let mut freq = Vec::new();
        let mut hv = 0.0;
        for s in 0..16 {
            let hf = spectral_synthesis(n, n, 1.0, &p, Seed(s)).unwrap();
            let spec = analysis::radial_power_spectrum(&hf, false).unwrap();
            if mean_power.is_empty() {
                mean_power = vec![0.0; spec.power.len()];
                freq = spec.frequency.clone();
            }
            for (m, v) in mean_power.iter_mut().zip(&spec.power) {
                *m += v / 16.0;
            }
        }
        // Variogram over lags 2..8 on 256² (4 seeds): shorter lags are biased up by
        // the Nyquist cut-off, longer ones down by the periodic tile (measured:
        // H 0.3 → 0.38, 0.5 → 0.53, 0.8 → 0.76).
        for s in 0..4 {
            let hf = spectral_synthesis(256, 256, 1.0, &p, Seed(100 + s)).unwrap();
            hv += analysis::variogram_h(&hf, 2, 8).unwrap() / 4.0;
        }
        let avg = analysis::RadialSpectrum {
            frequency: freq,
            power: mean_power,
        };
        let slope = avg.slope(4.0, 40.0).unwrap();
        assert!(
            (slope + 2.0 * h + 2.0).abs() < 0.2,
            "H = {h}: spectral slope {slope}"
        );
        assert!((hv - h).abs() < 0.1, "H = {h}: variogram estimate {hv}");
        // Seamless tiling: wrap-around differences look like interior ones.
        let hf = spectral_synthesis(n, n, 1.0, &p, Seed(99)).unwrap();
        let g = hf.heights();
        let interior: f64 = (0..n)
            .map(|y| f64::from(g[(1, y)] - g[(0, y)]).powi(2))
            .sum::<f64>()
            / n as f64;
        let wrap: f64 = (0..n)
            .map(|y| f64::from(g[(0, y)] - g[(n - 1, y)]).powi(2))
            .sum::<f64>()
            / n as f64;
        assert!(
            wrap < 4.0 * interior + 1e-9,
            "H = {h}: wrap {wrap} vs interior {interior}"
        );
    }
}

/// Noise synthesis from natura-noise fBm (Perlin basis, λ = 2, 8 octaves spanning
/// the grid's band): windowed radial spectrum slope −(2H + 2) ± 0.2 over the middle
/// decade, variogram H ± 0.1 (lags 2..8). For H = 0.3 the variogram reads ≈ 0.39
/// (the cubic basis distorts the spectrum, Saupe, Musgrave 1993, §2.3.2.1), so it is checked on
/// the slope only.
#[test]
fn noise_fbm_synthesis_has_the_fbm_spectrum() {
    use natura_noise::{Fbm, Perlin, Spectral};
    use natura_terrain::synth::{FieldMapping, fill_noise};
    for h in [0.3, 0.5, 0.8] {
        let (mut slope, mut hv) = (0.0, 0.0);
        for s in 0..8u64 {
            let sp = Spectral::default()
                .with_h(h)
                .with_lacunarity(2.0)
                .with_octaves(8.0)
                .with_frequency(1.0 / 64.0);
            let f = Fbm::new(Perlin::new(s), sp).unwrap();
            let map = FieldMapping {
                frequency: 1.0,
                height_m: 100.0,
                ..Default::default()
            };
            let hf = fill_noise(256, 256, 1.0, &map, &f).unwrap();
            slope += analysis::radial_power_spectrum(&hf, true)
                .unwrap()
                .slope(4.0, 40.0)
                .unwrap()
                / 8.0;
            hv += analysis::variogram_h(&hf, 2, 8).unwrap() / 8.0;
        }
        assert!(
            (slope + 2.0 * h + 2.0).abs() < 0.2,
            "H = {h}: slope {slope}"
        );
        if h >= 0.5 {
            assert!((hv - h).abs() < 0.1, "H = {h}: variogram {hv}");
        }
    }
}

/// FFC triangle subdivision: the per-level displacement std follows 2^(−H·level)
/// (log2 regression slope −H ± 0.03), and a coarse run is the subsampled fine run.
#[test]
fn subdivision_level_variance_scales_as_two_to_minus_two_h_level() {
    let levels = 6u32;
    for h in [0.4, 0.8] {
        let p = SubdivisionParams {
            midpoint: MidpointParams {
                h,
                scale: 1.0,
                ..Default::default()
            },
            scheme: SubdivisionScheme::Triangle,
            levels: Some(levels),
        };
        let n = (1usize << levels) + 1;
        let mut sums = vec![(0.0f64, 0u64); levels as usize + 1];
        for s in 0..300 {
            let hf = subdivide(n, n, 1.0, &p, Seed(s)).unwrap();
            let g = hf.heights();
            let z = |i: usize, j: usize| f64::from(g[(i, j)]);
            for l in 1..=levels {
                let st = 1usize << (levels - l);
                for b in 0..n / st + 1 {
                    for a in 0..n / st + 1 {
                        let (i, j) = (a * st, b * st);
                        if i >= n || j >= n {
                            continue;
                        }
                        let mean = match (a % 2, b % 2) {
                            (1, 0) => (z(i - st, j) + z(i + st, j)) / 2.0,
                            (0, 1) => (z(i, j - st) + z(i, j + st)) / 2.0,
                            (1, 1) => (z(i - st, j - st) + z(i + st, j + st)) / 2.0,
                            _ => continue,
                        };
                        let d = z(i, j) - mean;
                        sums[l as usize].0 += d * d;
                        sums[l as usize].1 += 1;
                    }
                }
            }
        }
        let pts: Vec<(f64, f64)> = (1..=levels as usize)
            .map(|l| (l as f64, 0.5 * (sums[l].0 / sums[l].1 as f64).log2()))
            .collect();
        let slope = {
            let n = pts.len() as f64;
            let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
            let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
            pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
                / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>()
        };
        assert!(
            (slope + h).abs() < 0.03,
            "H = {h}: log2 std slope per level {slope}"
        );
    }
}

/// Every synthesis method and every erosion model gives bit-identical output
/// on 1 and 2 threads.
#[test]
fn one_and_two_threads_are_bit_identical() {
    let run = |threads: usize| -> Vec<Vec<u32>> {
        pool(threads).install(|| {
            let mut out = Vec::new();
            let n = 96;
            out.push(bits(
                &subdivide(n, n, 5.0, &SubdivisionParams::default(), Seed(1)).unwrap(),
            ));
            out.push(bits(
                &spectral_synthesis(n, 70, 5.0, &SpectralParams::default(), Seed(1)).unwrap(),
            ));
            out.push(bits(
                &synth::successive_random_additions(n, n, 5.0, &SraParams::default(), Seed(1))
                    .unwrap(),
            ));
            out.push(bits(
                &synth::poisson_faults(n, n, 5.0, &FaultParams::default(), Seed(1)).unwrap(),
            ));
            let base = spectral_synthesis(
                n,
                n,
                5.0,
                &SpectralParams {
                    sigma_m: 50.0,
                    ..Default::default()
                },
                Seed(2),
            )
            .unwrap();
            let mut hf = base.clone();
            Thermal::new(
                ThermalParams {
                    talus_rate: 0.1,
                    ..Default::default()
                },
                &hf,
            )
            .unwrap()
            .run(&mut hf, 20, &NoProgress)
            .unwrap();
            Diffusion::new(DiffusionParams::default(), &hf)
                .unwrap()
                .run(&mut hf, 20, &NoProgress)
                .unwrap();
            out.push(bits(&hf));
            let mut hf = base.clone();
            let mut m = MusgraveHydraulic::new(
                MusgraveParams {
                    rain_period: 5,
                    ..Default::default()
                },
                &hf,
            )
            .unwrap();
            m.run(&mut hf, 40, &NoProgress).unwrap();
            out.push(bits(&hf));
            let mut hf = base.clone();
            PipeModel::new(PipeParams::default(), &hf)
                .unwrap()
                .run(&mut hf, 40, &NoProgress)
                .unwrap();
            out.push(bits(&hf));
            let mut hf = base.clone();
            DropletErosion::new(
                DropletParams {
                    batch: 64,
                    ..Default::default()
                },
                &hf,
                Seed(3),
            )
            .unwrap()
            .run(&mut hf, 3000, &NoProgress)
            .unwrap();
            out.push(bits(&hf));
            let mut hf = base.clone();
            StreamPower::new(StreamPowerParams::default(), &hf)
                .unwrap()
                .run(&mut hf, 10, &NoProgress)
                .unwrap();
            out.push(bits(&hf));
            out.push(bits(&analysis::fill_depressions(&base).unwrap().0));
            out
        })
    };
    let (a, b) = (run(1), run(2));
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        assert!(x == y, "output {k} differs between 1 and 2 threads");
    }
}

/// The render pipeline: stream power then hydraulic + thermal detail, with a
/// hardness map. Rivers reach the edge, nothing goes non-finite, and the flow
/// network is more concentrated than on the raw terrain.
#[test]
fn eroded_terrain_drains_to_the_edge() {
    let n = 128;
    let mut hf = spectral_synthesis(
        n,
        n,
        30.0,
        &SpectralParams {
            sigma_m: 300.0,
            ..Default::default()
        },
        Seed(5),
    )
    .unwrap();
    let (lo, _) = hf.min_max();
    hf.heights_mut()
        .as_mut_slice()
        .iter_mut()
        .for_each(|v| *v -= lo);
    let strata = Erodibility::strata(&hf, 40.0, 1.5, 0.5, None).unwrap();
    let mut sp = StreamPower::new(StreamPowerParams::default(), &hf)
        .unwrap()
        .with_erodibility(strata)
        .unwrap();
    sp.run(&mut hf, 100, &NoProgress).unwrap();
    let g = sp.flow_graph().unwrap();
    for i in 0..n * n {
        assert!(
            g.is_edge(g.terminus(i)),
            "cell {i} does not drain to the edge"
        );
    }
    let mut m = MusgraveHydraulic::new(
        MusgraveParams {
            rain_period: 10,
            ..Default::default()
        },
        &hf,
    )
    .unwrap();
    m.run(&mut hf, 100, &NoProgress).unwrap();
    Thermal::new(
        ThermalParams {
            talus_rate: 0.05,
            ..Default::default()
        },
        &hf,
    )
    .unwrap()
    .run(&mut hf, 50, &NoProgress)
    .unwrap();
    assert!(hf.check_finite().is_ok());
    // After filling, every cell drains by steepest descent.
    let (filled, depth) = analysis::fill_depressions(&hf).unwrap();
    assert!(depth.min() >= 0.0);
    let mut h = filled.heights().as_slice().to_vec();
    let g = FlowGraph::build(&mut h, n, n, Depressions::Keep).unwrap();
    for i in 0..n * n {
        assert!(g.is_edge(g.terminus(i)));
    }
    let area = analysis::flow_accumulation_d8(&hf, Depressions::Route).unwrap();
    let max = area.max();
    assert!(
        max > 0.02 * (n * n) as f32 * 900.0,
        "largest catchment {max} m²"
    );
}
