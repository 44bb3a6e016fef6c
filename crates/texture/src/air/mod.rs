//! Air: clouds, storms and the Coriolis-sheared clouds of Venus (Musgrave
//! 1998, "Clouds"; Musgrave 1993, §5.2–5.4).

pub mod cyclone;
pub mod planet_clouds;
pub mod puffy;
pub mod venus;

pub use cyclone::{Cyclone, CycloneParams};
pub use planet_clouds::{CloudBasis, CloudDistortion, PlanetClouds, PlanetCloudsParams};
pub use puffy::{PuffyClouds, PuffyCloudsParams};
pub use venus::{Venus, VenusParams};
