//! Water bodies on a terrain: the sea level ([`water_level`]), lakes filled
//! to their spill points under a sea ([`water_surface`]), connected water
//! bodies ([`large_components`]) and a coast sunk below the sea at the edge
//! of the data ([`sink_coast`]).
//!
//! The lakes are the depressions Priority-Flood fills (Barnes et al. 2014,
//! §2, Algorithm 1), through [`fill_depressions`](crate::analysis::fill_depressions);
//! which of them hold water, the interior quantile that sets the sea level
//! and the sunken coast are natura's own constructions, made so that a
//! synthetic terrain ends in a sea instead of a cliff at its border.

mod bodies;
mod coast;
mod lakes;
mod level;

pub use bodies::large_components;
pub use coast::{CoastParams, sink_coast};
pub use lakes::{LakeParams, water_surface};
pub use level::water_level;

#[cfg(test)]
mod tests;
