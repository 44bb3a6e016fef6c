//! Demo data for the examples that need a landscape or a look but not the
//! terrain crate: a height field made of octaves of bilinearly interpolated
//! position-indexed Gaussian values (natura-core's `Seed::gaussian2`, the
//! simplest stochastic surface core can make on its own), and a plain
//! natural albedo. Real synthesis lives in natura-terrain.

use natura::core::glam::Vec3;
use natura::core::{Boundary, Grid2, HeightField, Seed};

/// How [`lattice_terrain`] sums its octaves.
pub struct LatticeTerrain {
    /// Lattice cells per side of the coarsest octave; each next octave doubles it.
    pub first_lattice: usize,
    /// Weight of octave k ≥ 1 given the sum so far (amplitudes also halve per
    /// octave): a constant 1 gives plain fBm with H = 1, a weight rising with
    /// height gives Musgrave's heterogeneous terrain (smooth lowlands, rough
    /// highlands).
    pub weight: fn(f32) -> f32,
    /// Maps the final sum to metres.
    pub metres: fn(f32) -> f32,
}

impl LatticeTerrain {
    /// Heterogeneous terrain about 2 km high with flooded plains, as the
    /// trace examples show it.
    pub const HETERO: LatticeTerrain = LatticeTerrain {
        first_lattice: 3,
        weight: |h| (0.5 + 0.6 * h).clamp(0.03, 1.6),
        // Flood the lowest ground into flat water-level plains.
        metres: |h| 900.0 * h.max(-0.6) + 600.0,
    };

    /// Plain fBm (H = 1), amplitude 400 m in the coarsest octave.
    pub const FBM: LatticeTerrain = LatticeTerrain {
        first_lattice: 4,
        weight: |_| 1.0,
        metres: |h| 400.0 * h,
    };
}

/// An `n × n` height field with `cell`-metre spacing, from `seed`.
pub fn lattice_terrain(
    n: usize,
    cell: f32,
    seed: Seed,
    how: &LatticeTerrain,
) -> natura::core::Result<HeightField> {
    let mut octaves = Vec::new();
    let mut lattice = how.first_lattice;
    while lattice <= n / 2 {
        let s = seed.derive_index(lattice as u64);
        octaves.push(Grid2::from_fn(lattice + 1, lattice + 1, |i, j| {
            s.gaussian2(i as i64, j as i64) as f32
        })?);
        lattice *= 2;
    }
    let g = Grid2::<f32>::par_from_fn(n, n, |i, j| {
        let mut h = 0.0f32;
        let mut amp = 1.0f32;
        for (k, g) in octaves.iter().enumerate() {
            let f = (g.width() - 1) as f32 / (n - 1) as f32;
            let v = g.sample_bilinear(i as f32 * f, j as f32 * f, Boundary::Clamp);
            let w = if k == 0 { 1.0 } else { (how.weight)(h) };
            h += amp * w * v;
            amp *= 0.5;
        }
        (how.metres)(h)
    })?;
    HeightField::new(g, cell)
}

/// A plain natural albedo: grass low and gentle, rock on steep slopes, snow
/// high. `height01` is the height scaled to [0, 1] over the field's range.
pub fn albedo(height01: f32, normal_z: f32) -> Vec3 {
    let grass = Vec3::new(0.16, 0.22, 0.08);
    let rock = Vec3::new(0.30, 0.27, 0.24);
    let snow = Vec3::new(0.85, 0.87, 0.9);
    let steep = ((0.92 - normal_z) / 0.2).clamp(0.0, 1.0);
    let ground = grass.lerp(rock, steep.max(((height01 - 0.35) / 0.3).clamp(0.0, 1.0)));
    let snowy = (((height01 - 0.72) / 0.1).clamp(0.0, 1.0)) * (1.0 - steep * 0.8);
    ground.lerp(snow, snowy)
}
