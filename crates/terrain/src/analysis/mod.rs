//! Terrain analysis: surface derivatives ([`surface`]), flow routing and
//! drainage networks ([`flow`], [`hydrology`]) and fractal statistics
//! ([`stats`]).

pub mod flow;
pub mod hydrology;
pub mod stats;
pub mod surface;

pub use flow::{Depressions, FlowGraph, fill_depressions};
pub use hydrology::{
    WETNESS_MFD_EXPONENT, channel_network, d8_directions, flow_accumulation_d8,
    flow_accumulation_mfd, strahler_order, wetness, wetness_index,
};
pub use stats::{
    RadialSpectrum, hypsometric_curve, hypsometric_integral, path_h, radial_power_spectrum,
    spectral_h, variogram, variogram_h,
};
pub use surface::{Curvature, curvature, slope, surface_area};
