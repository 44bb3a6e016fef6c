//! Plates 2.10–2.11 (Musgrave et al. 1989, Plates 2 and 9): a patch made
//! for erosion, with a stream bed down its diagonal, before and after 2000
//! time steps of Musgrave–Kolb–Mace hydraulic erosion and thermal
//! weathering with the sources' constants (natura-terrain's
//! `MusgraveHydraulic` and `Thermal`); Plates 2.12–2.13 (MKM 7 and 8): a
//! patch of non-uniform lacunarity before and after 100 steps of thermal
//! weathering, "a rough approximation of sand dunes".

use natura::core::glam::{DVec2, Vec3};
use natura::core::{HeightField, Image};
use natura::noise::{DistNoise, Fbm, Field, Perlin, Spectral};
use natura::terrain::erosion::{MusgraveHydraulic, MusgraveParams, Thermal, ThermalParams};

use super::R;
use super::patches::{Facet, render_patch, rescaled};

/// The patch's side, m (200 samples a metre apart, the dissertation's
/// 200 × 200).
const SIDE_M: f64 = 200.0;

/// The stream bed's fall from the far end to the near, m.
const FALL_M: f64 = 10.0;

/// How steeply the banks rise from the bed, m per m of distance from it
/// (times the always-positive noise, mean about 1).
const BANK: f64 = 0.12;

/// The time steps of the combined run (Musgrave et al. 1989, Plate 9).
pub(crate) const STEPS: u32 = 2000;

/// The input terrain (Musgrave et al. 1989, §4.2; Musgrave 1993, §2.4.1):
/// always-positive noise weighted by the distance `d` from the patch's
/// diagonal, the diagonal higher at the far end, `d` perturbed by 1/f³
/// noise (fBm with H = 1) so the bed is not straight:
///
/// ```text
/// a(x, y) = FALL·s + BANK·d'·N⁺(p),   s = (x + y)/2 (0 near, 1 far),
/// d' = |x − y|/√2 + 0.08·fBm_{H=1}(p),   N⁺ = 1 + 0.6·fBm_{H=0.8}(p) > 0
/// ```
///
/// in metres over the `n` × `n` samples of a [`SIDE_M`]-metre patch. The
/// sources give the construction, not its constants; these are chosen.
pub(crate) fn stream_bed_patch(seed: u64, n: usize) -> R<HeightField> {
    let bend = Fbm::new(
        Perlin::new(seed),
        Spectral {
            h: 1.0,
            octaves: 6.0,
            frequency: 2.0,
            ..Spectral::default()
        },
    )?;
    let rough = Fbm::new(
        Perlin::new(seed.wrapping_add(1)),
        Spectral {
            h: 0.8,
            octaves: 7.0,
            frequency: 4.0,
            ..Spectral::default()
        },
    )?;
    let cell = (SIDE_M / n as f64) as f32;
    Ok(HeightField::from_fn(n, n, cell, |i, j| {
        let p = DVec2::new(i as f64 + 0.5, j as f64 + 0.5) / n as f64;
        let s = 0.5 * (p.x + p.y);
        let d = (p.x - p.y).abs() / std::f64::consts::SQRT_2 + 0.08 * bend.eval2(p);
        let positive = (1.0 + 0.6 * rough.eval2(p)).max(0.05);
        (FALL_M * s + BANK * SIDE_M * d.abs() * positive) as f32
    })?)
}

/// `steps` time steps of the combined run: each step the hydraulic model
/// (the sources' `K_c` 5, `K_d` 0.1, `K_s` 0.3, rain of 0.001·a every 65
/// steps: natura-terrain's defaults) and then thermal weathering at
/// `c_t` = 0.001 (the default talus angle; the sources give none).
pub(crate) fn erode(hf: &mut HeightField, steps: u32) -> R<()> {
    let mut water = MusgraveHydraulic::new(MusgraveParams::default(), hf)?;
    let mut talus = Thermal::new(ThermalParams::default(), hf)?;
    for _ in 0..steps {
        water.step(hf)?;
        talus.step(hf)?;
    }
    Ok(())
}

/// Dry ground of the wash: rock by altitude, darker where the run cut
/// into it and pale sand where it left sediment (`change` m).
fn wash(z: f32, relief: f32, change: f32) -> Vec3 {
    let a = (z / relief).clamp(0.0, 1.0);
    let rock = Vec3::new(0.55, 0.45, 0.36).lerp(Vec3::new(0.62, 0.56, 0.50), a);
    let sand = Vec3::new(0.82, 0.74, 0.58);
    let cut = Vec3::new(0.36, 0.28, 0.22);
    let c = change / (0.03 * relief);
    if c > 0.0 {
        rock.lerp(sand, c.min(1.0))
    } else {
        rock.lerp(cut, (-c).min(1.0))
    }
}

/// Pl. 2.10 and 2.11: the patch before and after the run, drawn from the
/// near corner looking up the bed.
pub(crate) fn fluvial(seed: u64, quick: bool) -> R<Vec<Image>> {
    let (n, steps) = if quick { (64, 200) } else { (200, STEPS) };
    let before = stream_bed_patch(seed, n)?;
    let mut after = before.clone();
    erode(&mut after, steps)?;
    let (lo, hi) = before.heights().min_max();
    let relief = hi - lo;
    let size = if quick { (320, 240) } else { (1000, 750) };
    let sky = Vec3::new(0.55, 0.66, 0.82);
    let inv = 1.0 / before.cell_size();
    // The change of height under a facet's centre (0 for the patch before).
    let change = |c: Vec3| {
        let (i, j) = (
            ((c.x * inv) as usize).min(n - 1),
            ((c.y * inv) as usize).min(n - 1),
        );
        after.heights()[(i, j)] - before.heights()[(i, j)]
    };
    Ok(vec![
        render_patch(&before, size, sky, &|c, _| Facet {
            albedo: wash(c.z - lo, relief, 0.0),
            emission: Vec3::ZERO,
        })?,
        render_patch(&after, size, sky, &|c, _| Facet {
            albedo: wash(c.z - lo, relief, change(c)),
            emission: Vec3::ZERO,
        })?,
    ])
}

/// The dune patch's relief, m, over [`SIDE_M`].
const DUNE_RELIEF_M: f32 = 36.0;

/// The thermal steps of Plate 2.13.
pub(crate) const DUNE_STEPS: u32 = 100;

/// Plate 2.12's patch: fBm of Perlin noise with locally modulated
/// lacunarity, the basis's point displaced by vector noise (Musgrave 1993,
/// §2.3.2.4: `N(p + N⃗(p))`, the basis of Plate 2.7d; natura-noise's
/// `DistNoise` at distortion 1), 4 octaves, H = 0.5, 2.5 lattice units across
/// the patch, rescaled to [`DUNE_RELIEF_M`] of relief. The sources give
/// no numbers.
pub(crate) fn dune_patch(seed: u64, n: usize) -> R<HeightField> {
    let f = Fbm::new(
        DistNoise::dist_noise(Perlin::new(seed), 1.0)?,
        Spectral {
            octaves: 4.0,
            frequency: 2.5,
            ..Spectral::default()
        },
    )?;
    let raw: Vec<f64> = (0..n * n)
        .map(|k| f.eval2(DVec2::new((k % n) as f64 + 0.5, (k / n) as f64 + 0.5) / n as f64))
        .collect();
    rescaled(
        &raw,
        (n, n),
        (SIDE_M / n as f64) as f32,
        f64::from(DUNE_RELIEF_M),
    )
}

/// Plate 2.13's slumping: thermal weathering toward sand's angle of
/// repose (33°, natura-terrain's default talus angle), moving a tenth of
/// each excess a step (the sources give neither; `c_t` 0.001 of their
/// combined run would barely move in 100 steps).
pub(crate) fn slump(hf: &mut HeightField, steps: u32) -> R<()> {
    let mut talus = Thermal::new(
        ThermalParams {
            talus_rate: 0.1,
            ..ThermalParams::default()
        },
        hf,
    )?;
    for _ in 0..steps {
        talus.step(hf)?;
    }
    Ok(())
}

/// Plates 2.12 and 2.13: the patch before and after slumping, in sand.
pub(crate) fn dunes(seed: u64, quick: bool) -> R<Vec<Image>> {
    let n = if quick { 64 } else { 200 };
    let before = dune_patch(seed, n)?;
    let mut after = before.clone();
    slump(&mut after, DUNE_STEPS)?;
    let size = if quick { (320, 240) } else { (1000, 750) };
    let sky = Vec3::new(0.62, 0.72, 0.86);
    let sand = |c: Vec3, _n: Vec3| Facet {
        albedo: Vec3::new(0.80, 0.62, 0.40).lerp(
            Vec3::new(0.90, 0.76, 0.52),
            (c.z / DUNE_RELIEF_M).clamp(0.0, 1.0),
        ),
        emission: Vec3::ZERO,
    };
    Ok(vec![
        render_patch(&before, size, sky, &sand)?,
        render_patch(&after, size, sky, &sand)?,
    ])
}

/// The steepest slope between 8-neighbours of `hf`, as an angle (degrees).
#[cfg(test)]
fn steepest_deg(hf: &HeightField) -> f64 {
    let (nx, ny, cell) = (hf.nx(), hf.ny(), f64::from(hf.cell_size()));
    let h = hf.heights();
    let mut m = 0.0f64;
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let z = f64::from(h[(i, j)]);
            for (a, b, d) in [
                (i + 1, j, cell),
                (i, j + 1, cell),
                (i + 1, j + 1, cell * 2f64.sqrt()),
            ] {
                m = m.max((f64::from(h[(a, b)]) - z).abs() / d);
            }
        }
    }
    m.atan().to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_patch_has_a_bed_down_its_diagonal_rising_to_the_far_end() {
        let hf = stream_bed_patch(5, 100).unwrap();
        let h = hf.heights();
        let n = hf.nx();
        for k in [20, 50, 80] {
            // The bed (the lowest point across the diagonal at this s) lies
            // near the diagonal, below both banks.
            let across: Vec<(usize, f32)> =
                (0..=30).map(|o| (o, h[(k + o - 15, k + 15 - o)])).collect();
            let (at, bed) = across
                .iter()
                .copied()
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            assert!(at.abs_diff(15) <= 10, "bed {at} steps off the diagonal");
            assert!(across[0].1 > bed + 1.0 && across[30].1 > bed + 1.0);
        }
        assert!(h[(n - 5, n - 5)] > h[(4, 4)] + 0.8 * FALL_M as f32);
    }

    #[test]
    fn the_run_moves_soil_down_the_bed() {
        // A short run on a small patch: water gathers in the bed and the
        // banks lose height to it (mass moves downhill), the patch's soil
        // total kept by the closed edges up to the sediment still carried.
        let mut hf = stream_bed_patch(5, 48).unwrap();
        let before = hf.clone();
        erode(&mut hf, 130).unwrap();
        let diff: Vec<f32> = hf
            .heights()
            .as_slice()
            .iter()
            .zip(before.heights().as_slice())
            .map(|(a, b)| a - b)
            .collect();
        let moved = diff.iter().map(|d| d.abs()).fold(0.0f32, f32::max);
        assert!(moved > 0.01, "nothing moved ({moved} m)");
        let (lo, hi) = before.heights().min_max();
        let (lo2, hi2) = hf.heights().min_max();
        assert!(hi2 <= hi && lo2 >= lo - 1e-3, "{lo} {hi} → {lo2} {hi2}");
    }

    #[test]
    fn slumping_brings_the_dunes_toward_the_angle_of_repose() {
        // Plate 2.13: thermal weathering relaxes every slope steeper than
        // the talus angle (33°) toward it, and keeps the soil.
        let mut hf = dune_patch(2, 100).unwrap();
        let (before, sum0) = (
            steepest_deg(&hf),
            hf.heights()
                .as_slice()
                .iter()
                .map(|&v| f64::from(v))
                .sum::<f64>(),
        );
        assert!(
            before > 45.0,
            "the patch should start steeper than sand stands ({before}°)"
        );
        slump(&mut hf, 2 * DUNE_STEPS).unwrap();
        let after = steepest_deg(&hf);
        assert!(after < before - 5.0, "{before}° → {after}°");
        let sum1: f64 = hf.heights().as_slice().iter().map(|&v| f64::from(v)).sum();
        assert!(
            (sum1 - sum0).abs() < 1e-6 * sum0.abs().max(1.0) * 1e3,
            "{sum0} → {sum1}"
        );
    }
}
