//! Giants: the banded gas giants and their rings (Musgrave 1993, §5.5;
//! Musgrave 1998, "Planetary Rings").

pub mod gas_giant;
pub mod rings;

pub use gas_giant::{Bands, GasGiant, GasGiantParams};
pub use rings::{Rings, RingsParams};
