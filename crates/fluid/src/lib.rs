//! Stable fluids, smoke with vorticity confinement, and liquids.
