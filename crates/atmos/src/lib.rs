//! Aerial perspective, sky, spectral colour, rainbow and mirage.
