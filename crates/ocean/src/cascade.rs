//! Cascades: two to four patches of different sizes whose spectra are split
//! into disjoint wavenumber bands and summed (beyond the notes; a common production technique).
//!
//! One patch of size L and N samples covers wavenumbers 2π/L … πN/L; its
//! period L shows as repetition when the view is much larger (Tessendorf
//! 2001, §3.3; slides "Random surface generation"). A cascade gives the long waves to a large patch and the
//! short ones to smaller patches with other, incommensurate periods, so the
//! sum repeats far less visibly and covers a wider band than a single
//! 2048² grid. Each band is kept by exactly one patch, so no energy is
//! counted twice: the variances add up to that of the whole band.

use natura_core::Seed;

use crate::error::{OceanError, Result, invalid, positive};
use crate::foam::Foam;
use crate::frame::Frame;
use crate::patch::{Ocean, OceanParams};
use crate::spectrum::Spectrum;
use crate::surface::Surface;

/// Most patches a cascade may have.
pub const MAX_CASCADES: usize = 4;

/// A set of ocean patches with disjoint spectral bands.
#[derive(Clone, Debug)]
pub struct Cascade {
    oceans: Vec<Ocean>,
    boundaries: Vec<f64>,
}

/// The frames of a [`Cascade`] at one time.
#[derive(Clone, Debug)]
pub struct CascadeFrame {
    frames: Vec<Frame>,
}

impl Cascade {
    /// Returns the default band boundaries (rad/m) between patches of sizes
    /// `sizes` (metres, decreasing) with `n` samples per side: the geometric
    /// mean of the larger patch's Nyquist wavenumber πN/Lᵢ and the smaller
    /// patch's fundamental 2π/Lᵢ₊₁, so each patch keeps a good share of its
    /// own resolution.
    #[must_use]
    pub fn default_boundaries(sizes: &[f64], n: usize) -> Vec<f64> {
        sizes
            .windows(2)
            .map(|w| {
                let nyq = std::f64::consts::PI * n as f64 / w[0];
                let fund = std::f64::consts::TAU / w[1];
                (nyq * fund).sqrt()
            })
            .collect()
    }

    /// Builds a cascade of square patches of side `sizes[i]` (metres,
    /// strictly decreasing, 2 to 4 of them) with the grid, dispersion,
    /// looping and choppiness of `base` (its `lx`, `ly`, `k_min` and `k_max`
    /// are replaced), splitting the spectrum at [`Cascade::default_boundaries`].
    ///
    /// # Errors
    ///
    /// As [`Cascade::with_boundaries`].
    pub fn new(
        base: &OceanParams,
        sizes: &[f64],
        spectrum: &dyn Spectrum,
        seed: Seed,
    ) -> Result<Self> {
        let b = Self::default_boundaries(sizes, base.nx.min(base.ny));
        Self::with_boundaries(base, sizes, &b, spectrum, seed)
    }

    /// As [`Cascade::new`] with explicit band `boundaries` (rad/m, strictly
    /// increasing, one fewer than `sizes`): patch i keeps
    /// `boundaries[i − 1] ≤ |k| < boundaries[i]`.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::InvalidParameter`] for fewer than 2 or more than 4 patches, sizes that are not
    /// positive and strictly decreasing, or boundaries that are not positive and strictly
    /// increasing; [`OceanError::SizeMismatch`] if `boundaries` does not have one fewer entry than
    /// `sizes`; and the errors of [`Ocean::new`](crate::Ocean::new) for each patch.
    pub fn with_boundaries(
        base: &OceanParams,
        sizes: &[f64],
        boundaries: &[f64],
        spectrum: &dyn Spectrum,
        seed: Seed,
    ) -> Result<Self> {
        if !(2..=MAX_CASCADES).contains(&sizes.len()) {
            return Err(invalid(
                "sizes",
                sizes.len(),
                "a cascade needs 2 to 4 patch sizes",
            ));
        }
        if boundaries.len() + 1 != sizes.len() {
            return Err(OceanError::SizeMismatch {
                expected: format!("{} boundaries", sizes.len() - 1),
                actual: format!("{}", boundaries.len()),
            });
        }
        for (i, &s) in sizes.iter().enumerate() {
            positive("sizes", s)?;
            if i > 0 && s >= sizes[i - 1] {
                return Err(invalid("sizes", s, "patch sizes must strictly decrease"));
            }
        }
        for (i, &b) in boundaries.iter().enumerate() {
            positive("boundaries", b)?;
            if i > 0 && b <= boundaries[i - 1] {
                return Err(invalid(
                    "boundaries",
                    b,
                    "boundaries must strictly increase",
                ));
            }
        }
        let mut oceans = Vec::with_capacity(sizes.len());
        for (i, &l) in sizes.iter().enumerate() {
            let p = OceanParams {
                lx: l,
                ly: l,
                k_min: if i == 0 { 0.0 } else { boundaries[i - 1] },
                k_max: boundaries.get(i).copied().unwrap_or(f64::INFINITY),
                ..*base
            };
            oceans.push(Ocean::new(&p, spectrum, seed.derive_index(i as u64))?);
        }
        Ok(Self {
            oceans,
            boundaries: boundaries.to_vec(),
        })
    }

    /// Returns the patches, largest first.
    #[must_use]
    pub fn oceans(&self) -> &[Ocean] {
        &self.oceans
    }

    /// Returns the band boundaries, rad/m.
    #[must_use]
    pub fn boundaries(&self) -> &[f64] {
        &self.boundaries
    }

    /// Allocates frames for every patch.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::Core`] if a frame's grids exceed the memory cap.
    pub fn frame(&self) -> Result<CascadeFrame> {
        Ok(CascadeFrame {
            frames: self.oceans.iter().map(Frame::new).collect::<Result<_>>()?,
        })
    }

    /// Evaluates every patch at time `t` into `frame`.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::SizeMismatch`] if `frame` was not made by this cascade, and the errors of
    /// [`Ocean::evaluate_into`](crate::Ocean::evaluate_into).
    pub fn evaluate_into(&self, t: f64, frame: &mut CascadeFrame) -> Result<()> {
        if frame.frames.len() != self.oceans.len() {
            return Err(OceanError::SizeMismatch {
                expected: format!("{} frames", self.oceans.len()),
                actual: format!("{}", frame.frames.len()),
            });
        }
        for (o, f) in self.oceans.iter().zip(&mut frame.frames) {
            o.evaluate_into(t, f)?;
        }
        Ok(())
    }

    /// Returns the summed expected height variance of all patches, m².
    #[must_use]
    pub fn expected_variance(&self, spectrum: &dyn Spectrum) -> f64 {
        self.oceans
            .iter()
            .map(|o| o.expected_variance(spectrum))
            .sum()
    }
}

impl CascadeFrame {
    /// Returns the frame of each patch, largest first.
    #[must_use]
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// Returns tiling samplers of every patch, to be summed with
    /// [`crate::WaterSurface`] on `[Surface]`. `foam`, if given, holds one
    /// map per patch.
    ///
    /// # Errors
    ///
    /// Returns [`OceanError::SizeMismatch`] if `foam` holds a different number of maps than there are patches
    /// or a map of the wrong size.
    pub fn surfaces(&self, foam: Option<&[Foam]>) -> Result<Vec<Surface>> {
        if let Some(f) = foam
            && f.len() != self.frames.len()
        {
            return Err(OceanError::SizeMismatch {
                expected: format!("{} foam maps", self.frames.len()),
                actual: format!("{}", f.len()),
            });
        }
        self.frames
            .iter()
            .enumerate()
            .map(|(i, fr)| Surface::new(fr, foam.map(|f| &f[i])))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::WaterSurface;
    use crate::spectrum::Phillips;
    use glam::Vec2;

    fn base() -> OceanParams {
        OceanParams {
            nx: 64,
            ny: 64,
            choppiness: 0.5,
            ..OceanParams::default()
        }
    }

    #[test]
    fn bands_are_disjoint_and_variances_add_up() {
        let s = Phillips {
            wind_speed: 8.0,
            small_wave_length: 0.0,
            ..Phillips::default()
        };
        let sizes = [400.0, 57.0, 9.1];
        let c = Cascade::new(&base(), &sizes, &s, Seed(5)).unwrap();
        let b = c.boundaries().to_vec();
        assert_eq!(b.len(), 2);
        for (i, o) in c.oceans().iter().enumerate() {
            let lo = if i == 0 { 0.0 } else { b[i - 1] };
            let hi = b.get(i).copied().unwrap_or(f64::INFINITY);
            for (idx, h) in o.h0().iter().enumerate() {
                if h.norm_sqr() > 0.0 {
                    let k = o.wave_vector(idx % 64, idx / 64).length();
                    assert!(
                        k >= lo && k < hi,
                        "cascade {i}: k = {k} outside [{lo}, {hi})"
                    );
                }
            }
        }
        // Each band's variance ≈ the integral of P over that band; their sum
        // ≈ the integral up to the smallest patch's resolution limit.
        let total = c.expected_variance(&s);
        let k_top = std::f64::consts::PI * 64.0 / 9.1;
        let whole = crate::spectrum::integrate(&s, k_top * 0.999, 2000);
        // Square vs disk and lattice sampling differ by a few per cent.
        assert!((total / whole - 1.0).abs() < 0.1, "{total} vs {whole}");
        // A frame samples as the sum of its patches.
        let mut f = c.frame().unwrap();
        c.evaluate_into(1.0, &mut f).unwrap();
        let surf = f.surfaces(None).unwrap();
        let p = Vec2::new(13.0, 7.0);
        let sum: f32 = surf.iter().map(|s| s.height_at(p)).sum();
        assert_eq!(surf.height_at(p), sum);
        assert!(surf.normal_at(p).z > 0.0);
    }

    #[test]
    fn bad_cascades_are_refused() {
        let s = Phillips::default();
        assert!(Cascade::new(&base(), &[100.0], &s, Seed(1)).is_err());
        assert!(Cascade::new(&base(), &[100.0, 200.0], &s, Seed(1)).is_err());
        assert!(Cascade::new(&base(), &[100.0, 10.0, 5.0, 2.0, 1.0], &s, Seed(1)).is_err());
        assert!(Cascade::with_boundaries(&base(), &[100.0, 10.0], &[], &s, Seed(1)).is_err());
        assert!(
            Cascade::with_boundaries(&base(), &[100.0, 10.0, 1.0], &[2.0, 1.0], &s, Seed(1))
                .is_err()
        );
        assert!(Cascade::new(&base(), &[100.0, f64::NAN], &s, Seed(1)).is_err());
    }
}
