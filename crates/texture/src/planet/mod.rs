//! Procedural planets: a sphere of Earth's radius displaced by a terran
//! height function in `f64`, sphere traced with a Lipschitz bound and only
//! as much detail as the pixel footprint shows, with a sea level,
//! natura-atmos's radial atmosphere and umbra, a cloud shell that casts its
//! shadow, rings, and export to cube-sphere and equirectangular maps.
//!
//! The model is Musgrave's Gaea (Musgrave 1993, ch. 5 and §4.1.6; Musgrave
//! 2001, "Building Planets"): a planet "covered with terrains that are
//! fractal", ensconced in an atmosphere that curves round it, wrapped in a
//! transparency-mapped cloud sphere "concentric with, and of radius slightly
//! greater than, the earth". Where the dissertation renders a smooth sphere
//! with a bump map — so that "the mountains cannot cast shadows, and they do
//! not rise up through the atmosphere", the future work it names — the
//! planet here is displaced geometry: mountains cast shadows and rise
//! through the haze. Rendering is "procedural, level-of-detail ray tracing":
//! no height field is stored; each ray marches the implicit surface
//! `|p| − R − h(p/|p|) = 0` with steps its Lipschitz bound makes safe
//! (sphere tracing), summing only the octaves its footprint at that distance
//! shows.
//!
//! Coordinates are world metres with the planet's centre at the origin and
//! its rotation axis (and ring plane normal) along z.

mod biome;
mod clouds;
mod cube;
mod height;
mod params;
mod shade;
mod trace;
mod views;

pub use biome::{BiomeParams, Biomes};
pub use clouds::CloudShell;
pub use cube::{CubeFace, CubeMap, Face, SurfaceMap};
pub use height::Relief;
pub use params::{
    CloudLayerParams, EARTH_RADIUS_M, LightParams, MAX_SUN_COLOUR, PlanetAtmosphereParams,
    PlanetDetailParams, PlanetParams, SurfaceParams, TEXTURE_SCALE_RANGE, TerrainParams,
};
pub use trace::{EPSILON_RESOLUTION, MAX_TRACE_STEPS, SurfaceHit, TraceSettings};
pub use views::{GroundViewParams, MAX_ALTITUDE_M, direction};

use glam::DVec3;
use natura_atmos::Dir3;
use natura_atmos::medium::{RadialAtmosphere, Umbra};

use crate::air::Venus;
use crate::earth::{Luna, Terran};
use crate::error::Result;
use crate::footprint::Footprint;
use crate::giants::{GasGiant, Rings};
use crate::texture::SolidTexture;

/// The surface of a built planet.
#[derive(Debug)]
enum Surface {
    /// Displaced terrain with a sea level.
    Terrain(Box<Relief>),
    /// A smooth sphere coloured (and bump mapped) by a solid texture.
    Textured(Box<dyn TexturedSurface>),
}

/// The solid textures a smooth planet may wear.
trait TexturedSurface: SolidTexture + std::fmt::Debug {}
impl TexturedSurface for Venus {}
impl TexturedSurface for GasGiant {}
impl TexturedSurface for Luna {}

/// The atmosphere of a built planet: day and night media switched on the
/// planet's shadow cylinder, and the day medium alone for sunlight.
#[derive(Debug)]
struct Air {
    umbra: Umbra<RadialAtmosphere, RadialAtmosphere>,
    day: RadialAtmosphere,
}

/// A planet ready to render: the validated [`PlanetParams`] with every
/// texture and medium built.
#[derive(Debug)]
pub struct Planet {
    params: PlanetParams,
    surface: Surface,
    air: Option<Air>,
    biomes: Option<Biomes>,
    clouds: Option<CloudShell>,
    rings: Option<Rings>,
    sun: DVec3,
}

impl Planet {
    /// Builds the planet for `params`.
    ///
    /// # Errors
    /// [`TextureError`](crate::TextureError) naming the first invalid
    /// parameter (radius, relief, atmosphere, clouds, rings, light).
    pub fn new(params: PlanetParams) -> Result<Self> {
        params.validate()?;
        let r = params.radius_m;
        let surface = match &params.surface {
            SurfaceParams::Terrain(t) => Surface::Terrain(Box::new(Relief::new(
                Terran::new(t.terran)?,
                r,
                t.relief_m,
                t.texture_scale,
                t.detail,
            )?)),
            SurfaceParams::Venus(v) => Surface::Textured(Box::new(Venus::new(*v)?)),
            SurfaceParams::GasGiant(g) => Surface::Textured(Box::new(GasGiant::new(*g)?)),
            SurfaceParams::Luna(l) => Surface::Textured(Box::new(Luna::new(*l)?)),
        };
        let biomes = match &params.surface {
            SurfaceParams::Terrain(t) => match &t.biomes {
                Some(b) => Some(Biomes::new(*b, t.terran.seed)?),
                None => None,
            },
            _ => None,
        };
        let sun = params.light.sun.normalize();
        let air = match &params.atmosphere {
            None => None,
            Some(a) => {
                let day = RadialAtmosphere::new(
                    a.extinction,
                    a.day_colour,
                    DVec3::ZERO,
                    r,
                    a.scale_height_m,
                )?;
                let night = RadialAtmosphere::new(
                    a.extinction,
                    a.night_colour,
                    DVec3::ZERO,
                    r,
                    a.scale_height_m,
                )?;
                let umbra = Umbra::new(
                    day,
                    night,
                    DVec3::ZERO,
                    r,
                    a.umbra_margin_m,
                    Dir3::new(sun)?,
                )?;
                Some(Air { umbra, day })
            }
        };
        let clouds = match &params.clouds {
            None => None,
            Some(c) => Some(CloudShell::new(*c)?),
        };
        let rings = match &params.rings {
            None => None,
            Some(r) => Some(Rings::new(*r)?),
        };
        Ok(Self {
            params,
            surface,
            air,
            biomes,
            clouds,
            rings,
            sun,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &PlanetParams {
        &self.params
    }

    /// The radius `R` of the sea-level sphere, metres.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.params.radius_m
    }

    /// The relief, if the surface is displaced terrain.
    #[must_use]
    pub fn relief(&self) -> Option<&Relief> {
        match &self.surface {
            Surface::Terrain(r) => Some(r),
            Surface::Textured(_) => None,
        }
    }

    /// The biome colouring, if the surface is terrain coloured by biome.
    #[must_use]
    pub fn biomes(&self) -> Option<&Biomes> {
        self.biomes.as_ref()
    }

    /// The cloud shell's density in the unit direction `dir` for a
    /// footprint of `footprint_m` metres on the shell (0 without clouds).
    #[must_use]
    pub fn cloud_density(&self, dir: DVec3, footprint_m: f64) -> f64 {
        match (&self.clouds, &self.params.clouds) {
            (Some(shell), Some(c)) => {
                let rc = self.radius() + c.altitude_m;
                let fp = Footprint::new(footprint_m / rc).unwrap_or(Footprint::POINT);
                shell.density(dir.normalize(), fp)
            }
            _ => 0.0,
        }
    }

    /// Unit direction towards the sun.
    #[must_use]
    pub fn sun(&self) -> DVec3 {
        self.sun
    }

    /// The radius of the outermost surface point: `R` plus the relief's
    /// height bound.
    #[must_use]
    pub fn max_radius(&self) -> f64 {
        self.radius() + self.relief().map_or(0.0, Relief::max_height)
    }

    /// The surface height above `R` (metres) in the unit direction `dir`
    /// for a footprint of `footprint_m` metres (0 for a smooth planet).
    #[must_use]
    pub fn height(&self, dir: DVec3, footprint_m: f64) -> f64 {
        self.relief()
            .map_or(0.0, |r| r.height(dir, r.footprint(footprint_m)))
    }
}
