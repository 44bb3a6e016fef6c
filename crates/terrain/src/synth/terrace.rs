//! Terraces: the altitude quantised into beds, as layered rock weathers into
//! cliffs and benches.
//!
//! Quantising the altitudes of a height field "yields terraced land, such as
//! mesas" (Musgrave et al. 1989, §2, of Gardner's noise terrains; Musgrave
//! 1993, §2.2.2.6), and Musgrave 1993, §2.4.4, proposes bedrock whose
//! hardness varies in strata. This module is the geometric form of that
//! differential weathering: within each bed of thickness `bed_m` the top
//! `cliff_fraction` of the altitude range is a hard layer that stands as a
//! cliff, the rest a soft layer worn back into a bench. The beds bend with a
//! warp field (metres of altitude), as the strata texture's layers do, so the
//! cliffs follow the rock's colour bands when both are warped alike.
//!
//! The quantisation is the monotone map of altitude, per bed of phase
//! `f ∈ [0, 1)`,
//!
//! ```text
//! T(f) = (1 − g)·f + g·smoothstep(1 − c, 1, f)
//! ```
//!
//! with `c` the cliff fraction and `g` the flatness of the benches (0 leaves
//! the terrain as it is, 1 makes the benches level). `T(0) = 0` and
//! `T(1) = 1`, so the terraced altitude is continuous across beds and a
//! slope keeps its direction: water still runs downhill wherever it did.
//! Where the slope is below `min_slope_deg` (valley floors, plains) or the
//! ground is below `min_altitude_m` (the soil-covered lowlands) the map fades
//! out, so terraces form only where bedrock shows on the hillsides.
//!
//! The published sources give this as a remark, not an algorithm: the
//! smoothstep riser, the fading by slope and altitude, and the warp are this
//! module's choices.

use natura_core::{Grid2, HeightField, smoothstep};

use crate::error::{Result, check_grid, in_range, positive, same_size};

/// Parameters of [`terrace`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default, deny_unknown_fields))]
pub struct TerraceParams {
    /// Thickness of one bed (a cliff and its bench), metres of altitude. Default 60.
    pub bed_m: f32,
    /// Share of each bed's altitude range that stands as cliff, in (0, 1]. Default 0.35.
    pub cliff_fraction: f32,
    /// Flatness of the benches, 0 (no terraces) to 1 (level benches). Default 0.85.
    pub flatness: f32,
    /// Slope below which no terraces form, degrees; they reach full strength
    /// 10° steeper. Default 14.
    pub min_slope_deg: f32,
    /// Altitude below which no terraces form, metres; they reach full
    /// strength `bed_m` higher. Default 0.
    pub min_altitude_m: f32,
}

impl Default for TerraceParams {
    fn default() -> Self {
        Self {
            bed_m: 60.0,
            cliff_fraction: 0.35,
            flatness: 0.85,
            min_slope_deg: 14.0,
            min_altitude_m: 0.0,
        }
    }
}

impl TerraceParams {
    /// Checks every parameter.
    ///
    /// # Errors
    ///
    /// Returns [`TerrainError::InvalidParameter`](crate::TerrainError::InvalidParameter)
    /// naming the first parameter that is NaN or out of range: `bed_m` must be
    /// positive and at most 10 000 m, `cliff_fraction` in (0, 1], `flatness`
    /// in [0, 1], `min_slope_deg` in [0, 80], `min_altitude_m` within ±10⁶ m.
    pub fn validate(&self) -> Result<()> {
        positive("bed_m", f64::from(self.bed_m))?;
        in_range("bed_m", f64::from(self.bed_m), 0.0, 10_000.0)?;
        positive("cliff_fraction", f64::from(self.cliff_fraction))?;
        in_range("cliff_fraction", f64::from(self.cliff_fraction), 0.0, 1.0)?;
        in_range("flatness", f64::from(self.flatness), 0.0, 1.0)?;
        in_range("min_slope_deg", f64::from(self.min_slope_deg), 0.0, 80.0)?;
        in_range("min_altitude_m", f64::from(self.min_altitude_m), -1e6, 1e6)?;
        Ok(())
    }

    /// The terraced altitude of `z` (metres) at full strength, with the beds
    /// raised by `warp` metres: monotone in `z`, equal to `z` on every bed
    /// boundary.
    #[inline]
    #[must_use]
    pub fn quantise(&self, z: f32, warp: f32) -> f32 {
        let b = self.bed_m;
        let x = (z + warp) / b;
        let k = x.floor();
        let f = x - k;
        let t = (1.0 - self.flatness) * f
            + self.flatness * smoothstep(1.0 - self.cliff_fraction, 1.0, f);
        b * (k + t) - warp
    }
}

/// Terraces `hf` in place (see the module docs): each sample moves toward
/// [`TerraceParams::quantise`] of its altitude by a weight that grows with
/// the slope (from `min_slope_deg` to 10° steeper, slopes by central
/// differences of the input) and the altitude (from `min_altitude_m` to
/// `bed_m` higher). `warp`, if given, raises the beds by that many metres per
/// sample. The result depends on the input alone, not on thread count.
///
/// # Errors
///
/// Returns the errors of [`TerraceParams::validate`];
/// [`TerrainError::SizeMismatch`](crate::TerrainError::SizeMismatch) if the
/// warp is not the field's size and
/// [`TerrainError::NonFinite`](crate::TerrainError::NonFinite) if it or the
/// field holds a NaN or an infinity; [`TerrainError::Core`](crate::TerrainError::Core)
/// if the slope weights cannot be allocated.
pub fn terrace(hf: &mut HeightField, p: &TerraceParams, warp: Option<&Grid2<f32>>) -> Result<()> {
    p.validate()?;
    let (nx, ny) = (hf.nx(), hf.ny());
    if let Some(w) = warp {
        same_size("terrace warp", w, nx, ny)?;
        check_grid("terrace warp", w)?;
    }
    check_grid("height", hf.heights())?;
    let cell = hf.cell_size();
    let lo = p.min_slope_deg.to_radians().tan();
    let hi = (p.min_slope_deg + 10.0).min(89.0).to_radians().tan();
    let h = hf.heights();
    // Weights from the input's slopes, before any sample moves.
    let weight = Grid2::from_fn(nx, ny, |i, j| {
        let (i0, i1) = (i.saturating_sub(1), (i + 1).min(nx - 1));
        let (j0, j1) = (j.saturating_sub(1), (j + 1).min(ny - 1));
        let gx = (h[(i1, j)] - h[(i0, j)]) / (cell * (i1 - i0).max(1) as f32);
        let gy = (h[(i, j1)] - h[(i, j0)]) / (cell * (j1 - j0).max(1) as f32);
        let z = h[(i, j)];
        smoothstep(lo, hi, gx.hypot(gy))
            * smoothstep(p.min_altitude_m, p.min_altitude_m + p.bed_m, z)
    })?;
    let g = hf.heights_mut();
    for j in 0..ny {
        for i in 0..nx {
            let w = weight[(i, j)];
            if w > 0.0 {
                let z = g[(i, j)];
                let q = p.quantise(z, warp.map_or(0.0, |w| w[(i, j)]));
                g[(i, j)] = z + w * (q - z);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(slope_deg: f32) -> HeightField {
        let t = slope_deg.to_radians().tan();
        let g = Grid2::from_fn(64, 8, |i, _| 100.0 + t * 10.0 * i as f32).unwrap();
        HeightField::new(g, 10.0).unwrap()
    }

    #[test]
    fn quantise_is_monotone_and_fixes_bed_boundaries() {
        let p = TerraceParams::default();
        for warp in [0.0, 17.5, -40.0] {
            let mut prev = f32::NEG_INFINITY;
            for k in 0..20_000 {
                let z = -300.0 + 0.05 * k as f32;
                let q = p.quantise(z, warp);
                assert!(q >= prev - 1e-3, "not monotone at z = {z}: {q} < {prev}");
                prev = q;
            }
            for k in -5..5 {
                let z = k as f32 * p.bed_m - warp;
                assert!(
                    (p.quantise(z, warp) - z).abs() < 1e-3,
                    "bed boundary {z} moved"
                );
            }
        }
        let flat = TerraceParams { flatness: 0.0, ..p };
        assert_eq!(flat.quantise(123.4, 5.0), 123.4 + 5.0 - 5.0);
    }

    #[test]
    fn steep_slopes_become_cliffs_and_benches_gentle_ones_stay() {
        let p = TerraceParams::default();
        // A 30° hillside turns into benches and cliffs steeper than it.
        let mut hill = ramp(30.0);
        let before = hill.clone();
        terrace(&mut hill, &p, None).unwrap();
        let steps: Vec<f32> = (1..63)
            .map(|i| {
                let g = hill.heights();
                (g[(i + 1, 4)] - g[(i, 4)]) / 10.0
            })
            .collect();
        let tan30 = 30f32.to_radians().tan();
        let steepest = steps.iter().copied().fold(0.0, f32::max);
        let gentlest = steps.iter().copied().fold(f32::INFINITY, f32::min);
        assert!(steepest > 1.8 * tan30, "no cliff: steepest {steepest}");
        assert!(gentlest < 0.5 * tan30, "no bench: gentlest {gentlest}");
        assert!(steps.iter().all(|&s| s >= 0.0), "the slope turned back");
        // Every sample stays within one bed of where it was.
        for (a, b) in hill
            .heights()
            .as_slice()
            .iter()
            .zip(before.heights().as_slice())
        {
            assert!((a - b).abs() <= p.bed_m);
        }
        // A 5° plain is left alone, bit for bit.
        let mut plain = ramp(5.0);
        let before = plain.clone();
        terrace(&mut plain, &p, None).unwrap();
        assert_eq!(plain, before);
    }

    #[test]
    fn zero_flatness_and_low_ground_are_untouched() {
        let mut hill = ramp(35.0);
        let before = hill.clone();
        let p = TerraceParams {
            flatness: 0.0,
            ..TerraceParams::default()
        };
        terrace(&mut hill, &p, None).unwrap();
        for (a, b) in hill
            .heights()
            .as_slice()
            .iter()
            .zip(before.heights().as_slice())
        {
            assert!((a - b).abs() < 1e-3);
        }
        let high = TerraceParams {
            min_altitude_m: 5000.0,
            ..TerraceParams::default()
        };
        let before = hill.clone();
        terrace(&mut hill, &high, None).unwrap();
        assert_eq!(hill, before, "ground below min_altitude_m moved");
    }

    #[test]
    fn bad_parameters_and_warps_are_refused() {
        let mut hf = ramp(30.0);
        for (name, p) in [
            (
                "bed_m",
                TerraceParams {
                    bed_m: 0.0,
                    ..TerraceParams::default()
                },
            ),
            (
                "bed_m",
                TerraceParams {
                    bed_m: f32::NAN,
                    ..TerraceParams::default()
                },
            ),
            (
                "cliff_fraction",
                TerraceParams {
                    cliff_fraction: 1.5,
                    ..TerraceParams::default()
                },
            ),
            (
                "flatness",
                TerraceParams {
                    flatness: -0.1,
                    ..TerraceParams::default()
                },
            ),
            (
                "min_slope_deg",
                TerraceParams {
                    min_slope_deg: 95.0,
                    ..TerraceParams::default()
                },
            ),
        ] {
            let e = terrace(&mut hf, &p, None).unwrap_err().to_string();
            assert!(e.contains(name), "{name}: {e}");
        }
        let small = Grid2::new(3, 3, 0.0f32).unwrap();
        assert!(terrace(&mut hf, &TerraceParams::default(), Some(&small)).is_err());
        let mut nan = Grid2::new(64, 8, 0.0f32).unwrap();
        nan[(3, 3)] = f32::NAN;
        assert!(terrace(&mut hf, &TerraceParams::default(), Some(&nan)).is_err());
    }
}
