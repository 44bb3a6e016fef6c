//! Worley's feature-point distributions (Musgrave 2001, "The Seed Tables"):
//! the default's values pinned, the exact search against brute force for
//! every distribution, batch against point, and the statistics each
//! distribution promises.

use crate::common::Rng;

use glam::{DVec2, DVec3};
use natura_noise::{Field, Metric, Simd, Worley, WorleyFeature, WorleyParams};

const METRICS: [Metric; 4] = [
    Metric::Euclidean,
    Metric::EuclideanSquared,
    Metric::Manhattan,
    Metric::Chebyshev,
];

const FEATURES: [WorleyFeature; 7] = [
    WorleyFeature::F1,
    WorleyFeature::F2,
    WorleyFeature::F3,
    WorleyFeature::F4,
    WorleyFeature::F2MinusF1,
    WorleyFeature::F3MinusF2,
    WorleyFeature::F4MinusF3,
];

/// FNV-1a over 64-bit words.
fn fnv(h: &mut u64, bits: u64) {
    for b in bits.to_le_bytes() {
        *h ^= u64::from(b);
        *h = h.wrapping_mul(0x0100_0000_01B3);
    }
}

/// The default distribution (one jittered point per cell) gives the values
/// it gave before the distributions were added, bit for bit: every metric,
/// feature and a few jitters, point values (2-D and 3-D) and batch rows
/// (span and per-lane kernels) at the portable level and the best one.
#[test]
fn default_distribution_values_are_pinned() {
    let mut h = 0xCBF2_9CE4_8422_2325u64;
    let mut rng = Rng(2001);
    for metric in METRICS {
        for feature in FEATURES {
            for jitter in [1.0, 0.6] {
                let w = Worley::new(
                    7,
                    WorleyParams {
                        feature,
                        metric,
                        jitter,
                        ..WorleyParams::default()
                    },
                )
                .unwrap();
                for _ in 0..64 {
                    fnv(&mut h, w.eval2(rng.p2(300.0)).to_bits());
                    fnv(&mut h, w.eval3(rng.p3(300.0)).to_bits());
                }
                for step in [0.013, 1.7] {
                    for simd in [Simd::baseline(), Simd::best()] {
                        let mut row = [0.0f32; 97];
                        w.fill_row2_with(simd, DVec2::new(-3.1, 5.7), step, &mut row);
                        row.iter().for_each(|v| fnv(&mut h, u64::from(v.to_bits())));
                        w.fill_row3_with(simd, DVec3::new(-3.1, 5.7, 0.4), step, &mut row);
                        row.iter().for_each(|v| fnv(&mut h, u64::from(v.to_bits())));
                    }
                }
            }
        }
    }
    assert_eq!(h, 0x3408_1707_5184_7a87, "hash {h:#018x}");
}
