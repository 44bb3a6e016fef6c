//! Earth: rock strata, whole Earth-like planets, the Moon, and the ridge of
//! Musgrave's statistics-by-altitude terrain (Musgrave 1998, "Earth";
//! Musgrave 1993, §2.3.2.3.3 and §5.6).

pub mod luna;
pub mod ridge;
pub mod strata;
pub mod terran;
pub mod terran_sphere;

pub use luna::{CraterProfile, Luna, LunaParams};
pub use ridge::{Ridge, RidgeParams, tent};
pub use strata::{Strata, StrataParams};
pub use terran::{Continents, Terran, TerranParams, TerranShade};
pub use terran_sphere::{SphereView, TerranSphere};
