//! Tessendorf FFT ocean waves, spectra, dispersion, Gerstner waves and water optics.
