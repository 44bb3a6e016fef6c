//! Seeds, named sub-seeds, and random numbers indexed by lattice position.
//!
//! Two kinds of randomness are used across natura:
//!
//! * **streams**: [`Seed::rng`] gives a `rand_pcg` generator for work whose
//!   order is fixed (placing droplets, faults, stars);
//! * **random numbers indexed by position**: [`Seed::uniform2`],
//!   [`Seed::gaussian2`] and friends hash an integer lattice position with the
//!   seed into a value that does not depend on evaluation order, level of
//!   detail or thread count. This is Fournier, Fussell & Carpenter's
//!   `GAUSS(seed, index)` (Fournier et al. 1982, §3.2.3): a point
//!   gets the same random number however and whenever it is computed, which is
//!   what makes subdivision consistent across levels and tiles.
//!
//! All arithmetic here is integer or goes through `libm`, so values are
//! bit-identical on every platform.

use rand_pcg::Pcg64Mcg;

/// splitmix64's golden-ratio increment.
const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;

/// The splitmix64 finaliser: a bijective avalanche mix of 64 bits
/// (Steele, Lea & Flood 2014).
#[inline]
#[must_use]
pub const fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Per-axis odd multipliers so that `(x, y)` and `(y, x)` hash differently.
const AXIS: [u64; 4] = [
    0xD6E8_FEB8_6659_FD93,
    0xA076_1D64_78BD_642F,
    0xE703_7ED1_A0B4_28DB,
    0x8EBC_6AF0_9C88_C6E3,
];

/// Converts the top 53 bits of `h` to a uniform `f64` in `[0, 1)`.
#[inline]
#[must_use]
pub fn unit_f64(h: u64) -> f64 {
    (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A 64-bit seed. The same seed gives bit-identical results everywhere in natura.
///
/// Derive independent sub-seeds for each part of a pipeline with
/// [`Seed::derive`] (`seed.derive("erosion")`), so adding a random draw in one
/// stage never changes another stage's output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(transparent))]
pub struct Seed(pub u64);

impl Seed {
    /// Returns the sub-seed named `name`: splitmix64 of the seed combined with an
    /// FNV-1a hash of the name. Different names give unrelated seeds.
    #[must_use]
    pub fn derive(self, name: &str) -> Seed {
        let mut h: u64 = 0xCBF2_9CE4_8422_2325;
        for b in name.bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01B3);
        }
        Seed(mix64(self.0.wrapping_add(GOLDEN) ^ mix64(h)))
    }

    /// Returns the `index`-th sub-seed (for per-octave, per-cascade or per-frame seeds).
    #[must_use]
    pub fn derive_index(self, index: u64) -> Seed {
        Seed(mix64(
            self.0
                ^ mix64(
                    index
                        .wrapping_mul(GOLDEN)
                        .wrapping_add(0x632B_E59B_D9B4_E019),
                ),
        ))
    }

    /// Returns a PCG generator (`Pcg64Mcg`, 128-bit state) seeded from this seed.
    #[must_use]
    pub fn rng(self) -> Pcg64Mcg {
        let lo = mix64(self.0);
        let hi = mix64(self.0 ^ GOLDEN);
        // The MCG state must be odd; Pcg64Mcg::new forces that itself.
        Pcg64Mcg::new((u128::from(hi) << 64) | u128::from(lo))
    }

    /// The 64-bit hash of lattice point `coords` under this seed.
    ///
    /// Up to 4 coordinates are mixed with distinct axis constants; extra
    /// coordinates reuse the constants cyclically.
    #[inline]
    #[must_use]
    pub fn hash(self, coords: &[i64]) -> u64 {
        let mut h = mix64(self.0 ^ 0x5851_F42D_4C95_7F2D);
        for (i, &c) in coords.iter().enumerate() {
            h = mix64(h ^ (c as u64).wrapping_mul(AXIS[i % 4]).wrapping_add(i as u64));
        }
        h
    }

    /// Hash of the 1-D lattice point `x`.
    #[inline]
    #[must_use]
    pub fn hash1(self, x: i64) -> u64 {
        self.hash(&[x])
    }

    /// Hash of the 2-D lattice point `(x, y)`.
    #[inline]
    #[must_use]
    pub fn hash2(self, x: i64, y: i64) -> u64 {
        self.hash(&[x, y])
    }

    /// Hash of the 3-D lattice point `(x, y, z)`.
    #[inline]
    #[must_use]
    pub fn hash3(self, x: i64, y: i64, z: i64) -> u64 {
        self.hash(&[x, y, z])
    }

    /// Uniform value in `[0, 1)` indexed by `coords`.
    #[inline]
    #[must_use]
    pub fn uniform(self, coords: &[i64]) -> f64 {
        unit_f64(self.hash(coords))
    }

    /// Uniform value in `[0, 1)` indexed by `x`.
    #[inline]
    #[must_use]
    pub fn uniform1(self, x: i64) -> f64 {
        self.uniform(&[x])
    }

    /// Uniform value in `[0, 1)` indexed by `(x, y)`.
    #[inline]
    #[must_use]
    pub fn uniform2(self, x: i64, y: i64) -> f64 {
        self.uniform(&[x, y])
    }

    /// Uniform value in `[0, 1)` indexed by `(x, y, z)`.
    #[inline]
    #[must_use]
    pub fn uniform3(self, x: i64, y: i64, z: i64) -> f64 {
        self.uniform(&[x, y, z])
    }

    /// Standard normal value (mean 0, variance 1) indexed by `coords`:
    /// FFC's `GAUSS(seed, index)`.
    ///
    /// Box–Muller on two independent uniforms drawn from the position's hash,
    /// evaluated with `libm` so results are identical on every platform.
    #[inline]
    #[must_use]
    pub fn gaussian(self, coords: &[i64]) -> f64 {
        let h = self.hash(coords);
        // u1 in (0, 1] so the logarithm is finite; u2 from an independent remix.
        let u1 = ((h >> 11) + 1) as f64 * (1.0 / (1u64 << 53) as f64);
        let u2 = unit_f64(mix64(h ^ GOLDEN));
        libm::sqrt(-2.0 * libm::log(u1)) * libm::cos(std::f64::consts::TAU * u2)
    }

    /// Standard normal value indexed by `x`.
    #[inline]
    #[must_use]
    pub fn gaussian1(self, x: i64) -> f64 {
        self.gaussian(&[x])
    }

    /// Standard normal value indexed by `(x, y)`.
    #[inline]
    #[must_use]
    pub fn gaussian2(self, x: i64, y: i64) -> f64 {
        self.gaussian(&[x, y])
    }

    /// Standard normal value indexed by `(x, y, z)`.
    #[inline]
    #[must_use]
    pub fn gaussian3(self, x: i64, y: i64, z: i64) -> f64 {
        self.gaussian(&[x, y, z])
    }
}

impl From<u64> for Seed {
    fn from(v: u64) -> Self {
        Seed(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::Rng;

    #[test]
    fn lattice_hash_is_deterministic_and_axis_sensitive() {
        let s = Seed(42);
        assert_eq!(s.hash2(3, -7), Seed(42).hash2(3, -7));
        assert_ne!(s.hash2(3, -7), s.hash2(-7, 3));
        assert_ne!(s.hash2(3, -7), Seed(43).hash2(3, -7));
        assert_ne!(s.hash(&[1]), s.hash(&[1, 0]));
        assert_eq!(s.gaussian3(1, 2, 3), Seed(42).gaussian3(1, 2, 3));
    }

    #[test]
    fn uniform_is_uniform() {
        let s = Seed(7);
        let n = 100_000;
        let mut bins = [0u32; 10];
        let mut sum = 0.0;
        for i in 0..n {
            let u = s.uniform2(i % 317, i / 317);
            assert!((0.0..1.0).contains(&u));
            bins[(u * 10.0) as usize] += 1;
            sum += u;
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.005);
        for b in bins {
            // Expected 10 000 per bin, σ ≈ 95: 6σ bounds.
            assert!((9_430..=10_570).contains(&b), "{bins:?}");
        }
    }

    #[test]
    fn gaussian_has_unit_variance() {
        let s = Seed(0x5EED);
        let n = 100_000i64;
        let (mut m1, mut m2, mut m4) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let g = s.gaussian2(i % 1000 - 500, i / 1000);
            m1 += g;
            m2 += g * g;
            m4 += g * g * g * g;
        }
        let nf = n as f64;
        let mean = m1 / nf;
        let var = m2 / nf - mean * mean;
        // Standard errors: mean 1/√n ≈ 0.0032, variance √(2/n) ≈ 0.0045.
        assert!(mean.abs() < 0.016, "mean {mean}");
        assert!((var - 1.0).abs() < 0.025, "variance {var}");
        // Fourth moment of N(0,1) is 3: rules out a uniform or triangular impostor.
        assert!((m4 / nf - 3.0).abs() < 0.15, "kurtosis {}", m4 / nf);
    }

    #[test]
    fn derived_seeds_differ_and_repeat() {
        let s = Seed(1);
        assert_eq!(s.derive("terrain"), Seed(1).derive("terrain"));
        assert_ne!(s.derive("terrain"), s.derive("erosion"));
        assert_ne!(s.derive_index(0), s.derive_index(1));
        let mut a = s.rng();
        let mut b = Seed(1).rng();
        assert_eq!(a.next_u64(), b.next_u64());
        assert_ne!(Seed(2).rng().next_u64(), Seed(1).rng().next_u64());
    }
}
