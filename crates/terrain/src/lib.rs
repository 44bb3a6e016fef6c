//! Terrain synthesis (subdivision, faulting, spectral, noise), erosion and analysis.
