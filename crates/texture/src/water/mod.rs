//! Water: noise ripples and wind-blown waves, the bump maps of Musgrave's
//! lakes and seas (Musgrave 1998, "Water").

pub mod ripples;
pub mod windywave;

pub use ripples::{Ripples, RipplesParams};
pub use windywave::{WindyWave, WindyWaveParams};
