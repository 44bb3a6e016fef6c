//! gerstner
