//! Spectral colour: wavelength sampling, the CIE 1931 colour-matching
//! functions, illuminants, XYZ → linear sRGB with chromatic adaptation,
//! RGB → spectrum upsampling, and Musgrave's 13-sample spectral rgb tables.
//!
//! Wavelengths are **vacuum wavelengths in nanometres** throughout (the
//! dissertation mixes frequency and wavelength, Musgrave 1993, §4.2.3.1 vs §4.2.4.3.2).
//! Colours are linear sRGB (Rec. 709 primaries, D65 white) in `DVec3`.

pub mod cie;
#[allow(missing_docs, clippy::excessive_precision, clippy::unreadable_literal)]
mod cie_data;
mod musgrave;
mod sampling;
mod upsample;

pub use cie::{
    Illuminant, bradford, cmf_1931, cmf_wyman_2013, linear_srgb_to_xyz, spectrum_to_xyz,
    xyz_to_linear_srgb, xyz_to_xy,
};
pub use cie_data::{TABLE_MAX_NM, TABLE_MIN_NM};
pub use musgrave::{SpectralRgbTable, clamp_sum};
pub use sampling::{HeroWavelengths, WavelengthSampler};
pub use upsample::SigmoidSpectrum;

/// Musgrave's visible range, 380–800 nm (eq. 4.2.8, Musgrave 1993, §4.2.4.1).
pub const VISIBLE_MUSGRAVE: (f64, f64) = (380.0, 800.0);
