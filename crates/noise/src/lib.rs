//! Noise bases, fractional Brownian motion, multifractals and domain distortion.
#![no_std]
