//! # natura-texture
//!
//! Musgrave's fractal solid textures — clouds, storms, fire, water, rock,
//! whole planets, a moon, painterly colour — as small named functions of a
//! 3-D point, and procedural planets built from them: displaced, sphere
//! traced at Earth scale, with atmosphere, clouds and rings.
//!
//! Sources: Musgrave 1993 (the dissertation, ch. 5 "Procedural Textures"),
//! Musgrave 1998 (*Texturing & Modeling*, ch. 15 "Fractal Solid Textures:
//! Some Examples") and Musgrave 2001 ("Building Planets"); keys as in
//! `docs/sources.md`. Every fractal is natura-noise's.
//!
//! ## Textures
//!
//! Each texture is a type with a `Params` struct (`Default` = the source's
//! values, `validate()`, serde behind the `serde` feature), named methods
//! for what it computes (a colour, a density, a height) and an
//! implementation of [`SolidTexture`], the seam the renderers use.
//!
//! | element | textures |
//! |---|---|
//! | [`air`] | [`PuffyClouds`](air::PuffyClouds), [`PlanetClouds`](air::PlanetClouds) (global circulation), [`Cyclone`](air::Cyclone), [`Venus`](air::Venus) (Coriolis twist) |
//! | [`fire`] | [`Flame`](fire::Flame) |
//! | [`water`] | [`Ripples`](water::Ripples), [`WindyWave`](water::WindyWave) |
//! | [`earth`] | [`Strata`](earth::Strata), [`Terran`](earth::Terran) (Gaea), [`Luna`](earth::Luna) (Selene, a rayed crater), [`Ridge`](earth::Ridge) (the tent `F(x)`) |
//! | [`giants`] | [`GasGiant`](giants::GasGiant) (Jupiter, Saturn), [`Rings`](giants::Rings) |
//! | [`multicolor`] | [`Multicolor`](multicolor::Multicolor) |
//! | [`git`] | [`Git`](git::Git) (the generalized Impressionistic texture) and the painterly [`git_filter`](git::git_filter) |
//!
//! **Antialiasing** lives in one place, [`footprint`]: a sample's
//! [`Footprint`] (the width it covers in texture space) becomes a real-valued
//! number of visible octaves, and every fractal is summed only that far, the
//! last octave fading in continuously — the dissertation's level of detail,
//! so a texture seen from far away does not shimmer. Bump and displacement
//! normals come from analytic fBm gradients where the texture has them and
//! from central differences over the footprint otherwise ([`normal`]).
//!
//! Each texture's rustdoc states the errata of its listing that it corrects.
//!
//! ## Planets
//!
//! [`planet`]: an `f64` sphere of Earth's radius displaced by a terran
//! height function (no cracks, 1 cm detail stable at 6 371 km), sphere
//! traced with a Lipschitz bound of the height and only as much detail as
//! the pixel footprint shows; a sea level; natura-atmos's radial
//! atmosphere and umbra seen from space and from the ground; a cloud shell
//! with its shadow; rings; and the cube-sphere and equirectangular export.
//!
//! ```
//! use natura_texture::glam::DVec3;
//! use natura_texture::{Footprint, SolidTexture, earth::{Terran, TerranParams}};
//! let earth = Terran::new(TerranParams::default())?;
//! let s = earth.sample(DVec3::new(0.3, -0.5, 0.81), Footprint::new(1e-3)?);
//! assert!(s.is_valid());
//! # Ok::<(), natura_texture::TextureError>(())
//! ```
#![forbid(unsafe_code)]

pub mod air;
pub mod earth;
mod error;
pub mod fire;
pub mod footprint;
mod fractals;
pub mod giants;
pub mod git;
pub mod multicolor;
pub mod normal;
pub mod planet;
pub mod preview;
pub mod row_fill;
pub mod spline;
mod texture;
pub mod view;
pub mod water;

pub use error::{Result, TextureError};
pub use footprint::Footprint;
/// The vector types of the API, so users need no `glam` dependency of their own.
pub use glam;
pub use spline::ColourSpline;
pub use texture::{Sample, SolidTexture, TextureKind, display_to_linear};
pub use view::View;
