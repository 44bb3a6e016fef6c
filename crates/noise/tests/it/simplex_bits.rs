//! Simplex noise's per-point values pinned bit for bit: checksums of
//! `eval2`/`eval3` over ten million points each (scattered points at scales
//! from 10⁻³ to 10¹⁶ lattice units, of both signs, lattice points and their
//! neighbours, and grids walked row by row), so any change to the per-point
//! arithmetic that moves a single bit of a single value fails here.

use glam::{DVec2, DVec3};
use natura_noise::{Field, Simplex};

/// splitmix64: a reproducible point stream without a generator crate.
struct Mix(u64);

impl Mix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A coordinate: mostly uniform in `±scale` for a scale drawn from
    /// 10⁻³…10¹⁶; sometimes a lattice integer or an ulp beside one.
    fn coord(&mut self) -> f64 {
        const SCALES: [f64; 8] = [1e-3, 1.0, 16.0, 1e3, 1e6, 1e9, 1e13, 1e16];
        let h = self.next();
        let u = (h >> 11) as f64 / 9_007_199_254_740_992.0;
        let v = (u * 2.0 - 1.0) * SCALES[(h & 7) as usize];
        match (h >> 3) & 15 {
            0 => v.round(),
            1 => next_up(v.round()),
            2 => -next_up(-v.round()),
            _ => v,
        }
    }
}

/// The next float above finite `x` (`f64::next_up`, which needs Rust 1.86).
fn next_up(x: f64) -> f64 {
    let bits = x.to_bits();
    let abs = bits & !(1 << 63);
    f64::from_bits(if abs == 0 {
        1
    } else if bits == abs {
        bits + 1
    } else {
        bits - 1
    })
}

/// FNV-1a over the values' bits.
#[derive(Default)]
struct Sum(u64);

impl Sum {
    fn add(&mut self, v: f64) {
        if self.0 == 0 {
            self.0 = 0xCBF2_9CE4_8422_2325;
        }
        for b in v.to_bits().to_le_bytes() {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01B3);
        }
    }
}

const N: usize = 10_000_000;
/// Grid spacing (cells per sample) of the row-walked sets.
const STEP: f64 = 0.731;

/// The grids' origins: near zero, negative, and far out.
const ORIGINS: [[f64; 3]; 4] = [
    [-374.137, -201.5, -3.25],
    [0.25, 0.125, 0.0625],
    [-1.0e6 - 0.3, 2.5e5 + 0.7, -7.1e4],
    [3.0e9 + 0.5, -4.0e8 - 0.25, 1.0e7],
];

fn sums2(s: &Simplex) -> (u64, u64) {
    let mut rng = Mix(0x5349_4D50_3244);
    let mut random = Sum::default();
    for _ in 0..N / 2 {
        random.add(s.eval2(DVec2::new(rng.coord(), rng.coord())));
    }
    let mut grid = Sum::default();
    let side = 1118; // ≈ √(N / 2 / 4) per origin
    for o in ORIGINS {
        for j in 0..side {
            for i in 0..side {
                let p = DVec2::new(o[0] + i as f64 * STEP, o[1] + j as f64 * STEP);
                grid.add(s.eval2(p));
            }
        }
    }
    (random.0, grid.0)
}

fn sums3(s: &Simplex) -> (u64, u64) {
    let mut rng = Mix(0x5349_4D50_3344);
    let mut random = Sum::default();
    for _ in 0..N / 2 {
        random.add(s.eval3(DVec3::new(rng.coord(), rng.coord(), rng.coord())));
    }
    let mut grid = Sum::default();
    let side = 108; // ≈ ∛(N / 2 / 4) per origin
    for o in ORIGINS {
        for k in 0..side {
            for j in 0..side {
                for i in 0..side {
                    let p = DVec3::new(
                        o[0] + i as f64 * STEP,
                        o[1] + j as f64 * STEP,
                        o[2] + k as f64 * STEP,
                    );
                    grid.add(s.eval3(p));
                }
            }
        }
    }
    (random.0, grid.0)
}

#[test]
fn simplex2_values_are_pinned_bit_for_bit() {
    let (random, grid) = sums2(&Simplex::new(0x1234_5678));
    assert_eq!(
        (random, grid),
        (0x4323_6370_a27f_9513, 0x4345_ec5a_2622_42aa),
        "2-D simplex values changed (random {random:#018x}, grid {grid:#018x})"
    );
}

#[test]
fn simplex3_values_are_pinned_bit_for_bit() {
    let (random, grid) = sums3(&Simplex::new(0x1234_5678));
    assert_eq!(
        (random, grid),
        (0x6278_668f_6a78_60ad, 0xa3b2_ad91_9430_61e2),
        "3-D simplex values changed (random {random:#018x}, grid {grid:#018x})"
    );
}
