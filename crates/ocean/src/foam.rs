//! foam
